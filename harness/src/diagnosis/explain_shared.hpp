// explain_shared.hpp: what the three parts of explain (explain_decide.cpp decides,
// explain_report.cpp writes text and JSON, explain_draw.cpp draws SVG) share.
#pragma once

#include <array>
#include <string>

#include "refraster/renderer.hpp"

namespace harness::explain_detail {

// The 4x sample positions (lp_rast.c, lp_sample_pos_4x), for the text and the drawing.
inline constexpr std::array<std::array<double, 2>, 4> kSampleOffsets{
    {{0.375, 0.125}, {0.875, 0.375}, {0.125, 0.625}, {0.625, 0.875}}};

// The colour of pixel (x, y) as floats: bytes for rgba8, values for rgba32f.
std::array<float, 4> color_at(const refraster::Framebuffer& fb, int x, int y);

// Bit for bit: -0 and 0 differ, and NaNs compare by their bits.
bool same_color(const std::array<float, 4>& a, const std::array<float, 4>& b);

// A primitive as a message names it: "draws[D] KIND N".
std::string where(const refraster::PrimitiveTrace& p);

// A colour as the text prints it: "255,0,0,255" for rgba8 (`is8`), the float values otherwise.
std::string color_text(const std::array<float, 4>& c, bool is8);

}  // namespace harness::explain_detail
