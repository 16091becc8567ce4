// estimate_work: an upper estimate of the pixels a draw list makes the rasterizer visit, so
// that the loader can refuse a scene that would take hours before anything is drawn
// (docs/limits.md). It follows the rasterizer only as far as it must never fall short: the
// draw region is the target intersected with the scissor (lp_setup.c), and a primitive whose
// vertices all have w > 0 projects inside the bounding box of its projected vertices, however
// the clipper cuts it.
#include <algorithm>
#include <cmath>

#include "harness/scene.hpp"
#include "refraster/renderer.hpp"

namespace harness {
namespace {

using refraster::PrimitiveType;

struct Box {
    double x0 = 0.0;
    double y0 = 0.0;
    double x1 = 0.0;
    double y1 = 0.0;
};

class DrawEstimate {
  public:
    DrawEstimate(const refraster::Draw& d, const refraster::Target& t)
        : draw_(d), positions_(d.vertices.data.data()), stride_(d.vertices.stride()) {
        region_ = {0.0, 0.0, static_cast<double>(t.width), static_cast<double>(t.height)};
        if (d.state.scissor) {
            const auto& s = *d.state.scissor;
            region_.x0 = std::max(region_.x0, static_cast<double>(s.x));
            region_.y0 = std::max(region_.y0, static_cast<double>(s.y));
            region_.x1 = std::min(region_.x1, static_cast<double>(s.x) + s.width);
            region_.y1 = std::min(region_.y1, static_cast<double>(s.y) + s.height);
        }
        if (t.samples > 1) {
            // Under multisampling the scissor lets a column and a row outside it through
            // (docs/precision.md, "Multisampling (4x)").
            region_.x0 = std::max(0.0, region_.x0 - 1.0);
            region_.y0 = std::max(0.0, region_.y0 - 1.0);
        }
        region_area_ = area(region_);
    }

    std::uint64_t region_area() const { return region_area_; }

    // A triangle filled, or drawn as its edges or corners under polygon_mode.
    std::uint64_t triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) const {
        switch (draw_.state.polygon_mode) {
            case refraster::PolygonMode::Line:
                return line(a, b) + line(b, c) + line(c, a);
            case refraster::PolygonMode::Point:
                return point(a) + point(b) + point(c);
            case refraster::PolygonMode::Fill:
                break;
        }
        Box b0;
        if (!window(a, b0)) return region_area_;
        Box box = b0;
        for (const auto v : {b, c}) {
            Box p;
            if (!window(v, p)) return region_area_;
            box = hull(box, p);
        }
        return clipped(widened(box, 1.0));
    }
    // A line of the draw's width: its bounding box, and never more than its length times its
    // width (a long diagonal line touches far fewer pixels than its box).
    std::uint64_t line(std::uint32_t a, std::uint32_t b) const {
        Box pa;
        Box pb;
        if (!window(a, pa) || !window(b, pb)) return region_area_;
        const double half = std::ceil(static_cast<double>(draw_.state.line_width) / 2.0) + 1.0;
        const std::uint64_t in_box = clipped(widened(hull(pa, pb), half));
        const double length = std::hypot(pb.x0 - pa.x0, pb.y0 - pa.y0);
        const double strip = (length + 2.0 * half) * (2.0 * half);
        return strip < static_cast<double>(in_box) ? static_cast<std::uint64_t>(strip) : in_box;
    }
    std::uint64_t point(std::uint32_t a) const {
        Box p;
        if (!window(a, p)) return region_area_;
        const double half = std::ceil(static_cast<double>(draw_.state.point_size) / 2.0) + 1.0;
        return clipped(widened(p, half));
    }

  private:
    static std::uint64_t area(const Box& b) {
        if (!(b.x1 > b.x0) || !(b.y1 > b.y0)) return 0;
        return static_cast<std::uint64_t>(std::ceil(b.x1 - b.x0)) *
               static_cast<std::uint64_t>(std::ceil(b.y1 - b.y0));
    }
    static Box hull(const Box& a, const Box& b) {
        return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1),
                std::max(a.y1, b.y1)};
    }
    static Box widened(const Box& b, double by) {
        return {b.x0 - by, b.y0 - by, b.x1 + by, b.y1 + by};
    }
    std::uint64_t clipped(const Box& b) const {
        return area({std::max(b.x0, region_.x0), std::max(b.y0, region_.y0),
                     std::min(b.x1, region_.x1), std::min(b.y1, region_.y1)});
    }
    // The window position of element vertex `v` as a point box; false when it has no finite
    // projection (w <= 0), so that the whole region must be assumed.
    bool window(std::uint32_t v, Box& out) const {
        // draw_.vertices.position(v), with the stride computed once a draw.
        const float* p = positions_ + std::size_t{v} * stride_;
        const double w = static_cast<double>(p[3]);
        if (!(w > 0.0)) return false;
        const auto& vp = draw_.state.viewport;
        const double x = vp.x + (static_cast<double>(p[0]) / w + 1.0) * 0.5 * vp.width;
        const double y = vp.y + (static_cast<double>(p[1]) / w + 1.0) * 0.5 * vp.height;
        if (!std::isfinite(x) || !std::isfinite(y)) return false;
        out = {x, y, x, y};
        return true;
    }

    const refraster::Draw& draw_;
    const float* positions_;
    std::size_t stride_;
    Box region_;
    std::uint64_t region_area_ = 0;
};

}  // namespace

SceneWork estimate_work(const refraster::Draw& d, const refraster::Target& t) {
    SceneWork w;
    const std::size_t n = d.element_count();
    w.primitives = refraster::primitive_count(d.primitive, n);
    const DrawEstimate e(d, t);
    if (e.region_area() == 0) return w;
    const auto el = [&](std::size_t i) { return d.element(i); };
    std::uint64_t f = 0;
    switch (d.primitive) {
        case PrimitiveType::Points:
            for (std::size_t i = 0; i < n; ++i) f += e.point(el(i));
            break;
        case PrimitiveType::Lines:
            for (std::size_t i = 0; i + 1 < n; i += 2) f += e.line(el(i), el(i + 1));
            break;
        case PrimitiveType::LineStrip:
        case PrimitiveType::LineLoop:
            for (std::size_t i = 0; i + 1 < n; ++i) f += e.line(el(i), el(i + 1));
            if (d.primitive == PrimitiveType::LineLoop && n >= 2) f += e.line(el(n - 1), el(0));
            break;
        case PrimitiveType::Triangles:
            for (std::size_t i = 0; i + 2 < n; i += 3) f += e.triangle(el(i), el(i + 1), el(i + 2));
            break;
        case PrimitiveType::TriangleStrip:
            for (std::size_t i = 0; i + 2 < n; ++i) f += e.triangle(el(i), el(i + 1), el(i + 2));
            break;
        case PrimitiveType::TriangleFan:
        case PrimitiveType::Polygon:
            for (std::size_t i = 1; i + 1 < n; ++i) f += e.triangle(el(0), el(i), el(i + 1));
            // A fill rule draws the polygon's triangles twice: into the stencil, then over it.
            if (d.state.fill_rule) f *= 2;
            break;
    }
    // Every sample of a 4x pixel is tested, and shaded through depth and blending.
    w.fragments = f * std::max<std::uint32_t>(t.samples, 1);
    return w;
}

SceneWork estimate_work(const refraster::DrawList& list) {
    SceneWork w;
    for (const auto& d : list.draws) {
        const SceneWork dw = estimate_work(d, list.target);
        w.primitives += dw.primitives;
        w.fragments += dw.fragments;
    }
    return w;
}

}  // namespace harness
