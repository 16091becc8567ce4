// The stage order, per draw (compare Mesa's draw module and llvmpipe):
//   assemble primitives         assembly.cpp, line_point.cpp
//   viewport, clip mask, clip   vertex_stage.cpp   (draw module)
//   float cull (draw pipeline)  vertex_stage.cpp   (draw_pipe_cull.c)
//   [polygon modes: offset, flat copy, unfilled edges or points: run_unfilled below]
//   snap, orient, cull, edges   setup.cpp          (lp_setup_tri.c), line_point.cpp (lines, points)
//   covered pixels              traverse.hpp       (lp_rast_tri_tmp.h)
//   planes, per-pixel values,   fragment.cpp       (lp_state_setup.c, lp_bld_interp.c,
//   depth, blend, write                             lp_bld_depth.c, lp_bld_blend*.c)
// or, for the exact profile, assemble -> ExactCoverage -> ExactShader.
#include "refraster/renderer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "assembly.hpp"
#include "exact_coverage.hpp"
#include "fragment.hpp"
#include "line_point.hpp"
#include "rules.hpp"
#include "setup.hpp"
#include "traverse.hpp"
#include "vertex_stage.hpp"

namespace refraster {

std::size_t primitive_count(PrimitiveType p, std::size_t n) {
    switch (p) {
        case PrimitiveType::Points: return n;
        case PrimitiveType::Lines: return n / 2;
        case PrimitiveType::LineStrip: return n >= 2 ? n - 1 : 0;
        case PrimitiveType::LineLoop: return n >= 2 ? n : 0;
        case PrimitiveType::Triangles: return n / 3;
        case PrimitiveType::TriangleStrip:
        case PrimitiveType::TriangleFan: return n >= 3 ? n - 2 : 0;
    }
    return 0;
}

bool host_has_fma() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_cpu_init();
    return __builtin_cpu_supports("fma");
#else
    return false;
#endif
}

namespace {

using detail::PixelRect;
using detail::StageTriangle;
using detail::StageVertex;

// glClearDepth stores RNE(double(z) * (2^bits - 1)), computed in double: measured for z24
// (docs/precision.md, "Depth"), the same packing for z16 (util_pack_z in
// gallium/auxiliary/util/u_pack_color.h). z32f stores the float itself.
std::uint32_t clear_depth_value(DepthFormat f, float z) {
    return detail::quantise_depth(static_cast<double>(z), f);
}

// Clears the whole target (scissor off, every mask on): unorm8 colours through
// float_to_ubyte as util_pack_color does for R8G8B8A8_UNORM, floats as given.
RenderOutcome clear(const DrawList& list, Framebuffer& out) {
    const auto& c = list.clear.color;
    if (list.target.color == ColorFormat::Rgba8) {
        std::array<std::uint8_t, 4> bytes{};
        for (std::size_t k = 0; k < 4; ++k) bytes[k] = detail::clear_to_unorm8(c[k]);
        for (std::size_t i = 0; i < out.pixel_count(); ++i) {
            std::copy(bytes.begin(), bytes.end(), out.color8.begin() + static_cast<std::ptrdiff_t>(i * 4));
        }
    } else {
        for (std::size_t i = 0; i < out.pixel_count(); ++i) {
            std::copy(c.begin(), c.end(), out.color32f.begin() + static_cast<std::ptrdiff_t>(i * 4));
        }
    }
    std::fill(out.depth.begin(), out.depth.end(), clear_depth_value(list.target.depth, list.clear.depth));
    return {};
}

bool is_triangle(PrimitiveType p) {
    return p == PrimitiveType::Triangles || p == PrimitiveType::TriangleStrip || p == PrimitiveType::TriangleFan;
}

std::string unsupported(const Draw& d, const Profile& profile) {
    if ((!is_triangle(d.primitive) || d.state.polygon_mode != PolygonMode::Fill) &&
        profile.coverage == CoverageModel::Exact) {
        return "the exact profile covers filled triangles only";
    }
    return {};
}

// Stands in for the trace records when no trace is requested; every use of a record sits in an
// `if constexpr (kTrace)` branch, so the untraced instantiation carries none of it.
struct NoTrace {};

class DrawRasterizer {
public:
    DrawRasterizer(std::size_t draw_index, const Draw& d, const Target& target, const Profile& profile,
                   Framebuffer& fb, PixelTrace* trace, RenderStage stop_after = RenderStage::Fragment)
        : index_(draw_index), draw_(d), target_(target), profile_(profile), fb_(fb), trace_(trace),
          params_(detail::setup_params(profile, d.state, target)),
          fma_(profile.viewport_fma == FmaMode::On || (profile.viewport_fma == FmaMode::Auto && host_has_fma())),
          stop_(stop_after) {}

