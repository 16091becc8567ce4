// Every fast path gives the model's bytes: random scenes and states rendered through the scalar
// model (quad packets, baseline instructions, one thread) and through every other kernel path
// this CPU runs (scalar over row blocks, AVX2, AVX-512) with 1, 2 and 3 threads, compared bit
// for bit (colour, depth and owners).
//
// The scenes mix what the fast paths decide differently: boxes below and above 64 pixels (the
// small-box path and the tiles), targets whose width is not a multiple of a vector and whose
// height spans several 64-row bands, clipped and culled primitives, scissors, lines, points and
// unfilled polygons, every shade model, depth format and function, blend and colour format, and
// values at the edge of float (denormal colours, depths and offsets, which the vector kernels
// flush in hardware and the model by emulation).
//
// Seeds: 1, 2 and REFRASTER_TEST_SEED (3 unless set). A longer run is one command:
//   REFRASTER_SAMENESS_SCENES=5000 REFRASTER_TEST_SEED=7 build/bin/core_tests
//       --gtest_filter='Seeds/Sameness*' (one line)
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "refraster/framebuffer.hpp"
#include "refraster/renderer.hpp"
#include "sameness_support.hpp"

namespace {

using refraster::ColorFormat;
using refraster::DepthFormat;
using refraster::KernelPath;

using sameness::ci_seed;
using sameness::first_difference;
using sameness::scene_count;

class SceneMaker : sameness::RandomChoices {
  public:
    // Textured: every draw samples the texture, into single-sample rgba8 targets (the vector
    // sampler's draws, vector_texture_body.hpp), mostly with the 8-bit path's wraps.
    // Multisample: every target 4x, mostly rgba8 (the vector 4x kernels and 4x row blocks,
    // vector_kernel_body.hpp shade_rows_4x, traverse.hpp convex_row_blocks_4x).
    // LinesAndPoints: every draw lines (width 1 mostly, at every angle, long and short) or
    // points (sizes 1 to 72, some not whole), mostly into single-sample targets (the row
    // kernels' pixels packed across rows, vector_kernel_body.hpp shade_packed).
    enum class Kind { Mixed, Textured, Multisample, LinesAndPoints };
    explicit SceneMaker(std::uint64_t seed, Kind kind = Kind::Mixed)
        : RandomChoices(seed), seed_(seed), textured_(kind == Kind::Textured), kind_(kind) {}
    std::uint64_t seed() const { return seed_; }

