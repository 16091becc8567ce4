#include "trace/trace_observer.hpp"

#include <algorithm>
#include <cstdint>

#include "models/exact/exact_coverage.hpp"
#include "models/llvmpipe/line_point.hpp"
#include "models/llvmpipe/traverse.hpp"
#include "models/softpipe/scanline_setup.hpp"
#include "stages/samples.hpp"
#include "stages/vertex_stage.hpp"

namespace refraster::detail {

void TraceObserver::begin_primitive(std::string_view kind, std::size_t draw, std::size_t primitive,
                                    std::span<const std::uint32_t> vertices,
                                    const VertexStage& stage, bool in_pipeline) {
    pt_ = PrimitiveTrace{};
    pt_.draw = draw;
    pt_.primitive = primitive;
    pt_.kind = std::string(kind);
    for (const auto v : vertices) {
        pt_.vertices.push_back(v);
        pt_.clip.push_back(stage.vertex(v).clip);
        pt_.clipmask.push_back(stage.vertex(v).clipmask);
    }
    pt_.in_draw_pipeline = in_pipeline;
    pt_.multisample = multisample_;
    polygons_.clear();
    open_.clear();
}

void TraceObserver::dropped_draw(std::size_t draw, const char* why) {
    PrimitiveTrace pt;
    pt.draw = draw;
    pt.note = why;
    trace_.primitives.push_back(pt);
}

void TraceObserver::clipped(bool nothing_left) {
    for (const auto& poly : polygons_) {
        auto& out = pt_.clipped_polygon.emplace_back();
        for (const auto& v : poly) out.push_back(v.clip);
    }
    polygons_.clear();
    if (nothing_left) pt_.note = "clipped away entirely";
}

void TraceObserver::triangle_start(const std::array<const StageVertex*, 3>& v, bool clipped,
                                   int bits) {
    s_ = SetupTrace{};
    for (std::size_t k = 0; k < 3; ++k) s_.window.push_back(v[k]->window);
    s_.clipped = clipped;
    s_.subpixel_bits = bits;
}

void TraceObserver::triangle_outcome(const char* outcome) {
    s_.outcome = outcome;
    pt_.setups.push_back(s_);
}

std::int64_t TraceObserver::point_offset(const EdgeFunction& e, int bits) const {
    if (!multisample_) return 0;
    const auto& pos = kSamplePositions4x[static_cast<std::size_t>(trace_.sample)];
    const float one = static_cast<float>(1 << bits);
    return e.sample_offset(static_cast<std::int32_t>(pos.x * one),
                           static_cast<std::int32_t>(pos.y * one));
}

template <class Setup>
void TraceObserver::record_edges(const Setup& t, std::size_t edge_count) {
    for (std::size_t k = 0; k < edge_count; ++k) {
        const auto& e = t.edges[k];
        const std::int64_t v = e.at(trace_.x, trace_.y, t.bits) + point_offset(e, t.bits);
        s_.edges.push_back({e.a, e.b, e.c, e.owns_ties, v, v - (e.owns_ties ? 1 : 0) == 0});
    }
}

// Every edge positive at the traced point (the pixel, or its sample), inside the box.
template <class Setup>
bool TraceObserver::covers(const Setup& t, std::size_t edge_count) {
    if (!in_box(t.bbox)) return false;
    if (multisample_ && leak_samples(t.scissor_leak, t.bbox, trace_.x, trace_.y) != 0xf) {
        const bool kept =
            (leak_samples(t.scissor_leak, t.bbox, trace_.x, trace_.y) & (1u << trace_.sample)) != 0;
        s_.coverage_note = std::string(
                               "the pixel is just outside the scissor's left or bottom side, where "
                               "llvmpipe's multisample scissor planes (+127) keep the samples more "
                               "than half a pixel in: this sample is ") +
                           (kept ? "kept" : "cut");
        if (!kept) return false;
    }
    for (std::size_t k = 0; k < edge_count; ++k) {
        const auto& e = t.edges[k];
        if (e.at(trace_.x, trace_.y, t.bits) + point_offset(e, t.bits) <= 0) return false;
    }
    return true;
}

void TraceObserver::triangle_setup(const TriangleSetup& t) {
    s_.x.assign(t.x.begin(), t.x.end());
    s_.y.assign(t.y.begin(), t.y.end());
    s_.order = t.order;
    s_.area = t.area;
    s_.front_facing = t.front_facing;
    record_edges(t, 3);
}

bool TraceObserver::in_box(const PixelRect& b) const {
    return trace_.x >= b.x0 && trace_.x <= b.x1 && trace_.y >= b.y0 && trace_.y <= b.y1;
}

// The set-up primitive just recorded covers the pixel or not; its fragment is traced when the
// primitive is about to be shaded.
void TraceObserver::covered(bool in, std::size_t list_index) {
    s_.covered = in;
    pt_.covered = pt_.covered || in;
    if (in) s_.has_fragment = true;
    s_.outcome = "drawn";
    pt_.setups.push_back(s_);
    if (in) open_.push_back({list_index, 0, pt_.setups.size() - 1});
}

void TraceObserver::triangle_drawn(const TriangleSetup& t, std::size_t list_index) {
    bool in = covers(t, 3);
    if (t.llvmpipe_walk && multisample_) {
        // llvmpipe's own walk decides instead (llvmpipe_walk.hpp), sample by sample.
        in = false;
        lp::walk_binned(t.walk, [&](const lp::Walk& w) {
            const int r = trace_.y - w.tile_y;
            const int c = trace_.x - w.tile_x;
            if (r < 0 || r >= 64 || c < 0 || c >= 64) return;
            in = in || ((w.rows[trace_.sample][r] >> c) & 1u) != 0;
        });
    } else if (t.llvmpipe_walk) {
        // llvmpipe's own walk decides instead (llvmpipe_walk.hpp).
        in = false;
        traverse_triangle(t, [&](int y, int x0, int x1) {
            in = in || (y == trace_.y && trace_.x >= x0 && trace_.x < x1);
        });
    }
    covered(in, list_index);
}

void TraceObserver::line_drawn(const StageVertex& v1, const StageVertex& v2, const LineSetup& s,
                               std::size_t list_index) {
    s_ = SetupTrace{};
    s_.window = {v1.window, v2.window};
    s_.clipped = v1.generated || v2.generated;
    s_.x.assign(s.x.begin(), s.x.end());
    s_.y.assign(s.y.begin(), s.y.end());
    s_.subpixel_bits = s.bits;
    record_edges(s, 4);
    covered(covers(s, 4), list_index);
}

void TraceObserver::point_drawn(const StageVertex& v, const PointSetup& s, std::size_t list_index) {
    s_ = SetupTrace{};
    s_.window = {v.window};
    s_.subpixel_bits = s.bits;
    record_edges(s, 4);
    covered(covers(s, 4), list_index);
}

void TraceObserver::exact_setup(const ExactCoverage& ex) {
    pt_.covered = ex.covers(trace_.x, trace_.y);
    const auto signs = ex.weight_signs(trace_.x, trace_.y);
    const auto owns = ex.owns_ties();
    SetupTrace s;
    s.outcome = "exact";
    s.edges.resize(3);
    for (std::size_t k = 0; k < 3; ++k) {
        s.edges[k].value = signs[k];
        s.edges[k].owns_ties = owns[k];
        s.edges[k].tie = signs[k] == 0;
    }
    s.covered = pt_.covered;
    s.front_facing = ex.front_facing();
    pt_.setups.push_back(s);
}

void TraceObserver::scanline_drawn(std::span<const std::array<float, 4>> window, bool clipped,
                                   std::span<const ScanlineRow> rows, std::size_t list_index) {
    s_ = SetupTrace{};
    s_.window.assign(window.begin(), window.end());
    s_.clipped = clipped;
    bool in = false;
    for (const auto& r : rows) {
        if (r.y != trace_.y) continue;
        in = trace_.x >= r.x0 && trace_.x < r.x1;
        s_.coverage_note = "softpipe's scanline row " + std::to_string(r.y) + " spans pixels " +
                           std::to_string(r.x0) + " to " + std::to_string(r.x1 - 1);
    }
    if (s_.coverage_note.empty()) s_.coverage_note = "softpipe's scanline rows miss this row";
    covered(in, list_index);
}

void TraceObserver::scanline_rejected(std::span<const std::array<float, 4>> window, bool clipped,
                                      const char* outcome) {
    s_ = SetupTrace{};
    s_.window.assign(window.begin(), window.end());
    s_.clipped = clipped;
    s_.outcome = outcome;
    pt_.setups.push_back(s_);
}

bool TraceObserver::near(const PrimitiveTrace& pt) const {
    // A primitive is worth showing when one of its set-up triangles' boxes (before the
    // draw region) holds the pixel.
    for (const auto& s : pt.setups) {
        if (s.x.empty()) {
            // Unsnapped setups (the scanline model): the window box, a pixel wider.
            if (s.window.empty()) continue;
            float x0 = s.window[0][0], x1 = x0, y0 = s.window[0][1], y1 = y0;
            for (const auto& w : s.window) {
                x0 = std::min(x0, w[0]);
                x1 = std::max(x1, w[0]);
                y0 = std::min(y0, w[1]);
                y1 = std::max(y1, w[1]);
            }
            const auto px = static_cast<float>(trace_.x), py = static_cast<float>(trace_.y);
            if (px >= x0 - 1.0f && px <= x1 + 1.0f && py >= y0 - 1.0f && py <= y1 + 1.0f)
                return true;
            continue;
        }
        const auto [xmin, xmax] = std::minmax_element(s.x.begin(), s.x.end());
        const auto [ymin, ymax] = std::minmax_element(s.y.begin(), s.y.end());
        const int b = s.subpixel_bits;
        // In 64 bits: a position that converted to 0x80000000 (llvmpipe_walk.hpp) is no
        // overflow here.
        const auto lo = [b](std::int32_t v) { return std::int64_t{v} >> b; };
        const auto hi = [b](std::int32_t v) { return ((std::int64_t{v} - 1) >> b) + 1; };
        if (trace_.x >= lo(*xmin) && trace_.x <= hi(*xmax) && trace_.y >= lo(*ymin) &&
            trace_.y <= hi(*ymax)) {
            return true;
        }
    }
    return false;
}

void TraceObserver::end_primitive(KeepRecord keep) {
    const bool kept = keep == KeepRecord::Always || pt_.covered ||
                      (keep == KeepRecord::CoveredOrNear && near(pt_));
    if (kept) {
        trace_.primitives.push_back(std::move(pt_));
        for (auto p : open_) {
            p.primitive = trace_.primitives.size() - 1;
            ready_.push_back(p);
        }
    }
    open_.clear();
    pt_ = PrimitiveTrace{};
}

}  // namespace refraster::detail