    template <bool kTrace>
    void run() {
        detail::VertexStage stage(draw_, {fma_, profile_.flush_denormals, profile_.clipping == Clipping::GuardBand});
        if (stop_ == RenderStage::Load) return;
        if (draw_.primitive == PrimitiveType::Points) return run_points<kTrace>(stage);
        if (!is_triangle(draw_.primitive)) return run_lines<kTrace>(stage);
        if (draw_.state.polygon_mode != PolygonMode::Fill) return run_unfilled<kTrace>(stage);
        const bool first = params_.provoking_first;
        const auto tris = detail::assemble_triangles(draw_.primitive, draw_.element_count(), first,
                                                     profile_.draw_segment_vertices, draw_.indices.has_value());
        const auto vertex_of = [&](std::uint32_t e) { return draw_.element(e); };

        // Segments with any vertex outside the view volume go through the draw pipeline.
        std::vector<bool> segment_clipped;
        for (const auto& t : tris) {
            if (t.segment >= segment_clipped.size()) segment_clipped.resize(t.segment + 1, false);
            for (auto e : t.element) {
                if (stage.vertex(vertex_of(e)).clipmask != 0) segment_clipped[t.segment] = true;
            }
        }
        if (nine_vertex_quirk_drops(stage, tris, segment_clipped)) {
            if constexpr (kTrace) {
                PrimitiveTrace pt;
                pt.draw = index_;
                pt.note = "draw dropped by llvmpipe's nine-vertex rectangle analysis";
                trace_->primitives.push_back(pt);
            }
            return;
        }

        const std::vector<bool> setup_ftz = pipeline_setup_ftz(stage, tris, segment_clipped);
        std::size_t pipeline_output = 0;  // the pipeline's output triangles so far, in order
        std::vector<StageTriangle> staged;
        for (std::size_t p = 0; p < tris.size(); ++p) {
            owner_ = owner_id(index_, p);
            const auto& at = tris[p];
            const std::array<std::uint32_t, 3> idx{vertex_of(at.element[0]), vertex_of(at.element[1]),
                                                   vertex_of(at.element[2])};
            [[maybe_unused]] std::conditional_t<kTrace, PrimitiveTrace, NoTrace> pt;
            if constexpr (kTrace) {
                pt.draw = index_;
                pt.primitive = p;
                for (std::size_t k = 0; k < 3; ++k) {
                    pt.vertices.push_back(idx[k]);
                    pt.clip.push_back(stage.vertex(idx[k]).clip);
                    pt.clipmask.push_back(stage.vertex(idx[k]).clipmask);
                }
                pt.in_draw_pipeline = segment_clipped[at.segment];
            }
            if (profile_.coverage == CoverageModel::Exact) {
                draw_exact<kTrace>(stage, idx, pt);
            } else {
                staged.clear();
                [[maybe_unused]] std::vector<std::vector<StageVertex>> polygons;
                stage.clip_triangle(idx, first, staged, kTrace ? &polygons : nullptr);
                if constexpr (kTrace) {
                    for (const auto& poly : polygons) {
                        auto& out = pt.clipped_polygon.emplace_back();
                        for (const auto& v : poly) out.push_back(v.clip);
                    }
                    if (staged.empty()) pt.note = "clipped away entirely";
                }
                for (const auto& st : staged) {
                    const bool in_pipeline = segment_clipped[at.segment];
                    const bool ftz = !in_pipeline || setup_ftz.empty() || setup_ftz[pipeline_output];
                    pipeline_output += in_pipeline;
                    draw_snapped<kTrace>(stage, st, in_pipeline, ftz, pt);
                }
            }
            if constexpr (kTrace) {
                if (pt.covered || relevant(pt)) trace_->primitives.push_back(std::move(pt));
            }
        }
    }

private:
    const detail::FragmentOptions fragment_options() const { return {fma_, profile_.flush_denormals}; }

