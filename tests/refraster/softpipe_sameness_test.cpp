// The softpipe model's fast path gives the model's bytes: random scenes rendered under the
// profile softpipe-22.3 through the model (KernelPath::Model: softpipe's tile cache as it
// copies whole tiles, the clipper's emulated flushes) and through every other kernel path this
// CPU runs with 1, 2 and 3 threads (the lazy tile cache, softpipe_lazy_tiles.hpp; the fast
// quad kernel, softpipe_fast_fragment.cpp; the vertex stage under the CPU's flush modes),
// compared bit for bit (colour, depth and owners).
//
// The scenes mix what the tile cache decides: targets wider than five tiles or taller than ten
// (two tiles then share one of the 50 slots, so tiles are evicted and their floats quantised
// between draws), blending over those quantised and raw floats (clear colours beyond [0, 1]
// included), rgba32f targets, several draws a scene, fill rules (whose stencil clear writes
// every tile back) and line and point rules of the other family (a draw of the snapped model
// in between); and what the kernel decides: every shade model, texture filter, wrap and
// environment (256x256 levels repeated across seams where softpipe's texture tile cache
// aliases: the fast path's bilinear shortcut), point sprites, every depth format and function
// (the z16 fast path among them), scissors, clipped and culled triangles, denormal positions
// and colours, and flushing on and off.
//
// Seeds: 1, 2 and REFRASTER_TEST_SEED (3 unless set). A longer run is one command:
//   REFRASTER_SAMENESS_SCENES=2000 REFRASTER_TEST_SEED=7 build/bin/core_tests
//       --gtest_filter='Seeds/SoftpipeSameness*' (one line)
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "refraster/framebuffer.hpp"
#include "refraster/profile.hpp"
#include "refraster/renderer.hpp"
#include "sameness_support.hpp"
#include "stages/output_merge.hpp"

namespace {

using refraster::ColorFormat;
using refraster::DepthFormat;
using refraster::KernelPath;

using sameness::ci_seed;
using sameness::scene_count;

class SoftpipeSceneMaker : sameness::RandomChoices {
  public:
    explicit SoftpipeSceneMaker(std::uint64_t seed) : RandomChoices(seed), seams_(seed + 1) {}

    // scene(), and for one scene in three a 256x256 base level whose textured draws repeat
    // in both directions half the time: the fast path's bilinear repeat shortcut
    // (softpipe_sampler.cpp, SoftpipeSampler::linear) against the model's tile cache
    // emulation, on a level where a repeat seam makes two fetches of one sample alias (tiles
    // (a + 1, 7) and (a, 0), or (0, b) and (7, b + 1), share an entry). Drawn from a second
    // generator, so scene() makes the same scenes as before.
    refraster::DrawList scene_with_seams() {
        refraster::DrawList l = scene();
        if (seams_() % 3 != 0) return l;
        refraster::TextureImage img;
        img.width = img.height = 256;
        img.rgba.resize(std::size_t{256} * 256 * 4);
        for (auto& b : img.rgba) b = static_cast<std::uint8_t>(seams_());
        l.textures.front().levels = {std::move(img)};
        for (auto& d : l.draws) {
            if (d.state.texture && seams_() % 2 == 0) {
                d.state.texture->wrap_s = refraster::TextureWrap::Repeat;
                d.state.texture->wrap_t = refraster::TextureWrap::Repeat;
            }
        }
        return l;
    }

