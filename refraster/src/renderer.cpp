#include "refraster/renderer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

namespace refraster {
namespace {

// glClearDepth stores RNE(double(z) * (2^bits - 1)), computed in double: measured for z24
// (mesa-22.3-rules.md 11.1), the same packing for z16 (util_pack_z in
// gallium/auxiliary/util/u_pack_color.h). z32f stores the float itself.
std::uint32_t clear_depth_value(DepthFormat f, float z) {
    const double zd = static_cast<double>(z);
    switch (f) {
        case DepthFormat::Z16: return static_cast<std::uint32_t>(std::nearbyint(zd * 65535.0));
        case DepthFormat::Z24: return static_cast<std::uint32_t>(std::nearbyint(zd * 16777215.0));
        case DepthFormat::Z32f: return std::bit_cast<std::uint32_t>(z);
        case DepthFormat::None: return 0;
    }
    return 0;
}

// Clears the whole target (scissor off, every mask on). A unorm8 clear colour is exact only
// when c * 255 is an integer after clamping to [0, 1]; the driver's rounding of other values
// is not yet established, so they are refused rather than guessed.
RenderOutcome clear(const DrawList& list, Framebuffer& out) {
    const auto& c = list.clear.color;
    if (list.target.color == ColorFormat::Rgba8) {
        std::array<std::uint8_t, 4> bytes{};
        for (std::size_t k = 0; k < 4; ++k) {
            const float v = std::clamp(c[k], 0.0f, 1.0f) * 255.0f;
            if (v != std::floor(v)) {
                return {RenderStatus::NotSupported,
                        "clear colour components must be multiples of 1/255 until unorm8 clear "
                        "rounding is implemented"};
            }
            bytes[k] = static_cast<std::uint8_t>(v);
        }
        for (std::size_t i = 0; i < out.pixel_count(); ++i) {
            std::copy(bytes.begin(), bytes.end(), out.color8.begin() + static_cast<std::ptrdiff_t>(i * 4));
        }
    } else {
        for (std::size_t i = 0; i < out.pixel_count(); ++i) {
            std::copy(c.begin(), c.end(), out.color32f.begin() + static_cast<std::ptrdiff_t>(i * 4));
        }
    }
    std::fill(out.depth.begin(), out.depth.end(), clear_depth_value(list.target.depth, list.clear.depth));
    return {};
}

}  // namespace

std::size_t primitive_count(PrimitiveType p, std::size_t n) {
    switch (p) {
        case PrimitiveType::Points: return n;
        case PrimitiveType::Lines: return n / 2;
        case PrimitiveType::LineStrip: return n >= 2 ? n - 1 : 0;
        case PrimitiveType::LineLoop: return n >= 2 ? n : 0;
        case PrimitiveType::Triangles: return n / 3;
        case PrimitiveType::TriangleStrip:
        case PrimitiveType::TriangleFan: return n >= 3 ? n - 2 : 0;
    }
    return 0;
}

RenderOutcome render(const DrawList& list, Framebuffer& out) {
    out = Framebuffer(list.target.width, list.target.height, list.target.color,
                      list.target.depth);
    if (list.target.samples != 1) {
        return {RenderStatus::NotSupported, "multisampled targets are not implemented yet"};
    }
    if (auto c = clear(list, out); c.status != RenderStatus::Ok) return c;
    for (std::size_t i = 0; i < list.draws.size(); ++i) {
        const Draw& d = list.draws[i];
        if (primitive_count(d.primitive, d.element_count()) == 0) continue;
        return {RenderStatus::NotSupported,
                "the reference rasterizer does not draw " + std::string(to_string(d.primitive)) +
                    " yet (draws[" + std::to_string(i) + "])"};
    }
    return {};
}

}  // namespace refraster