    template <bool kTrace, class PT, class Setup>
    void trace_edges(PT& pt, SetupTrace& s, const Setup& t, const detail::FragmentShader& shader) {
        if constexpr (kTrace) {
            s.subpixel_bits = t.bits;
            for (const auto& e : t.edges) {
                const std::int64_t v = e.at(trace_->x, trace_->y, t.bits);
                s.edges.push_back({e.a, e.b, e.c, e.owns_ties, v, v - (e.owns_ties ? 1 : 0) == 0});
            }
            bool in = pixel_in_box(t.bbox);
            for (const auto& e : t.edges) in = in && e.at(trace_->x, trace_->y, t.bits) > 0;
            s.covered = in;
            pt.covered = pt.covered || in;
            if (in) {
                s.has_fragment = true;
                s.fragment = shader.trace_pixel(trace_->x, trace_->y, fb_);
            }
            s.outcome = "drawn";
        }
    }

    // Lines: assembly, clipping (do_clip_line), then try_setup_line and the shared fragment
    // stage. Lines are never culled.
    template <bool kTrace>
    void run_lines(detail::VertexStage& stage) {
        const bool first = params_.provoking_first;
        const auto segs = detail::assemble_lines(draw_.primitive, draw_.element_count());
        for (std::size_t p = 0; p < segs.size(); ++p) {
            owner_ = owner_id(index_, p);
            const std::uint32_t a = draw_.element(segs[p][0]);
            const std::uint32_t b = draw_.element(segs[p][1]);
            [[maybe_unused]] std::conditional_t<kTrace, PrimitiveTrace, NoTrace> pt;
            if constexpr (kTrace) {
                pt.draw = index_;
                pt.primitive = p;
                pt.kind = "line";
                for (auto v : {a, b}) {
                    pt.vertices.push_back(v);
                    pt.clip.push_back(stage.vertex(v).clip);
                    pt.clipmask.push_back(stage.vertex(v).clipmask);
                }
            }
            const auto clipped = stage.clip_line(a, b, first);
            if (!clipped) {
                if constexpr (kTrace) {
                    pt.note = "clipped away entirely";
                    trace_->primitives.push_back(std::move(pt));
                }
                continue;
            }
            draw_segment<kTrace>(stage, (*clipped)[0], (*clipped)[1], pt);
            if constexpr (kTrace) {
                if (pt.covered || relevant(pt)) trace_->primitives.push_back(std::move(pt));
            }
        }
    }

    // One segment after clipping: try_setup_line, its planes, the fragment stage.
    template <bool kTrace, class PT>
    void draw_segment(const detail::VertexStage& stage, const StageVertex& v1, const StageVertex& v2, PT& pt) {
        const auto setup = detail::setup_line(v1, v2, draw_.state.line_width, params_);
        if (!setup) return;
        const detail::FragmentShader shader(
            detail::line_planes(v1, v2, stage, draw_, params_.provoking_first, fragment_options()), draw_, target_,
            fragment_options(), owner_);
        if constexpr (kTrace) {
            SetupTrace s;
            s.window = {v1.window, v2.window};
            s.clipped = v1.generated || v2.generated;
            s.x.assign(setup->x.begin(), setup->x.end());
            s.y.assign(setup->y.begin(), setup->y.end());
            trace_edges<kTrace>(pt, s, *setup, shader);
            pt.setups.push_back(s);
        }
        if (stop_ == RenderStage::Setup) return;
        if (stop_ == RenderStage::Raster) {
            detail::traverse_convex(*setup, [&](int, int x0, int x1) { fragments_ += static_cast<std::uint64_t>(x1 - x0); });
            return;
        }
        detail::traverse_convex(*setup, [&](int y, int x0, int x1) { shader.shade_span(y, x0, x1, fb_); });
    }

