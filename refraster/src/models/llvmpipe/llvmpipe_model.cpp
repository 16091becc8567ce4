// llvmpipe_model.cpp: the llvmpipe model's per-render state, its nine-vertex analysis, and
// its setup instantiated without an observer (llvmpipe_model_impl.hpp).
#include "models/llvmpipe/llvmpipe_model.hpp"

#include "models/llvmpipe/llvmpipe_model_impl.hpp"
#include "refraster/assert.hpp"
#include "refraster/renderer.hpp"

namespace refraster::detail {

LlvmpipeModel::RenderState::RenderState(const DrawList& list, const Profile& profile, Framebuffer&)
    : generated_(list.textures.size()) {
    // The blit that makes generated levels interpolates as the shaders do: fused when the
    // profile's viewport_fma says so.
    const FmaMode m = profile.gl.viewport_fma;
    const bool fma = m == FmaMode::On || (m == FmaMode::Auto && host_has_fma());
    levels_.reserve(list.textures.size());
    for (std::size_t t = 0; t < list.textures.size(); ++t) {
        if (list.textures[t].generate_mipmaps)
            generated_[t] = resolve_levels(list.textures[t], fma, profile.gl.texture_filtering);
        levels_.push_back(list.textures[t].generate_mipmaps ? &generated_[t]
                                                            : &list.textures[t].levels);
    }
    packed_.resize(levels_.size());
    packed_tried_.resize(levels_.size());
}

const PackedLevels* LlvmpipeModel::RenderState::packed(std::uint32_t texture) {
    REFRASTER_ASSERT(texture < levels_.size(), "a texture the draw list holds");
    if (!packed_tried_[texture]) {
        packed_[texture] = pack_levels(*levels_[texture]);
        packed_tried_[texture] = true;
    }
    return packed_[texture] ? &*packed_[texture] : nullptr;
}

const std::vector<TextureImage>& LlvmpipeModel::RenderState::levels(std::uint32_t texture) const {
    REFRASTER_ASSERT(texture < levels_.size(), "a texture the draw list holds");
    return *levels_[texture];
}

LlvmpipeModel::LlvmpipeModel(const DrawContext& ctx, RenderState& state) : DrawModule(ctx) {
    const Draw& d = ctx.draw;
    if (d.state.texture) {
        REFRASTER_ASSERT(d.vertices.attribute_offset(d.vertices.attributes.size()) >=
                             VertexArray::kPositionComponents + 8,
                         "colour and texture coordinates in a textured draw's vertices");
        unit_ = make_texture_unit(*d.state.texture, state.levels(d.state.texture->texture),
                                  ctx.profile.gl.texture_filtering);
        unit_->flush_border = ctx.profile.gl.flush_denormals;
        unit_->rho_approx = ctx.profile.gl.texture_rho == TextureRho::Approx;
        unit_->brilinear = ctx.profile.gl.texture_mip_blend == MipBlend::Brilinear;
        // Only the vector kernels gather from packed levels.
        const KernelPath path = resolve_kernel_path(ctx.kernels);
        if (path == KernelPath::Avx2 || path == KernelPath::Avx512)
            unit_->packed = state.packed(d.state.texture->texture);
    }
}

// lp_setup_analyse_triangles (lp_setup_analysis.c), reached from lp_setup_draw_arrays for
// a non-indexed triangle list of exactly 9 vertices drawn without constant-interpolated
// inputs and without the draw pipeline: when the last triangle's three window y values are
// equal, the function claims the whole draw. It hands the first two triangles to
// lp_rect_cw when they form a rectangle and drops them otherwise; measured in an FBO,
// neither case draws anything (scenes triangles.coverage.nine_vertex_quirk_*).
bool LlvmpipeModel::nine_vertex_quirk_drops(const VertexStage& stage,
                                            const std::vector<AssembledTriangle>& tris,
                                            const std::vector<bool>& segment_clipped) const {
    // The owner pass reads gl_PrimitiveID, a constant-interpolated input, and so bypasses
    // the analysis in the driver; the reference's owner pass does the same.
    const Draw& d = ctx_.draw;
    if (!ctx_.profile.quirks.nine_vertex_quirk || ctx_.record_owners) return false;
    if (d.primitive != PrimitiveType::Triangles || d.indices || d.element_count() != 9)
        return false;
    if (d.state.shade == ShadeModel::Flat || tris.size() != 3 || segment_clipped[0]) return false;
    const auto y = [&](std::uint32_t i) { return stage.vertex(i).window[1]; };
    return y(8) == y(7) && y(8) == y(6);
}

template void LlvmpipeModel::setup(VertexStage&, NoObserver&, const ListSink<List>&);

}  // namespace refraster::detail
