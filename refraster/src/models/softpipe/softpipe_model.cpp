// softpipe_model.cpp: the softpipe model's per-render and per-draw state, and its setup
// instantiated without an observer (softpipe_model_impl.hpp).
#include "models/softpipe/softpipe_model.hpp"

#include "models/softpipe/softpipe_model_impl.hpp"

namespace refraster::detail {

SoftpipeModel::RenderState::RenderState(const DrawList& list, const Profile& profile,
                                        Framebuffer& fb, bool fast)
    : list_(list),
      fb_(fb),
      truncate_colors_(profile.gl.color_rounding == Rounding::Truncate),
      fast_(fast),
      generated_levels_(list.textures.size()) {
    // The tile cache of a scanline render. glGenerateMipmap's blit, which the GL backends run
    // after the clear, flushes it.
    if (profile.model != CoverageModel::Scanline) return;
    if (fast_) {
        lazy_.emplace(fb, list.clear.color);
    } else {
        tiles_.emplace(fb, list.clear.color, truncate_colors_);
    }
    for (const auto& t : list.textures) {
        if (t.generate_mipmaps) {
            flush_shared_tiles();
            break;
        }
    }
}

SoftpipeModel::SoftpipeModel(const DrawContext& ctx, RenderState& state) : DrawModule(ctx) {
    // A scanline draw in a snapped render (the profile's line or point rule) gets a cache of its
    // own over the surface.
    if (state.fast_) {
        if (!state.lazy_) own_lazy_.emplace(state.fb_, std::nullopt);
        lazy_ = state.lazy_ ? &*state.lazy_ : &*own_lazy_;
        list_.fast = true;
    } else {
        if (!state.tiles_) own_tiles_.emplace(state.fb_, std::nullopt, state.truncate_colors_);
        tiles_ = state.tiles_ ? &*state.tiles_ : &*own_tiles_;
    }
    // softpipe's sampler of the draw's texture; generated levels are made once a texture.
    const Draw& d = ctx.draw;
    if (!d.state.texture) return;
    const std::uint32_t t = d.state.texture->texture;
    const Texture& texture = state.list_.textures[t];
    if (texture.generate_mipmaps && state.generated_levels_[t].empty()) {
        sampler_.emplace(*d.state.texture, texture.levels, true);
        state.generated_levels_[t] = sampler_->levels();
    } else if (texture.generate_mipmaps) {
        sampler_.emplace(*d.state.texture, state.generated_levels_[t], false);
    } else {
        sampler_.emplace(*d.state.texture, texture.levels, false);
    }
}

template void SoftpipeModel::setup(VertexStage&, NoObserver&, const ListSink<List>&);

}  // namespace refraster::detail