    // One point that survived clipping: try_setup_point, its planes, the fragment stage.
    template <bool kTrace, class PT>
    void draw_point(const detail::VertexStage& stage, const StageVertex& v, PT& pt) {
        const auto setup = detail::setup_point(v, draw_.state.point_size, params_);
        if (!setup) return;
        const detail::FragmentShader shader(detail::point_planes(v, stage, draw_, fragment_options()), draw_, target_,
                                            fragment_options(), owner_);
        if constexpr (kTrace) {
            SetupTrace s;
            s.window = {v.window};
            trace_edges<kTrace>(pt, s, *setup, shader);
            pt.setups.push_back(s);
        }
        if (stop_ == RenderStage::Setup) return;
        if (stop_ == RenderStage::Raster) {
            detail::traverse_convex(*setup, [&](int, int x0, int x1) { fragments_ += static_cast<std::uint64_t>(x1 - x0); });
            return;
        }
        detail::traverse_convex(*setup, [&](int y, int x0, int x1) { shader.shade_span(y, x0, x1, fb_); });
    }

    // Points: clipped by their centre (draw_pipe_clip.c clip_point), then quad points.
    template <bool kTrace>
    void run_points(detail::VertexStage& stage) {
        for (std::size_t p = 0; p < draw_.element_count(); ++p) {
            owner_ = owner_id(index_, p);
            const std::uint32_t i = draw_.element(p);
            const auto& v = stage.vertex(i);
            if (v.clipmask != 0) continue;
            [[maybe_unused]] std::conditional_t<kTrace, PrimitiveTrace, NoTrace> pt;
            if constexpr (kTrace) {
                pt.draw = index_;
                pt.primitive = p;
                pt.kind = "point";
                pt.vertices = {i};
                pt.clip = {v.clip};
                pt.clipmask = {v.clipmask};
            }
            draw_point<kTrace>(stage, v, pt);
            if constexpr (kTrace) {
                if (pt.covered) trace_->primitives.push_back(std::move(pt));
            }
        }
    }

