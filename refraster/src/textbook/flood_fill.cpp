#include "refraster/textbook/flood_fill.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
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

int winding_at_centre(const std::vector<Point2>& outline, int x, int y) {
    const double cx = x + 0.5;
    const double cy = y + 0.5;
    int w = 0;
    for (std::size_t k = 0; k < outline.size(); ++k) {
        const Point2 a = outline[k];
        const Point2 b = outline[(k + 1) % outline.size()];
        if ((a.y > cy) == (b.y > cy)) continue;
        const double xc = a.x + (cy - a.y) * (b.x - a.x) / (b.y - a.y);
        if (xc <= cx) w += b.y > a.y ? 1 : -1;
    }
    return w;
}

std::optional<PixelIndex> seed_inside(const Raster& boundary, const std::vector<Point2>& outline,
                                      std::size_t* examined) {
    if (examined != nullptr) *examined = 0;
    if (outline.empty() || boundary.width() == 0 || boundary.height() == 0) return std::nullopt;
    double x_lo = outline[0].x, x_hi = x_lo, y_lo = outline[0].y, y_hi = y_lo;
    double mx = 0.0, my = 0.0;
    for (const Point2& p : outline) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) return std::nullopt;
        x_lo = std::min(x_lo, p.x);
        x_hi = std::max(x_hi, p.x);
        y_lo = std::min(y_lo, p.y);
        y_hi = std::max(y_hi, p.y);
        mx += p.x;
        my += p.y;
    }
    mx /= static_cast<double>(outline.size());
    my /= static_cast<double>(outline.size());
    if (!std::isfinite(mx)) mx = (x_lo + x_hi) / 2.0;  // the sum overflowed: the box's middle
    if (!std::isfinite(my)) my = (y_lo + y_hi) / 2.0;
    // The pixels whose centres lie in the box, clipped to the raster (in double: the outline
    // may reach far outside it).
    const auto clip = [](double v, int lo, int hi) {
        return static_cast<int>(std::clamp(v, static_cast<double>(lo), static_cast<double>(hi)));
    };
    const int w = boundary.width();
    const int h = boundary.height();
    const int bx0 = clip(std::ceil(x_lo - 0.5), 0, w);
    const int bx1 = clip(std::floor(x_hi - 0.5), -1, w - 1);
    const int by0 = clip(std::ceil(y_lo - 0.5), 0, h);
    const int by1 = clip(std::floor(y_hi - 0.5), -1, h - 1);
    if (bx0 > bx1 || by0 > by1) return std::nullopt;
    // The centre of the rings (in 64 bits: the mean may lie far outside the raster; beyond 2^40
    // pixels away it is clamped), and the nearest and farthest rings that meet the box.
    using I = long long;
    constexpr double kFar = 1099511627776.0;  // 2^40
    const I cx = static_cast<I>(std::clamp(std::floor(mx), -kFar, kFar));
    const I cy = static_cast<I>(std::clamp(std::floor(my), -kFar, kFar));
    const I x0 = bx0, x1 = bx1, y0 = by0, y1 = by1;
    const auto gap = [](I c, I lo, I hi) { return c < lo ? lo - c : c > hi ? c - hi : I{0}; };
    const I r0 = std::max(gap(cx, x0, x1), gap(cy, y0, y1));
    const I r1 = std::max(
        {std::llabs(cx - x0), std::llabs(cx - x1), std::llabs(cy - y0), std::llabs(cy - y1)});
    std::size_t tested = 0;
    std::optional<PixelIndex> seed;
    // Tests pixel (x, y) of the box; true when it is the seed.
    const auto test = [&](I x, I y) {
        ++tested;
        const int px = static_cast<int>(x);
        const int py = static_cast<int>(y);
        if (boundary.at(px, py) > 0.0 || winding_at_centre(outline, px, py) == 0) return false;
        seed = PixelIndex{px, py};
        return true;
    };
    for (I r = r0; r <= r1 && !seed; ++r) {
        const I x_first = std::max(cx - r, x0);
        const I x_last = std::min(cx + r, x1);
        const bool left = cx - r >= x0 && cx - r <= x1;
        const bool right = r > 0 && cx + r >= x0 && cx + r <= x1;
        const I y_first = std::max(cy - r, y0);
        const I y_last = std::min(cy + r, y1);
        for (I y = y_first; y <= y_last && !seed; ++y) {
            if (y == cy - r || y == cy + r) {
                // A whole row of the ring.
                for (I x = x_first; x <= x_last && !test(x, y); ++x) {
                }
                continue;
            }
            if (!left && !right) {
                y = y_last - (cy + r <= y1 ? 1 : 0);  // straight to the ring's top row
                continue;
            }
            if (left && test(cx - r, y)) break;
            if (right) test(cx + r, y);
        }
    }
    if (examined != nullptr) *examined = tested;
    return seed;
}

FloodResult flood_fill(const Raster& boundary, PixelIndex seed, Connectivity connectivity,
                       Trace* trace) {
    FloodResult out{{}, Raster(boundary.width(), boundary.height())};
    const std::size_t neighbours = connectivity == Connectivity::Four ? 4 : 8;
    if (trace != nullptr) {
        trace->algorithm = connectivity == Connectivity::Four ? "boundary fill, 4-connected"
                                                              : "boundary fill, 8-connected";
        begin_part(trace, "fill");
        set_pseudo_code(trace,
                        {"push the seed", "while the stack is not empty:", "    pop a pixel p",
                         "    if p is outside, on the boundary or already filled: skip it",
                         "    else: fill p and push its neighbours (4 or 8)"});
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
        step.line = reject == nullptr ? 5 : 4;
        step.state.push_back({"stack", describe_stack(stack)});
        step.state.push_back({"filled", std::to_string(out.order.size())});
        step.pixels.push_back({p.x, p.y, reject == nullptr ? 1.0 : 0.0});
    }
    return out;
}

}  // namespace refraster::textbook
