// output_merge.cpp: the colour write for callers outside the compiled kernels, and the clear
// colour's conversion (output_merge.hpp).
#include "stages/output_merge.hpp"

namespace refraster::detail {

std::uint8_t clear_to_unorm8(float c) {
    if (!(c > 0.0f)) return 0;  // NaN too
    if (c >= 1.0f) return 255;
    const float t = c * (255.0f / 256.0f) + 32768.0f;
    return static_cast<std::uint8_t>(std::bit_cast<std::uint32_t>(t) & 0xffu);
}

namespace {

template <ColorFormat C>
void write_color_as(const Draw& draw, Framebuffer& fb, std::size_t i, const std::array<float, 4>& c,
                    const Fp& fp) {
    const auto s = source_color<C>(false, c);
    switch (draw.state.blend) {
        case BlendPreset::None:
            store_color<C, BlendPreset::None>(fb, i, s, fp);
            break;
        case BlendPreset::Alpha:
            store_color<C, BlendPreset::Alpha>(fb, i, s, fp);
            break;
        case BlendPreset::Add:
            store_color<C, BlendPreset::Add>(fb, i, s, fp);
            break;
    }
}

}  // namespace

void write_fragment_color(const Draw& draw, Framebuffer& fb, std::size_t i,
                          const std::array<float, 4>& c, bool flush_denormals) {
    const Fp fp{flush_denormals};
    if (fb.color_format == ColorFormat::Rgba8) {
        write_color_as<ColorFormat::Rgba8>(draw, fb, i, c, fp);
    } else {
        write_color_as<ColorFormat::Rgba32f>(draw, fb, i, c, fp);
    }
}

}  // namespace refraster::detail