    refraster::DrawList scene() {
        refraster::DrawList l;
        std::uint32_t w = 1 + pick(90);
        std::uint32_t h = 1 + pick(90);
        switch (pick(4)) {
            case 0:  // wide: tiles (5, 0) and (0, 1) share a slot
                w = 330 + pick(300);
                h = 70 + pick(120);
                break;
            case 1:  // tall and narrow: tiles 0 and 10 of a column share a slot
                w = 1 + pick(140);
                h = 650 + pick(200);
                break;
            default:
                break;
        }
        l.target = {w, h, pick(4) == 0 ? ColorFormat::Rgba32f : ColorFormat::Rgba8,
                    static_cast<DepthFormat>(pick(4)), 1u};
        l.clear.color = {uniform(-0.2f, 1.2f), uniform(0, 1), edge_value(0, 1), uniform(0, 1)};
        l.clear.depth = pick(6) == 0 ? 1e-40f : uniform(0, 1);
        refraster::Texture tex;
        refraster::TextureImage img;
        img.width = pick(3) == 0 ? 1u << pick(7) : 1 + pick(40);
        img.height = pick(3) == 0 ? 1u << pick(7) : 1 + pick(40);
        for (std::uint32_t i = 0; i < img.width * img.height * 4; ++i)
            img.rgba.push_back(static_cast<std::uint8_t>(pick(256)));
        tex.levels.push_back(std::move(img));
        tex.generate_mipmaps = pick(4) != 0;
        l.textures.push_back(std::move(tex));
        const int draws = 1 + static_cast<int>(pick(6));
        for (int i = 0; i < draws; ++i) l.draws.push_back(draw(l.target));
        return l;
    }

  private:
    refraster::Draw draw(const refraster::Target& target) {
        refraster::Draw d;
        static constexpr refraster::PrimitiveType kTypes[] = {
            refraster::PrimitiveType::Triangles,   refraster::PrimitiveType::Triangles,
            refraster::PrimitiveType::Triangles,   refraster::PrimitiveType::TriangleStrip,
            refraster::PrimitiveType::TriangleFan, refraster::PrimitiveType::Lines,
            refraster::PrimitiveType::LineStrip,   refraster::PrimitiveType::Points,
            refraster::PrimitiveType::Polygon};
        d.primitive = kTypes[pick(9)];
        auto& s = d.state;
        s.viewport = {0, 0, static_cast<std::int32_t>(target.width),
                      static_cast<std::int32_t>(target.height)};
        if (pick(4) == 0) {
            s.viewport = {static_cast<std::int32_t>(pick(target.width)) - 20,
                          static_cast<std::int32_t>(pick(target.height)) - 20,
                          static_cast<std::int32_t>(1 + pick(2 * target.width)),
                          static_cast<std::int32_t>(1 + pick(2 * target.height))};
        }
        if (pick(5) == 0) {
            s.scissor = refraster::Rect{static_cast<std::int32_t>(pick(target.width)),
                                        static_cast<std::int32_t>(pick(target.height)),
                                        static_cast<std::int32_t>(pick(target.width + 1)),
                                        static_cast<std::int32_t>(pick(target.height + 1))};
        }
        s.shade = static_cast<refraster::ShadeModel>(pick(3));
        // Blending more often than not: it reads the tile cache's floats.
        s.blend = static_cast<refraster::BlendPreset>(pick(5) == 0 ? 0 : 1 + pick(2));
        if (pick(4) != 0) s.depth_test = static_cast<refraster::CompareFunc>(pick(8));
        s.depth_write = pick(5) != 0;
        s.cull = static_cast<refraster::CullMode>(pick(6) < 3 ? 0 : pick(4));
        s.front_face = static_cast<refraster::FrontFace>(pick(2));
        s.provoking_vertex = static_cast<refraster::ProvokingVertex>(pick(2));
        if (pick(8) == 0) s.polygon_mode = static_cast<refraster::PolygonMode>(1 + pick(2));
        if (pick(5) == 0)
            s.polygon_offset = refraster::PolygonOffset{uniform(-2, 2), uniform(-4, 4)};
        if (pick(3) == 0) s.line_width = 1.0f + static_cast<float>(pick(6));
        if (pick(3) == 0) s.point_size = 1.0f + static_cast<float>(pick(9));
        if (d.primitive == refraster::PrimitiveType::Polygon && pick(2) == 0)
            s.fill_rule = static_cast<refraster::FillRule>(pick(2));
        d.vertices.attributes = {{"color", 4}};
        const bool textured = pick(3) == 0;
        if (textured) {
            d.vertices.attributes.push_back({"texcoord", 4});
            refraster::TextureState ts;
            ts.min_filter = static_cast<refraster::TextureFilter>(pick(6));
            ts.mag_filter = static_cast<refraster::TextureFilter>(pick(2));
            ts.wrap_s = static_cast<refraster::TextureWrap>(pick(4));
            ts.wrap_t = static_cast<refraster::TextureWrap>(pick(4));
            ts.border_color = {uniform(-0.2f, 1.2f), uniform(0, 1), uniform(0, 1),
                               edge_value(0, 1)};
            ts.env = static_cast<refraster::TextureEnv>(pick(2));
            ts.coord_replace = pick(3) == 0;
            ts.point_coord_origin = static_cast<refraster::PointCoordOrigin>(pick(2));
            s.texture = ts;
        }
        // Small primitives around a point, or large ones across (and beyond) the viewport.
        const bool large = pick(3) == 0;
        const int vertices = 3 * (1 + static_cast<int>(pick(16)));
        float cx = uniform(-1.1f, 1.1f), cy = uniform(-1.1f, 1.1f);
        for (int v = 0; v < vertices; ++v) {
            if (v % 3 == 0 && pick(2) == 0) {
                cx = uniform(-1.1f, 1.1f);
                cy = uniform(-1.1f, 1.1f);
            }
            const float spread = large ? 2.5f : uniform(0.005f, 0.4f);
            const float ww = pick(10) == 0 ? uniform(-0.5f, 0.2f) : uniform(0.3f, 3.0f);
            const float x = cx + uniform(-spread, spread);
            const float y = cy + uniform(-spread, spread);
            const auto tiny_or = [&](float value) {
                return pick(24) == 0 ? (pick(2) == 0 ? 3e-39f : -2e-40f) : value;
            };
            d.vertices.data.insert(
                d.vertices.data.end(),
                {tiny_or(x * ww), tiny_or(y * ww), edge_value(-1.05f, 1.05f) * ww, ww,
                 edge_value(-0.3f, 1.3f), edge_value(-0.3f, 1.3f), edge_value(-0.3f, 1.3f),
                 edge_value(-0.3f, 1.3f)});
            if (textured) {
                d.vertices.data.insert(d.vertices.data.end(),
                                       {edge_value(-3.0f, 3.0f), edge_value(-3.0f, 3.0f), 0.0f,
                                        pick(6) == 0 ? uniform(0.5f, 2.0f) : 1.0f});
            }
        }
        return d;
    }

