// vertex_stage.hpp: clip-space vertices to window-space triangles, as Mesa's draw module does.
//
// Implements, for triangles:
//  - the viewport transform of unclipped vertices as llvmpipe's generated vertex code does it
//    (gallium/auxiliary/draw/draw_llvm.c, generate_viewport): oow = 1/w, then
//    fmuladd(c * oow, scale, translate), fused iff the profile says so;
//  - the clip mask (draw_llvm.c, generate_clipmask): bits x>w, x+w<0, y>w, y+w<0, z+w<0, z>w;
//  - the clipper (gallium/auxiliary/draw/draw_pipe_clip.c, do_clip_tri and interp):
//    Sutherland-Hodgman over the set mask bits in increasing order, plane distances as
//    unfused float dot products, the new vertex at out + t*(in - out) with t and the roles of
//    in and out chosen exactly as the driver chooses them, new window coordinates in plain C
//    arithmetic (x * (1/w) * scale + translate, unfused), flat attributes copied to the fan's
//    first vertex, and the polygon emitted as a fan in provoking-vertex order;
//  - the draw module's float cull stage (draw_pipe_cull.c, cull_tri), which sees triangles
//    only when they go through the draw pipeline.
//
// With the guard band, the x/y bits of the clip mask test |x|, |y| <= 2w as the draw module's C
// path does (draw_cliptest_tmp.h, DO_CLIP_XY_GUARD_BAND, in double); the clipper still clips
// against the view-volume planes of the bits set.
//
// Deliberately does not: user clip planes, depth clamp, or any primitive but triangles.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/float_ops.hpp"
#include "refraster/assembly.hpp"
#include "refraster/draw.hpp"
#include "refraster/profile.hpp"

namespace refraster::detail {

// The viewport of one draw as Mesa stores it (mesa/main/viewport.c,
// _mesa_get_viewport_xform): float32 scale and translate.
struct ViewportTransform {
    std::array<float, 3> scale{};
    std::array<float, 3> translate{};
};
ViewportTransform viewport_transform(const DrawState& s);

// A vertex between the vertex stage and setup. `attributes` indexes the pool of the
// VertexStage that owns the vertex.
struct StageVertex {
    std::array<float, 4> clip{};
    std::array<float, 4> window{};  // x, y, z, 1/w
    std::uint32_t clipmask = 0;
    std::uint32_t attributes = 0;
    bool generated = false;  // made by the clipper
    bool edgeflag = true;    // false for a vertex the clipper put on a view-volume plane going out
};

// A triangle handed to setup: its three vertices in the order setup receives them.
struct StageTriangle {
    std::array<StageVertex, 3> v;
    bool clipped = false;      // produced by the clipper
    bool in_pipeline = false;  // went through the draw pipeline (its cull stage applies)
    // Which edges are polygon edges (DRAW_PIPE_EDGE_FLAG_0..2: v0-v1, v1-v2, v2-v0), for
    // polygon modes line and point.
    std::uint8_t edge_flags = 7;
};

// Clip-plane bit names, in clip-mask bit order.
inline constexpr const char* kClipPlaneNames[6] = {"x<=w",  "x>=-w", "y<=w",
                                                   "y>=-w", "z>=-w", "z<=w"};

struct VertexStageOptions {
    bool fma = true;
    bool flush_denormals = true;
    bool guard_band = false;
    // A draw of points under the guard band or point_line_clipping=pixels: x/y clip bits (the
    // guard band's) drop no point; z bits and w <= 0 do (draw_pipe_clip.c, clip_point_guard_xy).
    bool keep_points_past_xy = false;
    // The caller's fast path lets the CPU flush where the profile flushes (DrawContext::
    // cpu_flushes): the clip masks are computed with plain operations under its flush modes.
    bool cpu_flushes = false;
};

class VertexStage {
  public:
    VertexStage(const Draw& draw, VertexStageOptions options);

    // The unclipped vertex `index` of the draw (transform, clip mask, attributes), computed
    // when asked for: the stage keeps one clip-mask byte a vertex, not a record, so that a draw
    // of millions of vertices costs no copy of them (the transform is a pure function of the
    // vertex, so computing it twice gives the same bits).
    // With `cpu_flushes` the caller has set the CPU's flush modes (ScopedDenormalsAreZero)
    // where the profile flushes, and the window coordinates are computed with plain
    // operations: the same results, faster. The clip coordinates are then left unflushed
    // (the CPU reads a denormal as the zero of its sign, the flushed value).
    StageVertex vertex(std::uint32_t index, bool cpu_flushes = false) const;
    std::uint32_t clipmask(std::uint32_t index) const { return clipmasks_[index]; }
    // Whether the clipper keeps the point at `index` (draw_pipe_clip.c: clip_point drops any
    // clip bit; clip_point_guard_xy keeps x/y bits alone unless w <= 0).
    bool keeps_point(std::uint32_t index) const;
    std::size_t attribute_floats() const { return attribute_floats_; }
    // A vertex's attribute values: the draw's own for an original vertex, the pool's for one
    // the clipper made or duplicated. Valid until the stage makes another vertex.
    std::span<const float> attributes(const StageVertex& v) const {
        if ((v.attributes & kPooled) != 0)
            return {pool_.data() + (v.attributes & ~kPooled), attribute_floats_};
        return {draw_.vertices.data.data() + v.attributes, attribute_floats_};
    }

