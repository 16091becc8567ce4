#include "refraster/draw.hpp"

namespace refraster {

std::string_view to_string(PrimitiveType p) {
    switch (p) {
        case PrimitiveType::Points:
            return "points";
        case PrimitiveType::Lines:
            return "lines";
        case PrimitiveType::LineStrip:
            return "line_strip";
        case PrimitiveType::LineLoop:
            return "line_loop";
        case PrimitiveType::Triangles:
            return "triangles";
        case PrimitiveType::TriangleStrip:
            return "triangle_strip";
        case PrimitiveType::TriangleFan:
            return "triangle_fan";
        case PrimitiveType::Polygon:
            return "polygon";
    }
    return "?";
}

std::string_view to_string(FillRule r) {
    return r == FillRule::EvenOdd ? "evenodd" : "nonzero";
}

std::string_view to_string(ColorFormat f) {
    return f == ColorFormat::Rgba8 ? "rgba8" : "rgba32f";
}

std::string_view to_string(DepthFormat f) {
    switch (f) {
        case DepthFormat::None:
            return "none";
        case DepthFormat::Z16:
            return "z16";
        case DepthFormat::Z24:
            return "z24";
        case DepthFormat::Z32f:
            return "z32f";
    }
    return "?";
}

}  // namespace refraster
