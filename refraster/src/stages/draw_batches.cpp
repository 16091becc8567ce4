// draw_batches.cpp: the draw module's vbuf batches of pipeline triangles (model.hpp).
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "stages/draw_module.hpp"
#include "stages/vertex_stage.hpp"

namespace refraster::detail {

std::vector<bool> pipeline_batches_flushed(const DrawContext& ctx, VertexStage& stage,
                                           const std::vector<AssembledTriangle>& tris,
                                           const std::vector<bool>& segment_clipped) {
    constexpr std::size_t kMaxVertices = 4096 / 32;
    constexpr std::size_t kMaxIndices = 1024;
    const Draw& d = ctx.draw;
    std::vector<bool> out;
    if (!ctx.profile.gl.flush_denormals ||
        std::find(segment_clipped.begin(), segment_clipped.end(), true) == segment_clipped.end()) {
        return out;
    }
    std::size_t vertices = 0, indices = 0;
    // Indices into `out` of the triangles not yet set up. Every entry starts true (set up
    // with FTZ); only the last batch changes, so a flush with FTZ just forgets its batch.
    std::vector<std::size_t> pending;
    // Which vertices the current batch has counted: a stamp per original vertex, and a list
    // for the clipper's new ones, which only the triangles of one polygon share. A stamp names
    // one (batch, segment) pair: triangles come in order, so a pair never comes back, and
    // `epoch` counts the pairs.
    // An unindexed triangle list shares no vertex between its triangles: a vertex can only be
    // met again among the clipper's outputs of its own triangle, so three stamps do instead of
    // one a vertex of the draw.
    const bool unshared = d.primitive == PrimitiveType::Triangles && !d.indices;
    std::vector<std::uint32_t> counted(unshared ? 0 : d.vertices.size(), 0);
    std::array<std::uint32_t, 3> recent{};        // unshared: this triangle's counted vertices
    std::array<std::uint32_t, 3> recent_epoch{};  // and the epoch each was counted in
    std::vector<std::uint64_t> emitted;
    std::uint32_t epoch = 1;
    std::uint32_t epoch_segment = tris.empty() ? 0 : tris.front().segment;
    const auto flush = [&](bool ftz) {
        if (!ftz) {
            for (const auto i : pending) out[i] = false;
        }
        pending.clear();
        vertices = indices = 0;
        emitted.clear();
        ++epoch;
    };
    constexpr std::uint32_t kNotOriginal = 0xffffffffu;
    // `v` is read only for a vertex that is not an original one.
    const auto count_vertex = [&](std::uint32_t segment, const StageVertex* v,
                                  std::uint32_t original) {
        if (segment != epoch_segment) {
            epoch_segment = segment;
            ++epoch;
        }
        if (original != kNotOriginal) {
            if (unshared) {
                // The slot of `original` among its triangle's three vertices.
                const std::size_t k = original % 3;
                if (recent_epoch[k] != epoch || recent[k] != original) {
                    recent[k] = original;
                    recent_epoch[k] = epoch;
                    ++vertices;
                }
                return;
            }
            if (counted[original] != epoch) {
                counted[original] = epoch;
                ++vertices;
            }
            return;
        }
        const std::uint64_t key = (std::uint64_t{segment} << 32) | v->attributes;
        if (std::find(emitted.begin(), emitted.end(), key) == emitted.end()) {
            emitted.push_back(key);
            ++vertices;
        }
    };
    const auto reaches_setup = [&](const std::array<const StageVertex*, 3>& v) {
        return !ctx.profile.quirks.draw_pipeline_cull ||
               passes_draw_cull(v, d.state.cull, ctx.params.front_ccw);
    };
    std::vector<StageTriangle> staged;
    for (const auto& at : tris) {
        if (!segment_clipped[at.segment]) {
            if (!pending.empty()) flush(true);
            continue;
        }
        const std::array<std::uint32_t, 3> idx{d.element(at.element[0]), d.element(at.element[1]),
                                               d.element(at.element[2])};
        const auto stage_vertices = [&] {
            return std::array<StageVertex, 3>{stage.vertex(idx[0]), stage.vertex(idx[1]),
                                              stage.vertex(idx[2])};
        };
        if ((stage.clipmask(idx[0]) | stage.clipmask(idx[1]) | stage.clipmask(idx[2])) == 0) {
            // The clipper hands it on unchanged, with its own three vertices (the cull stage
            // alone needs their window coordinates).
            if (d.state.cull != CullMode::None) {
                const auto sv = stage_vertices();
                if (!reaches_setup({&sv[0], &sv[1], &sv[2]})) {
                    out.push_back(true);
                    continue;
                }
            }
            if (vertices + 3 > kMaxVertices || indices + 3 > kMaxIndices) flush(true);
            for (std::size_t k = 0; k < 3; ++k) count_vertex(at.segment, nullptr, idx[k]);
            indices += 3;
            pending.push_back(out.size());
            out.push_back(true);
            continue;
        }
        const auto sv = stage_vertices();
        const std::array<const StageVertex*, 3> v{&sv[0], &sv[1], &sv[2]};
        staged.clear();
        stage.clip_triangle(idx, ctx.params.provoking_first, staged, nullptr);
        for (const auto& st : staged) {
            if (!reaches_setup({&st.v[0], &st.v[1], &st.v[2]})) {
                out.push_back(true);  // never reaches setup
                continue;
            }
            if (vertices + 3 > kMaxVertices || indices + 3 > kMaxIndices) flush(true);
            for (std::size_t k = 0; k < 3; ++k) {
                // An original vertex of a clipped triangle is one of the three (the same
                // attribute slot); a new or duplicated one is not.
                std::uint32_t original = kNotOriginal;
                for (std::size_t j = 0; j < 3; ++j) {
                    if (v[j]->attributes == st.v[k].attributes) original = idx[j];
                }
                count_vertex(at.segment, &st.v[k], original);
            }
            indices += 3;
            pending.push_back(out.size());
            out.push_back(true);
        }
    }
    flush(false);
    return out;
}

}  // namespace refraster::detail
