#include "refraster/framebuffer.hpp"

namespace refraster {

Framebuffer::Framebuffer(std::uint32_t w, std::uint32_t h, ColorFormat cf, DepthFormat df)
    : width(w), height(h), color_format(cf), depth_format(df) {
    const std::size_t n = pixel_count();
    if (cf == ColorFormat::Rgba8) {
        color8.assign(n * 4, 0);
    } else {
        color32f.assign(n * 4, 0.0f);
    }
    if (df != DepthFormat::None) depth.assign(n, 0);
}

}  // namespace refraster
