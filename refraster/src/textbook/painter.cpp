#include "refraster/textbook/painter.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "snap.hpp"

namespace refraster::textbook {

namespace {

using detail::Int128;
using detail::kSnapOne;
using detail::SnappedPoint;

constexpr int kDepthBits = 16;
constexpr double kMaxDepth = 256.0;

std::int64_t snap_depth(double z) {
    REFRASTER_ASSERT(std::isfinite(z) && std::fabs(z) <= kMaxDepth, "a depth within 2^8");
    return static_cast<std::int64_t>(std::llround(std::ldexp(z, kDepthBits)));
}

// A triangle prepared for exact tests: counter-clockwise vertices and their depths.
struct Prepared {
    std::array<SnappedPoint, 3> p{};
    std::array<std::int64_t, 3> z{};
    std::int64_t twice_area = 0;  // > 0 unless degenerate
};

Prepared prepare(const DepthTriangle& t) {
    Prepared r;
    for (std::size_t i = 0; i < 3; ++i) {
        r.p[i] = {detail::snap(t.position[i].x), detail::snap(t.position[i].y)};
        r.z[i] = snap_depth(t.depth[i]);
    }
    r.twice_area = detail::orient(r.p[0], r.p[1], r.p[2]);
    if (r.twice_area < 0) {
        std::swap(r.p[1], r.p[2]);
        std::swap(r.z[1], r.z[2]);
        r.twice_area = -r.twice_area;
    }
    return r;
}

SnappedPoint centre_of(int x, int y) {
    return {std::int64_t{x} * kSnapOne + kSnapOne / 2, std::int64_t{y} * kSnapOne + kSnapOne / 2};
}

// The edge function of a -> b at c, nudged: inside when > 0, or when 0 and the nudge
// (+e, +e^2) moves c inside: d/dx = -(b.y - a.y), then d/dy = b.x - a.x.
bool inside_edge(SnappedPoint a, SnappedPoint b, SnappedPoint c, std::int64_t& value) {
    value = detail::orient(a, b, c);
    if (value != 0) return value > 0;
    const std::int64_t ddx = -(b.y - a.y);
    if (ddx != 0) return ddx > 0;
    return b.x - a.x > 0;
}

// Whether the prepared triangle covers c; the edge functions (barycentric numerators) in e.
bool covers(const Prepared& t, SnappedPoint c, std::array<std::int64_t, 3>& e) {
    if (t.twice_area == 0) return false;
    // e[i] is the edge opposite vertex i.
    const bool in0 = inside_edge(t.p[1], t.p[2], c, e[0]);
    const bool in1 = inside_edge(t.p[2], t.p[0], c, e[1]);
    const bool in2 = inside_edge(t.p[0], t.p[1], c, e[2]);
    return in0 && in1 && in2;
}

// The depth at a covered centre as numerator / twice_area.
Int128 depth_numerator(const Prepared& t, const std::array<std::int64_t, 3>& e) {
    Int128 n = 0;
    for (std::size_t i = 0; i < 3; ++i) n += static_cast<Int128>(e[i]) * t.z[i];
    return n;
}

VisibilityResult empty_result(int width, int height) {
    VisibilityResult r;
    r.width = width;
    r.height = height;
    r.visible.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), -1);
    r.raster = Raster(width, height);
    return r;
}

std::size_t index_of(int width, int x, int y) {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
           static_cast<std::size_t>(x);
}

void describe_input(Trace* trace, const std::vector<DepthTriangle>& triangles, const char* name) {
    if (trace == nullptr) return;
    trace->algorithm = name;
    for (const DepthTriangle& t : triangles) {
        for (std::size_t i = 0; i < 3; ++i) {
            const Point2 a = t.position[i];
            const Point2 b = t.position[(i + 1) % 3];
            trace->input.push_back({a.x, a.y, b.x, b.y, "edge"});
        }
    }
}

void add_outline(Step& step, const DepthTriangle& t) {
    for (std::size_t i = 0; i < 3; ++i) {
        const Point2 a = t.position[i];
        const Point2 b = t.position[(i + 1) % 3];
        step.overlay.push_back({a.x, a.y, b.x, b.y, "edge"});
    }
}

}  // namespace

int VisibilityResult::at(int x, int y) const {
    if (x < 0 || y < 0 || x >= width || y >= height) return -1;
    return visible[index_of(width, x, y)];
}

bool covers_centre(const DepthTriangle& triangle, int x, int y) {
    std::array<std::int64_t, 3> e{};
    return covers(prepare(triangle), centre_of(x, y), e);
}

