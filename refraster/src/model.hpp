// model.hpp: what a coverage model is given for one draw, and what it hands on.
//
// Implements: DrawContext, the draw, its target and profile and the values derived from them
// once per draw (setup parameters, whether the viewport transform fuses), and the shape every
// model has, which the stage order (pipeline.hpp) relies on:
//   Model(const DrawContext&)
//   setup(VertexStage&, Observer&, sink)  set-up primitives in API order, a List at a time
//   traverse(list, primitive, emit)       quad packets of the pixels it covers, a tile at a time
//   kernel()                              the per-draw fragment kernel: shade(list, primitive,
//                                         quads, framebuffer) and trace(list, primitive, x, y, fb)
// Models today: LlvmpipeModel (llvmpipe_model.hpp) and ExactModel (exact_model.hpp).
//
// Deliberately does not: choose the model (pipeline.hpp does, once per draw).
#pragma once

#include <cstddef>
#include <functional>

#include "fragment.hpp"
#include "refraster/draw.hpp"
#include "refraster/profile.hpp"
#include "setup.hpp"
#include "vertex_stage.hpp"

namespace refraster::detail {

struct DrawContext {
    std::size_t index = 0;  // of the draw in its DrawList
    const Draw& draw;
    const Target& target;
    const Profile& profile;
    SetupParams params;
    bool fma = false;            // the viewport transform and plane evaluation fuse
    bool record_owners = false;  // Framebuffer::owner is filled

    VertexStageOptions vertex_options() const {
        return {fma, profile.gl.flush_denormals, profile.gl.clipping == Clipping::GuardBand};
    }
    FragmentOptions fragment_options() const { return {fma, profile.gl.flush_denormals}; }
};

// Receives each full list of set-up primitives, and the last one, in API order.
template <class List>
using ListSink = std::function<void(const List&)>;

}  // namespace refraster::detail
