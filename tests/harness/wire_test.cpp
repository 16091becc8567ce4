// wire_test.cpp: the worker protocol (harness/src/backends/wire.hpp) round-trips every field, and a
// short or corrupt stream is an error, never a wrong value.
#include "backends/wire.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cmath>
#include <limits>
#include <thread>

namespace {

using namespace refraster;
using harness::wire::FrameReader;
using harness::wire::FrameType;
using harness::wire::WireError;

DrawList sample_draw_list() {
    DrawList list;
    list.target = Target{17, 9, ColorFormat::Rgba32f, DepthFormat::Z16, 4};
    list.clear.color = {0.1f, -2.0f, std::numeric_limits<float>::infinity(), 1.0f};
    list.clear.depth = 0.375f;

    Draw a;
    a.primitive = PrimitiveType::TriangleFan;
    a.state.viewport = Rect{-3, 4, 100, 200};
    a.state.depth_near = 0.75f;
    a.state.depth_far = 0.25f;
    a.state.scissor = Rect{1, 2, 0, 5};
    a.state.cull = CullMode::FrontAndBack;
    a.state.front_face = FrontFace::Cw;
    a.state.depth_test = CompareFunc::Gequal;
    a.state.depth_write = false;
    a.state.shade = ShadeModel::NoPerspective;
    a.state.provoking_vertex = ProvokingVertex::First;
    a.state.polygon_mode = PolygonMode::Point;
    a.state.polygon_offset = PolygonOffset{-1.5f, 2.0f};
    a.state.line_width = 3.5f;
    a.state.point_size = 255.0f;
    a.state.blend = BlendPreset::Add;
    a.state.multisample = false;
    a.vertices.attributes = {{"color", 4}, {"extra", 2}};
    for (int i = 0; i < 3 * 10; ++i) a.vertices.data.push_back(static_cast<float>(i) * 0.125f);
    a.vertices.data.push_back(-0.0f);  // the sign of zero must survive too
    a.vertices.data.back() = std::nextafter(0.0f, 1.0f);
    a.indices = std::vector<std::uint32_t>{2, 0, 1, 0xffffffffu};

    Draw b;  // defaults, no indices, no attributes
    b.primitive = PrimitiveType::Points;
    b.vertices.data = {0.0f, 0.5f, -0.0f, 1.0f};

    Draw c;  // empty
    c.primitive = PrimitiveType::LineLoop;
    c.indices = std::vector<std::uint32_t>{};
    c.state.depth_test = CompareFunc::Never;

    Draw t;  // textured: color then texcoord
    t.primitive = PrimitiveType::TriangleStrip;
    t.state.shade = ShadeModel::Flat;
    t.state.texture = TextureState{1,
                                   TextureFilter::NearestMipmapLinear,
                                   TextureFilter::Nearest,
                                   TextureWrap::MirroredRepeat,
                                   TextureWrap::ClampToBorder,
                                   {0.25f, -0.0f, 1.0f, std::nextafter(0.0f, 1.0f)},
                                   TextureEnv::Replace};
    t.vertices.attributes = {{"color", 4}, {"texcoord", 4}};
    for (int i = 0; i < 12 * 3; ++i) t.vertices.data.push_back(static_cast<float>(i) * -0.5f);

    Draw u;  // textured with every default of the texture state
    u.state.texture = TextureState{};

    list.draws = {a, b, c, t, u};

    // Texture 0: generated mipmaps from a 3x2 base. Texture 1: a 4x2 chain given in full,
    // 4x2, 2x1, 1x1. Texture 2: no levels at all (the wire carries what it is given).
    const auto image = [](std::uint32_t w, std::uint32_t h, int seed) {
        TextureImage img{w, h, {}};
        for (std::uint32_t i = 0; i < w * h * 4; ++i) {
            img.rgba.push_back(static_cast<std::uint8_t>(static_cast<int>(i) * 29 + seed));
        }
        return img;
    };
    list.textures = {Texture{{image(3, 2, 1)}, true},
                     Texture{{image(4, 2, 2), image(2, 1, 3), image(1, 1, 4)}, false}, Texture{}};
    return list;
}

harness::RenderResult sample_result() {
    harness::RenderResult r;
    r.status = harness::RenderStatus::NotSupported;
    r.message = "no 4x here";
    r.image = Framebuffer(3, 2, ColorFormat::Rgba8, DepthFormat::Z24);
    for (std::size_t i = 0; i < r.image.color8.size(); ++i) {
        r.image.color8[i] = static_cast<std::uint8_t>(i * 37);
    }
    for (std::size_t i = 0; i < r.image.depth.size(); ++i) {
        r.image.depth[i] = static_cast<std::uint32_t>(i * 0x123457u);
    }
    // A 4x sample set beside the resolve: every sample its own value.
    r.samples = Framebuffer(3, 2, ColorFormat::Rgba8, DepthFormat::Z24, 4);
    for (std::size_t i = 0; i < r.samples.color8.size(); ++i) {
        r.samples.color8[i] = static_cast<std::uint8_t>(i * 11 + 5);
    }
    for (std::size_t i = 0; i < r.samples.depth.size(); ++i) {
        r.samples.depth[i] = static_cast<std::uint32_t>(i * 0x10101u);
    }
    r.samples.owner.assign(r.samples.depth.size(), 0);
    for (std::size_t i = 0; i < r.samples.owner.size(); ++i) {
        r.samples.owner[i] = static_cast<std::uint32_t>((i % 3) << 24 | i);
    }
    r.provenance = {{"renderer", "llvmpipe (LLVM 15.0.6, 256 bits)"}, {"env", ""}, {"k", "v"}};
    r.seconds = 0.1234567890123;
    return r;
}

TEST(Wire, DrawListRoundTrip) {
    const DrawList list = sample_draw_list();
    const auto bytes = harness::wire::encode_draw_list(list);
    const DrawList back = harness::wire::decode_draw_list(bytes);
    EXPECT_EQ(back, list);
    // operator== on floats cannot see -0.0 vs 0.0; the bits must be equal as well.
    ASSERT_EQ(back.draws[1].vertices.data.size(), 4u);
    EXPECT_TRUE(std::signbit(back.draws[1].vertices.data[2]));
    EXPECT_TRUE(std::isinf(back.clear.color[2]));
}

TEST(Wire, TexturesRoundTrip) {
    const DrawList list = sample_draw_list();
    const DrawList back = harness::wire::decode_draw_list(harness::wire::encode_draw_list(list));
    ASSERT_EQ(back.textures.size(), 3u);
    EXPECT_EQ(back.textures, list.textures);
    EXPECT_TRUE(back.textures[0].generate_mipmaps);
    ASSERT_EQ(back.textures[1].levels.size(), 3u);
    EXPECT_EQ(back.textures[1].levels[1].width, 2u);
    EXPECT_EQ(back.textures[1].levels[1].height, 1u);
    EXPECT_EQ(back.textures[1].levels[2].rgba, list.textures[1].levels[2].rgba);
    ASSERT_EQ(back.draws.size(), 5u);
    EXPECT_FALSE(back.draws[0].state.texture.has_value());
    ASSERT_TRUE(back.draws[3].state.texture.has_value());
    EXPECT_EQ(*back.draws[3].state.texture, *list.draws[3].state.texture);
    EXPECT_TRUE(std::signbit(back.draws[3].state.texture->border_color[1]));
    EXPECT_EQ(back.draws[3].vertices, list.draws[3].vertices);
    EXPECT_EQ(back.draws[4].state.texture, TextureState{});

    // Every value of every texture enum survives.
    DrawList every;
    for (int f = 0; f <= static_cast<int>(TextureFilter::LinearMipmapLinear); ++f) {
        for (int w = 0; w <= static_cast<int>(TextureWrap::ClampToBorder); ++w) {
            for (int env = 0; env <= static_cast<int>(TextureEnv::Replace); ++env) {
                Draw d;
                TextureState ts;
                ts.min_filter = static_cast<TextureFilter>(f);
                ts.mag_filter = static_cast<TextureFilter>(f % 2);
                ts.wrap_s = static_cast<TextureWrap>(w);
                ts.wrap_t = static_cast<TextureWrap>(3 - w);
                ts.env = static_cast<TextureEnv>(env);
                ts.coord_replace = (f + w) % 2 == 0;
                ts.point_coord_origin = static_cast<PointCoordOrigin>(env);
                d.state.texture = ts;
                every.draws.push_back(d);
            }
        }
    }
    every.textures.resize(1);
    EXPECT_EQ(harness::wire::decode_draw_list(harness::wire::encode_draw_list(every)), every);
}

TEST(Wire, LargeTextureTravelsAsOneBlock) {
    // 1024x1024 and its level 1: the payload is the texels plus a fixed overhead, nothing per
    // texel.
    DrawList list;
    TextureImage base{1024, 1024, std::vector<std::uint8_t>(std::size_t{1024} * 1024 * 4)};
    for (std::size_t i = 0; i < base.rgba.size(); ++i) {
        base.rgba[i] = static_cast<std::uint8_t>(i * 7 + (i >> 12));
    }
    TextureImage level1{512, 512, std::vector<std::uint8_t>(std::size_t{512} * 512 * 4, 0x5a)};
    list.textures = {Texture{{base, level1}, false}};
    const auto bytes = harness::wire::encode_draw_list(list);
    const std::size_t empty = harness::wire::encode_draw_list(DrawList{}).size();
    EXPECT_EQ(bytes.size(), empty + 1 + 8 + 2 * 16 + base.rgba.size() + level1.rgba.size());
    EXPECT_EQ(harness::wire::decode_draw_list(bytes), list);
}

TEST(Wire, ManyEmptyDrawsRoundTrip) {
    DrawList list;
    list.draws.resize(1000);
    EXPECT_EQ(harness::wire::decode_draw_list(harness::wire::encode_draw_list(list)), list);
}

TEST(Wire, ResultRoundTrip) {
    const harness::RenderResult r = sample_result();
    const auto back = harness::wire::decode_result(harness::wire::encode_result(r));
    EXPECT_EQ(back.status, r.status);
    EXPECT_EQ(back.message, r.message);
    EXPECT_EQ(back.image, r.image);
    EXPECT_EQ(back.samples, r.samples);
    EXPECT_EQ(back.samples.samples, 4u);
    EXPECT_EQ(back.provenance, r.provenance);
    EXPECT_EQ(back.seconds, r.seconds);

    harness::RenderResult f;
    f.image = Framebuffer(2, 2, ColorFormat::Rgba32f, DepthFormat::Z32f);
    f.image.color32f[5] = -1.0e30f;
    f.samples = Framebuffer(2, 2, ColorFormat::Rgba32f, DepthFormat::Z32f, 4);
    f.samples.color32f[7] = std::numeric_limits<float>::denorm_min();
    f.samples.color32f[9] = -std::numeric_limits<float>::infinity();
    f.samples.color32f[11] = std::bit_cast<float>(0x7fc01234u);  // a NaN with a payload
    const auto fb = harness::wire::decode_result(harness::wire::encode_result(f));
    EXPECT_EQ(fb.image, f.image);
    EXPECT_EQ(fb.status, harness::RenderStatus::Ok);
    // operator== cannot compare NaNs: the bits must survive.
    ASSERT_EQ(fb.samples.color32f.size(), f.samples.color32f.size());
    for (std::size_t i = 0; i < f.samples.color32f.size(); ++i) {
        EXPECT_EQ(std::bit_cast<std::uint32_t>(fb.samples.color32f[i]),
                  std::bit_cast<std::uint32_t>(f.samples.color32f[i]))
            << "float " << i;
    }
    EXPECT_EQ(fb.samples.samples, 4u);
}

// A result the caller gives up is encoded, and a payload it gives up decoded, a block at a time
// while the pages already copied are given back: the bytes and the images are those of the
// plain encode and decode, for images of several blocks (16 MiB each) and a tail.
TEST(Wire, GivenUpResultsGiveTheSameBytes) {
    harness::RenderResult r;
    r.image = Framebuffer(1500, 1300, ColorFormat::Rgba32f, DepthFormat::Z32f);
    r.image.owner.assign(r.image.pixel_count(), 0);
    std::uint32_t x = 12345;
    const auto next = [&] { return x = x * 1664525u + 1013904223u; };
    for (auto& v : r.image.color32f) v = std::bit_cast<float>(next() & 0x7f7fffffu);
    for (auto& v : r.image.depth) v = next();
    for (auto& v : r.image.owner) v = next();
    r.message = "m";
    const auto plain = harness::wire::encode_result(r);
    harness::RenderResult copy = r;
    const auto given = harness::wire::encode_result(std::move(copy));
    EXPECT_EQ(given, plain);
    auto payload = plain;
    const auto back = harness::wire::decode_result(std::move(payload));
    EXPECT_EQ(back.image, r.image);
    EXPECT_EQ(back.message, r.message);
    EXPECT_EQ(harness::wire::decode_result(std::span<const std::uint8_t>(plain)).image, r.image);
}

TEST(Wire, SingleSampleResultHasEmptySamples) {
    harness::RenderResult r;
    r.image = Framebuffer(4, 4, ColorFormat::Rgba8, DepthFormat::None);
    const auto back = harness::wire::decode_result(harness::wire::encode_result(r));
    EXPECT_EQ(back.samples.width, 0u);
    EXPECT_EQ(back.samples.height, 0u);
    EXPECT_TRUE(back.samples.color8.empty());
    EXPECT_EQ(back.image, r.image);
}

TEST(Wire, MultisampleFlagRoundTripsPerDraw) {
    DrawList list;
    list.draws.resize(3);
    list.draws[1].state.multisample = false;
    const DrawList back = harness::wire::decode_draw_list(harness::wire::encode_draw_list(list));
    ASSERT_EQ(back.draws.size(), 3u);
    EXPECT_TRUE(back.draws[0].state.multisample);
    EXPECT_FALSE(back.draws[1].state.multisample);
    EXPECT_TRUE(back.draws[2].state.multisample);
}

// The encoding of a list with one empty draw and the given textures, and where its texture
// part starts.
struct TextureBytes {
    std::vector<std::uint8_t> bytes;
    std::size_t textures_at = 0;  // the texture count
};

TextureBytes encode_with_textures(std::vector<Texture> textures) {
    DrawList list;
    list.draws.resize(1);
    TextureBytes out;
    out.textures_at = harness::wire::encode_draw_list(list).size() - 8;
    list.textures = std::move(textures);
    out.bytes = harness::wire::encode_draw_list(list);
    return out;
}

TEST(Wire, CorruptTexturesAreErrors) {
    const Texture one{{TextureImage{2, 1, {1, 2, 3, 4, 5, 6, 7, 8}}}, false};
    const auto good = encode_with_textures({one});
    ASSERT_NO_THROW(harness::wire::decode_draw_list(good.bytes));
    // Layout after the count: generate flag (1), level count (8), width (4), height (4),
    // byte count (8), bytes.
    const std::size_t flag_at = good.textures_at + 8;
    const std::size_t levels_at = flag_at + 1;
    const std::size_t width_at = levels_at + 8;
    const std::size_t height_at = width_at + 4;

    auto bytes = good.bytes;
    bytes[flag_at] = 2;  // a boolean is 0 or 1
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);

