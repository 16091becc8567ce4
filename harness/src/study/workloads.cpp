#include "workloads.hpp"

#include <cmath>
#include <numbers>

namespace harness::study {

ClipVertex clip_vertex(const Viewport& vp, double wx, double wy, double zndc, double w,
                       double attribute) {
    const double nx = wx / (vp.width / 2.0) - 1.0;
    const double ny = wy / (vp.height / 2.0) - 1.0;
    // The inputs are float32: rounded into float storage first. (GCC 12's vectorizer at -O2 was
    // seen to drop a double -> float -> double round trip written as one expression here.)
    const std::array<float, 5> f{static_cast<float>(nx * w), static_cast<float>(ny * w),
                                 static_cast<float>(zndc * w), static_cast<float>(w),
                                 static_cast<float>(attribute)};
    ClipVertex v;
    for (std::size_t i = 0; i < 4; ++i) v.position[i] = f[i];
    v.attribute = f[4];
    return v;
}

namespace {

// Depths in layers: each triangle lies near NDC z = 0.2 + 10^-k (k uniform in [1, 7], either
// side), its vertices within a tenth of that offset of it, so that the depth differences of
// overlapping triangles spread over six decades, from far above the z16 step to below the z24
// step: the range in which depth formats and plane arithmetic decide the order.
struct DepthLayer {
    double centre = 0.0;
    double spread = 0.0;
    explicit DepthLayer(StudyRandom& r) {
        const double offset = std::pow(10.0, -r.uniform(1.0, 7.0));
        centre = 0.2 + (r.uniform(0.0, 1.0) < 0.5 ? -offset : offset);
        spread = offset / 10.0;
    }
    double vertex(StudyRandom& r) const { return centre + r.uniform(-spread, spread); }
};

// A triangle of the given size around a random centre inside the viewport (inset by `size`).
ClipTriangle random_triangle(StudyRandom& r, const Viewport& vp, double size, double lo_x,
                             double lo_y, const std::array<double, 3>& w) {
    const double cx = r.uniform(lo_x + size, vp.width - size);
    const double cy = r.uniform(lo_y + size, vp.height - size);
    const DepthLayer layer(r);
    ClipTriangle t;
    for (std::size_t i = 0; i < 3; ++i)
        t[i] = clip_vertex(vp, cx + r.uniform(-size, size), cy + r.uniform(-size, size),
                           layer.vertex(r), w[i], r.uniform(0.0, 1.0));
    return t;
}

Family random_family(StudyRandom& r, std::string name, std::string description, int count,
                     double min_size, double max_size) {
    Family f{std::move(name), std::move(description), {256, 256}, {}, false};
    for (int i = 0; i < count; ++i) {
        const double size = r.uniform(min_size, max_size) / 2.0;
        f.triangles.push_back(random_triangle(r, f.viewport, size, 0.0, 0.0, {1.0, 1.0, 1.0}));
    }
    return f;
}

Family sliver_family(StudyRandom& r, int count) {
    Family f{"sliver", "20-150 px long, 0.02-1 px wide, any direction", {256, 256}, {}, false};
    for (int i = 0; i < count; ++i) {
        const double length = r.uniform(20.0, 150.0);
        const double width = r.uniform(0.02, 1.0);
        const double angle = r.uniform(0.0, 2.0 * std::numbers::pi);
        const double dx = std::cos(angle), dy = std::sin(angle);
        const double ax = r.uniform(80.0, 176.0) - dx * length / 2.0;
        const double ay = r.uniform(80.0, 176.0) - dy * length / 2.0;
        const double t = r.uniform(0.2, 0.8);
        const double side = r.uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0;
        const double cx = ax + dx * length * t - dy * width * side;
        const double cy = ay + dy * length * t + dx * width * side;
        const DepthLayer layer(r);
        ClipTriangle tri;
        tri[0] = clip_vertex(f.viewport, ax, ay, layer.vertex(r), 1.0, r.uniform(0, 1));
        tri[1] = clip_vertex(f.viewport, ax + dx * length, ay + dy * length, layer.vertex(r), 1.0,
                             r.uniform(0, 1));
        tri[2] = clip_vertex(f.viewport, cx, cy, layer.vertex(r), 1.0, r.uniform(0, 1));
        f.triangles.push_back(tri);
    }
    return f;
}

// A jittered mesh over the square [origin, origin + size)^2 of a viewport of `side` pixels.
Family mesh_family(StudyRandom& r, std::string name, int size, int side) {
    const int origin = side - size;
    Family f{
        std::move(name),
        "jittered grid of shared-edge quads over " + std::to_string(size) + " x " +
            std::to_string(size) + " px" +
            (origin > 0 ? " in the far corner of a " + std::to_string(side) + " px viewport" : "") +
            ", random diagonals, a quarter of the vertices on the 1/16-pixel grid",
        {side, side},
        {},
        true,
        origin,
        size};
    const double cell = 8.0;
    const int n = size / 8 + 3;  // from -8 to size + 8
    std::vector<ClipVertex> v(static_cast<std::size_t>(n * n));
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            double x = origin + (i - 1) * cell, y = origin + (j - 1) * cell;
            const bool inner = i > 0 && j > 0 && i < n - 1 && j < n - 1;
            if (inner) {
                x += r.uniform(-3.0, 3.0);
                y += r.uniform(-3.0, 3.0);
                if (r.uniform(0.0, 1.0) < 0.25) {
                    x = std::round(x * 16.0) / 16.0;
                    y = std::round(y * 16.0) / 16.0;
                }
            }
            // The outer ring lies one cell outside the square (and outside the viewport where
            // the square reaches its edge: no kernel clips against x and y, the viewport bounds
            // the pixels), so the mesh covers every centre of the square.
            v[static_cast<std::size_t>(j * n + i)] =
                clip_vertex(f.viewport, x, y, r.uniform(-0.9, 0.9), 1.0, r.uniform(0.0, 1.0));
        }
    }
    for (int j = 0; j + 1 < n; ++j) {
        for (int i = 0; i + 1 < n; ++i) {
            const auto at = [&](int a, int b) { return v[static_cast<std::size_t>(b * n + a)]; };
            const ClipVertex a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
            // A jittered quad may be non-convex: only the diagonal whose two triangles both
            // keep the quad's orientation tiles it without overlap; a random one when both do.
            const auto ccw = [](const ClipVertex& p, const ClipVertex& q, const ClipVertex& o) {
                return (q.position[0] - p.position[0]) * (o.position[1] - p.position[1]) -
                           (q.position[1] - p.position[1]) * (o.position[0] - p.position[0]) >
                       0.0;
            };
            const bool ac = ccw(a, b, c) && ccw(a, c, d);
            const bool bd = ccw(a, b, d) && ccw(b, c, d);
            const bool pick_ac = r.uniform(0.0, 1.0) < 0.5 ? ac || !bd : !(bd || !ac);
            if (pick_ac) {
                f.triangles.push_back({a, b, c});
                f.triangles.push_back({a, c, d});
            } else {
                f.triangles.push_back({a, b, d});
                f.triangles.push_back({b, c, d});
            }
        }
    }
    return f;
}