    // Clips one assembled triangle (vertex indices in setup order, provoking vertex last or
    // first by `provoking_first`, polygon edges `edge_flags` as assembly gives them) and appends
    // the triangles it becomes to `out`. A triangle with no clip bit set is appended unchanged; one
    // entirely outside a plane appends nothing.
    void clip_triangle(const std::array<std::uint32_t, 3>& indices, bool provoking_first,
                       std::vector<StageTriangle>& out,
                       std::vector<std::vector<StageVertex>>* polygon_trace,
                       std::uint8_t edge_flags = kEdgeFlagsAll);

    // draw_pipe_clip.c clip_line / do_clip_line: the segment (a, b) in setup order, cut back
    // by the largest t from each end over the set planes; nullopt when nothing is left. New
    // ends get the provoking vertex's flat attributes (copy_flat).
    std::optional<std::array<StageVertex, 2>> clip_line(std::uint32_t a, std::uint32_t b,
                                                        bool provoking_first);

    const ViewportTransform& viewport() const { return vp_; }

    // dup_vert + copy_flat: `v` with the flat attributes of `provoking` (all of them: the only
    // attribute is the colour, flat or not as the draw says).
    StageVertex duplicate_with_flat(const StageVertex& v, const StageVertex& provoking);

  private:
    // StageVertex::attributes: an offset in the draw's vertex data, or, with this bit, in
    // pool_ (the draw's data holds fewer than 2^31 floats: docs/limits.md).
    static constexpr std::uint32_t kPooled = 0x80000000u;
    StageVertex interpolate(float t, const StageVertex& out, const StageVertex& in);
#if defined(__SSE2__)
    void clipmasks_sse(const float* data, std::size_t n);
#endif
    float ftz(float v) const {
        return options_.flush_denormals ? flush_denormal(v) : v;
    }

    const Draw& draw_;
    VertexStageOptions options_;
    ViewportTransform vp_;
    std::size_t attribute_floats_ = 0;
    std::size_t stride_ = 0;               // floats a vertex record of the draw holds
    std::vector<std::uint8_t> clipmasks_;  // one a vertex of the draw
    std::vector<float> pool_;              // attribute values of vertices the stage made
    // The viewport transform of one vertex, compiled for FMA where the CPU has it.
    void (*window_)(const float* clip, VertexStageOptions, const ViewportTransform&,
                    std::array<float, 4>& window) = nullptr;
};

// draw_pipe_cull.c cull_tri: false when the triangle is culled by the draw module's float
// determinant (computed from window coordinates; zero counts as back-facing).
bool passes_draw_cull(const std::array<const StageVertex*, 3>& v, CullMode cull, bool front_ccw);
inline bool passes_draw_cull(const StageTriangle& t, CullMode cull, bool front_ccw) {
    return passes_draw_cull({&t.v[0], &t.v[1], &t.v[2]}, cull, front_ccw);
}

// draw_pipe_cull.c's determinant of window coordinates: (v0 - v2) x (v1 - v2).
float draw_determinant(const StageTriangle& t, bool flush_denormals);

// draw_pipe_offset.c do_offset_tri: adds the polygon offset computed from `det` to each
// vertex's window z and saturates it to [0, 1] (used for polygon modes line and point, where
// the draw module, not llvmpipe, applies the offset). SATURATE is util/macros.h's
// CLAMP(z, 0, 1) = z > 0 ? (z > 1 ? 1 : z) : 0, which turns a NaN into 0 (and -0 into +0);
// with `nan_to_zero` false a NaN z is kept (the quirk draw_offset_nan_to_zero=false). A
// degenerate triangle (det == 0, so 1/det is infinite) has NaN slopes whenever its z does not
// vary, and so a NaN offset. The units are multiplied by `units_scale` (the profile's
// offset_units_scale, a power of two) first. Returns whether the offset was NaN.
bool apply_draw_offset(StageTriangle& t, float det, const PolygonOffset& o, DepthFormat depth,
                       bool flush_denormals, bool nan_to_zero, float units_scale);

}  // namespace refraster::detail