    // Polygon modes line and point: always the draw pipeline (llvmpipe hands unfilled
    // polygons to it, lp_state_rasterizer.c): clip, the float cull stage, the draw module's
    // polygon offset (draw_pipe_offset.c; llvmpipe's own is off then), the flat-shade copy
    // (draw_pipe_flatshade.c), then draw_pipe_unfilled.c's edges (v2,v0), (v0,v1), (v1,v2) or
    // points v0, v1, v2, each only where the polygon's edge flag and the starting vertex's
    // edge flag are set, so that clip-plane edges and fan diagonals are not drawn.
    template <bool kTrace>
    void run_unfilled(detail::VertexStage& stage) {
        const bool first = params_.provoking_first;
        const auto tris = detail::assemble_triangles(draw_.primitive, draw_.element_count(), first,
                                                     profile_.draw_segment_vertices, draw_.indices.has_value());
        std::vector<StageTriangle> staged;
        for (std::size_t p = 0; p < tris.size(); ++p) {
            owner_ = owner_id(index_, p);
            const auto& at = tris[p];
            const std::array<std::uint32_t, 3> idx{draw_.element(at.element[0]), draw_.element(at.element[1]),
                                                   draw_.element(at.element[2])};
            [[maybe_unused]] std::conditional_t<kTrace, PrimitiveTrace, NoTrace> pt;
            if constexpr (kTrace) {
                pt.draw = index_;
                pt.primitive = p;
                pt.kind = draw_.state.polygon_mode == PolygonMode::Line ? "polygon edges" : "polygon vertices";
                for (std::size_t k = 0; k < 3; ++k) {
                    pt.vertices.push_back(idx[k]);
                    pt.clip.push_back(stage.vertex(idx[k]).clip);
                    pt.clipmask.push_back(stage.vertex(idx[k]).clipmask);
                }
            }
            staged.clear();
            stage.clip_triangle(idx, first, staged, nullptr);
            for (auto t : staged) {
                if (!detail::passes_draw_cull(t, draw_.state.cull, params_.front_ccw)) continue;
                if (draw_.state.polygon_offset) {
                    detail::apply_draw_offset(t, detail::draw_determinant(t, profile_.flush_denormals),
                                              *draw_.state.polygon_offset, target_.depth, profile_.flush_denormals);
                }
                if (draw_.state.shade == ShadeModel::Flat) {
                    const StageVertex prov = t.v[first ? 0 : 2];
                    for (std::size_t k = 0; k < 3; ++k) {
                        if (k != (first ? 0u : 2u)) t.v[k] = stage.duplicate_with_flat(t.v[k], prov);
                    }
                }
                const auto edge = [&](unsigned bit, std::size_t from) {
                    return (t.edge_flags & bit) != 0 && t.v[from].edgeflag;
                };
                if (draw_.state.polygon_mode == PolygonMode::Line) {
                    if (edge(4, 2)) draw_segment<kTrace>(stage, t.v[2], t.v[0], pt);
                    if (edge(1, 0)) draw_segment<kTrace>(stage, t.v[0], t.v[1], pt);
                    if (edge(2, 1)) draw_segment<kTrace>(stage, t.v[1], t.v[2], pt);
                } else {
                    if (edge(1, 0)) draw_point<kTrace>(stage, t.v[0], pt);
                    if (edge(2, 1)) draw_point<kTrace>(stage, t.v[1], pt);
                    if (edge(4, 2)) draw_point<kTrace>(stage, t.v[2], pt);
                }
            }
            if constexpr (kTrace) {
                if (pt.covered || relevant(pt)) trace_->primitives.push_back(std::move(pt));
            }
        }
    }

    // lp_setup_analyse_triangles (lp_setup_analysis.c), reached from lp_setup_draw_arrays for
    // a non-indexed triangle list of exactly 9 vertices drawn without constant-interpolated
    // inputs and without the draw pipeline: when the last triangle's three window y values are
    // equal, the function claims the whole draw. It hands the first two triangles to
    // lp_rect_cw when they form a rectangle and drops them otherwise; measured in an FBO,
    // neither case draws anything (scenes triangles.coverage.nine_vertex_quirk_*).
    bool nine_vertex_quirk_drops(const detail::VertexStage& stage,
                                 const std::vector<detail::AssembledTriangle>& tris,
                                 const std::vector<bool>& segment_clipped) const {
        // The owner pass reads gl_PrimitiveID, a constant-interpolated input, and so bypasses
        // the analysis in the driver; the reference's owner pass does the same.
        if (!profile_.nine_vertex_quirk || profile_.coverage != CoverageModel::Snapped || !fb_.owner.empty()) return false;
        if (draw_.primitive != PrimitiveType::Triangles || draw_.indices || draw_.element_count() != 9) return false;
        if (draw_.state.shade == ShadeModel::Flat || tris.size() != 3 || segment_clipped[0]) return false;
        const auto y = [&](std::uint32_t i) { return stage.vertex(i).window[1]; };
        return y(8) == y(7) && y(8) == y(6);
    }

