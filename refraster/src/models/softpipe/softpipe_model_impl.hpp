// softpipe_model_impl.hpp: softpipe's setup templates, from the draw module to set-up rows
// and planes (softpipe_model.hpp), included where the model is instantiated for an observer:
// softpipe_model.cpp (no observer) and trace/traced_models.cpp (the trace).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

#include "common/cpu.hpp"
#include "models/softpipe/softpipe_model.hpp"
#include "stages/observer.hpp"
#include "stages/rules.hpp"

namespace refraster::detail {

namespace softpipe_setup {

inline ScanlineInterp interp_of(ShadeModel s) {
    switch (s) {
        case ShadeModel::Flat:
            return ScanlineInterp::Constant;
        case ShadeModel::NoPerspective:
            return ScanlineInterp::Linear;
        case ShadeModel::Smooth:
            break;
    }
    return ScanlineInterp::Perspective;
}

// (int) of a float or double as softpipe's x86-64 build converts it (cvttss2si/cvttsd2si):
// towards zero, INT_MIN for NaN or a value outside int's range.
template <class Real>
int truncate_to_int(Real v) {
    if (!(v > Real(-2147483648.0) && v < Real(2147483648.0))) return INT32_MIN;
    return static_cast<int>(v);
}

// Rows of the pixels (x, y) listed in order, merged into runs per row: the rows of a set of
// pixels with at most one run a row (a Bresenham line, a square).
inline void pixels_to_rows(std::vector<std::array<int, 2>>& px, const PixelRect& region,
                           std::vector<ScanlineRow>& rows) {
    rows.clear();
    std::sort(px.begin(), px.end(), [](const auto& a, const auto& b) {
        return a[1] != b[1] ? a[1] < b[1] : a[0] < b[0];
    });
    for (const auto& [x, y] : px) {
        if (x < region.x0 || x > region.x1 || y < region.y0 || y > region.y1) continue;
        if (!rows.empty() && rows.back().y == y && rows.back().x1 == x) {
            ++rows.back().x1;
        } else {
            rows.push_back({y, x, x + 1});
        }
    }
}

}  // namespace softpipe_setup

inline ScanlinePrimitive& SoftpipeModel::add_primitive(std::span<const ScanlineRow> rows,
                                                       ScanlineInterp interp) {
    ScanlinePrimitive& prim = list_.primitives.emplace_back();
    prim.first_row = static_cast<std::uint32_t>(list_.rows.size());
    prim.row_count = static_cast<std::uint32_t>(rows.size());
    list_.rows.insert(list_.rows.end(), rows.begin(), rows.end());
    prim.planes = static_cast<std::uint32_t>(list_.planes.size());
    prim.interp = interp;
    prim.owner = owner_;
    return prim;
}

template <class Observer>
void SoftpipeModel::setup(VertexStage& stage, Observer& obs, const ListSink<List>& sink) {
    begin_lists(sink, stage);
    // softpipe sets primitives up inside draw_vbo, under the flush-to-zero and
    // denormals-are-zero modes draw_pt.c sets for its duration (the vertex stage emulates
    // them on its own; with the modes set it computes the same).
    {
        const ScopedDenormalsAreZero mode(ctx_.profile.gl.flush_denormals);
        dispatch(stage, obs);
    }
    end_lists(obs);
}

// Filled triangles: the draw module's clipper for triangles with a clip-mask bit, its float
// cull for triangles of segments that go through its pipeline, and its polygon offset stage
// (softpipe has no offset of its own: draw_pipe_offset.c), then softpipe's setup.
template <class Observer>
void SoftpipeModel::triangles(VertexStage& stage, Observer& obs) {
    const Draw& d = ctx_.draw;
    const bool first = ctx_.params.provoking_first;
    const auto tris = draw_triangles(ctx_);
    std::vector<bool> segment_clipped = clipped_segments(stage, d, tris);
    // Polygon offset puts every triangle through the pipeline.
    const bool offset = d.state.polygon_offset.has_value();
    if (offset) segment_clipped.assign(segment_clipped.size(), true);
    // The pipeline's last batch reaches softpipe after draw_vbo has returned, without the
    // flush modes (pipeline_batches_flushed).
    const std::vector<bool> flushed = pipeline_batches_flushed(ctx_, stage, tris, segment_clipped);
    std::size_t pipeline_output = 0;
    std::vector<StageTriangle> staged;
    // The fast paths compute an unclipped triangle's window positions with plain operations
    // under the CPU's flush modes, which setup() has set where the profile flushes (the same
    // results, VertexStage::vertex).
    const bool cpu_flushes = ctx_.cpu_flushes();
    for (std::size_t p = 0; p < tris.size(); ++p) {
        next_primitive(p, obs);
        const auto& at = tris[p];
        const std::array<std::uint32_t, 3> idx{d.element(at.element[0]), d.element(at.element[1]),
                                               d.element(at.element[2])};
        const bool in_pipeline = segment_clipped[at.segment];
        obs.begin_primitive("triangle", ctx_.index, p, idx, stage, in_pipeline);
        staged.clear();
        if (cpu_flushes && obs.clip_polygons() == nullptr &&
            (stage.clipmask(idx[0]) | stage.clipmask(idx[1]) | stage.clipmask(idx[2])) == 0) {
            // Inside the view volume: the clipper hands the triangle on unchanged
            // (VertexStage::clip_triangle).
            staged.push_back({{stage.vertex(idx[0], true), stage.vertex(idx[1], true),
                               stage.vertex(idx[2], true)},
                              false,
                              false,
                              kEdgeFlagsAll});
        } else {
            stage.clip_triangle(idx, first, staged, obs.clip_polygons());
        }
        obs.clipped(staged.empty());
        for (auto& t : staged) {
            const bool flush = !in_pipeline || flushed.empty() || flushed[pipeline_output];
            pipeline_output += in_pipeline;
            const ScopedDenormalMode plain(!flush && ctx_.profile.gl.flush_denormals, false);
            if (in_pipeline && ctx_.profile.quirks.draw_pipeline_cull &&
                !passes_draw_cull(t, d.state.cull, ctx_.params.front_ccw)) {
                continue;
            }
            if (offset) {
                apply_draw_offset(t, draw_determinant(t, ctx_.profile.gl.flush_denormals),
                                  *d.state.polygon_offset, ctx_.target.depth,
                                  ctx_.profile.gl.flush_denormals,
                                  ctx_.profile.quirks.draw_offset_nan_to_zero,
                                  ctx_.profile.gl.offset_units_scale);
            }
            const std::size_t before = list_.primitives.size();
            triangle(stage, {&t.v[0], &t.v[1], &t.v[2]}, t.clipped, false, obs);
            if (list_.primitives.size() > before) list_.primitives.back().flush = flush;
        }
        obs.end_primitive(KeepRecord::CoveredOrNear);
    }
}

// sp_setup_tri: setup_sort_vertices, setup_tri_coefficients, subtriangle. `v` in the order the
// draw module emits them; `sprite` for the triangles of the wide-point and wide-line stages,
// which they emit under their own rasterizer state (draw_get_rasterizer_no_cull: no culling,
// front_ccw set, flatshade_first clear, depth clipping off, so that softpipe clamps their
// depth to the depth range and never takes the z16 fast path).
template <class Observer>
void SoftpipeModel::triangle(const VertexStage& stage, const std::array<const StageVertex*, 3>& v,
                             bool clipped, bool sprite, Observer& obs,
                             const std::array<std::array<float, 2>, 3>* point_coords) {
    const Draw& d = ctx_.draw;
    const std::array<std::array<float, 2>, 3> w{{{v[0]->window[0], v[0]->window[1]},
                                                 {v[1]->window[0], v[1]->window[1]},
                                                 {v[2]->window[0], v[2]->window[1]}}};
    const std::array<std::array<float, 4>, 3> window{v[0]->window, v[1]->window, v[2]->window};
    const auto outcome = setup_scanline_triangle(w, sprite ? CullMode::None : d.state.cull,
                                                 sprite ? true : ctx_.params.front_ccw,
                                                 ctx_.params.draw_region, triangle_);
    if (outcome != ScanlineOutcome::Ok) {
        obs.scanline_rejected(window, clipped,
                              outcome == ScanlineOutcome::Culled ? "culled" : "zero area");
        return;
    }
    const ScanlineInterp interp = softpipe_setup::interp_of(d.state.shade);
    ScanlinePrimitive& prim = add_primitive(triangle_.rows, interp);
    prim.clamp_depth = sprite;
    const ScanlineTriangle& t = triangle_;
    const std::array<float, 3> z{v[0]->window[2], v[1]->window[2], v[2]->window[2]};
    const std::array<float, 3> oow{v[0]->window[3], v[1]->window[3], v[2]->window[3]};
    // setup_tri_coefficients: the position's z and w are linear.
    list_.planes.push_back(scanline_plane(t, z));
    list_.planes.push_back(scanline_plane(t, oow));
    const std::array<std::span<const float>, 3> attrs{
        stage.attributes(*v[0]), stage.attributes(*v[1]), stage.attributes(*v[2])};
    // The provoking vertex of the input order (setup->vprovoke: v2, or v0 with
    // flatshade_first), before sorting; the sprite rasterizer's flatshade_first is 0.
    const std::size_t provoking = ctx_.params.provoking_first && !sprite ? 0 : 2;
    for (std::size_t f = 0; f < list_.attribute_floats; ++f) {
        const std::array<float, 3> a{attrs[0][f], attrs[1][f], attrs[2][f]};
        switch (interp) {
            case ScanlineInterp::Constant:
                list_.planes.push_back({a[provoking], 0.0f, 0.0f});
                break;
            case ScanlineInterp::Linear:
                list_.planes.push_back(scanline_plane(t, a));
                break;
            case ScanlineInterp::Perspective:
                list_.planes.push_back(scanline_persp_plane(t, a, oow));
                break;
        }
    }
    if (point_coords != nullptr) {
        // The wide-point stage's sprite coordinate slot, interpolated with perspective.
        prim.point_coords = true;
        for (std::size_t c = 0; c < 2; ++c) {
            list_.planes.push_back(scanline_persp_plane(
                t, {(*point_coords)[0][c], (*point_coords)[1][c], (*point_coords)[2][c]}, oow));
        }
    }
    obs.scanline_drawn(window, clipped, list_.rows_of(prim), list_.primitives.size() - 1);
}

// sp_setup_line: Bresenham from the truncated start to the truncated end, the end excluded;
// attributes on the line's planes (setup_line_coefficients: line_linear_coeff,
// line_persp_coeff), whose "area" is the squared length.
template <class Observer>
void SoftpipeModel::segment(const VertexStage& stage, const StageVertex& v0, const StageVertex& v1,
                            Observer& obs) {
    const Draw& d = ctx_.draw;
    // st_atom_rasterizer.c clamps the width to [1, 255]; draw_pipe_validate.c sends a line to
    // the wide-line stage when width != 1 and roundf(width) > 1, that is from 1.5 on.
    const float width = std::clamp(d.state.line_width, 1.0f, 255.0f);
    if (width != 1.0f && std::round(width) > 1.0f) return wide_segment(stage, v0, v1, width, obs);
    const std::array<std::array<float, 4>, 2> window{v0.window, v1.window};
    const int x0 = softpipe_setup::truncate_to_int(v0.window[0]);
    const int y0 = softpipe_setup::truncate_to_int(v0.window[1]);
    const int x1 = softpipe_setup::truncate_to_int(v1.window[0]);
    const int y1 = softpipe_setup::truncate_to_int(v1.window[1]);
    const int dx = x1 - x0;
    const int dy = y1 - y0;
    if (dx == 0 && dy == 0) {
        obs.scanline_rejected(window, v0.generated || v1.generated, "zero length");
        return;
    }
    const float emaj_dx = v1.window[0] - v0.window[0];
    const float emaj_dy = v1.window[1] - v0.window[1];
    const float area = emaj_dx * emaj_dx + emaj_dy * emaj_dy;
    const float one_over_area = 1.0f / area;
    if (area == 0.0f || !std::isfinite(area)) {
        obs.scanline_rejected(window, v0.generated || v1.generated, "zero area");
        return;
    }
    // One walk for both major axes: m the major axis (x iff |dx| > |dy|), n the minor one.
    const std::array<int, 2> step{dx < 0 ? -1 : 1, dy < 0 ? -1 : 1};
    const std::array<int, 2> len{std::abs(dx), std::abs(dy)};
    const std::size_t m = len[0] > len[1] ? 0 : 1;
    const std::size_t n = 1 - m;
    const int inc = len[n] + len[n];
    int error = inc - len[m];
    const int dec = error - len[m];
    std::array<int, 2> at{x0, y0};
    std::vector<std::array<int, 2>> px;
    for (int i = 0; i < len[m]; ++i) {
        px.push_back(at);
        at[m] += step[m];
        if (error < 0) {
            error += inc;
        } else {
            error += dec;
            at[n] += step[n];
        }
    }
    // plot(): pixels gathered into the quad they fall in, a quad handed on (clipped to the
    // draw region, clip_emit_quad) when the next pixel leaves it.
    const PixelRect& region = ctx_.params.draw_region;
    const auto first_quad = static_cast<std::uint32_t>(list_.quads.size());
    QuadPacket quad{0, 0, 0};
    const auto emit_quad = [&] {
        if (quad.mask != 0) list_.quads.push_back(quad);
    };
    for (const auto& [x, y] : px) {
        if (quad.mask == 0 || quad.x != (x & ~1) || quad.y != (y & ~1)) {
            emit_quad();
            quad = {x & ~1, y & ~1, 0};
        }
        if (x >= region.x0 && x <= region.x1 && y >= region.y0 && y <= region.y1)
            quad.mask = static_cast<std::uint16_t>(
                quad.mask | (1u << quad_bit(static_cast<unsigned>((x & 1) + 2 * (y & 1)), 0)));
    }
    emit_quad();
    const auto quad_count = static_cast<std::uint32_t>(list_.quads.size()) - first_quad;
    softpipe_setup::pixels_to_rows(px, region, rows_);
    const ScanlineInterp interp = softpipe_setup::interp_of(d.state.shade);
    ScanlinePrimitive& prim = add_primitive(rows_, interp);
    prim.first_quad = first_quad;
    prim.quad_count = quad_count;
    // line_linear_coeff: dadx = da * dx * (1/area), a0 at vmin less the half pixel.
    const auto linear = [&](float a_min, float a_max) {
        const float da = a_max - a_min;
        ScanlinePlane pl;
        pl.dadx = da * emaj_dx * one_over_area;
        pl.dady = da * emaj_dy * one_over_area;
        pl.a0 = a_min - (pl.dadx * (v0.window[0] - 0.5f) + pl.dady * (v0.window[1] - 0.5f));
        return pl;
    };
    list_.planes.push_back(linear(v0.window[2], v1.window[2]));
    list_.planes.push_back(linear(v0.window[3], v1.window[3]));
    const auto a0 = stage.attributes(v0);
    const auto a1 = stage.attributes(v1);
    const bool first = ctx_.params.provoking_first;
    for (std::size_t f = 0; f < list_.attribute_floats; ++f) {
        switch (interp) {
            case ScanlineInterp::Constant:
                list_.planes.push_back({first ? a0[f] : a1[f], 0.0f, 0.0f});
                break;
            case ScanlineInterp::Linear:
                list_.planes.push_back(linear(a0[f], a1[f]));
                break;
            case ScanlineInterp::Perspective:
                list_.planes.push_back(linear(a0[f] * v0.window[3], a1[f] * v1.window[3]));
                break;
        }
    }
    obs.scanline_drawn(window, v0.generated || v1.generated, list_.rows_of(prim),
                       list_.primitives.size() - 1);
}

// A wide line as the draw module's wide-line stage hands it to softpipe
// (draw_pipe_wide_line.c, wideline_line): the end points moved ±width/2 across the major axis
// (x-major iff |dx| > |dy| of the window positions) with a bias of 0.125 (subtracted in y for
// an x-major line, added in x for a y-major one), and the whole quad shifted half a pixel
// along the major axis towards the start, not extended; A, B copies of the first end and C,
// D of the second, drawn as (A, C, D) then (A, D, B) under the stage's own rasterizer state
// (no culling, depth clamped to the range). The flat-shade stage before it has given both ends
// the provoking vertex's attributes.
template <class Observer>
void SoftpipeModel::wide_segment(const VertexStage& stage, const StageVertex& v0,
                                 const StageVertex& v1, float width, Observer& obs) {
    const float hw = 0.5f * width;
    const float bias = 0.125f;
    const auto& p0 = v0.window;
    const auto& p1 = v1.window;
    const float dx = std::fabs(p0[0] - p1[0]);
    const float dy = std::fabs(p0[1] - p1[1]);
    StageVertex a = v0, b = v0, c = v1, e = v1;
    if (dx > dy) {
        a.window[1] = (p0[1] - hw) - bias;
        b.window[1] = (p0[1] + hw) - bias;
        c.window[1] = (p1[1] - hw) - bias;
        e.window[1] = (p1[1] + hw) - bias;
        const float shift = p0[0] < p1[0] ? -0.5f : 0.5f;
        a.window[0] = p0[0] + shift;
        b.window[0] = p0[0] + shift;
        c.window[0] = p1[0] + shift;
        e.window[0] = p1[0] + shift;
    } else {
        a.window[0] = (p0[0] - hw) + bias;
        b.window[0] = (p0[0] + hw) + bias;
        c.window[0] = (p1[0] - hw) + bias;
        e.window[0] = (p1[0] + hw) + bias;
        const float shift = p0[1] < p1[1] ? -0.5f : 0.5f;
        a.window[1] = p0[1] + shift;
        b.window[1] = p0[1] + shift;
        c.window[1] = p1[1] + shift;
        e.window[1] = p1[1] + shift;
    }
    if (ctx_.draw.state.shade == ShadeModel::Flat) {
        // draw_pipe_flatshade.c flatshade_line_0/1: the provoking end's values on both.
        const std::uint32_t provoking = ctx_.params.provoking_first ? v0.attributes : v1.attributes;
        a.attributes = b.attributes = c.attributes = e.attributes = provoking;
    }
    const bool clipped = v0.generated || v1.generated;
    triangle(stage, {&a, &c, &e}, clipped, true, obs);
    triangle(stage, {&a, &e, &b}, clipped, true, obs);
}

// A point as the draw module's wide-point stage hands it to softpipe (the project's GL state
// enables GL_POINT_SPRITE, so every point of every size takes this path:
// draw_pipe_wide_point.c, widepoint_point): two triangles of the corners x - h + 0.125 and
// x + h + 0.125, y - h - 0.125 and y + h - 0.125 (h = size / 2, each offset rounded before it
// is added), (v0, v2, v3) then (v0, v3, v1), every corner with the point's z, 1/w and
// attributes, drawn by softpipe's triangle setup. The size is glPointSize clamped to [0, 255]
// (st_atom_rasterizer.c), not rounded.
template <class Observer>
void SoftpipeModel::point(const VertexStage& stage, const StageVertex& v, Observer& obs) {
    const float size = std::clamp(ctx_.draw.state.point_size, 0.0f, 255.0f);
    const float half = 0.5f * size;
    const float left = -half + 0.125f;
    const float right = half + 0.125f;
    const float bottom = -half + -0.125f;  // gallium's "top" (y down), GL's bottom in an FBO
    const float top = half + -0.125f;
    const auto corner = [&](float dx, float dy) {
        StageVertex c = v;
        c.window[0] = v.window[0] + dx;
        c.window[1] = v.window[1] + dy;
        return c;
    };
    const StageVertex v0 = corner(left, bottom);
    const StageVertex v1 = corner(left, top);
    const StageVertex v2 = corner(right, bottom);
    const StageVertex v3 = corner(right, top);
    if (!ctx_.draw.samples_point_coords()) {
        triangle(stage, {&v0, &v2, &v3}, false, true, obs);
        triangle(stage, {&v0, &v3, &v1}, false, true, obs);
        return;
    }
    // draw_pipe_wide_point.c set_texcoords: (0, 0) .. (1, 1) over the corners; in an FBO GL's
    // upper-left origin is gallium's lower-left one (st_atom_rasterizer.c), t = 1 - y.
    const bool upper_left =
        ctx_.draw.state.texture->point_coord_origin == PointCoordOrigin::UpperLeft;
    const auto pc = [&](float x, float y) {
        return std::array<float, 2>{x, upper_left ? 1.0f - y : y};
    };
    const std::array<float, 2> c0 = pc(0, 0), c1 = pc(0, 1), c2 = pc(1, 0), c3 = pc(1, 1);
    const std::array<std::array<float, 2>, 3> a{c0, c2, c3};
    const std::array<std::array<float, 2>, 3> b{c0, c3, c1};
    triangle(stage, {&v0, &v2, &v3}, false, true, obs, &a);
    triangle(stage, {&v0, &v3, &v1}, false, true, obs, &b);
}

}  // namespace refraster::detail