Family perspective_family(StudyRandom& r, int count) {
    Family f{"perspective",
             "10-50 px triangles, vertex w from 1 to 10^4 (ratios up to 10^4)",
             {256, 256},
             {},
             false};
    for (int i = 0; i < count; ++i) {
        const std::array<double, 3> w{std::pow(10.0, r.uniform(0.0, 4.0)),
                                      std::pow(10.0, r.uniform(0.0, 4.0)), 1.0};
        const double size = r.uniform(10.0, 50.0) / 2.0;
        f.triangles.push_back(random_triangle(r, f.viewport, size, 0.0, 0.0, w));
    }
    return f;
}

Family large_family(StudyRandom& r, int count) {
    const int side = 1 << kMaxViewportBits;
    Family f{"large-coordinates",
             "10-50 px triangles anywhere in a 16384 x 16384 viewport, half in its far quarter",
             {side, side},
             {},
             false};
    for (int i = 0; i < count; ++i) {
        const double size = r.uniform(10.0, 50.0) / 2.0;
        const double lo = i % 2 == 0 ? side / 2.0 : 0.0;
        f.triangles.push_back(random_triangle(r, f.viewport, size, lo, lo, {1.0, 1.0, 1.0}));
    }
    return f;
}

}  // namespace

std::vector<Family> precision_families(std::uint64_t seed, bool quick) {
    StudyRandom r(seed);
    const int k = quick ? 1 : 10;
    std::vector<Family> out;
    out.push_back(random_family(r, "small", "1-4 px across, anywhere in a 256 x 256 viewport",
                                300 * k, 1.0, 4.0));
    out.push_back(random_family(r, "medium", "10-50 px across, anywhere in a 256 x 256 viewport",
                                30 * k, 10.0, 50.0));
    out.push_back(sliver_family(r, 30 * k));
    out.push_back(mesh_family(r, "mesh", quick ? 64 : 256, quick ? 64 : 256));
    out.push_back(perspective_family(r, 30 * k));
    out.push_back(large_family(r, 30 * k));
    out.push_back(mesh_family(r, "mesh-far", quick ? 64 : 256, 1 << kMaxViewportBits));
    return out;
}

}  // namespace harness::study
