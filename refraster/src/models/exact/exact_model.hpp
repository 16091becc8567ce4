// exact_model.hpp: the exact oracle as a model: filled triangles decided and shaded exactly.
//
// Implements: setup of a triangle draw into ExactPrimitives in API order (the exact coverage
// test of exact_coverage.hpp, GL's cull decision on its exact orientation, the exact shader
// of fragment.hpp), their traversal over the candidate pixels into quad packets, and the
// kernel that shades those packets.
//
// Deliberately does not: snap, clip, or reproduce any driver's rounding; draw lines, points
// or polygon modes (render() refuses those with NotSupported); trace fragments (the trace
// records the oracle's weights instead).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "models/exact/exact_coverage.hpp"
#include "models/llvmpipe/fragment.hpp"
#include "stages/model.hpp"
#include "stages/quad.hpp"

namespace refraster::detail {

struct ExactPrimitive {
    std::unique_ptr<ExactCoverage> coverage;
    std::unique_ptr<ExactShader> shader;  // reads *coverage
    std::uint32_t owner = 0;
};

struct ExactList {
    static constexpr std::size_t kCapacity = 1024;
    std::vector<ExactPrimitive> primitives;
    bool full() const { return primitives.size() >= kCapacity; }
    void clear() { primitives.clear(); }
};

class ExactKernel {
  public:
    void shade(const ExactList&, const ExactPrimitive& p, std::span<const QuadPacket> quads,
               Framebuffer& fb) const {
        for (const QuadPacket& q : quads) {
            for (unsigned i = 0; i < 4; ++i) {
                if ((q.mask & (1u << quad_bit(i, 0))) != 0) {
                    p.shader->shade(q.x + static_cast<int>(i & 1u), q.y + static_cast<int>(i >> 1),
                                    fb, p.owner);
                }
            }
        }
    }
    bool hardware_denormals() const { return false; }
    FragmentTrace trace(const ExactList&, const ExactPrimitive&, int, int, unsigned,
                        const Framebuffer&) const {
        return {};
    }
};

class ExactModel {
  public:
    using List = ExactList;
    using Primitive = ExactPrimitive;

    explicit ExactModel(const DrawContext& ctx) : ctx_(ctx) {}
    static constexpr bool kRowBlocks = false;  // quad packets only

    template <class Observer>
    void setup(VertexStage& stage, Observer& obs, const ListSink<List>& sink);

    // The candidate pixels, a row pair at a time, as quad packets of the covered ones.
    template <class Emit>
    static void traverse(const List&, const ExactPrimitive& p, Emit&& emit) {
        const PixelRect r = p.coverage->candidates();
        if (r.empty()) return;
        std::vector<QuadPacket> quads;
        for (int y = r.y0 & ~1; y <= r.y1; y += 2) {
            quads.clear();
            for (int x = r.x0 & ~1; x <= r.x1; x += 2) {
                std::uint16_t mask = 0;
                for (unsigned i = 0; i < 4; ++i) {
                    const int px = x + static_cast<int>(i & 1u);
                    const int py = y + static_cast<int>(i >> 1);
                    if (px >= r.x0 && px <= r.x1 && py >= r.y0 && py <= r.y1 &&
                        p.coverage->covers(px, py)) {
                        mask = static_cast<std::uint16_t>(mask | (1u << quad_bit(i, 0)));
                    }
                }
                if (mask != 0) quads.push_back({x, y, mask});
            }
            if (!quads.empty()) emit(std::span<const QuadPacket>(quads));
        }
    }

    ExactKernel kernel() const { return {}; }

  private:
    const DrawContext& ctx_;
};

}  // namespace refraster::detail
