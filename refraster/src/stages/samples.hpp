// samples.hpp: where the four samples of a 4x pixel lie, in the two forms llvmpipe uses.
//
// Implements: the standard 4x pattern (lp_rast.c: lp_sample_pos_4x; the D3D pattern, and what
// glGetMultisamplefv(GL_SAMPLE_POSITION) reports in an FBO), as offsets from the pixel's
// bottom-left corner in GL window coordinates (y up, an FBO is not flipped): in float, as the
// fragment shader adds them to the pixel's coordinates for per-sample depth, and in 1/256
// pixel fixed point, as the rasterizer adds them to its edge constants (round(pos * 256)).
//
// Deliberately does not: other sample counts (llvmpipe supports 1 and 4 only, lp_screen.c) or
// programmable sample locations.
#pragma once

#include <array>
#include <cstdint>

namespace refraster::detail {

inline constexpr unsigned kMsaaSamples = 4;

struct SamplePosition {
    float x;
    float y;
    std::int32_t fixed_x;  // x * 2^8, exact
    std::int32_t fixed_y;
};

inline constexpr std::array<SamplePosition, kMsaaSamples> kSamplePositions4x{{
    {0.375f, 0.125f, 96, 32},
    {0.875f, 0.375f, 224, 96},
    {0.125f, 0.625f, 32, 160},
    {0.625f, 0.875f, 160, 224},
}};

// The fixed-point offsets have 8 fraction bits (FIXED_ORDER) and must equal the floats
// exactly: every position is a multiple of 1/8.
constexpr bool sample_positions_consistent() {
    for (const auto& s : kSamplePositions4x) {
        if (static_cast<float>(s.fixed_x) / 256.0f != s.x) return false;
        if (static_cast<float>(s.fixed_y) / 256.0f != s.y) return false;
        if (s.fixed_x <= 0 || s.fixed_x >= 256 || s.fixed_y <= 0 || s.fixed_y >= 256) return false;
    }
    return true;
}
static_assert(sample_positions_consistent(), "the 4x pattern in float and 8-bit fixed point");

}  // namespace refraster::detail