    bytes = good.bytes;  // a level count past what the payload could hold
    for (std::size_t i = levels_at; i < levels_at + 8; ++i) bytes[i] = 0xff;
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);

    // A level whose size disagrees with its texels, either way: glTexImage2D would read past
    // the block, or leave texels unread.
    bytes = good.bytes;
    bytes[width_at] = 3;
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);
    bytes = good.bytes;
    bytes[width_at] = 1;
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);
    bytes = good.bytes;
    bytes[height_at] = 0;
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);
    // Sizes whose product overflows 32 bits must not wrap to a match:
    // (2^29 + 1) x 2 x 4 = 2^32 + 8.
    bytes = good.bytes;
    bytes[width_at] = 1;
    bytes[width_at + 3] = 0x20;
    bytes[height_at] = 2;
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);

    // A 0x0 level with no bytes is consistent; what to make of it is the renderer's business.
    EXPECT_NO_THROW(harness::wire::decode_draw_list(
        encode_with_textures({Texture{{TextureImage{0, 0, {}}}, false}}).bytes));
}

// A polygon's fill rule goes through the wire, and a fill rule the format does not have is an
// error.
TEST(Wire, FillRuleRoundTripsAndACorruptOneIsAnError) {
    DrawList list;
    list.draws.resize(1);
    list.draws[0].primitive = refraster::PrimitiveType::Polygon;
    list.draws[0].state.fill_rule = refraster::FillRule::NonZero;
    const auto good = harness::wire::encode_draw_list(list);
    EXPECT_EQ(harness::wire::decode_draw_list(good), list);
    // The state's last byte, before the draw's attribute count (8), vertex block and index
    // flag (8 + 1), and the texture count (8).
    const std::size_t rule_at = good.size() - 8 - 9 - 8 - 1;
    ASSERT_EQ(good[rule_at], static_cast<std::uint8_t>(refraster::FillRule::NonZero));
    auto bytes = good;
    bytes[rule_at] = 2;
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);
}