    // Whether llvmpipe sets up each output triangle of the draw pipeline, in order, with
    // denormals flushed. The pipeline's last stage (draw_pipe_vbuf.c, vbuf_tri and check_space)
    // collects triangles and hands them to setup when the next one might not fit (vertices + 3
    // > 128: lp_setup_vbuf.c's 4096-byte buffer over 32-byte vertices of position and colour;
    // or indices + 3 > 1024), when a segment that skips the pipeline is emitted (draw_pt_emit.c
    // flushes first), and otherwise after draw_vbo has returned. draw_vbo (draw_pt.c) sets
    // FTZ/DAZ for its own duration only, so a draw's last batch is set up without them. A
    // vertex counts once per batch: the segment's own vertices are shared between its
    // triangles, the clipper's new ones between the triangles of one polygon. Empty when no
    // triangle needs telling apart (no pipeline segment, or no flushing at all).
    std::vector<bool> pipeline_setup_ftz(detail::VertexStage& stage, const std::vector<detail::AssembledTriangle>& tris,
                                         const std::vector<bool>& segment_clipped) const {
        constexpr std::size_t kMaxVertices = 4096 / 32;
        constexpr std::size_t kMaxIndices = 1024;
        std::vector<bool> out;
        if (!profile_.flush_denormals || profile_.coverage != CoverageModel::Snapped ||
            std::find(segment_clipped.begin(), segment_clipped.end(), true) == segment_clipped.end()) {
            return out;
        }
        std::size_t vertices = 0, indices = 0;
        std::vector<std::size_t> pending;  // indices into `out` of the triangles not yet set up
        std::vector<std::uint64_t> emitted;
        const auto flush = [&](bool ftz) {
            for (const auto i : pending) out[i] = ftz;
            pending.clear();
            vertices = indices = 0;
            emitted.clear();
        };
        std::vector<StageTriangle> staged;
        for (const auto& at : tris) {
            if (!segment_clipped[at.segment]) {
                if (!pending.empty()) flush(true);
                continue;
            }
            staged.clear();
            stage.clip_triangle({draw_.element(at.element[0]), draw_.element(at.element[1]), draw_.element(at.element[2])},
                                params_.provoking_first, staged, nullptr);
            for (const auto& st : staged) {
                if (profile_.draw_pipeline_cull && !detail::passes_draw_cull(st, draw_.state.cull, params_.front_ccw)) {
                    out.push_back(true);  // never reaches setup
                    continue;
                }
                if (vertices + 3 > kMaxVertices || indices + 3 > kMaxIndices) flush(true);
                for (const auto& v : st.v) {
                    const std::uint64_t key = (std::uint64_t{at.segment} << 32) | v.attributes;
                    if (std::find(emitted.begin(), emitted.end(), key) == emitted.end()) {
                        emitted.push_back(key);
                        ++vertices;
                    }
                }
                indices += 3;
                pending.push_back(out.size());
                out.push_back(true);
            }
        }
        flush(false);
        return out;
    }

    bool pixel_in_box(const PixelRect& b) const {
        return trace_->x >= b.x0 && trace_->x <= b.x1 && trace_->y >= b.y0 && trace_->y <= b.y1;
    }

    bool relevant(const PrimitiveTrace& pt) const {
        // A primitive is worth showing when one of its set-up triangles' boxes (before the
        // draw region) holds the pixel.
        for (const auto& s : pt.setups) {
            if (s.x.empty()) continue;
            const auto [xmin, xmax] = std::minmax_element(s.x.begin(), s.x.end());
            const auto [ymin, ymax] = std::minmax_element(s.y.begin(), s.y.end());
            const int b = s.subpixel_bits;
            if (trace_->x >= (*xmin >> b) && trace_->x <= ((*xmax - 1) >> b) + 1 && trace_->y >= (*ymin >> b) &&
                trace_->y <= ((*ymax - 1) >> b) + 1) {
                return true;
            }
        }
        return false;
    }

