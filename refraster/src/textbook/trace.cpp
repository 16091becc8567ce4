#include "refraster/textbook/trace.hpp"

#include <array>
#include <charconv>
#include <cstddef>

#include "refraster/assert.hpp"

namespace refraster::textbook {

Raster::Raster(int width, int height) : width_(width), height_(height) {
    REFRASTER_ASSERT(width >= 0 && height >= 0, "a raster of non-negative size");
    weight_.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0.0);
}

double Raster::at(int x, int y) const {
    if (!contains(x, y)) return 0.0;
    return weight_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
                   static_cast<std::size_t>(x)];
}

void Raster::set(int x, int y, double weight) {
    if (!contains(x, y)) return;
    weight_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
            static_cast<std::size_t>(x)] = weight;
}

void Raster::add(int x, int y, double weight) {
    if (!contains(x, y)) return;
    weight_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
            static_cast<std::size_t>(x)] += weight;
}

int Raster::count_nonzero() const {
    int n = 0;
    for (const double w : weight_) {
        if (w != 0.0) ++n;
    }
    return n;
}

std::string format_number(double v) {
    std::array<char, 32> buf{};
    const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    return std::string(buf.data(), r.ptr);
}

std::string format_number(long long v) {
    return std::to_string(v);
}

std::string format_pixel(int x, int y) {
    return "(" + std::to_string(x) + ", " + std::to_string(y) + ")";
}

bool Trace::recording() const {
    const std::size_t pixels =
        pixels_before_last + (steps.empty() ? 0 : steps.back().pixels.size());
    return steps.size() < max_steps && pixels < max_pixels;
}

Step& add_step(Trace& trace, std::string title) {
    if (!trace.recording()) {
        ++trace.omitted;
        trace.discarded = Step{};
        trace.discarded.title = std::move(title);
        return trace.discarded;
    }
    if (!trace.steps.empty()) trace.pixels_before_last += trace.steps.back().pixels.size();
    trace.steps.emplace_back();
    trace.steps.back().title = std::move(title);
    return trace.steps.back();
}

void add_outline(std::vector<Segment>& into, const std::vector<Point2>& polygon,
                 const std::string& role) {
    for (std::size_t i = 0; i < polygon.size(); ++i) {
        const Point2 a = polygon[i];
        const Point2 b = polygon[(i + 1) % polygon.size()];
        into.push_back({a.x, a.y, b.x, b.y, role});
    }
}

}  // namespace refraster::textbook