    std::mt19937_64 seams_;
};

class SoftpipeSameness : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(SoftpipeSameness, EveryPathAndThreadCountGivesTheModelsBytes) {
    const std::uint64_t seed = GetParam();
    SoftpipeSceneMaker maker(seed);
    sameness::expect_every_path_gives_the_models_bytes(
        seed, scene_count(), [&] { return maker.scene_with_seams(); },
        [](int n) {
            refraster::RenderOptions model;
            model.profile = refraster::builtin_profile("softpipe-22.3");
            model.kernels = KernelPath::Model;
            model.record_owners = n % 3 == 0;
            model.profile.gl.flush_denormals = n % 7 != 0;
            // Now and then a line or point rule of the snapped family: its draws write the
            // surface between the tile cache's write-backs.
            if (n % 5 == 1) model.profile.gl.line_rule = refraster::LineRule::Parallelogram;
            if (n % 5 == 2) model.profile.gl.point_rule = refraster::PointRule::Square;
            if (n % 4 == 3) model.profile.gl.depth_rounding = refraster::Rounding::Nearest;
            return model;
        });
}

INSTANTIATE_TEST_SUITE_P(Seeds, SoftpipeSameness, ::testing::Values(1u, 2u, ci_seed()));

// What the lazy tile cache relies on: every byte survives the model's load
// (b * (1.0f / 255.0f)) and write-back (float_to_ubyte) unchanged.
TEST(SoftpipeLazyTiles, EveryByteSurvivesLoadAndWriteBack) {
    for (unsigned b = 0; b < 256; ++b) {
        const float loaded = static_cast<float>(b) * (1.0f / 255.0f);
        EXPECT_EQ(refraster::detail::color_to_unorm8(loaded), b) << b;
    }
}

}  // namespace