    template <bool kTrace, class PT>
    void draw_snapped(const detail::VertexStage& stage, const StageTriangle& st, bool in_pipeline, bool setup_ftz,
                      PT& pt) {
        [[maybe_unused]] std::conditional_t<kTrace, SetupTrace, NoTrace> s;
        if constexpr (kTrace) {
            for (std::size_t k = 0; k < 3; ++k) s.window.push_back(st.v[k].window);
            s.clipped = st.clipped;
            s.subpixel_bits = params_.bits;
        }
        const auto finish = [&](const char* outcome) {
            if constexpr (kTrace) {
                s.outcome = outcome;
                pt.setups.push_back(s);
            }
        };
        if (in_pipeline && profile_.draw_pipeline_cull &&
            !detail::passes_draw_cull(st, draw_.state.cull, params_.front_ccw)) {
            return finish("culled by the draw module's float cull");
        }
        detail::TriangleSetup t;
        const std::array<std::array<float, 2>, 3> w{{{st.v[0].window[0], st.v[0].window[1]},
                                                     {st.v[1].window[0], st.v[1].window[1]},
                                                     {st.v[2].window[0], st.v[2].window[1]}}};
        const auto outcome = detail::setup_triangle(w, params_, t);
        if constexpr (kTrace) {
            s.x.assign(t.x.begin(), t.x.end());
            s.y.assign(t.y.begin(), t.y.end());
            s.order = t.order;
            s.area = t.area;
            s.front_facing = t.front_facing;
            for (std::size_t k = 0; k < 3; ++k) {
                const auto& e = t.edges[k];
                const std::int64_t v = e.at(trace_->x, trace_->y, t.bits);
                s.edges.push_back({e.a, e.b, e.c, e.owns_ties, v, v - (e.owns_ties ? 1 : 0) == 0});
            }
        }
        switch (outcome) {
            case detail::SetupOutcome::ZeroArea: return finish("zero area");
            case detail::SetupOutcome::Culled: return finish("culled");
            case detail::SetupOutcome::OutOfRange: return finish("snapped position out of range");
            case detail::SetupOutcome::Outside: return finish("outside the draw region");
            case detail::SetupOutcome::Ok: break;
        }
        // Attribute setup sees the vertices in setup's order, after the orientation swap.
        const detail::FragmentOptions fo{fma_, profile_.flush_denormals};
        const detail::FragmentOptions setup_fo{fma_, profile_.flush_denormals && setup_ftz};
        const detail::FragmentShader shader(
            detail::triangle_planes({&st.v[static_cast<std::size_t>(t.order[0])],
                                     &st.v[static_cast<std::size_t>(t.order[1])],
                                     &st.v[static_cast<std::size_t>(t.order[2])]},
                                    stage, draw_, target_, params_.provoking_first, setup_fo),
            draw_, target_, fo, owner_);
        if constexpr (kTrace) {
            s.covered = pixel_in_box(t.bbox) && detail::covers_pixel(t, trace_->x, trace_->y);
            if (t.llvmpipe_walk) {
                // llvmpipe's own walk decides instead (llvmpipe_walk.hpp).
                s.covered = false;
                detail::traverse_triangle(t, [&](int y, int x0, int x1) {
                    s.covered = s.covered || (y == trace_->y && trace_->x >= x0 && trace_->x < x1);
                });
            }
            pt.covered = pt.covered || s.covered;
            if (s.covered) {
                s.has_fragment = true;
                s.fragment = shader.trace_pixel(trace_->x, trace_->y, fb_);
            }
        }
        if (stop_ == RenderStage::Setup) return;
        if (stop_ == RenderStage::Raster) {
            detail::traverse_triangle(t, [&](int, int x0, int x1) { fragments_ += static_cast<std::uint64_t>(x1 - x0); });
            return;
        }
        detail::traverse_triangle(t, [&](int y, int x0, int x1) { shader.shade_span(y, x0, x1, fb_); });
        finish("drawn");
    }

