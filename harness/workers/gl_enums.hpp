// gl_enums.hpp: the scene's formats, primitives and state as the GL enums a worker passes to
// GL. Each map covers every value of its refraster enum.
#pragma once

#include <GL/gl.h>

#include "refraster/draw.hpp"
#include "refraster/framebuffer.hpp"

namespace harness::gl {

GLenum color_internal_format(refraster::ColorFormat f);

// A target without depth still gets z24: see the spec, a depth-less colour buffer can change
// llvmpipe's clipping path. With `stencil` (a draw has a fill rule) a packed depth-stencil
// format.
GLenum depth_internal_format(refraster::DepthFormat f, bool stencil);

GLenum primitive_mode(refraster::PrimitiveType p);
GLenum compare_func(refraster::CompareFunc f);
GLenum polygon_mode(refraster::PolygonMode m);
GLint texture_filter(refraster::TextureFilter f);
GLint texture_wrap(refraster::TextureWrap w);

}  // namespace harness::gl
