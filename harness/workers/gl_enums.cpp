// gl_enums.cpp: see gl_enums.hpp.
#define GL_GLEXT_PROTOTYPES 1
#include "gl_enums.hpp"

#include <GL/glext.h>

namespace harness::gl {

using refraster::ColorFormat;
using refraster::DepthFormat;

GLenum color_internal_format(ColorFormat f) {
    return f == ColorFormat::Rgba8 ? GL_RGBA8 : GL_RGBA32F;
}

GLenum depth_internal_format(DepthFormat f, bool stencil) {
    if (stencil && f == DepthFormat::Z32f) return GL_DEPTH32F_STENCIL8;
    if (stencil && f != DepthFormat::Z16) return GL_DEPTH24_STENCIL8;
    switch (f) {
        case DepthFormat::Z16:
            return GL_DEPTH_COMPONENT16;
        case DepthFormat::Z32f:
            return GL_DEPTH_COMPONENT32F;
        case DepthFormat::Z24:
        case DepthFormat::None:
            return GL_DEPTH_COMPONENT24;
    }
    return GL_DEPTH_COMPONENT24;
}

GLenum primitive_mode(refraster::PrimitiveType p) {
    using refraster::PrimitiveType;
    switch (p) {
        case PrimitiveType::Points:
            return GL_POINTS;
        case PrimitiveType::Lines:
            return GL_LINES;
        case PrimitiveType::LineStrip:
            return GL_LINE_STRIP;
        case PrimitiveType::LineLoop:
            return GL_LINE_LOOP;
        case PrimitiveType::Triangles:
            return GL_TRIANGLES;
        case PrimitiveType::TriangleStrip:
            return GL_TRIANGLE_STRIP;
        case PrimitiveType::TriangleFan:
            return GL_TRIANGLE_FAN;
        case PrimitiveType::Polygon:
            return GL_POLYGON;
    }
    return GL_TRIANGLES;
}

GLenum compare_func(refraster::CompareFunc f) {
    using refraster::CompareFunc;
    switch (f) {
        case CompareFunc::Never:
            return GL_NEVER;
        case CompareFunc::Less:
            return GL_LESS;
        case CompareFunc::Equal:
            return GL_EQUAL;
        case CompareFunc::Lequal:
            return GL_LEQUAL;
        case CompareFunc::Greater:
            return GL_GREATER;
        case CompareFunc::NotEqual:
            return GL_NOTEQUAL;
        case CompareFunc::Gequal:
            return GL_GEQUAL;
        case CompareFunc::Always:
            return GL_ALWAYS;
    }
    return GL_ALWAYS;
}

GLenum polygon_mode(refraster::PolygonMode m) {
    using refraster::PolygonMode;
    switch (m) {
        case PolygonMode::Fill:
            return GL_FILL;
        case PolygonMode::Line:
            return GL_LINE;
        case PolygonMode::Point:
            return GL_POINT;
    }
    return GL_FILL;
}

GLint texture_filter(refraster::TextureFilter f) {
    using refraster::TextureFilter;
    switch (f) {
        case TextureFilter::Nearest:
            return GL_NEAREST;
        case TextureFilter::Linear:
            return GL_LINEAR;
        case TextureFilter::NearestMipmapNearest:
            return GL_NEAREST_MIPMAP_NEAREST;
        case TextureFilter::LinearMipmapNearest:
            return GL_LINEAR_MIPMAP_NEAREST;
        case TextureFilter::NearestMipmapLinear:
            return GL_NEAREST_MIPMAP_LINEAR;
        case TextureFilter::LinearMipmapLinear:
            return GL_LINEAR_MIPMAP_LINEAR;
    }
    return GL_LINEAR;
}

GLint texture_wrap(refraster::TextureWrap w) {
    using refraster::TextureWrap;
    switch (w) {
        case TextureWrap::Repeat:
            return GL_REPEAT;
        case TextureWrap::ClampToEdge:
            return GL_CLAMP_TO_EDGE;
        case TextureWrap::MirroredRepeat:
            return GL_MIRRORED_REPEAT;
        case TextureWrap::ClampToBorder:
            return GL_CLAMP_TO_BORDER;
    }
    return GL_REPEAT;
}

}  // namespace harness::gl