VisibilityResult painter(const std::vector<DepthTriangle>& triangles, PainterKey key, int width,
                         int height, Trace* trace) {
    describe_input(trace, triangles, "painter's algorithm");
    set_pseudo_code(trace, {"sort the triangles back to front by their key (the farthest "
                            "vertex's depth, or the mean depth)",
                            "for each triangle in that order:",
                            "    draw it over what is there, no depth test"});
    VisibilityResult out = empty_result(width, height);
    std::vector<Prepared> prepared;
    std::vector<std::int64_t> keys;
    for (const DepthTriangle& t : triangles) {
        prepared.push_back(prepare(t));
        const auto& z = prepared.back().z;
        // Snapped depths: the mean as the sum (three times the mean, same order).
        keys.push_back(key == PainterKey::FarthestVertex ? std::max({z[0], z[1], z[2]})
                                                         : z[0] + z[1] + z[2]);
    }
    out.order.resize(triangles.size());
    std::iota(out.order.begin(), out.order.end(), 0);
    std::stable_sort(out.order.begin(), out.order.end(), [&](int a, int b) {
        return keys[static_cast<std::size_t>(a)] > keys[static_cast<std::size_t>(b)];
    });
    if (trace != nullptr) {
        std::string order;
        for (const int i : out.order) order += (order.empty() ? "T" : ", T") + std::to_string(i);
        Step& s = add_step(
            *trace, std::string("sort back to front by ") +
                        (key == PainterKey::FarthestVertex ? "farthest vertex" : "mean depth"));
        s.line = 1;
        s.state.push_back({"order", "[" + order + "]"});
    }
    for (const int ti : out.order) {
        const Prepared& t = prepared[static_cast<std::size_t>(ti)];
        int drawn = 0;
        int overwritten = 0;
        Step* step = nullptr;
        if (trace != nullptr) {
            const double k =
                std::ldexp(static_cast<double>(keys[static_cast<std::size_t>(ti)]), -kDepthBits) /
                (key == PainterKey::MeanDepth ? 3.0 : 1.0);
            step = &add_step(*trace,
                             "draw T" + std::to_string(ti) + " (key " + format_number(k) + ")");
            step->line = 3;
            add_outline(*step, triangles[static_cast<std::size_t>(ti)]);
        }
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                std::array<std::int64_t, 3> e{};
                if (!covers(t, centre_of(x, y), e)) continue;
                int& v = out.visible[index_of(width, x, y)];
                if (v >= 0) ++overwritten;
                v = ti;
                ++drawn;
                out.raster.set(x, y, 1.0);
                if (step != nullptr) step->pixels.push_back({x, y, 1.0});
            }
        }
        if (step != nullptr) {
            step->state.push_back({"pixels", std::to_string(drawn)});
            step->state.push_back({"painted over", std::to_string(overwritten)});
        }
    }
    return out;
}

VisibilityResult z_buffer(const std::vector<DepthTriangle>& triangles, int width, int height,
                          Trace* trace) {
    describe_input(trace, triangles, "z-buffer");
    set_pseudo_code(
        trace, {"clear the depth buffer to the far plane", "for each triangle in the draw order:",
                "    at each covered centre: draw it where its depth is less than "
                "the stored one, and store its depth"});
    VisibilityResult out = empty_result(width, height);
    // The stored depth per pixel as numerator / denominator.
    std::vector<Int128> depth_num(out.visible.size(), 0);
    std::vector<Int128> depth_den(out.visible.size(), 1);
    for (std::size_t ti = 0; ti < triangles.size(); ++ti) {
        out.order.push_back(static_cast<int>(ti));
        const Prepared t = prepare(triangles[ti]);
        int passed = 0;
        int failed = 0;
        Step* step = nullptr;
        if (trace != nullptr) {
            step = &add_step(*trace, "draw T" + std::to_string(ti) + " with the depth test");
            step->line = 3;
            add_outline(*step, triangles[ti]);
        }
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                std::array<std::int64_t, 3> e{};
                if (!covers(t, centre_of(x, y), e)) continue;
                const std::size_t i = index_of(width, x, y);
                const Int128 n = depth_numerator(t, e);
                const Int128 d = t.twice_area;
                const bool pass = out.visible[i] < 0 || n * depth_den[i] < depth_num[i] * d;
                if (pass) {
                    out.visible[i] = static_cast<int>(ti);
                    depth_num[i] = n;
                    depth_den[i] = d;
                    out.raster.set(x, y, 1.0);
                    ++passed;
                } else {
                    ++failed;
                }
                if (step != nullptr) step->pixels.push_back({x, y, pass ? 1.0 : 0.0});
            }
        }
        if (step != nullptr) {
            step->state.push_back({"passed", std::to_string(passed)});
            step->state.push_back({"failed", std::to_string(failed)});
        }
    }
    return out;
}

std::optional<VisibilityDifference> first_difference(const VisibilityResult& painted,
                                                     const VisibilityResult& z_buffered) {
    REFRASTER_ASSERT(painted.width == z_buffered.width && painted.height == z_buffered.height,
                     "results of the same size");
    for (int y = 0; y < painted.height; ++y) {
        for (int x = 0; x < painted.width; ++x) {
            if (painted.at(x, y) != z_buffered.at(x, y)) {
                return VisibilityDifference{x, y, painted.at(x, y), z_buffered.at(x, y)};
            }
        }
    }
    return std::nullopt;
}

}  // namespace refraster::textbook
