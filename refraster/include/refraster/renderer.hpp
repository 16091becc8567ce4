// renderer.hpp: the reference rasterizer's entry point.
//
// Implements: clearing the target and running every draw of a DrawList in order.
//
// Deliberately does not (yet): rasterize primitives. Until the coverage rules land, every draw
// with at least one complete primitive is refused with RenderStatus::NotSupported, never
// answered with a wrong image. A draw that assembles no primitive (empty, or a leftover
// vertex) is a correct no-op and is accepted.
#pragma once

#include <string>

#include "refraster/draw.hpp"
#include "refraster/framebuffer.hpp"

namespace refraster {

enum class RenderStatus : std::uint8_t { Ok, NotSupported };

struct RenderOutcome {
    RenderStatus status = RenderStatus::Ok;
    std::string message;  // why, when status != Ok
};

// Number of complete primitives a draw assembles under GL's rules (OpenGL 4.6 compatibility
// profile, section 10.1 "Primitive Types"): a leftover vertex draws nothing.
std::size_t primitive_count(PrimitiveType p, std::size_t vertex_count);

RenderOutcome render(const DrawList& list, Framebuffer& out);

}  // namespace refraster
