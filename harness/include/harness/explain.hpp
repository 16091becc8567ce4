// explain.hpp: why one pixel looks the way it does, and where the reference and a GL
// backend part.
//
// Implements: running the reference with its trace hook on one pixel, reading the GL
// backend's bytes there, a one-line verdict naming the first rule where the two can part (the
// tie rule when the pixel centre lies exactly on an edge whose ownership decides it; snapping
// when an edge passes within a subpixel step; the clipper when a clipped primitive is
// involved; depth or colour arithmetic when coverage agrees), and three renderings of it all:
// text, JSON, and an SVG of the neighbourhood at subpixel zoom (pixel grid, centres, the
// snapped edges, covered pixels in their colours, tie-breaks ringed) for teaching.
//
// Deliberately does not: know which primitive the GL backend drew at the pixel; the verdict
// reasons from the reference's trace and the two results.
#pragma once

#include <optional>
#include <string>

#include "harness/backend.hpp"
#include "harness/scene.hpp"
#include "refraster/trace.hpp"

namespace harness {

struct Explanation {
    refraster::PixelTrace trace;
    refraster::Framebuffer reference_image;
    std::array<float, 4> reference_color{};
    std::optional<std::uint32_t> reference_depth;
    std::optional<RenderResult> backend;  // the GL render, when one was asked for
    std::array<float, 4> backend_color{};
    std::optional<std::uint32_t> backend_depth;
    bool agree = true;
    std::string verdict;
    std::string rule;  // "tie rule", "snapping", "clipper", "depth", "colour", "none"
};

// Throws std::runtime_error when the pixel lies outside the target or the reference cannot
// render the scene.
Explanation explain_pixel(const Scene& scene, const refraster::Profile& profile, int x, int y, Backend* backend);

std::string explanation_text(const Explanation& e);
std::string explanation_json(const Explanation& e);
// The neighbourhood of the pixel, `radius` pixels around it, drawn from the reference.
std::string explanation_svg(const Explanation& e, int radius = 4);

}  // namespace harness
