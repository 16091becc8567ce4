#include "stages/vertex_stage.hpp"

#include <bit>
#include <cmath>
#include <limits>

#include "common/cpu.hpp"
#include "refraster/assert.hpp"
#include "stages/rules.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace refraster::detail {

namespace {

// The view-volume planes of draw_context.c (draw->plane[0..5]), as (x, y, z, w) coefficients.
constexpr float kPlanes[6][4] = {
    {-1, 0, 0, 1}, {1, 0, 0, 1}, {0, -1, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {0, 0, -1, 1},
};

}  // namespace

ViewportTransform viewport_transform(const DrawState& s) {
    // mesa/main/viewport.c, _mesa_get_viewport_xform: half sizes in float, depth in double
    // then stored as float. An FBO is not y-flipped (st_atom_viewport.c).
    ViewportTransform t;
    const float half_w = 0.5f * static_cast<float>(s.viewport.width);
    const float half_h = 0.5f * static_cast<float>(s.viewport.height);
    t.scale[0] = half_w;
    t.translate[0] = half_w + static_cast<float>(s.viewport.x);
    t.scale[1] = half_h;
    t.translate[1] = half_h + static_cast<float>(s.viewport.y);
    const double n = s.depth_near;
    const double f = s.depth_far;
    t.scale[2] = static_cast<float>(0.5 * (f - n));
    t.translate[2] = static_cast<float>(0.5 * (n + f));
    return t;
}

namespace {

// draw_llvm.c generate_clipmask (or the C path's guard band test) of flushed clip coordinates.
std::uint8_t compute_clipmask(const std::array<float, 4>& c, VertexStageOptions options,
                              const Fp& fp) {
    std::uint32_t m = 0;
    if (options.guard_band) {
        // draw_cliptest_tmp.h, DO_CLIP_XY_GUARD_BAND: -0.50 * x + w >= 0 and friends, in
        // double (0.50 is a double literal).
        const auto outside = [](double t) { return !(t >= 0.0); };
        m = (outside(-0.50 * double{c[0]} + double{c[3]}) ? 1u : 0u) |
            (outside(0.50 * double{c[0]} + double{c[3]}) ? 2u : 0u) |
            (outside(-0.50 * double{c[1]} + double{c[3]}) ? 4u : 0u) |
            (outside(0.50 * double{c[1]} + double{c[3]}) ? 8u : 0u);
    } else {
        // draw_llvm.c generate_clipmask: compares, and the sums x+w, y+w in float.
        m = (c[0] > c[3] ? 1u : 0u) | (0.0f > fp.add(c[0], c[3]) ? 2u : 0u) |
            (c[1] > c[3] ? 4u : 0u) | (0.0f > fp.add(c[1], c[3]) ? 8u : 0u);
    }
    m |= (0.0f > fp.add(c[2], c[3]) ? 16u : 0u) | (c[2] > c[3] ? 32u : 0u);
    return static_cast<std::uint8_t>(m);
}

// draw_llvm.c generate_viewport: a true division for 1/w, a multiply, then lp_build_fmuladd,
// which LLVM fuses when the CPU has FMA. `clip` is already flushed.
[[gnu::always_inline]] inline void window_of(const float* c, VertexStageOptions options,
                                             const ViewportTransform& vp,
                                             std::array<float, 4>& window) {
    const Fp fp{options.flush_denormals};
    const float oow = fp.div(1.0f, c[3]);
    for (std::size_t k = 0; k < 3; ++k) {
        const float ndc = fp.mul(c[k], oow);
        window[k] = options.fma ? fp.fma(ndc, vp.scale[k], vp.translate[k])
                                : fp.add(fp.mul(ndc, vp.scale[k]), vp.translate[k]);
    }
    window[3] = oow;
}

void window_baseline(const float* c, VertexStageOptions options, const ViewportTransform& vp,
                     std::array<float, 4>& window) {
    window_of(c, options, vp, window);
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// The same operations compiled for CPUs with FMA and SSE4.1 (chosen at run time), so that the
// fused multiply-adds are single instructions rather than library calls: the same results.
[[gnu::target("fma,sse4.1,popcnt"), gnu::flatten]] void window_fma(const float* c,
                                                                   VertexStageOptions options,
                                                                   const ViewportTransform& vp,
                                                                   std::array<float, 4>& window) {
    window_of(c, options, vp, window);
}
#endif

}  // namespace

VertexStage::VertexStage(const Draw& draw, VertexStageOptions options)
    : draw_(draw), options_(options), vp_(viewport_transform(draw.state)) {
    stride_ = draw.vertices.stride();
    attribute_floats_ = stride_ - VertexArray::kPositionComponents;
    REFRASTER_ASSERT(draw.vertices.data.size() % draw.vertices.stride() == 0,
                     "whole vertex records");
    REFRASTER_ASSERT(draw.vertices.data.size() < kPooled, "offsets below the pool bit");
    window_ = &window_baseline;
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    if (host_runs_fma_sse41()) window_ = &window_fma;
#endif
    // Under the CPU's flush modes the clip coordinates stay as they are (compares and sums see
    // them flushed) and the sums run plain.
    const ScopedDenormalsAreZero mode(options_.cpu_flushes);
    const Fp fp{options_.flush_denormals && !options_.cpu_flushes};
    const std::size_t n = draw.vertices.size();
    clipmasks_.resize(n);
    const float* data = draw.vertices.data.data();
#if defined(__SSE2__)
    // Plain operations (the CPU flushes, or nothing does): each vertex as one SSE vector.
    if (!options_.guard_band && !fp.flush) {
        clipmasks_sse(data, n);
        return;
    }
#endif
    for (std::size_t i = 0; i < n; ++i) {
        const float* src = data + i * stride_;
        std::array<float, 4> c{};
        for (std::size_t k = 0; k < 4; ++k) {
            REFRASTER_ASSERT(std::isfinite(src[k]), "finite clip coordinates");
            c[k] = fp.f(src[k]);
        }
        clipmasks_[i] = compute_clipmask(c, options_, fp);
    }
}

#if defined(__SSE2__)
// compute_clipmask's view-volume bits for plain operations, a vertex (x, y, z, w) at a time:
// x > w, y > w, z > w from one compare with w in every lane, x + w < 0, y + w < 0, z + w < 0
// from one sum and one compare; the same float operations, so the same bits (under the CPU's
// flush modes too, which apply to vector and scalar operations alike).
void VertexStage::clipmasks_sse(const float* data, std::size_t n) {
    // Bits of the two 3-lane compares (lanes x, y, z) in clip-mask order: x>w 1, y>w 4, z>w 32;
    // x+w<0 2, y+w<0 8, z+w<0 16.
    constexpr std::array<std::uint8_t, 8> kAbove{0, 1, 4, 5, 32, 33, 36, 37};
    constexpr std::array<std::uint8_t, 8> kBelow{0, 2, 8, 10, 16, 18, 24, 26};
    const __m128 zero = _mm_setzero_ps();
    for (std::size_t i = 0; i < n; ++i) {
        const __m128 c = _mm_loadu_ps(data + i * stride_);
        const __m128 w = _mm_shuffle_ps(c, c, _MM_SHUFFLE(3, 3, 3, 3));
        const int above = _mm_movemask_ps(_mm_cmpgt_ps(c, w)) & 7;
        const int below = _mm_movemask_ps(_mm_cmplt_ps(_mm_add_ps(c, w), zero)) & 7;
        clipmasks_[i] = static_cast<std::uint8_t>(kAbove[static_cast<std::size_t>(above)] |
                                                  kBelow[static_cast<std::size_t>(below)]);
    }
}
#endif

StageVertex VertexStage::vertex(std::uint32_t index, bool cpu_flushes) const {
    // Under the CPU's flush modes the clip coordinates stay as they are: DAZ reads a denormal
    // as the zero of its sign, which is what the flush would store.
    const Fp fp{options_.flush_denormals && !cpu_flushes};
    const float* src = draw_.vertices.data.data() + std::size_t{index} * stride_;
    StageVertex v;
    for (std::size_t k = 0; k < 4; ++k) v.clip[k] = fp.f(src[k]);
    v.clipmask = clipmasks_[index];
    VertexStageOptions o = options_;
    if (cpu_flushes) o.flush_denormals = false;
    window_(v.clip.data(), o, vp_, v.window);
    v.attributes = static_cast<std::uint32_t>(index * stride_ + VertexArray::kPositionComponents);
    return v;
}

StageVertex VertexStage::interpolate(float t, const StageVertex& out, const StageVertex& in) {
    // draw_pipe_clip.c interp(): LINTERP(t, out, in) = out + t * (in - out), unfused.
    const Fp fp{options_.flush_denormals};
    const auto lerp = [&](float o, float i) { return fp.add(o, fp.mul(t, fp.sub(i, o))); };
    StageVertex d;
    d.generated = true;
    for (std::size_t k = 0; k < 4; ++k) d.clip[k] = lerp(out.clip[k], in.clip[k]);
    const float oow = fp.div(1.0f, d.clip[3]);
    for (std::size_t k = 0; k < 3; ++k) {
        d.window[k] = fp.add(fp.mul(fp.mul(d.clip[k], oow), vp_.scale[k]), vp_.translate[k]);
    }
    d.window[3] = oow;

    // Attributes: smooth ones with the clip-space t; noperspective ones with a t recomputed
    // in screen space from the first of x, y that differs; flat ones are left to the copy
    // from the provoking vertex (their values here are never read).
    float t_attr = t;
    if (draw_.state.shade == ShadeModel::NoPerspective) {
        for (std::size_t k = 0; k < 2; ++k) {
            if (in.clip[k] != out.clip[k]) {
                const float in_coord = fp.div(in.clip[k], in.clip[3]);
                const float out_coord = fp.div(out.clip[k], out.clip[3]);
                const float dst_coord = fp.div(d.clip[k], d.clip[3]);
                t_attr = fp.div(fp.sub(dst_coord, out_coord), fp.sub(in_coord, out_coord));
                break;
            }
        }
    }
    d.attributes = static_cast<std::uint32_t>(pool_.size()) | kPooled;
    for (std::size_t a = 0; a < attribute_floats_; ++a) {
        // Read afresh each time: the pool may move as it grows.
        const float o = attributes(out)[a];
        const float i = attributes(in)[a];
        pool_.push_back(fp.add(o, fp.mul(t_attr, fp.sub(i, o))));
    }
    return d;
}

StageVertex VertexStage::duplicate_with_flat(const StageVertex& v, const StageVertex& provoking) {
    // draw_pipe_clip.c dup_vert + copy_flat: flat attributes come from the provoking vertex.
    StageVertex d = v;
    d.attributes = static_cast<std::uint32_t>(pool_.size()) | kPooled;
    for (std::size_t a = 0; a < attribute_floats_; ++a) pool_.push_back(attributes(provoking)[a]);
    return d;
}

void VertexStage::clip_triangle(const std::array<std::uint32_t, 3>& idx, bool provoking_first,
                                std::vector<StageTriangle>& out,
                                std::vector<std::vector<StageVertex>>* polygon_trace,
                                std::uint8_t edge_flags) {
    const StageVertex v0 = vertex(idx[0]);
    const StageVertex v1 = vertex(idx[1]);
    const StageVertex v2 = vertex(idx[2]);
    std::uint32_t mask = v0.clipmask | v1.clipmask | v2.clipmask;
    if (mask == 0) {
        out.push_back({{v0, v1, v2}, false, false, edge_flags});
        return;
    }
    if ((v0.clipmask & v1.clipmask & v2.clipmask) != 0) return;  // clip_tri: all outside one plane

    const Fp fp{options_.flush_denormals};
    std::vector<StageVertex> in_list{v0, v1, v2};
    std::vector<StageVertex> out_list;
    // Edge flags parallel to the vertex lists: edge k runs from vertex k to vertex k + 1.
    // do_clip_tri starts them from the header's DRAW_PIPE_EDGE_FLAG bits, which assembly set.
    std::vector<bool> in_edges{(edge_flags & kEdgeFlag0) != 0, (edge_flags & kEdgeFlag1) != 0,
                               (edge_flags & kEdgeFlag2) != 0};
    std::vector<bool> out_edges;
    const auto distance = [&](const StageVertex& v, int plane) {
        // draw_pipe_clip.c dot4: a[0]*b[0] + a[1]*b[1] + a[2]*b[2] + a[3]*b[3], left to right.
        const float* p = kPlanes[plane];
        return fp.add(fp.add(fp.add(fp.mul(v.clip[0], p[0]), fp.mul(v.clip[1], p[1])),
                             fp.mul(v.clip[2], p[2])),
                      fp.mul(v.clip[3], p[3]));
    };
    while (mask != 0 && in_list.size() >= 3) {
        const int plane = std::countr_zero(mask);
        mask &= mask - 1;
        out_list.clear();
        out_edges.clear();
        const std::size_t n = in_list.size();
        in_list.push_back(in_list[0]);  // "prevent rotation of vertices"
        in_edges.push_back(in_edges[0]);
        float dp_prev = distance(in_list[0], plane);
        if (std::isnan(dp_prev) || std::isinf(dp_prev)) return;
        for (std::size_t i = 1; i <= n; ++i) {
            const StageVertex& prev = in_list[i - 1];
            const StageVertex& cur = in_list[i];
            const bool edge_prev = in_edges[i - 1];
            const float dp = distance(cur, plane);
            if (std::isnan(dp) || std::isinf(dp)) return;
            bool different_sign;
            if (dp_prev >= 0.0f) {
                out_list.push_back(prev);
                out_edges.push_back(edge_prev);
                different_sign = dp < 0.0f;
            } else {
                different_sign = !(dp < 0.0f);
            }
            if (different_sign) {
                const float denom = fp.sub(dp, dp_prev);
                StageVertex nv;
                if (dp < 0.0f) {
                    // Going out; no edge along a view-volume plane.
                    nv = -dp < dp_prev ? interpolate(fp.div(dp, denom), cur, prev)
                                       : interpolate(fp.div(-dp_prev, denom), prev, cur);
                    nv.edgeflag = false;
                } else {
                    // Coming back in.
                    nv = -dp_prev < dp ? interpolate(fp.div(-dp_prev, denom), prev, cur)
                                       : interpolate(fp.div(dp, denom), cur, prev);
                    nv.edgeflag = prev.edgeflag;
                }
                out_list.push_back(nv);
                out_edges.push_back(edge_prev);
            }
            dp_prev = dp;
        }
        std::swap(in_list, out_list);
        std::swap(in_edges, out_edges);
    }
    if (in_list.size() < 3) return;
    const StageVertex& provoking = provoking_first ? v0 : v2;
    if (draw_.state.shade == ShadeModel::Flat && in_list[0].attributes != provoking.attributes) {
        in_list[0] = duplicate_with_flat(in_list[0], provoking);
    }
    if (polygon_trace != nullptr) polygon_trace->push_back(in_list);
    // draw_pipe_clip.c emit_poly: a fan that keeps the provoking vertex in its place, with the
    // polygon's edge flags on the fan's outer edges only.
    const std::uint8_t flag0 = 1, flag1 = 2, flag2 = 4;
    std::uint8_t edge_first = provoking_first ? flag0 : flag2;
    const std::uint8_t edge_middle = provoking_first ? flag1 : flag0;
    const std::uint8_t edge_last = provoking_first ? flag2 : flag1;
    if (!in_edges[0]) edge_first = 0;
    std::uint8_t flags = static_cast<std::uint8_t>(edge_first | edge_middle);
    for (std::size_t i = 2; i < in_list.size(); ++i, flags = edge_middle) {
        StageTriangle t;
        t.v = provoking_first ? std::array<StageVertex, 3>{in_list[0], in_list[i - 1], in_list[i]}
                              : std::array<StageVertex, 3>{in_list[i - 1], in_list[i], in_list[0]};
        if (!in_edges[i - 1]) flags = static_cast<std::uint8_t>(flags & ~edge_middle);
        if (i == in_list.size() - 1 && in_edges[i])
            flags = static_cast<std::uint8_t>(flags | edge_last);
        t.edge_flags = flags;
        t.clipped = true;
        out.push_back(t);
    }
}

// The x/y bits of a clip mask (kClipPlaneNames: x<=w, x>=-w, y<=w, y>=-w).
constexpr std::uint32_t kXyClipBits = 0xfu;

bool VertexStage::keeps_point(std::uint32_t index) const {
    const std::uint32_t mask = clipmasks_[index];
    if (mask == 0) return true;
    if (!options_.keep_points_past_xy || (mask & ~kXyClipBits) != 0) return false;
    // clip_point_guard_xy: x/y bits alone keep the point unless w <= 0 (finite positions only
    // reach here).
    return draw_.vertices.position(index)[3] > 0.0f;
}

std::optional<std::array<StageVertex, 2>> VertexStage::clip_line(std::uint32_t a, std::uint32_t b,
                                                                 bool provoking_first) {
    const StageVertex v0 = vertex(a);
    const StageVertex v1 = vertex(b);
    std::uint32_t mask = v0.clipmask | v1.clipmask;
    if (mask == 0) return std::array<StageVertex, 2>{v0, v1};
    if ((v0.clipmask & v1.clipmask) != 0) return std::nullopt;
    const Fp fp{options_.flush_denormals};
    const auto distance = [&](const StageVertex& v, int plane) {
        const float* p = kPlanes[plane];
        return fp.add(fp.add(fp.add(fp.mul(v.clip[0], p[0]), fp.mul(v.clip[1], p[1])),
                             fp.mul(v.clip[2], p[2])),
                      fp.mul(v.clip[3], p[3]));
    };
    float t0 = 0.0f;
    float t1 = 0.0f;
    while (mask != 0) {
        const int plane = std::countr_zero(mask);
        mask &= mask - 1;
        const float dp0 = distance(v0, plane);
        const float dp1 = distance(v1, plane);
        if (!std::isfinite(dp0) || !std::isfinite(dp1)) return std::nullopt;
        if (dp1 < 0.0f) {
            const float t = fp.div(dp1, fp.sub(dp1, dp0));
            t1 = t1 > t ? t1 : t;  // MAX2
        }
        if (dp0 < 0.0f) {
            const float t = fp.div(dp0, fp.sub(dp0, dp1));
            t0 = t0 > t ? t0 : t;
        }
        if (fp.add(t0, t1) >= 1.0f) return std::nullopt;
    }
    const StageVertex& provoking = provoking_first ? v0 : v1;
    std::array<StageVertex, 2> out{v0, v1};
    if (v0.clipmask != 0) {
        out[0] = interpolate(t0, v0, v1);
        if (draw_.state.shade == ShadeModel::Flat) out[0] = duplicate_with_flat(out[0], provoking);
    }
    if (v1.clipmask != 0) {
        out[1] = interpolate(t1, v1, v0);
        if (draw_.state.shade == ShadeModel::Flat) out[1] = duplicate_with_flat(out[1], provoking);
    }
    return out;
}

float draw_determinant(const StageTriangle& t, bool flush_denormals) {
    const Fp fp{flush_denormals};
    const float ex = fp.sub(t.v[0].window[0], t.v[2].window[0]);
    const float ey = fp.sub(t.v[0].window[1], t.v[2].window[1]);
    const float fx = fp.sub(t.v[1].window[0], t.v[2].window[0]);
    const float fy = fp.sub(t.v[1].window[1], t.v[2].window[1]);
    return fp.sub(fp.mul(ex, fy), fp.mul(ey, fx));
}

bool apply_draw_offset(StageTriangle& t, float det, const PolygonOffset& o, DepthFormat depth,
                       bool flush_denormals, bool nan_to_zero, float units_scale) {
    const Fp fp{flush_denormals};
    const float inv_det = fp.div(1.0f, det);
    const auto& v0 = t.v[0].window;
    const auto& v1 = t.v[1].window;
    const auto& v2 = t.v[2].window;
    const float ex = fp.sub(v0[0], v2[0]), ey = fp.sub(v0[1], v2[1]), ez = fp.sub(v0[2], v2[2]);
    const float fx = fp.sub(v1[0], v2[0]), fy = fp.sub(v1[1], v2[1]), fz = fp.sub(v1[2], v2[2]);
    const float a = fp.sub(fp.mul(ey, fz), fp.mul(ez, fy));
    const float b = fp.sub(fp.mul(ez, fx), fp.mul(ex, fz));
    const float dzdx = std::fabs(fp.mul(a, inv_det));
    const float dzdy = std::fabs(fp.mul(b, inv_det));
    const float mult = fp.mul(dzdx > dzdy ? dzdx : dzdy, o.factor);  // MAX2
    const float units = o.units * units_scale;  // exact: a power of two (offset_units_scale)
    float zoffset = 0.0f;
    if (depth == DepthFormat::Z32f) {
        const float maxz = std::max(std::max(std::fabs(v0[2]), std::fabs(v1[2])), std::fabs(v2[2]));
        zoffset = fp.add(fp.mul(units, z32f_offset_scale(maxz)), mult);
    } else {
        // Without a depth buffer z is never read; z24's step stands in.
        const DepthFormat fixed = depth == DepthFormat::Z16 ? DepthFormat::Z16 : DepthFormat::Z24;
        zoffset = fp.add(fixed_depth_offset_units(units, fixed), mult);
    }
    for (auto& v : t.v) {
        const float z = fp.add(v.window[2], zoffset);
        if (nan_to_zero) {
            v.window[2] = z > 0.0f ? (z > 1.0f ? 1.0f : z) : 0.0f;  // SATURATE, util/macros.h CLAMP
        } else {
            v.window[2] = z < 0.0f ? 0.0f : (z > 1.0f ? 1.0f : z);  // a NaN passes on
        }
    }
    return std::isnan(zoffset);
}

bool passes_draw_cull(const std::array<const StageVertex*, 3>& v, CullMode cull, bool front_ccw) {
    if (cull == CullMode::None) return true;
    // draw_pipe_cull.c cull_tri: e = v0 - v2, f = v1 - v2, det = ex*fy - ey*fx (unfused).
    // The driver runs this under FTZ as well; a flushed product changes no sign tested here
    // except through a zero, which the flush cannot create from two nonzero normal factors
    // whose product is representable.
    const float ex = v[0]->window[0] - v[2]->window[0];
    const float ey = v[0]->window[1] - v[2]->window[1];
    const float fx = v[1]->window[0] - v[2]->window[0];
    const float fy = v[1]->window[1] - v[2]->window[1];
    const float det = flush_denormal(flush_denormal(ex * fy) - flush_denormal(ey * fx));
    if (det == 0.0f) return !is_culled(cull, false);  // zero area counts as back-facing
    const bool ccw = det < 0.0f;
    return !is_culled(cull, ccw == front_ccw);
}

}  // namespace refraster::detail
