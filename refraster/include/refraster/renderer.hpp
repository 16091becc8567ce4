// renderer.hpp: the reference rasterizer's entry point.
//
// Implements: clearing the target and drawing every draw of a DrawList in order under a
// Profile: triangle primitive assembly (triangles, strips, fans, with GL's provoking-vertex
// conventions in the vertex order Mesa's draw module emits), clipping, culling, coverage
// (snapped, or exact for the gl-exact profile), and colour writes of constant colours (flat
// shading, or smooth and noperspective shading of one colour across a draw).
//
// Deliberately does not (yet), answering RenderStatus::NotSupported instead of a guess:
// lines and points, non-fill polygon modes, interpolated colours, depth testing, blending,
// multisampling, and unorm8 clear colours that are not multiples of 1/255.
#pragma once

#include <string>

#include "refraster/draw.hpp"
#include "refraster/framebuffer.hpp"
#include "refraster/profile.hpp"
#include "refraster/trace.hpp"

namespace refraster {

enum class RenderStatus : std::uint8_t { Ok, NotSupported };

struct RenderOutcome {
    RenderStatus status = RenderStatus::Ok;
    std::string message;  // why, when status != Ok
};

struct RenderOptions {
    Profile profile;
    // When set, render() records every decision about pixel (trace->x, trace->y).
    PixelTrace* trace = nullptr;
    // Fill Framebuffer::owner: which primitive wrote each pixel last.
    bool record_owners = false;
};

// Number of complete primitives a draw assembles under GL's rules (OpenGL 4.6 compatibility
// profile, section 10.1 "Primitive Types"): a leftover vertex draws nothing.
std::size_t primitive_count(PrimitiveType p, std::size_t vertex_count);

// Whether this CPU fuses as gallivm would (FMA present); FmaMode::Auto resolves to this.
bool host_has_fma();

RenderOutcome render(const DrawList& list, const RenderOptions& options, Framebuffer& out);
inline RenderOutcome render(const DrawList& list, Framebuffer& out) {
    return render(list, RenderOptions{}, out);
}

}  // namespace refraster