    refraster::DrawList scene() {
        refraster::DrawList l;
        const bool big = pick(3) == 0;
        const auto w = static_cast<std::uint32_t>(big ? 140 + pick(200) : 1 + pick(90));
        const auto h = static_cast<std::uint32_t>(big ? 130 + pick(200) : 1 + pick(90));
        l.target = {w, h, pick(4) == 0 ? ColorFormat::Rgba32f : ColorFormat::Rgba8,
                    static_cast<DepthFormat>(pick(4)), pick(8) == 0 ? 4u : 1u};
        if (textured_) {
            l.target.color = ColorFormat::Rgba8;
            l.target.samples = 1;
        }
        if (kind_ == Kind::Multisample) {
            l.target.color = pick(6) == 0 ? ColorFormat::Rgba32f : ColorFormat::Rgba8;
            l.target.samples = 4;
        }
        if (kind_ == Kind::LinesAndPoints) l.target.samples = pick(6) == 0 ? 4u : 1u;
        l.clear.color = {uniform(0, 1), uniform(0, 1), uniform(0, 1), uniform(0, 1)};
        l.clear.depth = pick(6) == 0 ? 1e-40f : uniform(0, 1);
        // A texture some draws sample (texture.cpp: every filter and wrap, both paths).
        refraster::Texture tex;
        refraster::TextureImage img;
        // Sizes of any kind, and powers of two up to 64 (the repeat wrap's other code, and
        // more mip levels for the vector sampler's per-lane levels).
        img.width = pick(3) == 0 ? 1u << pick(7) : 1 + pick(20);
        img.height = pick(3) == 0 ? 1u << pick(7) : 1 + pick(20);
        for (std::uint32_t i = 0; i < img.width * img.height * 4; ++i)
            img.rgba.push_back(static_cast<std::uint8_t>(pick(256)));
        tex.levels.push_back(std::move(img));
        tex.generate_mipmaps = true;
        l.textures.push_back(std::move(tex));
        const int draws = 1 + static_cast<int>(pick(5));
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
            refraster::PrimitiveType::LineStrip,   refraster::PrimitiveType::Points};
        d.primitive = kTypes[pick(8)];
        auto& s = d.state;
        s.viewport = {0, 0, static_cast<std::int32_t>(target.width),
                      static_cast<std::int32_t>(target.height)};
        if (pick(4) == 0) {
            s.viewport = {static_cast<std::int32_t>(pick(target.width)) - 20,
                          static_cast<std::int32_t>(pick(target.height)) - 20,
                          static_cast<std::int32_t>(1 + pick(2 * target.width)),
                          static_cast<std::int32_t>(1 + pick(2 * target.height))};
        }
        if (pick(4) == 0) {
            s.scissor = refraster::Rect{static_cast<std::int32_t>(pick(target.width)),
                                        static_cast<std::int32_t>(pick(target.height)),
                                        static_cast<std::int32_t>(pick(target.width + 1)),
                                        static_cast<std::int32_t>(pick(target.height + 1))};
        }
        s.shade = static_cast<refraster::ShadeModel>(pick(3));
        s.blend = static_cast<refraster::BlendPreset>(pick(3));
        if (pick(4) != 0) s.depth_test = static_cast<refraster::CompareFunc>(pick(8));
        s.depth_write = pick(5) != 0;
        s.cull = static_cast<refraster::CullMode>(pick(6) < 3 ? 0 : pick(4));
        s.front_face = static_cast<refraster::FrontFace>(pick(2));
        s.provoking_vertex = static_cast<refraster::ProvokingVertex>(pick(2));
        if (pick(8) == 0) s.polygon_mode = static_cast<refraster::PolygonMode>(1 + pick(2));
        if (pick(4) == 0)
            s.polygon_offset = refraster::PolygonOffset{uniform(-2, 2), uniform(-4, 4)};
        if (pick(3) == 0) s.line_width = 1.0f + static_cast<float>(pick(6));
        if (pick(3) == 0) s.point_size = 1.0f + static_cast<float>(pick(9));
        if (kind_ == Kind::LinesAndPoints) {
            static constexpr refraster::PrimitiveType kLinesAndPoints[] = {
                refraster::PrimitiveType::Lines,     refraster::PrimitiveType::Lines,
                refraster::PrimitiveType::LineStrip, refraster::PrimitiveType::LineLoop,
                refraster::PrimitiveType::Points,    refraster::PrimitiveType::Points};
            d.primitive = kLinesAndPoints[pick(6)];
            s.line_width = pick(2) == 0 ? 1.0f : 1.0f + static_cast<float>(pick(12));
            s.point_size =
                pick(2) == 0 ? 1.0f + static_cast<float>(pick(72)) : uniform(0.5f, 20.0f);
            s.polygon_mode = refraster::PolygonMode::Fill;
        }
        s.multisample = pick(4) != 0;
        d.vertices.attributes = {{"color", 4}};
        const bool textured = textured_ || pick(4) == 0;
        if (textured) {
            d.vertices.attributes.push_back({"texcoord", 4});
            refraster::TextureState ts;
            ts.min_filter = static_cast<refraster::TextureFilter>(pick(6));
            ts.mag_filter = static_cast<refraster::TextureFilter>(pick(2));
            ts.wrap_s = static_cast<refraster::TextureWrap>(pick(4));
            ts.wrap_t = static_cast<refraster::TextureWrap>(pick(4));
            if (textured_ && pick(4) != 0) {
                // Repeat or clamp to edge: the 8-bit path.
                ts.wrap_s = pick(2) == 0 ? refraster::TextureWrap::Repeat
                                         : refraster::TextureWrap::ClampToEdge;
                ts.wrap_t = pick(2) == 0 ? refraster::TextureWrap::Repeat
                                         : refraster::TextureWrap::ClampToEdge;
            }
            ts.border_color = {uniform(-0.2f, 1.2f), uniform(0, 1), uniform(0, 1), uniform(0, 1)};
            ts.env = static_cast<refraster::TextureEnv>(pick(2));
            ts.coord_replace = pick(3) == 0;  // sprite coordinates where points are drawn
            ts.point_coord_origin = static_cast<refraster::PointCoordOrigin>(pick(2));
            s.texture = ts;
        }
        // Small primitives around a point, or large ones across (and beyond) the viewport.
        const bool large = pick(3) == 0 || (kind_ == Kind::LinesAndPoints && pick(2) == 0);
        const int vertices = 3 * (1 + static_cast<int>(pick(12)));
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
            // Now and then a denormal x or y (which the CPU's DAZ reads as zero on the fast
            // paths, and the model flushes by emulation).
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

