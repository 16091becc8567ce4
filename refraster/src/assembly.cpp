#include "refraster/assembly.hpp"

#include <algorithm>

namespace refraster {

std::vector<AssembledTriangle> assemble_triangles(PrimitiveType p, std::size_t count,
                                                  bool provoking_first, int segment_vertices) {
    std::vector<AssembledTriangle> out;
    const auto u = [](std::size_t v) { return static_cast<std::uint32_t>(v); };
    // Triangles per segment (draw_split_tmp.h): lists split at a multiple of 3 vertices,
    // strips at the full segment with two vertices of overlap, fans longer than the segment at
    // vsplit's segment size (at most 1024 vertices) with the centre repeated.
    const auto seg = static_cast<std::size_t>(std::max(segment_vertices, 3));
    switch (p) {
        case PrimitiveType::Triangles: {
            const std::size_t per = std::max<std::size_t>(seg / 3, 1);
            for (std::size_t i = 0; i + 2 < count; i += 3) {
                out.push_back({{u(i), u(i + 1), u(i + 2)}, u((i / 3) / per)});
            }
            break;
        }
        case PrimitiveType::TriangleStrip: {
            const std::size_t per = seg - 2;
            for (std::size_t k = 0; k + 2 < count; ++k) {
                std::array<std::uint32_t, 3> e;
                if (k % 2 == 0) {
                    e = {u(k), u(k + 1), u(k + 2)};
                } else if (provoking_first) {
                    e = {u(k), u(k + 2), u(k + 1)};
                } else {
                    e = {u(k + 1), u(k), u(k + 2)};
                }
                out.push_back({e, u(k / per)});
            }
            break;
        }
        case PrimitiveType::TriangleFan: {
            // Mesa's draw_split_tmp.h (FUNC, as vsplit_run_linear of draw_pt_vsplit_tmp.h):
            // a draw of at most max_count_simple = max_vertices vertices is one segment
            // ("no splitting required"); a longer fan splits at max_count_fan = segment_size
            // = MIN2(SEGMENT_SIZE 1024, max_vertices) vertices, rolling back two.
            const bool split = count > seg;
            const std::size_t per = std::min<std::size_t>(seg, 1024) - 2;
            for (std::size_t k = 0; k + 2 < count; ++k) {
                const auto e = provoking_first
                                   ? std::array<std::uint32_t, 3>{u(k + 1), u(k + 2), 0}
                                   : std::array<std::uint32_t, 3>{0, u(k + 1), u(k + 2)};
                out.push_back({e, split ? u(k / per) : 0u});
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
            // Segments change nothing about the vertices: one segment covering the draw.
            for (const auto& t : assemble_triangles(p, count, provoking_first, 1 << 30)) {
                out.push_back({t.element[0], t.element[1], t.element[2]});
            }
            break;
    }
    return out;
}

}  // namespace refraster
