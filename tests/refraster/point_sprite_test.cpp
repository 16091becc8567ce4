// Point sprite coordinates through the whole reference (line_point.cpp, point_planes;
// docs/precision.md "Point sprites"): a point of side n over an n x n texture puts each texel's
// centre on one pixel centre, so nearest and bilinear sampling both show the texture itself,
// one texel a pixel, turned upside down for GL's upper-left origin. Expected values come from
// that geometry alone, not from the planes' arithmetic.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>

#include "refraster/renderer.hpp"

namespace {

using refraster::PointCoordOrigin;
using refraster::TextureFilter;

constexpr std::uint32_t kTarget = 16;
constexpr std::uint32_t kSide = 8;

refraster::TextureImage random_image(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    refraster::TextureImage img;
    img.width = kSide;
    img.height = kSide;
    img.rgba.resize(std::size_t{kSide} * kSide * 4);
    for (auto& b : img.rgba) b = static_cast<std::uint8_t>(rng() & 0xff);
    return img;
}

struct SpriteCase {
    PointCoordOrigin origin = PointCoordOrigin::UpperLeft;
    TextureFilter filter = TextureFilter::Nearest;
    float w = 1.0f;  // the vertex's clip w (perspective planes)
    refraster::PrimitiveType primitive = refraster::PrimitiveType::Points;
};

// One point of side kSide centred on window (8, 8) (clip (0, 0) times w), sampled with replace:
// pixels 4..11 in x and y.
refraster::DrawList sprite_list(const SpriteCase& c, const refraster::TextureImage& img) {
    refraster::DrawList l;
    l.target = {kTarget, kTarget, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None, 1};
    l.clear.color = {0.0f, 0.0f, 0.0f, 0.0f};
    refraster::Texture tex;
    tex.levels.push_back(img);
    l.textures.push_back(tex);
    refraster::Draw d;
    d.primitive = c.primitive;
    d.state.viewport = {0, 0, static_cast<std::int32_t>(kTarget),
                        static_cast<std::int32_t>(kTarget)};
    d.state.point_size = static_cast<float>(kSide);
    if (c.primitive != refraster::PrimitiveType::Points)
        d.state.polygon_mode = refraster::PolygonMode::Point;
    refraster::TextureState ts;
    ts.min_filter = c.filter;
    ts.mag_filter = c.filter;
    ts.env = refraster::TextureEnv::Replace;
    ts.coord_replace = true;
    ts.point_coord_origin = c.origin;
    d.state.texture = ts;
    d.vertices.attributes = {{"color", 4}, {"texcoord", 4}};
    // The vertex's own coordinate (a corner texel) must not be what is sampled.
    const std::size_t copies = c.primitive == refraster::PrimitiveType::Points ? 1 : 3;
    for (std::size_t i = 0; i < copies; ++i) {
        d.vertices.data.insert(d.vertices.data.end(), {0.0f, 0.0f, 0.0f, c.w, 1.0f, 1.0f, 1.0f,
                                                       1.0f, 0.01f, 0.01f, 0.0f, 1.0f});
    }
    l.draws.push_back(d);
    return l;
}

std::string describe(const SpriteCase& c) {
    return std::string(c.origin == PointCoordOrigin::UpperLeft ? "upper_left" : "lower_left") +
           (c.filter == TextureFilter::Nearest ? " nearest" : " linear") +
           " w=" + std::to_string(c.w) +
           (c.primitive == refraster::PrimitiveType::Points ? " points" : " polygon points");
}

TEST(PointSprite, EachPixelOfAnNByNPointShowsItsTexel) {
    const auto img = random_image(42);
    for (const auto origin : {PointCoordOrigin::UpperLeft, PointCoordOrigin::LowerLeft})
        for (const auto filter : {TextureFilter::Nearest, TextureFilter::Linear})
            for (const float w : {1.0f, 2.5f})
                for (const auto prim :
                     {refraster::PrimitiveType::Points, refraster::PrimitiveType::Triangles}) {
                    const SpriteCase c{origin, filter, w, prim};
                    // Bilinear at a texel centre is that texel when the coordinate lands
                    // exactly; with w != 1 the perspective planes may miss it by an ulp.
                    if (filter == TextureFilter::Linear && w != 1.0f) continue;
                    refraster::Framebuffer fb;
                    const auto r = refraster::render(sprite_list(c, img), fb);
                    ASSERT_EQ(r.status, refraster::RenderStatus::Ok) << r.message;
                    int wrong = 0;
                    for (std::uint32_t y = 0; y < kTarget; ++y)
                        for (std::uint32_t x = 0; x < kTarget; ++x) {
                            const bool inside = x >= 4 && x < 12 && y >= 4 && y < 12;
                            const std::uint32_t i = x - 4;
                            const std::uint32_t j =
                                origin == PointCoordOrigin::UpperLeft ? kSide - 1 - (y - 4) : y - 4;
                            for (std::size_t ch = 0; ch < 4; ++ch) {
                                const std::uint8_t got = fb.color8[4 * (y * kTarget + x) + ch];
                                const std::uint8_t want =
                                    inside ? img.rgba[4 * (j * kSide + i) + ch] : 0;
                                if (got != want && wrong++ < 4) {
                                    ADD_FAILURE() << describe(c) << ": pixel (" << x << ", " << y
                                                  << ") channel " << ch << " is " << int{got}
                                                  << ", want " << int{want};
                                }
                            }
                        }
                    EXPECT_EQ(wrong, 0) << describe(c);
                }
}

TEST(PointSprite, WithoutCoordReplaceThePointSamplesItsVertexCoordinate) {
    const auto img = random_image(7);
    auto l = sprite_list({}, img);
    l.draws[0].state.texture->coord_replace = false;
    refraster::Framebuffer fb;
    ASSERT_EQ(refraster::render(l, fb).status, refraster::RenderStatus::Ok);
    // (0.01, 0.01) is texel (0, 0), everywhere in the point.
    for (std::uint32_t y = 4; y < 12; ++y)
        for (std::uint32_t x = 4; x < 12; ++x)
            for (std::size_t ch = 0; ch < 4; ++ch)
                EXPECT_EQ(fb.color8[4 * (y * kTarget + x) + ch], img.rgba[ch]);
}

}  // namespace
