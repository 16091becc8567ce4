#include "refraster/assembly.hpp"

#include <algorithm>

namespace refraster {

std::vector<AssembledTriangle> assemble_triangles(PrimitiveType p, std::size_t count,
                                                  bool provoking_first, int segment_vertices,
                                                  bool indexed) {
    std::vector<AssembledTriangle> out;
    const auto u = [](std::size_t v) { return static_cast<std::uint32_t>(v); };
    // draw_pt_vsplit.c: segment_size = MIN2(SEGMENT_SIZE 1024, max_vertices). FUNC of
    // draw_split_tmp.h runs a draw of at most max_count_simple vertices as one segment; that is
    // max_vertices for an unindexed draw (vsplit_run_linear) and segment_size for 32-bit
    // indices (vsplit_run_uint: the index buffer cannot be used directly, and
    // vsplit_primitive_uint gives up on more than segment_size indices). A longer draw splits
    // at seg_max = MIN2(max_count_simple, count) trimmed to whole primitives: lists at a
    // multiple of 3, strips with two vertices of overlap (seg_max one less when it would
    // flush an odd number of triangles), fans at max_count_fan = segment_size with the centre
    // repeated.
    const auto max_vertices = static_cast<std::size_t>(std::max(segment_vertices, 3));
    const std::size_t segment_size =
        std::max<std::size_t>(std::min<std::size_t>(1024, max_vertices), 3);
    const std::size_t simple = indexed ? segment_size : max_vertices;
    const bool split = count > simple;
    out.reserve(p == PrimitiveType::Triangles ? count / 3 : (count >= 2 ? count - 2 : 0));
    switch (p) {
        case PrimitiveType::Triangles: {
            const std::size_t per = std::max<std::size_t>(simple / 3, 1);
            // Triangle i / 3 of segment (i / 3) / per, counted rather than divided.
            std::uint32_t segment = 0;
            std::size_t in_segment = 0;
            for (std::size_t i = 0; i + 2 < count; i += 3) {
                out.push_back({{u(i), u(i + 1), u(i + 2)}, split ? segment : 0u});
                if (++in_segment == per) {
                    in_segment = 0;
                    ++segment;
                }
            }
            break;
        }
        case PrimitiveType::TriangleStrip: {
            std::size_t seg_max = simple;
            if (((seg_max - 3) & 1) == 0) --seg_max;  // an even number of triangles per segment
            const std::size_t per = std::max<std::size_t>(seg_max - 2, 1);
            for (std::size_t k = 0; k + 2 < count; ++k) {
                std::array<std::uint32_t, 3> e;
                if (k % 2 == 0) {
                    e = {u(k), u(k + 1), u(k + 2)};
                } else if (provoking_first) {
                    e = {u(k), u(k + 2), u(k + 1)};
                } else {
                    e = {u(k + 1), u(k), u(k + 2)};
                }
                out.push_back({e, split ? u(k / per) : 0u});
            }
            break;
        }
        case PrimitiveType::TriangleFan: {
            const std::size_t per = segment_size - 2;
            for (std::size_t k = 0; k + 2 < count; ++k) {
                const auto e = provoking_first
                                   ? std::array<std::uint32_t, 3>{u(k + 1), u(k + 2), 0}
                                   : std::array<std::uint32_t, 3>{0, u(k + 1), u(k + 2)};
                out.push_back({e, split ? u(k / per) : 0u});
            }
            break;
        }
        case PrimitiveType::Polygon: {
            // Split like a fan (draw_split_tmp.h: POLYGON shares the fan's case), each segment
            // a fan around element 0. draw_decompose_tmp.h gives the first triangle of the
            // polygon's first segment the edge from v0, each triangle the outline edge between
            // its two newest vertices, and the last triangle of the last segment the edge back
            // to v0; DRAW_SPLIT_BEFORE and DRAW_SPLIT_AFTER withhold the first and last of
            // those where a segment boundary falls.
            const std::size_t per = segment_size - 2;
            const std::size_t n = count >= 3 ? count - 2 : 0;
            const std::uint8_t first_edge = provoking_first ? kEdgeFlag0 : kEdgeFlag2;
            const std::uint8_t next_edge = provoking_first ? kEdgeFlag1 : kEdgeFlag0;
            const std::uint8_t finish_edge = provoking_first ? kEdgeFlag2 : kEdgeFlag1;
            for (std::size_t k = 0; k < n; ++k) {
                const auto e = provoking_first
                                   ? std::array<std::uint32_t, 3>{0, u(k + 1), u(k + 2)}
                                   : std::array<std::uint32_t, 3>{u(k + 1), u(k + 2), 0};
                std::uint8_t flags = next_edge;
                // A segment starts at triangle k when k is a multiple of `per` (split draws).
                if (k == 0) flags = static_cast<std::uint8_t>(flags | first_edge);
                if (k + 1 == n) flags = static_cast<std::uint8_t>(flags | finish_edge);
                out.push_back({e, split ? u(k / per) : 0u, flags});
            }
            break;
        }
        default:
            break;
    }
    return out;
}

std::vector<std::array<std::uint32_t, 2>> assemble_lines(PrimitiveType p, std::size_t count) {
    std::vector<std::array<std::uint32_t, 2>> out;
    const auto u = [](std::size_t v) { return static_cast<std::uint32_t>(v); };
    switch (p) {
        case PrimitiveType::Lines:
            for (std::size_t i = 0; i + 1 < count; i += 2) out.push_back({u(i), u(i + 1)});
            break;
        case PrimitiveType::LineStrip:
        case PrimitiveType::LineLoop:
            for (std::size_t i = 0; i + 1 < count; ++i) out.push_back({u(i), u(i + 1)});
            if (p == PrimitiveType::LineLoop && count >= 2) out.push_back({u(count - 1), 0});
            break;
        default:
            break;
    }
    return out;
}

std::vector<std::vector<std::uint32_t>> assemble_primitives(PrimitiveType p, std::size_t count,
                                                            bool provoking_first) {
    std::vector<std::vector<std::uint32_t>> out;
    switch (p) {
        case PrimitiveType::Points:
            for (std::size_t i = 0; i < count; ++i) out.push_back({static_cast<std::uint32_t>(i)});
            break;
        case PrimitiveType::Lines:
        case PrimitiveType::LineStrip:
        case PrimitiveType::LineLoop:
            for (const auto& s : assemble_lines(p, count)) out.push_back({s[0], s[1]});
            break;
        case PrimitiveType::Triangles:
        case PrimitiveType::TriangleStrip:
        case PrimitiveType::TriangleFan:
        case PrimitiveType::Polygon:
            // Segments change nothing about the vertices: one segment covering the draw.
            for (const auto& t : assemble_triangles(p, count, provoking_first, 1 << 30)) {
                out.push_back({t.element[0], t.element[1], t.element[2]});
            }
            break;
    }
    return out;
}

}  // namespace refraster