TEST(Wire, CorruptTextureStateIsAnError) {
    DrawList list;
    list.draws.resize(1);
    list.draws[0].state.texture = TextureState{};
    list.textures.resize(1);
    const auto good = harness::wire::encode_draw_list(list);
    ASSERT_NO_THROW(harness::wire::decode_draw_list(good));
    // From the end: the texture count (8) and the empty texture (1 + 8); before them the
    // draw's empty vertex block and index flag (8 + 1) and its attribute count (8) follow
    // the state, which ends with the texture state: index (4), four enums (1 each), the
    // border colour (16), the env (1), coord_replace (1) and the point coord origin (1), then
    // the fill rule's flag (1, no rule).
    const std::size_t origin_at = good.size() - 8 - 9 - 9 - 8 - 1 - 1;
    const std::size_t env_at = origin_at - 2;
    const std::size_t min_filter_at = env_at - 16 - 4;
    ASSERT_EQ(good[env_at], 0);
    ASSERT_EQ(good[min_filter_at], static_cast<std::uint8_t>(TextureFilter::Linear));

    auto bytes = good;
    bytes[env_at] = 2;
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);
    bytes = good;
    bytes[origin_at] = 2;
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);
    bytes = good;
    bytes[origin_at - 1] = 2;  // a boolean: 0 or 1
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);
    bytes = good;
    bytes[min_filter_at] = 6;
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);
    bytes = good;
    bytes[min_filter_at + 2] = 4;  // wrap_s: 0..3
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);
    bytes = good;
    bytes[min_filter_at + 2] = 3;
    const DrawList back = harness::wire::decode_draw_list(bytes);
    EXPECT_EQ(back.draws[0].state.texture->wrap_s, TextureWrap::ClampToBorder);
    // The has-texture flag is a boolean.
    bytes = good;
    bytes[min_filter_at - 4 - 1] = 2;
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);
}

