// assembly.hpp: triangles from a draw's vertex stream, in the vertex order Mesa emits them.
//
// Implements GL's triangle assembly (OpenGL 4.6 compatibility, 10.1.8-10.1.10) with the
// vertex order of llvmpipe's vbuf path (gallium/drivers/llvmpipe/lp_setup_vbuf.c,
// lp_setup_draw_arrays; the draw pipeline's draw_decompose_tmp.h emits the same order):
//   triangles            (i, i+1, i+2)
//   strip, last  vertex  even k: (k, k+1, k+2)   odd k: (k+1, k, k+2)
//   strip, first vertex  even k: (k, k+1, k+2)   odd k: (k, k+2, k+1)
//   fan,   last  vertex  (0, k+1, k+2)
//   fan,   first vertex  (k+1, k+2, 0)
// so that the provoking vertex is always the last (or first) of the three. Also the vertex
// segments the draw module splits a draw into (draw_pt_vsplit.c, draw_split_tmp.h).
//
// Deliberately does not: assemble lines or points.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "refraster/draw.hpp"

namespace refraster::detail {

struct AssembledTriangle {
    std::array<std::uint32_t, 3> element;  // positions in the draw's element stream
    std::uint32_t segment = 0;             // the draw module's vertex segment
};

// `segment_vertices` is the draw module's max_vertices; `indexed` draws (glDrawElements with
// 32-bit indices) split at vsplit's segment size instead (draw_pt_vsplit_tmp.h).
std::vector<AssembledTriangle> assemble_triangles(PrimitiveType p, std::size_t count, bool provoking_first,
                                                  int segment_vertices, bool indexed = false);

}  // namespace refraster::detail
