// exact_shader.hpp: the exact oracle's fragments.
//
// Implements: attributes and depth from the exact homogeneous weights of the pixel centre
// (exact_coverage.hpp), the GL specification's polygon offset, and the output merge every model
// shares (stages/output_merge.hpp).
//
// Deliberately does not: round as any driver does (depth is rounded to nearest from the real
// value), texture, or multisample.
#pragma once

#include <array>
#include <cstdint>

#include "models/exact/exact_coverage.hpp"
#include "refraster/draw.hpp"
#include "refraster/framebuffer.hpp"
#include "stages/vertex_stage.hpp"

namespace refraster::detail {

// The exact oracle's fragments: attributes and depth from the exact homogeneous weights of the
// pixel centre (perspective-correct: sum b_i a_i; noperspective: the screen-space weights
// b_i w_i; flat: the provoking vertex), depth quantised by rounding the real value to
// nearest, polygon offset as the GL specification states it (14.6.5: m * factor + r * units
// with r = 1 / (2^n - 1), or 2^(e - 23) for float depth), the same output merge as llvmpipe's.
class ExactShader {
  public:
    ExactShader(const ExactCoverage& coverage, const std::array<StageVertex, 3>& v,
                const VertexStage& stage, const Draw& draw, const Target& target,
                bool provoking_first, double offset_units_scale);
    void shade(int x, int y, Framebuffer& fb, std::uint32_t owner = 0) const;

  private:
    const ExactCoverage& coverage_;
    std::array<StageVertex, 3> v_;
    const VertexStage& stage_;
    const Draw& draw_;
    Target target_;
    bool provoking_first_;
    double offset_ = 0.0;
    bool depth_test_ = false;
};

}  // namespace refraster::detail
