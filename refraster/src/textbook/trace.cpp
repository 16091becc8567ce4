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
    const bool any = !steps.empty();
    const std::size_t pixels = pixels_before_last + (any ? steps.back().pixels.size() : 0);
    const std::size_t segments = segments_before_last + (any ? steps.back().overlay.size() : 0);
    return steps.size() < max_steps && pixels < max_pixels && segments < max_segments;
}

Step& add_step(Trace& trace, std::string title) {
    if (!trace.recording()) {
        ++trace.omitted;
        trace.discarded = Step{};
        trace.discarded.title = std::move(title);
        return trace.discarded;
    }
    if (!trace.steps.empty()) {
        Step& last = trace.steps.back();
        trim_step(last, trace.max_values, trace.max_value_chars);
        trace.pixels_before_last += last.pixels.size();
        trace.segments_before_last += last.overlay.size();
    }
    trace.steps.emplace_back();
    trace.steps.back().title = std::move(title);
    trace.steps.back().group = trace.group;
    return trace.steps.back();
}

void set_pseudo_code(Trace* trace, std::vector<std::string> lines) {
    if (trace != nullptr) trace->pseudo_code = std::move(lines);
}

void begin_part(Trace* trace, std::string_view kind) {
    if (trace == nullptr) return;
    ++trace->parts;
    trace->group = std::string(kind) + " " + std::to_string(trace->parts);
}

void trim_step(Step& step, std::size_t max_values, std::size_t max_value_chars) {
    if (max_values > 0 && step.state.size() > max_values) {
        const std::size_t more = step.state.size() - (max_values - 1);
        step.state.resize(max_values - 1);
        step.state.push_back({"...", std::to_string(more) + " more values not shown"});
    }
    for (auto& [key, value] : step.state) {
        if (value.size() <= max_value_chars) continue;
        const std::size_t more = value.size() - max_value_chars;
        value.resize(max_value_chars);
        value.shrink_to_fit();
        value += " ... (" + std::to_string(more) + " more characters)";
    }
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