TEST(Wire, EveryTruncationIsAnError) {
    const auto list_bytes = harness::wire::encode_draw_list(sample_draw_list());
    for (std::size_t n = 0; n < list_bytes.size(); ++n) {
        EXPECT_THROW(harness::wire::decode_draw_list(std::span(list_bytes.data(), n)), WireError)
            << "prefix of " << n << " bytes";
    }
    const auto result_bytes = harness::wire::encode_result(sample_result());
    for (std::size_t n = 0; n < result_bytes.size(); ++n) {
        EXPECT_THROW(harness::wire::decode_result(std::span(result_bytes.data(), n)), WireError)
            << "prefix of " << n << " bytes";
    }
}

TEST(Wire, TrailingBytesAndBadEnumsAreErrors) {
    auto bytes = harness::wire::encode_draw_list(sample_draw_list());
    bytes.push_back(0);
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);

    // Byte 8 is the target's colour format: 0 or 1.
    bytes = harness::wire::encode_draw_list(DrawList{});
    bytes[8] = 7;
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);

    // A huge draw count must be refused, not reserved. An empty list ends with the draw
    // count, then the texture count.
    bytes = harness::wire::encode_draw_list(DrawList{});
    const std::size_t count_at = bytes.size() - 16;
    for (std::size_t i = count_at; i < count_at + 8; ++i) bytes[i] = 0xff;
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);
    // And a huge texture count.
    bytes = harness::wire::encode_draw_list(DrawList{});
    for (std::size_t i = bytes.size() - 8; i < bytes.size(); ++i) bytes[i] = 0xff;
    EXPECT_THROW(harness::wire::decode_draw_list(bytes), WireError);

    // The status is the first byte; past InternalError is corrupt.
    bytes = harness::wire::encode_result(harness::RenderResult{});
    bytes[0] = 5;
    EXPECT_THROW(harness::wire::decode_result(bytes), WireError);

    // A framebuffer's sample count is 1 or 4. The image's follows the status (1 byte), the
    // empty message (8) and width, height and the two formats (4 + 4 + 1 + 1).
    bytes = harness::wire::encode_result(harness::RenderResult{});
    constexpr std::size_t kSamplesAt = 1 + 8 + 4 + 4 + 1 + 1;
    ASSERT_EQ(bytes[kSamplesAt], 1);
    bytes[kSamplesAt] = 2;
    EXPECT_THROW(harness::wire::decode_result(bytes), WireError);
    bytes[kSamplesAt] = 4;
    EXPECT_NO_THROW(harness::wire::decode_result(bytes));
}

