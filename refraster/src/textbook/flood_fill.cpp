#include "refraster/textbook/flood_fill.hpp"

#include <array>
#include <string>

namespace refraster::textbook {

namespace {

// The order in which a recursive fill would visit the neighbours; pushed in reverse.
constexpr std::array<PixelIndex, 8> kNeighbours = {
    {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1}}};

std::string describe_stack(const std::vector<PixelIndex>& stack) {
    constexpr std::size_t kShown = 12;
    std::string s = "[";
    const std::size_t n = stack.size();
    for (std::size_t k = 0; k < n && k < kShown; ++k) {
        if (k > 0) s += ", ";
        const PixelIndex& p = stack[n - 1 - k];  // the top first
        s += format_pixel(p.x, p.y);
    }
    if (n > kShown) s += ", ... " + std::to_string(n - kShown) + " more";
    return s + "]";
}

}  // namespace

FloodResult flood_fill(const Raster& boundary, PixelIndex seed, Connectivity connectivity,
                       Trace* trace) {
    FloodResult out{{}, Raster(boundary.width(), boundary.height())};
    const std::size_t neighbours = connectivity == Connectivity::Four ? 4 : 8;
    if (trace != nullptr) {
        trace->algorithm = connectivity == Connectivity::Four ? "boundary fill, 4-connected"
                                                              : "boundary fill, 8-connected";
    }
    std::vector<PixelIndex> stack{seed};
    while (!stack.empty()) {
        const PixelIndex p = stack.back();
        stack.pop_back();
        const char* reject = nullptr;
        if (!boundary.contains(p.x, p.y)) {
            reject = "outside the raster";
        } else if (boundary.at(p.x, p.y) > 0.0) {
            reject = "a boundary pixel";
        } else if (out.raster.at(p.x, p.y) > 0.0) {
            reject = "already filled";
        }
        if (reject == nullptr) {
            out.raster.set(p.x, p.y, 1.0);
            out.order.push_back(p);
            for (std::size_t k = neighbours; k > 0; --k) {
                const PixelIndex d = kNeighbours[k - 1];
                stack.push_back({p.x + d.x, p.y + d.y});
            }
        }
        if (trace == nullptr) continue;
        Step& step = add_step(*trace, "pop " + format_pixel(p.x, p.y) + ": " +
                                          (reject == nullptr ? "fill, push its neighbours"
                                                             : std::string(reject) + ", skip"));
        step.state.push_back({"stack", describe_stack(stack)});
        step.state.push_back({"filled", std::to_string(out.order.size())});
        step.pixels.push_back({p.x, p.y, reject == nullptr ? 1.0 : 0.0});
    }
    return out;
}

}  // namespace refraster::textbook
