// The fragment kernels compiled for a wider instruction set (FMA, SSE4.1; chosen at run time)
// give the bytes of the baseline kernels: random triangles under every shade model, depth
// format and function, blend preset, colour format and polygon offset, rendered both ways.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "refraster/framebuffer.hpp"
#include "refraster/renderer.hpp"

namespace {

using refraster::ColorFormat;

// Bit for bit: float colours compare by their bits, so that a NaN equals the same NaN.
bool same_bits(const refraster::Framebuffer& a, const refraster::Framebuffer& b) {
    if (a.color8 != b.color8 || a.depth != b.depth || a.color32f.size() != b.color32f.size())
        return false;
    for (std::size_t i = 0; i < a.color32f.size(); ++i) {
        if (std::bit_cast<std::uint32_t>(a.color32f[i]) !=
            std::bit_cast<std::uint32_t>(b.color32f[i]))
            return false;
    }
    return true;
}
using refraster::DepthFormat;

refraster::Draw random_draw(std::mt19937& rng) {
    std::uniform_real_distribution<float> pos(-1.3f, 1.3f);
    std::uniform_real_distribution<float> z(-1.0f, 1.0f);
    std::uniform_real_distribution<float> w(0.3f, 3.0f);
    std::uniform_real_distribution<float> col(-0.2f, 1.2f);
    refraster::Draw d;
    d.primitive = refraster::PrimitiveType::Triangles;
    d.state.viewport = {0, 0, 64, 64};
    d.vertices.attributes = {{"color", 4}};
    for (int v = 0; v < 3 * 8; ++v) {
        const float ww = w(rng);
        d.vertices.data.insert(d.vertices.data.end(), {pos(rng) * ww, pos(rng) * ww, z(rng) * ww,
                                                       ww, col(rng), col(rng), col(rng), col(rng)});
    }
    auto& s = d.state;
    s.shade = static_cast<refraster::ShadeModel>(rng() % 3);
    s.blend = static_cast<refraster::BlendPreset>(rng() % 3);
    if (rng() % 4 != 0) s.depth_test = static_cast<refraster::CompareFunc>(rng() % 8);
    s.depth_write = rng() % 5 != 0;
    if (rng() % 3 == 0) s.polygon_offset = refraster::PolygonOffset{1.5f, -2.0f};
    return d;
}

TEST(KernelVariants, WideKernelsGiveTheBaselineBytes) {
    std::mt19937 rng(12345);
    int compared = 0;
    for (int scene = 0; scene < 120; ++scene) {
        refraster::DrawList l;
        const auto depth = static_cast<DepthFormat>(rng() % 4);
        const auto color = rng() % 3 == 0 ? ColorFormat::Rgba32f : ColorFormat::Rgba8;
        l.target = {64, 64, color, depth, 1};
        l.clear.color = {0.1f, 0.2f, 0.3f, 0.4f};
        l.clear.depth = 0.75f;
        for (int d = 0; d < 6; ++d) l.draws.push_back(random_draw(rng));
        for (const bool fma : {true, false}) {
            for (const auto path : {refraster::KernelPath::Scalar, refraster::KernelPath::Avx2,
                                    refraster::KernelPath::Avx512}) {
                if (!refraster::kernel_path_available(path)) continue;
                refraster::RenderOptions wide;
                wide.profile.gl.viewport_fma =
                    fma ? refraster::FmaMode::On : refraster::FmaMode::Off;
                wide.kernels = path;
                refraster::RenderOptions base = wide;
                base.kernels = refraster::KernelPath::Model;
                refraster::Framebuffer a, b;
                ASSERT_EQ(refraster::render(l, wide, a).status, refraster::RenderStatus::Ok);
                ASSERT_EQ(refraster::render(l, base, b).status, refraster::RenderStatus::Ok);
                if (!same_bits(a, b)) {
                    std::size_t i = 0;
                    while (i < a.color8.size() && a.color8[i] == b.color8[i]) ++i;
                    std::size_t j = 0;
                    while (j < a.color32f.size() && std::bit_cast<std::uint32_t>(a.color32f[j]) ==
                                                        std::bit_cast<std::uint32_t>(b.color32f[j]))
                        ++j;
                    std::size_t k = 0;
                    while (k < a.depth.size() && a.depth[k] == b.depth[k]) ++k;
                    FAIL() << "scene " << scene << " fma " << fma << " path "
                           << refraster::to_string(path) << " colour8 at " << i << "/"
                           << a.color8.size() << " colour32f at " << j << "/" << a.color32f.size()
                           << (j < a.color32f.size()
                                   ? " (" + std::to_string(a.color32f[j]) + " vs " +
                                         std::to_string(b.color32f[j]) + ")"
                                   : std::string())
                           << " depth at " << k << "/" << a.depth.size();
                }
                // Something was drawn: the comparison is not of two cleared targets.
                refraster::Framebuffer cleared;
                refraster::DrawList empty = l;
                empty.draws.clear();
                ASSERT_EQ(refraster::render(empty, base, cleared).status,
                          refraster::RenderStatus::Ok);
                compared += !same_bits(cleared, b);
            }
        }
    }
    EXPECT_GT(compared, 200);
}

}  // namespace