struct Pipe {
    int r = -1;
    int w = -1;
    Pipe() {
        int fds[2];
        if (::pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe2");
        r = fds[0];
        w = fds[1];
    }
    void close_write() {
        if (w >= 0) ::close(w);
        w = -1;
    }
    ~Pipe() {
        if (r >= 0) ::close(r);
        close_write();
    }
};

TEST(Wire, FramesCrossAPipeInPieces) {
    Pipe p;
    // Several MiB: far more than a pipe holds, so both ends see short writes and reads.
    std::vector<std::uint8_t> big(5u << 20);
    for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<std::uint8_t>(i * 131);
    const auto list_bytes = harness::wire::encode_draw_list(sample_draw_list());

    std::thread writer([&] {
        harness::wire::write_frame(p.w, FrameType::Render, list_bytes);
        harness::wire::write_frame(p.w, FrameType::Reply, big);
        harness::wire::write_frame(p.w, FrameType::Crash, {});
        p.close_write();
    });
    auto f1 = harness::wire::read_frame(p.r);
    auto f2 = harness::wire::read_frame(p.r);
    auto f3 = harness::wire::read_frame(p.r);
    auto f4 = harness::wire::read_frame(p.r);
    writer.join();

    ASSERT_TRUE(f1 && f2 && f3);
    EXPECT_EQ(f1->type, static_cast<std::uint32_t>(FrameType::Render));
    EXPECT_EQ(harness::wire::decode_draw_list(f1->payload), sample_draw_list());
    EXPECT_EQ(f2->type, static_cast<std::uint32_t>(FrameType::Reply));
    EXPECT_EQ(f2->payload, big);
    EXPECT_EQ(f3->type, static_cast<std::uint32_t>(FrameType::Crash));
    EXPECT_TRUE(f3->payload.empty());
    EXPECT_FALSE(f4.has_value()) << "end of stream between frames is a clean end";
}

TEST(Wire, NonBlockingReaderReportsProgress) {
    Pipe p;
    ASSERT_EQ(::fcntl(p.r, F_SETFL, O_NONBLOCK), 0);
    FrameReader reader;
    EXPECT_EQ(reader.read_some(p.r), FrameReader::Progress::NeedMore);  // EAGAIN
    harness::wire::write_frame(p.w, FrameType::Hang, {1, 2, 3});
    FrameReader::Progress got = FrameReader::Progress::NeedMore;
    for (int i = 0; i < 4 && got == FrameReader::Progress::NeedMore; ++i) {
        got = reader.read_some(p.r);
    }
    ASSERT_EQ(got, FrameReader::Progress::Complete);
    const auto f = reader.take();
    EXPECT_EQ(f.type, static_cast<std::uint32_t>(FrameType::Hang));
    EXPECT_EQ(f.payload, (std::vector<std::uint8_t>{1, 2, 3}));
    p.close_write();
    EXPECT_EQ(reader.read_some(p.r), FrameReader::Progress::Eof);
}

TEST(Wire, StreamEndingInsideAFrameIsAnError) {
    {
        Pipe p;  // inside the payload
        std::vector<std::uint8_t> header(12, 0);
        header[0] = 3;
        header[4] = 100;  // 100 payload bytes promised
        ASSERT_EQ(::write(p.w, header.data(), header.size()), 12);
        ASSERT_EQ(::write(p.w, header.data(), 10), 10);  // only 10 delivered
        p.close_write();
        EXPECT_THROW(harness::wire::read_frame(p.r), WireError);
    }
    {
        Pipe p;  // inside the header
        const std::uint8_t half[5] = {2, 0, 0, 0, 1};
        ASSERT_EQ(::write(p.w, half, sizeof half), 5);
        p.close_write();
        EXPECT_THROW(harness::wire::read_frame(p.r), WireError);
    }
    {
        Pipe p;  // an absurd length is refused before anything is allocated
        std::vector<std::uint8_t> header(12, 0xff);
        ASSERT_EQ(::write(p.w, header.data(), header.size()), 12);
        p.close_write();
        EXPECT_THROW(harness::wire::read_frame(p.r), WireError);
    }
}

TEST(Wire, WritingToAClosedPipeIsAnErrorWithErrno) {
    Pipe p;
    ::close(p.r);
    p.r = -1;
    // SIGPIPE would end the test binary; the GL backend ignores it the same way.
    struct sigaction ignore {};
    struct sigaction old {};
    ignore.sa_handler = SIG_IGN;
    ::sigaction(SIGPIPE, &ignore, &old);
    try {
        harness::wire::write_frame(p.w, FrameType::Render, {1});
        ADD_FAILURE() << "expected EPIPE";
    } catch (const WireError& e) {
        EXPECT_EQ(e.error_number(), EPIPE);
    }
    ::sigaction(SIGPIPE, &old, nullptr);
}

}  // namespace