    std::uint64_t seed_;
    bool textured_ = false;
    Kind kind_ = Kind::Mixed;
};

class Sameness : public ::testing::TestWithParam<std::uint64_t> {};

void expect_every_path_gives_the_models_bytes(SceneMaker& maker, int scenes);

TEST_P(Sameness, EveryPathAndThreadCountGivesTheModelsBytes) {
    SceneMaker maker(GetParam());
    expect_every_path_gives_the_models_bytes(maker, scene_count());
}

// Every draw textured: the vector sampler against the scalar one, filters, wraps, levels.
TEST_P(Sameness, TexturedDrawsGiveTheModelsBytes) {
    SceneMaker maker(GetParam() + 1000, SceneMaker::Kind::Textured);
    expect_every_path_gives_the_models_bytes(maker, scene_count() / 2);
}

// Every draw lines or points: thin lines at every angle (rows of one or two pixels, packed
// across rows by the vector kernels), wide lines, points of many sizes, scissors, bands and
// threads.
TEST_P(Sameness, LinesAndPointsGiveTheModelsBytes) {
    SceneMaker maker(GetParam() + 3000, SceneMaker::Kind::LinesAndPoints);
    expect_every_path_gives_the_models_bytes(maker, scene_count() / 2);
}

// Every target 4x: per-sample row blocks and the vector 4x kernels against the quad packets of
// the scalar model, the scissor leak of multisampled boxes, bands and threads.
TEST_P(Sameness, MultisampleTargetsGiveTheModelsBytes) {
    SceneMaker maker(GetParam() + 2000, SceneMaker::Kind::Multisample);
    expect_every_path_gives_the_models_bytes(maker, scene_count() / 2);
}

INSTANTIATE_TEST_SUITE_P(Seeds, Sameness, ::testing::Values(1u, 2u, ci_seed()));

void expect_every_path_gives_the_models_bytes(SceneMaker& maker, int scenes) {
    sameness::expect_every_path_gives_the_models_bytes(
        maker.seed(), scenes, [&] { return maker.scene(); },
        [](int n) {
            refraster::RenderOptions model;
            model.kernels = KernelPath::Model;
            model.record_owners = n % 3 == 0;
            model.profile.gl.viewport_fma =
                n % 5 == 0 ? refraster::FmaMode::Off : refraster::FmaMode::On;
            model.profile.gl.flush_denormals = n % 7 != 0;
            return model;
        });
}

// The comparison can fail: a render under another tie rule differs from the model somewhere
// over the same scenes.
TEST(SamenessSensitivity, AnotherRuleIsDetected) {
    SceneMaker maker(11);
    int differing = 0;
    for (int n = 0; n < 40; ++n) {
        const refraster::DrawList l = maker.scene();
        refraster::RenderOptions model;
        model.kernels = KernelPath::Model;
        refraster::RenderOptions other;
        other.kernels = KernelPath::Fastest;
        other.threads = 2;
        other.profile.gl.tie_rule = refraster::TieRule::RightTop;
        refraster::Framebuffer a, b;
        ASSERT_EQ(refraster::render(l, model, a).status, refraster::RenderStatus::Ok);
        ASSERT_EQ(refraster::render(l, other, b).status, refraster::RenderStatus::Ok);
        differing += !first_difference(a, b).empty();
    }
    EXPECT_GT(differing, 0);
}

}  // namespace
