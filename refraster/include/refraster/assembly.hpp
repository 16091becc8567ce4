// assembly.hpp: primitives from a draw's element stream, in the vertex order Mesa emits them.
//
// Implements GL's primitive assembly (OpenGL 4.6 compatibility profile, 10.1 "Primitive
// Types") with the vertex order of llvmpipe's vbuf path (gallium/drivers/llvmpipe/
// lp_setup_vbuf.c, lp_setup_draw_arrays; the draw pipeline's draw_decompose_tmp.h emits the
// same order):
//   triangles            (i, i+1, i+2)
//   strip, last  vertex  even k: (k, k+1, k+2)   odd k: (k+1, k, k+2)
//   strip, first vertex  even k: (k, k+1, k+2)   odd k: (k, k+2, k+1)
//   fan,   last  vertex  (0, k+1, k+2)
//   fan,   first vertex  (k+1, k+2, 0)
//   polygon, last  vertex  (k+1, k+2, 0)     (lp_setup_vbuf.c: GL_POLYGON's flat vertex is
//   polygon, first vertex  (0, k+1, k+2)      its first, so it goes last or first)
//   lines (i, i+1); strips and loops (i, i+1), a loop closed by (n-1, 0); points (i)
// so that the provoking vertex is always the last (or first) of a primitive. Also the vertex
// segments the draw module splits a triangle draw into (draw_pt_vsplit.c, draw_split_tmp.h).
// Public so that every tool that needs the driver's primitives (the reducer) uses this one.
//
// Deliberately does not: fetch or transform vertices, or decide anything about coverage.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "refraster/draw.hpp"

namespace refraster {

// Edge flags of an assembled triangle (DRAW_PIPE_EDGE_FLAG_0..2): which of its edges v0-v1,
// v1-v2, v2-v0 are edges of the primitive the application drew, and so drawn by polygon modes
// line and point. Every edge of a triangle, strip or fan triangle is; of a polygon's fan only
// its outline (draw_decompose_tmp.h, the POLYGON case, with its DRAW_SPLIT flags).
inline constexpr std::uint8_t kEdgeFlag0 = 1;
inline constexpr std::uint8_t kEdgeFlag1 = 2;
inline constexpr std::uint8_t kEdgeFlag2 = 4;
inline constexpr std::uint8_t kEdgeFlagsAll = 7;

struct AssembledTriangle {
    std::array<std::uint32_t, 3> element;  // positions in the draw's element stream
    std::uint32_t segment = 0;             // the draw module's vertex segment
    std::uint8_t edge_flags = kEdgeFlagsAll;
};

// The triangles of a triangle draw of `count` elements; `segment_vertices` is the draw
// module's max_vertices (Profile quirk draw_segment_vertices); `indexed` draws (glDrawElements
// with 32-bit indices) split at vsplit's segment size instead (draw_pt_vsplit_tmp.h).
std::vector<AssembledTriangle> assemble_triangles(PrimitiveType p, std::size_t count,
                                                  bool provoking_first, int segment_vertices,
                                                  bool indexed = false);

// The segments of a line draw, as pairs of element positions in setup's (first, second) order.
std::vector<std::array<std::uint32_t, 2>> assemble_lines(PrimitiveType p, std::size_t count);

// Every primitive of a draw of any type as its element positions (1 for points, 2 for lines,
// 3 for triangles), in the order and vertex order above.
std::vector<std::vector<std::uint32_t>> assemble_primitives(PrimitiveType p, std::size_t count,
                                                            bool provoking_first);

}  // namespace refraster