    template <bool kTrace, class PT>
    void draw_exact(const detail::VertexStage& stage, const std::array<std::uint32_t, 3>& idx, PT& pt) {
        const detail::ExactCoverage ex({stage.vertex(idx[0]).clip, stage.vertex(idx[1]).clip,
                                        stage.vertex(idx[2]).clip},
                                       draw_.state, params_.draw_region, profile_.tie_rule);
        if (ex.degenerate()) {
            if constexpr (kTrace) pt.note = "degenerate (det = 0)";
            return;
        }
        const bool front = ex.front_facing() == (draw_.state.front_face == FrontFace::Ccw);
        if (detail::is_culled(draw_.state.cull, front)) {
            if constexpr (kTrace) pt.note = "culled";
            return;
        }
        const detail::ExactShader shader(ex, {&stage.vertex(idx[0]), &stage.vertex(idx[1]), &stage.vertex(idx[2])},
                                         stage, draw_, target_, params_.provoking_first);
        const PixelRect r = ex.candidates();
        for (int y = r.y0; y <= r.y1; ++y) {
            for (int x = r.x0; x <= r.x1; ++x) {
                if (ex.covers(x, y)) shader.shade(x, y, fb_, owner_);
            }
        }
        if constexpr (kTrace) {
            pt.covered = ex.covers(trace_->x, trace_->y);
            const auto signs = ex.weight_signs(trace_->x, trace_->y);
            const auto owns = ex.owns_ties();
            SetupTrace s;
            s.outcome = "exact";
            s.edges.resize(3);
            for (std::size_t k = 0; k < 3; ++k) {
                s.edges[k].value = signs[k];
                s.edges[k].owns_ties = owns[k];
                s.edges[k].tie = signs[k] == 0;
            }
            s.covered = pt.covered;
            s.front_facing = ex.front_facing();
            pt.setups.push_back(s);
        }
    }

    std::size_t index_;
    const Draw& draw_;
    const Target& target_;
    const Profile& profile_;
    Framebuffer& fb_;
    PixelTrace* trace_;
    detail::SetupParams params_;
    bool fma_;
    RenderStage stop_;
    std::uint32_t owner_ = 0;  // of the primitive being drawn

public:
    std::uint64_t fragments_ = 0;  // covered pixels, counted when stopping after traversal
};

}  // namespace

RenderOutcome render(const DrawList& list, const RenderOptions& options, Framebuffer& out) {
    out = Framebuffer(list.target.width, list.target.height, list.target.color, list.target.depth);
    if (options.record_owners) out.owner.assign(out.pixel_count(), 0);
    if (list.target.samples != 1) {
        return {RenderStatus::NotSupported, "multisampled targets are not implemented yet"};
    }
    if (auto c = clear(list, out); c.status != RenderStatus::Ok) return c;
    PixelTrace* trace = options.trace;
    if (trace != nullptr) {
        trace->profile = options.profile.name;
        trace->primitives.clear();
    }
    for (std::size_t i = 0; i < list.draws.size(); ++i) {
        const Draw& d = list.draws[i];
        if (primitive_count(d.primitive, d.element_count()) == 0) continue;
        if (auto why = unsupported(d, options.profile); !why.empty()) {
            return {RenderStatus::NotSupported, why + " (draws[" + std::to_string(i) + "])"};
        }
    }
    RenderOutcome outcome;
    for (std::size_t i = 0; i < list.draws.size(); ++i) {
        const Draw& d = list.draws[i];
        if (primitive_count(d.primitive, d.element_count()) == 0) continue;
        DrawRasterizer r(i, d, list.target, options.profile, out, trace, options.stop_after);
        if (trace != nullptr) {
            r.run<true>();
        } else {
            r.run<false>();
        }
        outcome.fragments += r.fragments_;
    }
    if (trace != nullptr && trace->x >= 0 && trace->y >= 0 && static_cast<std::uint32_t>(trace->x) < out.width &&
        static_cast<std::uint32_t>(trace->y) < out.height) {
        const std::size_t i = 4 * out.index(static_cast<std::uint32_t>(trace->x), static_cast<std::uint32_t>(trace->y));
        for (std::size_t k = 0; k < 4; ++k) {
            trace->final_color[k] = out.color_format == ColorFormat::Rgba8 ? out.color8[i + k] : out.color32f[i + k];
        }
    }
    return outcome;
}

}  // namespace refraster
