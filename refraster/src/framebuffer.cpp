#include "refraster/framebuffer.hpp"

namespace refraster {

Framebuffer::Framebuffer(std::uint32_t w, std::uint32_t h, ColorFormat cf, DepthFormat df,
                         std::uint32_t sample_count)
    : width(w), height(h), color_format(cf), depth_format(df), samples(sample_count) {
    const std::size_t n = pixel_count() * samples;
    if (cf == ColorFormat::Rgba8) {
        color8.assign(n * 4, 0);
    } else {
        color32f.assign(n * 4, 0.0f);
    }
    if (df != DepthFormat::None) depth.assign(n, 0);
}

}  // namespace refraster
