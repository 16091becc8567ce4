// gl_backend_test.cpp: the OSMesa or EGL backend (one binary each, chosen by
// REFRASTER_TEST_EGL) renders small draw lists built here, and the pixels are checked
// against values derived by hand; crash and timeout handling is proven with the workers'
// test frames. The scenes keep every pixel centre away from every edge, so the expected
// images hold for any rasterizer that follows GL's rules, llvmpipe and softpipe alike.
#include <gtest/gtest.h>
#include <sched.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "backends/backend_gl.hpp"
#include "harness/backend.hpp"
#include "harness/explain.hpp"
#include "harness/fingerprint.hpp"
#include "harness/gl_verdict.hpp"
#include "harness/profile_io.hpp"
#include "harness/scene.hpp"

#ifndef REFRASTER_TEST_EGL
#error "REFRASTER_TEST_EGL must be 0 (osmesa) or 1 (egl)"
#endif

namespace {

using namespace refraster;
using harness::Driver;
using harness::RenderStatus;

constexpr harness::BackendKind kKind =
    REFRASTER_TEST_EGL ? harness::BackendKind::Egl : harness::BackendKind::OSMesa;

using Rgba = std::array<std::uint8_t, 4>;
constexpr Rgba kTransparent{0, 0, 0, 0};

struct Vertex {
    std::array<float, 4> clip;
    std::array<float, 4> color;
};

Draw make_draw(PrimitiveType p, const std::vector<Vertex>& vs, const Target& t) {
    Draw d;
    d.primitive = p;
    d.state.viewport =
        Rect{0, 0, static_cast<std::int32_t>(t.width), static_cast<std::int32_t>(t.height)};
    d.vertices.attributes = {{"color", 4}};
    for (const auto& v : vs) {
        d.vertices.data.insert(d.vertices.data.end(), v.clip.begin(), v.clip.end());
        d.vertices.data.insert(d.vertices.data.end(), v.color.begin(), v.color.end());
    }
    return d;
}

// A quad over the whole target at NDC depth z, as two indexed triangles.
Draw full_quad(const Target& t, float z, std::array<float, 4> color) {
    Draw d = make_draw(PrimitiveType::Triangles,
                       {{{-1, -1, z, 1}, color},
                        {{1, -1, z, 1}, color},
                        {{1, 1, z, 1}, color},
                        {{-1, 1, z, 1}, color}},
                       t);
    d.indices = std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3};
    return d;
}

// Window (0,0), (7.5,0), (0,7.5) on an 8x8 target: clip x = 7.5/4 - 1 = 0.875, exact. Pixel
// (i, j) has its centre at (i+.5, j+.5); the hypotenuse x+y = 7.5 meets no centre (their sums
// are integers) and the other two edges lie on pixel borders. Covered: i + j <= 6.
Draw lower_left_triangle(const Target& t, std::array<float, 4> c0, std::array<float, 4> c1,
                         std::array<float, 4> c2) {
    return make_draw(PrimitiveType::Triangles,
                     {{{-1, -1, 0, 1}, c0}, {{0.875f, -1, 0, 1}, c1}, {{-1, 0.875f, 0, 1}, c2}}, t);
}

harness::Scene make_scene(const std::string& name, DrawList list) {
    harness::Scene s;
    s.path = "inline/" + name + ".json";
    s.file.name = name;
    s.file.target = list.target;
    s.file.clear = list.clear;
    s.draw_list = std::move(list);
    return s;
}

Rgba pixel(const Framebuffer& fb, std::uint32_t x, std::uint32_t y) {
    const std::size_t i = fb.index(x, y) * 4;
    return {fb.color8[i], fb.color8[i + 1], fb.color8[i + 2], fb.color8[i + 3]};
}

std::string show(const Rgba& c) {
    return "(" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) +
           "," + std::to_string(c[3]) + ")";
}

class GlBackend : public ::testing::TestWithParam<Driver> {
  protected:
    void SetUp() override {
        // ctest sets the variable; this keeps the binary runnable on its own.
        ::setenv("REFRASTER_WORKER_DIR", REFRASTER_TEST_WORKER_DIR, 0);
    }

    std::unique_ptr<harness::GlWorkerBackend> make(double timeout = 60.0) const {
        harness::BackendOptions o;
        o.kind = kKind;
        o.driver = GetParam();
        o.timeout_seconds = timeout;
        return std::make_unique<harness::GlWorkerBackend>(o);
    }

    static bool softpipe() { return GetParam() == Driver::Softpipe; }

    // Renders and requires success.
    static Framebuffer render_ok(harness::GlWorkerBackend& b, const harness::Scene& s) {
        const auto r = b.render(s);
        EXPECT_EQ(r.status, RenderStatus::Ok) << r.message;
        return r.image;
    }
};

TEST_P(GlBackend, ClearColour) {
    auto b = make();
    DrawList list;
    list.target = Target{8, 8, ColorFormat::Rgba8, DepthFormat::None, 1};
    // RNE(c * 255) with no ties: 51, 102, 153, 255.
    list.clear.color = {0.2f, 0.4f, 0.6f, 1.0f};
    const auto fb = render_ok(*b, make_scene("clear", list));
    ASSERT_EQ(fb.color8.size(), 8u * 8u * 4u);
    EXPECT_TRUE(fb.depth.empty()) << "no depth readback for a depth-less target";
    for (std::uint32_t y = 0; y < 8; ++y) {
        for (std::uint32_t x = 0; x < 8; ++x) {
            ASSERT_EQ(pixel(fb, x, y), (Rgba{51, 102, 153, 255})) << x << "," << y;
        }
    }
}

// The time a result carries is the worker's own (first GL call to finished read-back), the
// round trip with the transfer of the scene and the images beside it: the bench times GL by
// the former.
TEST_P(GlBackend, RenderTimeIsTheWorkersOwnAndTheRoundTripIsKeptBeside) {
    auto b = make();
    DrawList list;
    list.target = Target{512, 512, ColorFormat::Rgba8, DepthFormat::Z24, 1};
    const std::array<float, 4> red{1, 0, 0, 1};
    list.draws.push_back(lower_left_triangle(list.target, red, red, red));
    const auto r = b->render(make_scene("timed", list));
    ASSERT_EQ(r.status, RenderStatus::Ok) << r.message;
    EXPECT_GT(r.seconds, 0.0);
    EXPECT_GT(r.round_trip_seconds, 0.0);
    EXPECT_GE(r.round_trip_seconds, r.seconds);
}

TEST_P(GlBackend, LowerLeftTriangleCoversExactlyItsPixels) {
    auto b = make();
    DrawList list;
    list.target = Target{8, 8, ColorFormat::Rgba8, DepthFormat::None, 1};
    const std::array<float, 4> red{1, 0, 0, 1};
    list.draws.push_back(lower_left_triangle(list.target, red, red, red));
    const auto fb = render_ok(*b, make_scene("lower-left-triangle", list));
    ASSERT_EQ(fb.color8.size(), 8u * 8u * 4u);
    int covered = 0;
    for (std::uint32_t y = 0; y < 8; ++y) {
        for (std::uint32_t x = 0; x < 8; ++x) {
            const Rgba want = x + y <= 6 ? Rgba{255, 0, 0, 255} : kTransparent;
            EXPECT_EQ(pixel(fb, x, y), want) << "pixel " << x << "," << y << " (row 0 = bottom)";
            covered += pixel(fb, x, y) == want && x + y <= 6 ? 1 : 0;
        }
    }
    EXPECT_EQ(covered, 28);
}

TEST_P(GlBackend, FlatShadingTakesTheProvokingVertex) {
    auto b = make();
    const std::array<float, 4> red{1, 0, 0, 1};
    const std::array<float, 4> green{0, 1, 0, 1};
    const std::array<float, 4> blue{0, 0, 1, 1};
    for (const auto pv : {ProvokingVertex::Last, ProvokingVertex::First}) {
        DrawList list;
        list.target = Target{8, 8, ColorFormat::Rgba8, DepthFormat::Z24, 1};
        Draw d = lower_left_triangle(list.target, red, green, blue);
        d.state.shade = ShadeModel::Flat;
        d.state.provoking_vertex = pv;
        list.draws.push_back(d);
        const auto fb = render_ok(*b, make_scene("flat", list));
        ASSERT_EQ(fb.color8.size(), 8u * 8u * 4u);
        const Rgba want = pv == ProvokingVertex::Last ? Rgba{0, 0, 255, 255} : Rgba{255, 0, 0, 255};
        for (std::uint32_t y = 0; y < 8; ++y) {
            for (std::uint32_t x = 0; x + y <= 6; ++x) {
                ASSERT_EQ(pixel(fb, x, y), want)
                    << x << "," << y << " got " << show(pixel(fb, x, y));
            }
        }
    }
}

TEST_P(GlBackend, DepthClearValuesReadBack) {
    auto b = make();
    struct Case {
        DepthFormat format;
        float clear;
        std::uint32_t want;
    };
    // glClearDepth quantises the double: z24 RNE(0.25 * (2^24-1)) = RNE(4194303.75),
    // z16 RNE(0.25 * 65535) = RNE(16383.75); z32f keeps the float's bits.
    const Case cases[] = {
        {DepthFormat::Z24, 0.25f, 4194304u},
        {DepthFormat::Z24, 1.0f, 16777215u},
        {DepthFormat::Z24, 0.0f, 0u},
        {DepthFormat::Z16, 0.25f, 16384u},
        {DepthFormat::Z32f, 0.25f, std::bit_cast<std::uint32_t>(0.25f)},
        {DepthFormat::Z32f, 0.1f, std::bit_cast<std::uint32_t>(0.1f)},
    };
    for (const auto& c : cases) {
        DrawList list;
        list.target = Target{4, 3, ColorFormat::Rgba8, c.format, 1};
        list.clear.depth = c.clear;
        const auto fb = render_ok(*b, make_scene("depth-clear", list));
        ASSERT_EQ(fb.depth.size(), 12u);
        EXPECT_EQ(fb.depth_format, c.format);
        for (std::uint32_t v : fb.depth) {
            ASSERT_EQ(v, c.want) << "format " << to_string(c.format) << " clear " << c.clear;
        }
    }
}

TEST_P(GlBackend, DepthTestOnlyWithADepthTarget) {
    auto b = make();
    for (const auto depth : {DepthFormat::Z24, DepthFormat::None}) {
        DrawList list;
        list.target = Target{8, 8, ColorFormat::Rgba8, depth, 1};
        Draw near = full_quad(list.target, -0.5f, {1, 0, 0, 1});
        Draw far = full_quad(list.target, 0.5f, {0, 1, 0, 1});
        near.state.depth_test = CompareFunc::Less;
        far.state.depth_test = CompareFunc::Less;
        list.draws = {near, far};
        const auto fb = render_ok(*b, make_scene("depth-test", list));
        ASSERT_EQ(fb.color8.size(), 8u * 8u * 4u);
        // Without depth the test has no effect, as in GL: the later quad wins.
        const Rgba want = depth == DepthFormat::None ? Rgba{0, 255, 0, 255} : Rgba{255, 0, 0, 255};
        for (std::uint32_t y = 0; y < 8; ++y) {
            for (std::uint32_t x = 0; x < 8; ++x) ASSERT_EQ(pixel(fb, x, y), want);
        }
    }
}

TEST_P(GlBackend, FloatTargetKeepsUnclampedValues) {
    auto b = make();
    DrawList list;
    list.target = Target{2, 2, ColorFormat::Rgba32f, DepthFormat::None, 1};
    list.clear.color = {0.1f, -2.0f, 3.5f, 1.0f};
    Draw d = full_quad(list.target, 0.0f, {-0.25f, 7.0f, 0.1f, 0.5f});
    d.state.scissor = Rect{1, 0, 1, 2};  // right column only
    list.draws.push_back(d);
    const auto fb = render_ok(*b, make_scene("float", list));
    ASSERT_EQ(fb.color32f.size(), 16u);
    for (std::uint32_t y = 0; y < 2; ++y) {
        const auto left = fb.index(0, y) * 4;
        const auto right = fb.index(1, y) * 4;
        EXPECT_EQ(fb.color32f[left + 0], 0.1f);
        EXPECT_EQ(fb.color32f[left + 1], -2.0f);
        EXPECT_EQ(fb.color32f[left + 2], 3.5f);
        EXPECT_EQ(fb.color32f[left + 3], 1.0f);
        EXPECT_EQ(fb.color32f[right + 0], -0.25f);
        EXPECT_EQ(fb.color32f[right + 1], 7.0f);
        EXPECT_EQ(fb.color32f[right + 2], 0.1f);
        EXPECT_EQ(fb.color32f[right + 3], 0.5f);
    }
}

TEST_P(GlBackend, MultisampleResolvesOrIsNotSupported) {
    auto b = make();
    DrawList list;
    list.target = Target{8, 8, ColorFormat::Rgba8, DepthFormat::Z24, 4};
    list.clear.depth = 0.25f;
    list.draws.push_back(full_quad(list.target, 0.0f, {0.2f, 0.4f, 0.6f, 1.0f}));
    const auto r = b->render(make_scene("msaa", list));
    if (softpipe()) {
        // softpipe reports GL_MAX_SAMPLES 1.
        EXPECT_EQ(r.status, RenderStatus::NotSupported) << r.message;
        return;
    }
    ASSERT_EQ(r.status, RenderStatus::Ok) << r.message;
    // Every sample covered with one colour: the average is that colour.
    for (std::uint32_t y = 0; y < 8; ++y) {
        for (std::uint32_t x = 0; x < 8; ++x) {
            ASSERT_EQ(pixel(r.image, x, y), (Rgba{51, 102, 153, 255}));
        }
    }
    // With the depth test off GL writes no depth, so every sample keeps the clear value
    // and the depth resolve (one sample of each pixel) returns it.
    ASSERT_EQ(r.image.depth.size(), 64u);
    for (std::uint32_t v : r.image.depth) ASSERT_EQ(v, 4194304u);
}

// A 4x render, or nullopt (after checking that it was refused) on softpipe, which has no
// multisampling.
std::optional<harness::RenderResult> render_4x(harness::GlWorkerBackend& b, const harness::Scene& s,
                                               bool owners = false) {
    auto r = owners ? b.render_owners(s) : b.render(s);
    if (b.name().ends_with("softpipe")) {
        EXPECT_EQ(r.status, RenderStatus::NotSupported) << r.message;
        return std::nullopt;
    }
    EXPECT_EQ(r.status, RenderStatus::Ok) << r.message;
    if (r.status != RenderStatus::Ok) return std::nullopt;
    return r;
}

TEST_P(GlBackend, MultisampleReturnsEverySampleAndTheBlitIsTheirResolve) {
    auto b = make();
    DrawList list;
    list.target = Target{8, 8, ColorFormat::Rgba8, DepthFormat::Z24, 4};
    list.clear.color = {0.0f, 0.0f, 0.0f, 1.0f};
    const std::array<float, 4> c0{1, 0, 0, 1};
    const std::array<float, 4> c1{0, 1, 0.5f, 1};
    const std::array<float, 4> c2{0.2f, 0.3f, 1, 0.7f};
    Draw d = lower_left_triangle(list.target, c0, c1, c2);
    d.state.depth_test = CompareFunc::Less;
    list.draws.push_back(d);
    const auto r = render_4x(*b, make_scene("msaa-samples", list));
    if (!r) return;
    const auto& ms = r->samples;
    ASSERT_EQ(ms.samples, 4u);
    ASSERT_EQ(ms.width, 8u);
    ASSERT_EQ(ms.height, 8u);
    EXPECT_EQ(ms.color_format, ColorFormat::Rgba8);
    EXPECT_EQ(ms.depth_format, DepthFormat::Z24);
    ASSERT_EQ(ms.color8.size(), 8u * 8u * 4u * 4u);
    ASSERT_EQ(ms.depth.size(), 8u * 8u * 4u);
    EXPECT_TRUE(ms.color32f.empty());
    EXPECT_TRUE(ms.owner.empty());
    EXPECT_EQ(r->image.samples, 1u);
    // The blit's colour is the reference's model of it applied to the samples; the image's
    // depth is sample 0's.
    const auto resolved = resolve_samples(ms);
    EXPECT_EQ(resolved.color8, r->image.color8);
    EXPECT_EQ(resolved.depth, r->image.depth);
    // Pixels along the hypotenuse x + y = 7.5 are partly covered: some sample differs from
    // another there, and the resolve mixes them.
    int mixed = 0;
    for (std::uint32_t y = 0; y < 8; ++y) {
        for (std::uint32_t x = 0; x < 8; ++x) {
            const std::size_t i = ms.sample_index(x, y, 0) * 4;
            bool differ = false;
            for (std::uint32_t s = 1; s < 4; ++s) {
                differ |= std::memcmp(&ms.color8[i], &ms.color8[i + s * 4], 4) != 0;
            }
            mixed += differ ? 1 : 0;
            if (x + y <= 5 || x + y >= 9) {
                EXPECT_FALSE(differ) << x << "," << y;
            }
        }
    }
    EXPECT_GT(mixed, 0);
    // Where the triangle did not reach, every sample keeps the clear colour and depth 1.
    const std::size_t far = ms.sample_index(7, 7, 0);
    for (std::uint32_t s = 0; s < 4; ++s) {
        EXPECT_EQ(ms.color8[(far + s) * 4 + 3], 255);
        EXPECT_EQ(ms.color8[(far + s) * 4 + 0], 0);
        EXPECT_EQ(ms.depth[far + s], 16777215u);
    }
}

// GL_MULTISAMPLE off on a 4x target: the single-sample rules decide coverage (x + y <= 6) and
// the colour goes to every sample of a covered pixel. Measured on llvmpipe 22.3: the depth
// goes to sample 0 only; samples 1-3 keep the depth they had.
TEST_P(GlBackend, MultisampleOffWritesEverySampleOfAPixelAlike) {
    auto b = make();
    for (const bool multisample : {false, true}) {
        DrawList list;
        list.target = Target{8, 8, ColorFormat::Rgba8, DepthFormat::Z16, 4};
        list.clear.depth = 1.0f;
        Draw d = lower_left_triangle(list.target, {1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1});
        d.state.depth_test = CompareFunc::Always;
        d.state.multisample = multisample;
        list.draws.push_back(d);
        const auto r = render_4x(*b, make_scene("msaa-off", list));
        if (!r) return;
        const auto& ms = r->samples;
        ASSERT_EQ(ms.color8.size(), 8u * 8u * 16u);
        int uneven = 0;
        for (std::size_t i = 0; i < ms.pixel_count(); ++i) {
            bool differ = false;
            for (std::uint32_t s = 1; s < 4; ++s) {
                differ |= std::memcmp(&ms.color8[i * 16], &ms.color8[i * 16 + s * 4], 4) != 0;
            }
            uneven += differ ? 1 : 0;
        }
        if (multisample) {
            EXPECT_GT(uneven, 0) << "with GL_MULTISAMPLE on, edge pixels are partly covered";
            continue;
        }
        EXPECT_EQ(uneven, 0) << "GL_MULTISAMPLE off writes one colour to every sample";
        for (std::uint32_t y = 0; y < 8; ++y) {
            for (std::uint32_t x = 0; x < 8; ++x) {
                const bool covered = x + y <= 6;
                EXPECT_EQ(ms.color8[ms.sample_index(x, y, 0) * 4 + 3], covered ? 255 : 0)
                    << x << "," << y;
                // z = 0 in NDC: depth 0.5, RNE(0.5 * 65535) = 32768; the clear is 65535.
                EXPECT_EQ(ms.depth[ms.sample_index(x, y, 0)], covered ? 32768u : 65535u)
                    << x << "," << y;
                for (std::uint32_t s = 1; s < 4; ++s) {
                    EXPECT_EQ(ms.depth[ms.sample_index(x, y, s)], 65535u)
                        << x << "," << y << " sample " << s;
                }
            }
        }
    }
}

// Depth per sample in every format: the clear, and constant-depth quads over the whole
// target, each sample equal to what a single-sample target stores for the same scene.
// (Not scissored columns: at 4x llvmpipe 22.3's scissor also passes samples 1 and 3, whose
// x offsets exceed 0.5, of the pixel left of the rectangle.)
TEST_P(GlBackend, MultisampleDepthOfEverySampleMatchesSingleSample) {
    auto b = make();
    for (const auto format : {DepthFormat::Z16, DepthFormat::Z24, DepthFormat::Z32f}) {
        std::vector<std::uint32_t> seen;
        for (const float z : {2.0f, -0.7f, 0.123456f, 0.999f, -0.2f, 0.5f, 0.0f, -1.0f, 1.0f}) {
            DrawList list;
            list.target = Target{4, 4, ColorFormat::Rgba8, format, 4};
            list.clear.depth = 0.3f;
            if (z <= 1.0f) {  // 2.0: the clear alone
                Draw d = full_quad(list.target, z, {0.5f, 0.5f, 0.5f, 1});
                d.state.depth_test = CompareFunc::Always;
                list.draws.push_back(d);
            }
            const auto r = render_4x(*b, make_scene("msaa-depth", list));
            if (!r) return;
            list.target.samples = 1;
            const auto one = render_ok(*b, make_scene("msaa-depth-1x", list));
            ASSERT_EQ(one.depth.size(), 16u);
            ASSERT_EQ(r->samples.depth.size(), 16u * 4u);
            for (std::size_t i = 0; i < 16; ++i) {
                for (std::uint32_t s = 0; s < 4; ++s) {
                    ASSERT_EQ(r->samples.depth[i * 4 + s], one.depth[i])
                        << to_string(format) << " z " << z << " pixel " << i << " sample " << s;
                }
            }
            EXPECT_EQ(r->image.depth, one.depth) << "the image's depth is sample 0's";
            seen.push_back(one.depth[0]);
        }
        // Every scene stored a different depth, the largest among them (z = 1: 2^n - 1).
        std::sort(seen.begin(), seen.end());
        EXPECT_EQ(std::adjacent_find(seen.begin(), seen.end()), seen.end()) << to_string(format);
    }
}

// The scissor test at 4x, as llvmpipe 22.3 does it (measured): a full quad scissored to
// [3, 5) x [3, 5) writes every sample inside, and also the samples of the pixels left of and
// below the rectangle that lie within half a pixel of it (sample positions (0.375, 0.125),
// (0.875, 0.375), (0.125, 0.625), (0.625, 0.875)); nothing right of or above it.
TEST_P(GlBackend, MultisampleScissorPassesSamplesAsMeasured) {
    auto b = make();
    DrawList list;
    list.target = Target{8, 8, ColorFormat::Rgba8, DepthFormat::None, 4};
    Draw d = full_quad(list.target, 0.0f, {1, 1, 1, 1});
    d.state.scissor = Rect{3, 3, 2, 2};
    list.draws.push_back(d);
    const auto r = render_4x(*b, make_scene("msaa-scissor", list));
    if (!r) return;
    for (std::uint32_t y = 0; y < 8; ++y) {
        for (std::uint32_t x = 0; x < 8; ++x) {
            unsigned mask = 0;
            for (std::uint32_t s = 0; s < 4; ++s) {
                if (r->samples.color8[r->samples.sample_index(x, y, s) * 4] == 255) {
                    mask |= 1u << s;
                }
            }
            const bool in_x = x == 3 || x == 4;
            const bool in_y = y == 3 || y == 4;
            unsigned want = 0;
            if (in_x && in_y) want = 0xf;
            if (x == 2 && in_y) want = 0xa;  // samples 1 and 3: x offsets 0.875, 0.625
            if (in_x && y == 2) want = 0xc;  // samples 2 and 3: y offsets 0.625, 0.875
            if (x == 2 && y == 2) want = 0x8;
            EXPECT_EQ(mask, want) << "pixel " << x << "," << y;
        }
    }
}

TEST_P(GlBackend, MultisampleOwnersPerSample) {
    auto b = make();
    DrawList list;
    list.target = Target{8, 8, ColorFormat::Rgba32f, DepthFormat::Z24, 4};
    Draw quad = full_quad(list.target, 0.5f, {0, 0, 1, 1});
    quad.state.scissor = Rect{0, 0, 8, 2};  // rows 0-1: draw 0, primitives 0 and 1
    list.draws.push_back(quad);
    list.draws.push_back(
        lower_left_triangle(list.target, {1, 0, 0, 1}, {1, 0, 0, 1}, {1, 0, 0, 1}));
    const auto r = render_4x(*b, make_scene("msaa-owners", list), true);
    if (!r) return;
    const auto& ms = r->samples;
    ASSERT_EQ(ms.owner.size(), 64u * 4u);
    ASSERT_EQ(r->image.owner.size(), 64u);
    const std::uint32_t tri = owner_id(1, 0);
    int partial = 0;
    for (std::uint32_t y = 0; y < 8; ++y) {
        for (std::uint32_t x = 0; x < 8; ++x) {
            int by_triangle = 0;
            for (std::uint32_t s = 0; s < 4; ++s) {
                const std::uint32_t o = ms.owner[ms.sample_index(x, y, s)];
                // Red samples are the triangle's, blue the quad's, the rest untouched.
                const float red = ms.color32f[ms.sample_index(x, y, s) * 4];
                const float blue = ms.color32f[ms.sample_index(x, y, s) * 4 + 2];
                if (red == 1.0f) {
                    EXPECT_EQ(o, tri) << x << "," << y << " sample " << s;
                    ++by_triangle;
                } else if (blue == 1.0f) {
                    EXPECT_TRUE(o == owner_id(0, 0) || o == owner_id(0, 1)) << o;
                } else {
                    EXPECT_EQ(o, 0u) << x << "," << y << " sample " << s;
                }
            }
            if (x + y <= 5) {
                EXPECT_EQ(by_triangle, 4) << x << "," << y;
            } else if (x + y >= 9) {
                EXPECT_EQ(by_triangle, 0) << x << "," << y;
            }
            partial += by_triangle > 0 && by_triangle < 4 ? 1 : 0;
            EXPECT_EQ(r->image.owner[r->image.index(x, y)], ms.owner[ms.sample_index(x, y, 0)]);
        }
    }
    EXPECT_GT(partial, 0);
    // rgba32f: the blit's resolve is resolve_samples's too, bit for bit.
    const auto resolved = resolve_samples(ms);
    ASSERT_EQ(resolved.color32f.size(), r->image.color32f.size());
    for (std::size_t i = 0; i < resolved.color32f.size(); ++i) {
        ASSERT_EQ(std::bit_cast<std::uint32_t>(resolved.color32f[i]),
                  std::bit_cast<std::uint32_t>(r->image.color32f[i]))
            << "float " << i;
    }
}

TEST_P(GlBackend, SingleSampleTargetsHaveNoSamples) {
    auto b = make();
    DrawList list;
    list.target = Target{8, 8, ColorFormat::Rgba8, DepthFormat::Z24, 1};
    list.draws.push_back(
        lower_left_triangle(list.target, {1, 0, 0, 1}, {1, 0, 0, 1}, {1, 0, 0, 1}));
    for (const bool owners : {false, true}) {
        // Owners are checked on llvmpipe only, as everywhere else: softpipe's owner pass
        // leaves this colour at the clear.
        if (owners && softpipe()) continue;
        const auto s = make_scene("single-sample", list);
        const auto r = owners ? b->render_owners(s) : b->render(s);
        ASSERT_EQ(r.status, RenderStatus::Ok) << r.message;
        EXPECT_EQ(r.samples, Framebuffer{});
        EXPECT_EQ(r.image.samples, 1u);
        EXPECT_EQ(pixel(r.image, 0, 0), (Rgba{255, 0, 0, 255}));
        EXPECT_EQ(pixel(r.image, 7, 7), kTransparent);
        EXPECT_EQ(r.image.owner.size(), owners ? 64u : 0u);
    }
}

TEST_P(GlBackend, UnsupportedExtensionNeverReachesTheWorker) {
    auto b = make();
    auto s = make_scene("ext", DrawList{});
    s.unsupported_extensions = {"textures"};
    const auto r = b->render(s);
    EXPECT_EQ(r.status, RenderStatus::NotSupported);
    EXPECT_NE(r.message.find("textures"), std::string::npos);
    EXPECT_EQ(b->worker_pid(), -1);
}

TEST_P(GlBackend, ProvenanceNamesTheDriver) {
    auto b = make();
    const auto r = b->render(make_scene("provenance", DrawList{}));
    ASSERT_EQ(r.status, RenderStatus::Ok) << r.message;
    const auto& p = r.provenance;
    const std::string driver = softpipe() ? "softpipe" : "llvmpipe";
    ASSERT_TRUE(p.contains("renderer"));
    EXPECT_NE(p.at("renderer").find(driver), std::string::npos) << p.at("renderer");
    EXPECT_NE(p.at("gl_version").find("Compatibility Profile"), std::string::npos)
        << p.at("gl_version");
    EXPECT_EQ(p.at("driver"), driver);
    EXPECT_EQ(p.at("backend"), REFRASTER_TEST_EGL ? "egl" : "osmesa");
    EXPECT_NE(p.at("env").find("GALLIUM_DRIVER=" + driver), std::string::npos) << p.at("env");
    EXPECT_TRUE(p.contains("mesa_version"));
    EXPECT_TRUE(p.contains("commit")) << "host provenance is merged in";
    EXPECT_EQ(b->name(), std::string(REFRASTER_TEST_EGL ? "egl-" : "osmesa-") + driver);
}

TEST_P(GlBackend, WorkerPersistsAcrossScenes) {
    auto b = make();
    DrawList list;
    list.target = Target{4, 4, ColorFormat::Rgba8, DepthFormat::None, 1};
    render_ok(*b, make_scene("a", list));
    const pid_t pid = b->worker_pid();
    EXPECT_GT(pid, 0);
    for (int i = 0; i < 20; ++i) render_ok(*b, make_scene("b", list));
    EXPECT_EQ(b->worker_pid(), pid);
}

// BackendOptions::cpu holds the worker to one CPU from its start (the bench times
// single-threaded drivers on the reference's CPU); without it the worker may run anywhere
// the harness may, and the harness's own thread keeps its set either way.
TEST_P(GlBackend, WorkerRunsOnTheCpuItIsGiven) {
    const auto allowed_of = [](pid_t pid) {
        cpu_set_t set;
        CPU_ZERO(&set);
        EXPECT_EQ(::sched_getaffinity(pid, sizeof set, &set), 0);
        std::vector<int> cpus;
        for (int c = 0; c < CPU_SETSIZE; ++c)
            if (CPU_ISSET(static_cast<std::size_t>(c), &set)) cpus.push_back(c);
        return cpus;
    };
    const std::vector<int> ours = allowed_of(0);
    ASSERT_FALSE(ours.empty());
    DrawList list;
    list.target = Target{4, 4, ColorFormat::Rgba8, DepthFormat::None, 1};

    harness::BackendOptions o;
    o.kind = kKind;
    o.driver = GetParam();
    o.cpu = ours.back();
    harness::GlWorkerBackend pinned(o);
    render_ok(pinned, make_scene("pinned", list));
    ASSERT_GT(pinned.worker_pid(), 0);
    EXPECT_EQ(allowed_of(pinned.worker_pid()), std::vector<int>{ours.back()});
    EXPECT_EQ(allowed_of(0), ours) << "the spawning thread gets its own set back";

    auto free = make();
    render_ok(*free, make_scene("free", list));
    EXPECT_EQ(allowed_of(free->worker_pid()), ours);
}

TEST_P(GlBackend, CrashIsReportedAndTheNextSceneRenders) {
    auto b = make();
    DrawList list;
    list.target = Target{8, 8, ColorFormat::Rgba8, DepthFormat::None, 1};
    list.clear.color = {0.2f, 0.4f, 0.6f, 1.0f};
    ASSERT_TRUE(b->debug_crash_worker());
    const pid_t crashed = b->worker_pid();
    const auto r = b->render(make_scene("crashes", list));
    EXPECT_EQ(r.status, RenderStatus::Crash);
    EXPECT_NE(r.message.find("inline/crashes.json"), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("SIGABRT"), std::string::npos) << r.message;
    EXPECT_EQ(b->worker_pid(), -1);

    const auto fb = render_ok(*b, make_scene("after-crash", list));
    ASSERT_EQ(fb.color8.size(), 8u * 8u * 4u);
    EXPECT_EQ(pixel(fb, 3, 3), (Rgba{51, 102, 153, 255}));
    EXPECT_NE(b->worker_pid(), crashed);
}

TEST_P(GlBackend, KilledWorkerIsACrash) {
    auto b = make();
    DrawList list;
    list.target = Target{4, 4, ColorFormat::Rgba8, DepthFormat::None, 1};
    render_ok(*b, make_scene("before-kill", list));
    ASSERT_EQ(::kill(b->worker_pid(), SIGKILL), 0);
    const auto r = b->render(make_scene("killed", list));
    EXPECT_EQ(r.status, RenderStatus::Crash);
    EXPECT_NE(r.message.find("SIGKILL"), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("inline/killed.json"), std::string::npos) << r.message;
    render_ok(*b, make_scene("after-kill", list));
}

TEST_P(GlBackend, KillAtHookCrashesTheFirstWorkerOnly) {
    ::setenv("REFRASTER_WORKER_KILL_AT", "2", 1);
    auto b = make();
    DrawList list;
    list.target = Target{4, 4, ColorFormat::Rgba8, DepthFormat::None, 1};
    std::vector<RenderStatus> got;
    for (int i = 0; i < 5; ++i) got.push_back(b->render(make_scene("kill-at", list)).status);
    ::unsetenv("REFRASTER_WORKER_KILL_AT");
    const std::vector<RenderStatus> want{RenderStatus::Ok, RenderStatus::Crash, RenderStatus::Ok,
                                         RenderStatus::Ok, RenderStatus::Ok};
    EXPECT_EQ(got, want);
}

TEST_P(GlBackend, HangTimesOutAndTheNextSceneRenders) {
    auto b = make(1.0);
    DrawList list;
    list.target = Target{8, 8, ColorFormat::Rgba8, DepthFormat::None, 1};
    list.clear.color = {0.2f, 0.4f, 0.6f, 1.0f};
    // The first scene starts the worker, so the hang below is the only thing timed.
    render_ok(*b, make_scene("before-hang", list));
    ASSERT_TRUE(b->debug_hang_worker());
    const auto start = std::chrono::steady_clock::now();
    const auto r = b->render(make_scene("hangs", list));
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(r.status, RenderStatus::Timeout) << r.message;
    EXPECT_NE(r.message.find("inline/hangs.json"), std::string::npos) << r.message;
    EXPECT_GE(waited, 0.9);
    EXPECT_LT(waited, 5.0);
    EXPECT_EQ(b->worker_pid(), -1);

    const auto fb = render_ok(*b, make_scene("after-hang", list));
    ASSERT_EQ(fb.color8.size(), 8u * 8u * 4u);
    EXPECT_EQ(pixel(fb, 0, 0), (Rgba{51, 102, 153, 255}));
}

TEST_P(GlBackend, MissingWorkerDirectoryIsRefusedUpFront) {
    ::setenv("REFRASTER_WORKER_DIR", "/nonexistent-refraster-workers", 1);
    harness::BackendOptions o;
    o.kind = kKind;
    o.driver = GetParam();
    EXPECT_THROW(harness::GlWorkerBackend{o}, std::runtime_error);
    ::setenv("REFRASTER_WORKER_DIR", REFRASTER_TEST_WORKER_DIR, 1);
}

// Textures (extension "textures"): a draw's vertex records are position, colour, texcoord.
struct TexVertex {
    std::array<float, 4> clip;
    std::array<float, 4> color;
    std::array<float, 4> texcoord;
};

// A quad over the whole target, two indexed triangles, texture coordinates (0, 0) at the
// bottom-left corner and (s1, t1) at the top-right, all multiplied by q (textureProj divides
// them back). On a target of the texture's size every pixel centre then samples its own
// texel centre exactly.
Draw textured_quad(const Target& t, std::array<float, 4> color, float s1, float t1, float q,
                   TextureState state) {
    const std::vector<TexVertex> vs = {{{-1, -1, 0, 1}, color, {0, 0, 0, q}},
                                       {{1, -1, 0, 1}, color, {s1 * q, 0, 0, q}},
                                       {{1, 1, 0, 1}, color, {s1 * q, t1 * q, 0, q}},
                                       {{-1, 1, 0, 1}, color, {0, t1 * q, 0, q}}};
    Draw d;
    d.primitive = PrimitiveType::Triangles;
    d.state.viewport =
        Rect{0, 0, static_cast<std::int32_t>(t.width), static_cast<std::int32_t>(t.height)};
    d.state.texture = state;
    d.vertices.attributes = {{"color", 4}, {"texcoord", 4}};
    for (const auto& v : vs) {
        d.vertices.data.insert(d.vertices.data.end(), v.clip.begin(), v.clip.end());
        d.vertices.data.insert(d.vertices.data.end(), v.color.begin(), v.color.end());
        d.vertices.data.insert(d.vertices.data.end(), v.texcoord.begin(), v.texcoord.end());
    }
    d.indices = std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3};
    return d;
}

// A 2x2 RGBA8 image from its texels, rows bottom to top: (0,0), (1,0), (0,1), (1,1).
TextureImage image2x2(const std::array<Rgba, 4>& texels) {
    TextureImage img{2, 2, {}};
    for (const auto& t : texels) img.rgba.insert(img.rgba.end(), t.begin(), t.end());
    return img;
}

TextureState nearest_state(TextureEnv env) {
    TextureState s;
    s.min_filter = TextureFilter::Nearest;
    s.mag_filter = TextureFilter::Nearest;
    s.env = env;
    return s;
}

TEST_P(GlBackend, TextureReplaceGivesEachPixelItsTexel) {
    auto b = make();
    const std::array<Rgba, 4> texels = {Rgba{255, 0, 0, 255}, Rgba{0, 255, 1, 128},
                                        Rgba{3, 7, 254, 64}, Rgba{17, 34, 51, 0}};
    // q = 1 and q = 2: the coordinates are divided by q (textureProj). With q ignored, the
    // q = 2 quad would sample (0.5, 0.5) and (1.5, 1.5) and give texel (1,1) everywhere but
    // the pixel (0,0).
    for (const float q : {1.0f, 2.0f}) {
        DrawList list;
        list.target = Target{2, 2, ColorFormat::Rgba8, DepthFormat::None, 1};
        list.clear.color = {0.5f, 0.5f, 0.5f, 0.5f};
        list.textures = {Texture{{image2x2(texels)}, false}};
        list.draws.push_back(textured_quad(list.target, {0.2f, 0.4f, 0.6f, 0.8f}, 1, 1, q,
                                           nearest_state(TextureEnv::Replace)));
        const auto fb = render_ok(*b, make_scene("texture-replace", list));
        ASSERT_EQ(fb.color8.size(), 2u * 2u * 4u);
        for (std::uint32_t y = 0; y < 2; ++y) {
            for (std::uint32_t x = 0; x < 2; ++x) {
                EXPECT_EQ(pixel(fb, x, y), texels[y * 2 + x])
                    << "q " << q << ", pixel " << x << "," << y << " got " << show(pixel(fb, x, y));
            }
        }
    }
}

TEST_P(GlBackend, TextureModulateMultipliesTheColour) {
    auto b = make();
    // Texels that the colour's factors divide exactly: cvt8(c * t / 255) = c * t with no
    // rounding to decide.
    const std::array<Rgba, 4> texels = {Rgba{200, 40, 120, 254}, Rgba{0, 252, 8, 2},
                                        Rgba{16, 100, 44, 128}, Rgba{96, 4, 252, 60}};
    const std::array<float, 4> color{0.5f, 0.25f, 1.0f, 0.5f};
    DrawList list;
    list.target = Target{2, 2, ColorFormat::Rgba8, DepthFormat::None, 1};
    list.textures = {Texture{{image2x2(texels)}, false}};
    list.draws.push_back(
        textured_quad(list.target, color, 1, 1, 1, nearest_state(TextureEnv::Modulate)));
    const auto fb = render_ok(*b, make_scene("texture-modulate", list));
    ASSERT_EQ(fb.color8.size(), 2u * 2u * 4u);
    for (std::uint32_t y = 0; y < 2; ++y) {
        for (std::uint32_t x = 0; x < 2; ++x) {
            const Rgba& t = texels[y * 2 + x];
            Rgba want{};
            for (std::size_t c = 0; c < 4; ++c) {
                want[c] =
                    static_cast<std::uint8_t>(std::lround(static_cast<double>(color[c]) * t[c]));
            }
            EXPECT_EQ(pixel(fb, x, y), want)
                << "pixel " << x << "," << y << " got " << show(pixel(fb, x, y));
        }
    }
}

// An untextured draw after a textured one: the texcoord array of the first must not leak
// into the second, whose records are shorter. The untextured quad is scissored to the right
// column.
TEST_P(GlBackend, UntexturedDrawAfterATexturedOne) {
    auto b = make();
    const std::array<Rgba, 4> texels = {Rgba{10, 20, 30, 40}, Rgba{50, 60, 70, 80},
                                        Rgba{90, 100, 110, 120}, Rgba{130, 140, 150, 160}};
    DrawList list;
    list.target = Target{2, 2, ColorFormat::Rgba8, DepthFormat::None, 1};
    list.textures = {Texture{{image2x2(texels)}, false}};
    list.draws.push_back(
        textured_quad(list.target, {1, 1, 1, 1}, 1, 1, 1, nearest_state(TextureEnv::Replace)));
    Draw plain = full_quad(list.target, 0.0f, {0.0f, 0.0f, 1.0f, 1.0f});
    plain.state.scissor = Rect{1, 0, 1, 2};
    list.draws.push_back(plain);
    const auto fb = render_ok(*b, make_scene("texture-then-plain", list));
    ASSERT_EQ(fb.color8.size(), 2u * 2u * 4u);
    EXPECT_EQ(pixel(fb, 0, 0), texels[0]);
    EXPECT_EQ(pixel(fb, 0, 1), texels[2]);
    EXPECT_EQ(pixel(fb, 1, 0), (Rgba{0, 0, 255, 255}));
    EXPECT_EQ(pixel(fb, 1, 1), (Rgba{0, 0, 255, 255}));
}

// Heavy minification (32 repeats of the texture a pixel) with nearest_mipmap_nearest: every
// pixel is the last level's one texel.
TextureState minified_state() {
    TextureState s;
    s.min_filter = TextureFilter::NearestMipmapNearest;
    s.mag_filter = TextureFilter::Nearest;
    s.env = TextureEnv::Replace;
    return s;
}

TEST_P(GlBackend, GivenMipmapLevelIsSampledWhenMinified) {
    auto b = make();
    const Rgba level1{9, 99, 199, 249};
    DrawList list;
    list.target = Target{2, 2, ColorFormat::Rgba8, DepthFormat::None, 1};
    list.textures = {Texture{{image2x2({Rgba{255, 0, 0, 255}, Rgba{0, 255, 0, 255},
                                        Rgba{0, 0, 255, 255}, Rgba{255, 255, 255, 255}}),
                              TextureImage{1, 1, {level1.begin(), level1.end()}}},
                             false}};
    list.draws.push_back(textured_quad(list.target, {1, 1, 1, 1}, 64, 64, 1, minified_state()));
    const auto fb = render_ok(*b, make_scene("texture-given-mipmaps", list));
    ASSERT_EQ(fb.color8.size(), 2u * 2u * 4u);
    for (std::uint32_t y = 0; y < 2; ++y) {
        for (std::uint32_t x = 0; x < 2; ++x) {
            EXPECT_EQ(pixel(fb, x, y), level1) << x << "," << y << " got " << show(pixel(fb, x, y));
        }
    }
    // The same texture with its base level alone is sampled at the base.
    list.textures[0].levels.pop_back();
    const auto base = render_ok(*b, make_scene("texture-base-only", list));
    ASSERT_EQ(base.color8.size(), 2u * 2u * 4u);
    EXPECT_NE(pixel(base, 0, 0), level1);
}

// glGenerateMipmap's level 1 of a 2x2 texture. llvmpipe (a linear blit, 8-bit lerps): per
// channel the average of the row averages, each rounded half up,
// (((a + b + 1) >> 1) + ((c + d + 1) >> 1) + 1) >> 1, a and b the bottom row; the channels
// are chosen so that other roundings differ (a four-way (a+b+c+d+2)>>2, truncation). softpipe
// filters in float (measured: 0, 1, 0, 1 gives 0 there, 1 in llvmpipe): its texel is only
// required to be within half a step of the four-way mean.
TEST_P(GlBackend, GeneratedMipmapIsTheCascadedAverage) {
    auto b = make();
    const std::array<Rgba, 4> texels = {Rgba{0, 0, 0, 255}, Rgba{1, 1, 3, 0}, Rgba{0, 1, 0, 100},
                                        Rgba{1, 2, 0, 201}};
    Rgba want{};
    for (std::size_t c = 0; c < 4; ++c) {
        const int a = texels[0][c], bb = texels[1][c], cc = texels[2][c], d = texels[3][c];
        want[c] = static_cast<std::uint8_t>((((a + bb + 1) >> 1) + ((cc + d + 1) >> 1) + 1) >> 1);
    }
    DrawList list;
    list.target = Target{2, 2, ColorFormat::Rgba8, DepthFormat::None, 1};
    list.textures = {Texture{{image2x2(texels)}, true}};
    list.draws.push_back(textured_quad(list.target, {1, 1, 1, 1}, 64, 64, 1, minified_state()));
    const auto fb = render_ok(*b, make_scene("texture-generated-mipmaps", list));
    ASSERT_EQ(fb.color8.size(), 2u * 2u * 4u);
    for (std::uint32_t y = 0; y < 2; ++y) {
        for (std::uint32_t x = 0; x < 2; ++x) {
            const Rgba got = pixel(fb, x, y);
            if (!softpipe()) {
                EXPECT_EQ(got, want) << x << "," << y << " got " << show(got);
                continue;
            }
            for (std::size_t c = 0; c < 4; ++c) {
                const int sum = texels[0][c] + texels[1][c] + texels[2][c] + texels[3][c];
                EXPECT_LE(std::abs(4 * got[c] - sum), 2)
                    << x << "," << y << " channel " << c << " got " << show(got);
            }
        }
    }
}

TEST_P(GlBackend, BadTexturesAreCleanFailures) {
    auto b = make();
    DrawList list;
    list.target = Target{2, 2, ColorFormat::Rgba8, DepthFormat::None, 1};
    list.textures = {Texture{{image2x2({})}, false}};
    TextureState state = nearest_state(TextureEnv::Replace);
    state.texture = 1;  // there is one texture
    list.draws.push_back(textured_quad(list.target, {1, 1, 1, 1}, 1, 1, 1, state));
    auto r = b->render(make_scene("texture-missing", list));
    EXPECT_EQ(r.status, RenderStatus::InternalError) << r.message;
    EXPECT_NE(r.message.find("texture 1"), std::string::npos) << r.message;

    // Wider than any GL_MAX_TEXTURE_SIZE: the driver cannot, and says so.
    list.draws[0].state.texture->texture = 0;
    list.textures[0].levels[0] =
        TextureImage{1u << 16, 1, std::vector<std::uint8_t>(std::size_t{4} << 16, 7)};
    r = b->render(make_scene("texture-too-wide", list));
    EXPECT_EQ(r.status, RenderStatus::NotSupported) << r.message;
    EXPECT_NE(r.message.find("GL_MAX_TEXTURE_SIZE"), std::string::npos) << r.message;

    // The worker lives on and textures again.
    list.textures[0].levels[0] =
        image2x2({Rgba{1, 2, 3, 4}, Rgba{5, 6, 7, 8}, Rgba{9, 10, 11, 12}, Rgba{13, 14, 15, 16}});
    const auto fb = render_ok(*b, make_scene("texture-after-failures", list));
    ASSERT_EQ(fb.color8.size(), 2u * 2u * 4u);
    EXPECT_EQ(pixel(fb, 1, 1), (Rgba{13, 14, 15, 16}));
}

#if REFRASTER_TEST_EGL
// Both backends render into framebuffer objects of the same formats with the same driver, so
// they must agree bit for bit (measured: every scene of a 400-scene random sweep did).
TEST_P(GlBackend, EglAndOsmesaAgreeBitForBit) {
    const auto osmesa_worker =
        std::filesystem::path(REFRASTER_TEST_WORKER_DIR) / "refraster-worker-osmesa";
    if (!std::filesystem::exists(osmesa_worker)) GTEST_SKIP() << "osmesa worker not built";
    auto egl = make();
    harness::BackendOptions o;
    o.kind = harness::BackendKind::OSMesa;
    o.driver = GetParam();
    harness::GlWorkerBackend osmesa(o);

    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> pos(-1.3f, 1.3f);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (const auto depth : {DepthFormat::Z24, DepthFormat::Z16, DepthFormat::Z32f}) {
        DrawList list;
        list.target = Target{64, 64, ColorFormat::Rgba8, depth, 1};
        list.clear.color = {0.1f, 0.2f, 0.3f, 1.0f};
        for (int k = 0; k < 7; ++k) {
            std::vector<Vertex> vs;
            for (int v = 0; v < 90; ++v) {
                const float w = 0.5f + 2.0f * unit(rng);
                vs.push_back({{pos(rng) * w, pos(rng) * w, (2.0f * unit(rng) - 1.0f) * w, w},
                              {unit(rng), unit(rng), unit(rng), unit(rng)}});
            }
            Draw d = make_draw(static_cast<PrimitiveType>(k), vs, list.target);
            d.state.depth_test = CompareFunc::Lequal;
            d.state.shade = k % 2 ? ShadeModel::Smooth : ShadeModel::Flat;
            d.state.blend = static_cast<BlendPreset>(k % 3);
            d.state.line_width = static_cast<float>(1 + k % 3);
            d.state.point_size = static_cast<float>(1 + k % 4);
            list.draws.push_back(d);
        }
        const auto s = make_scene("cross-backend", list);
        const auto a = render_ok(osmesa, s);
        const auto b = render_ok(*egl, s);
        EXPECT_EQ(a.color8, b.color8) << "depth format " << to_string(depth);
        EXPECT_EQ(a.depth, b.depth) << "depth format " << to_string(depth);

        // And at 4x, every sample (llvmpipe only: softpipe has no multisampling).
        if (softpipe()) continue;
        list.target.samples = 4;
        for (std::size_t k = 0; k < list.draws.size(); ++k) {
            list.draws[k].state.multisample = k % 3 != 2;
        }
        const auto s4 = make_scene("cross-backend-4x", list);
        const auto a4 = osmesa.render_owners(s4);
        const auto b4 = egl->render_owners(s4);
        ASSERT_EQ(a4.status, RenderStatus::Ok) << a4.message;
        ASSERT_EQ(b4.status, RenderStatus::Ok) << b4.message;
        EXPECT_EQ(a4.samples, b4.samples) << "4x, depth format " << to_string(depth);
        EXPECT_EQ(a4.image, b4.image) << "4x, depth format " << to_string(depth);
    }
}
#endif

std::string driver_label(const ::testing::TestParamInfo<Driver>& p) {
    return p.param.name();
}

#if REFRASTER_TEST_EGL
// zink (GL on Vulkan, here on lavapipe) through --driver zink: the loader override chooses it,
// and the provenance names zink, its Vulkan driver and the variables that chose them.
TEST(GlBackendZink, NamesZinkItsVulkanDriverAndTheVariablesThatChoseThem) {
    ::setenv("REFRASTER_WORKER_DIR", REFRASTER_TEST_WORKER_DIR, 0);
    harness::BackendOptions o;
    o.kind = harness::BackendKind::Egl;
    o.driver = Driver::Zink;
    harness::GlWorkerBackend b(o);
    EXPECT_EQ(b.name(), "egl-zink");
    DrawList list;
    list.target = Target{8, 8, ColorFormat::Rgba8, DepthFormat::None, 1};
    list.draws.push_back(
        lower_left_triangle(list.target, {1, 0, 0, 1}, {1, 0, 0, 1}, {1, 0, 0, 1}));
    const auto r = b.render(make_scene("zink-triangle", list));
    ASSERT_EQ(r.status, RenderStatus::Ok) << r.message;
    EXPECT_EQ(r.provenance.at("driver"), "zink");
    EXPECT_EQ(r.provenance.at("renderer").rfind("zink", 0), 0u) << r.provenance.at("renderer");
    EXPECT_NE(r.provenance.at("vulkan_driver").find("lavapipe"), std::string::npos);
    EXPECT_FALSE(r.provenance.at("gl_vendor").empty());
    const std::string env = r.provenance.at("env");
    EXPECT_NE(env.find("MESA_LOADER_DRIVER_OVERRIDE=zink"), std::string::npos) << env;
    EXPECT_NE(env.find("LIBGL_ALWAYS_SOFTWARE=1"), std::string::npos) << env;
    EXPECT_EQ(env.find("GALLIUM_DRIVER="), std::string::npos) << env;
    EXPECT_EQ(pixel(r.image, 0, 0), (Rgba{255, 0, 0, 255}));
    EXPECT_EQ(pixel(r.image, 7, 7), kTransparent);
}

// A worker whose GL runs another driver than the one asked for is refused, never labelled
// with the name asked for.
TEST(GlBackendZink, AWorkerRunningAnotherDriverThanAskedIsRefused) {
    ::setenv("REFRASTER_WORKER_DIR", REFRASTER_TEST_WORKER_DIR, 0);
    harness::BackendOptions o;
    o.kind = harness::BackendKind::Egl;
    o.driver = Driver::Llvmpipe;
    o.environment = {"MESA_LOADER_DRIVER_OVERRIDE=zink"};
    harness::GlWorkerBackend b(o);
    DrawList list;
    list.target = Target{4, 4, ColorFormat::Rgba8, DepthFormat::None, 1};
    const auto r = b.render(make_scene("wrong-driver", list));
    EXPECT_EQ(r.status, RenderStatus::InternalError);
    EXPECT_NE(r.message.find("asked for llvmpipe but Mesa loaded zink"), std::string::npos)
        << r.message;
}

// llvmpipe under GALLIVM_PERF=rho_approx (OpenGL 4.6, 8.14.1's approximation of rho),
// brilinear, no_aos_sampling and combinations: every shipped textured scene byte for byte as
// the reference under the profile rules (texture_rho, texture_mip_blend, texture_filtering),
// some of them different under the default rules, and the fingerprint recovers the rules.
TEST(GlBackendTexture, GallivmPerfTextureRulesAreProfileRules) {
    ::setenv("REFRASTER_WORKER_DIR", REFRASTER_TEST_WORKER_DIR, 0);
    struct Case {
        const char* perf;
        std::vector<std::string> rules;
    };
    for (const auto& c :
         {Case{"rho_approx", {"texture_rho=approx"}},
          Case{"brilinear", {"texture_mip_blend=brilinear"}},
          Case{"rho_approx,brilinear", {"texture_rho=approx", "texture_mip_blend=brilinear"}},
          Case{"no_aos_sampling", {"texture_filtering=float"}},
          Case{"no_aos_sampling,brilinear",
               {"texture_filtering=float", "texture_mip_blend=brilinear"}}}) {
        harness::BackendOptions o;
        o.kind = harness::BackendKind::Egl;
        o.driver = Driver::Llvmpipe;
        o.environment = {std::string("GALLIVM_PERF=") + c.perf};
        harness::GlWorkerBackend gl(o);
        auto want = refraster::llvmpipe_22_3_profile();
        harness::apply_profile_overrides(want, c.rules);
        const auto same = [](const harness::RenderResult& a, const harness::RenderResult& b) {
            return a.image.color8 == b.image.color8 && a.image.color32f == b.image.color32f &&
                   a.image.depth == b.image.depth && a.samples.color8 == b.samples.color8 &&
                   a.samples.color32f == b.samples.color32f;
        };
        std::size_t textured = 0, differ_under_default = 0;
        for (const auto& e : std::filesystem::recursive_directory_iterator(
                 std::filesystem::path(REFRASTER_SOURCE_DIR) / "conformance/scenes")) {
            if (!e.is_regular_file() || e.path().extension() != ".json") continue;
            harness::Scene scene;
            try {
                scene = harness::load_scene(e.path());
            } catch (const harness::SceneError&) {
                continue;  // a PNG texture: this program reads no image files
            }
            const auto& draws = scene.draw_list.draws;
            if (std::none_of(draws.begin(), draws.end(),
                             [](const auto& d) { return d.state.texture.has_value(); }))
                continue;
            ++textured;
            const auto backend = gl.render(scene);
            ASSERT_EQ(backend.status, RenderStatus::Ok) << e.path() << ": " << backend.message;
            for (const bool modelled : {true, false}) {
                const auto ref = harness::make_reference_backend(
                                     modelled ? want : refraster::llvmpipe_22_3_profile())
                                     ->render(scene);
                ASSERT_EQ(ref.status, RenderStatus::Ok) << e.path();
                if (modelled) {
                    EXPECT_TRUE(same(ref, backend)) << c.perf << ": " << e.path();
                } else {
                    differ_under_default += !same(ref, backend);
                }
            }
        }
        EXPECT_GT(textured, 50u);
        EXPECT_GT(differ_under_default, 0u) << c.perf;
        const auto f = harness::fingerprint(gl);
        EXPECT_EQ(harness::profile_rules(f.profile), harness::profile_rules(want))
            << c.perf << "\n"
            << harness::fingerprint_text(f);
        EXPECT_TRUE(f.complete()) << harness::fingerprint_text(f);
    }
}

// The GL verdict on zink, an implementation no profile models, one case per kind: its twice
// Mesa's polygon offset r (single sample and sample by sample on 4x) and its points clipped by
// their pixels are legal; its ignoring GL_MULTISAMPLE disabled and a polygon's edge flags are
// violations named by the requirement. The fingerprint finds both of its freedoms.
TEST(GlBackendZink, VerdictsNameEachKindAndTheFingerprintFindsItsFreedoms) {
    ::setenv("REFRASTER_WORKER_DIR", REFRASTER_TEST_WORKER_DIR, 0);
    harness::BackendOptions o;
    o.kind = harness::BackendKind::Egl;
    o.driver = Driver::Zink;
    harness::GlWorkerBackend zink(o);
    const auto profile = refraster::llvmpipe_22_3_profile();
    const auto judge = [&](const char* relative) {
        const auto scene = harness::load_scene(std::filesystem::path(REFRASTER_SOURCE_DIR) /
                                               "conformance/scenes" / relative);
        const auto ref = harness::make_reference_backend(profile)->render(scene);
        const auto r = zink.render(scene);
        EXPECT_EQ(ref.status, RenderStatus::Ok) << ref.message;
        EXPECT_EQ(r.status, RenderStatus::Ok) << r.message;
        // A 4x target sample by sample.
        const bool ms = ref.samples.width > 0;
        return harness::gl_verdict(scene, profile, ms ? ref.samples : ref.image,
                                   ms ? r.samples : r.image);
    };
    const auto named = [](const harness::GlVerdict& v, const std::string& words, bool legal) {
        for (const auto& f : v.findings)
            if (f.legal == legal && f.rule.find(words) != std::string::npos) return true;
        return false;
    };
    for (const char* legal : {"triangles/attributes/polygon_offset_z24_f0_um2.json",
                              "msaa/polygon_offset_z24_units_coplanar.json"}) {
        const auto v = judge(legal);
        EXPECT_GT(v.differing, 0u) << legal;
        EXPECT_TRUE(v.passes()) << legal << ": " << v.summary();
        EXPECT_TRUE(named(v, "polygon offset", true)) << legal << ": " << v.summary();
    }
    {
        const auto v = judge("points/clipped_by_centre.json");
        EXPECT_TRUE(v.passes()) << v.summary();
        EXPECT_TRUE(named(v, "point and line clipping policy", true)) << v.summary();
    }
    {
        const auto v = judge("msaa/multisample_off_triangles.json");
        EXPECT_EQ(v.unit, "samples");
        EXPECT_GT(v.violations, 0u) << v.summary();
        EXPECT_TRUE(named(v, "GL_MULTISAMPLE disabled is ignored", false)) << v.summary();
    }
    {
        const auto v = judge("polygons/outline_polygon_mode_line_first.json");
        EXPECT_GT(v.violations, 0u) << v.summary();
        EXPECT_TRUE(named(v, "edge flags ignored", false)) << v.summary();
    }
    const auto f = harness::fingerprint(zink, {}, [&o]() -> std::unique_ptr<harness::Backend> {
        return std::make_unique<harness::GlWorkerBackend>(o);
    });
    EXPECT_TRUE(f.complete()) << harness::fingerprint_text(f);
    EXPECT_EQ(f.profile.gl.point_line_clipping, refraster::PointLineClipping::Pixels)
        << harness::fingerprint_text(f);
    EXPECT_EQ(f.profile.gl.offset_units_scale, 2.0f) << harness::fingerprint_text(f);
    EXPECT_EQ(f.profile.gl.clipping, refraster::Clipping::ViewVolume)
        << harness::fingerprint_text(f);
    // The state it ignores: findings, each naming what GL requires.
    for (const char* key : {"multisample_enable", "edge_flags"}) {
        const auto it = std::find_if(f.rules.begin(), f.rules.end(),
                                     [&](const auto& r) { return r.key == key; });
        ASSERT_NE(it, f.rules.end()) << key;
        EXPECT_EQ(it->value, "ignored") << key << ": " << it->evidence;
    }
    // The point sprite origin of the worker's first sprite sticks: told from an ignored one by
    // swapping the origins in a fresh worker.
    const auto sprite = std::find_if(f.rules.begin(), f.rules.end(),
                                     [](const auto& r) { return r.key == "point_sprite_origin"; });
    ASSERT_NE(sprite, f.rules.end());
    EXPECT_EQ(sprite->value, "order-dependent") << sprite->evidence;
    // explain names the rule zink breaks in an outline, as the verdict does.
    const auto outline = harness::load_scene(std::filesystem::path(REFRASTER_SOURCE_DIR) /
                                             "conformance/scenes/polygons/outline_clipped.json");
    harness::Explainer ex(outline, profile, &zink);
    const auto& ref = ex.reference_image();
    std::size_t named_edge_flags = 0, differing = 0;
    for (std::uint32_t y = 0; y < ref.height; ++y) {
        for (std::uint32_t x = 0; x < ref.width; ++x) {
            if (ex.classifier()->at(ref.index(x, y)).cls == harness::PixelClass::Equal) continue;
            ++differing;
            const auto e = ex.explain(static_cast<int>(x), static_cast<int>(y), false);
            named_edge_flags += e.rule == "edge flags";
        }
    }
    EXPECT_GT(differing, 0u);
    EXPECT_EQ(named_edge_flags, differing);
}
#endif

INSTANTIATE_TEST_SUITE_P(Drivers, GlBackend, ::testing::Values(Driver::Llvmpipe, Driver::Softpipe),
                         driver_label);

}  // namespace

// A Mesa build of one's own (--mesa-prefix): a copy of the system's libraries placed under a
// temporary prefix is what the worker loads, and its provenance names the copy, not the
// system's library, with the version GL reports.
TEST(GlBackendMesaPrefix, LoadsTheLibrariesUnderThePrefix) {
    ::setenv("REFRASTER_WORKER_DIR", REFRASTER_TEST_WORKER_DIR, 0);
    namespace fs = std::filesystem;
    const auto system_library = [](const std::string& name) -> fs::path {
        for (const char* d : {"/usr/lib/x86_64-linux-gnu", "/usr/lib/aarch64-linux-gnu",
                              "/usr/lib64", "/usr/lib"}) {
            if (fs::exists(fs::path(d) / name)) return fs::canonical(fs::path(d) / name);
        }
        return {};
    };
    const std::string main_library =
        kKind == harness::BackendKind::Egl ? "libEGL_mesa.so.0" : "libOSMesa.so.8";
    const fs::path original = system_library(main_library);
    if (original.empty()) GTEST_SKIP() << main_library << " not found";
    char tmpl[] = "/tmp/refraster-mesa-prefix-XXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    const fs::path prefix = tmpl;
    const fs::path lib = prefix / "lib/x86_64-linux-gnu";
    fs::create_directories(lib);
    fs::copy_file(original, lib / main_library);
    if (kKind == harness::BackendKind::Egl) {
        const fs::path dri = system_library("dri/swrast_dri.so");
        ASSERT_FALSE(dri.empty());
        fs::create_directories(lib / "dri");
        fs::copy_file(dri, lib / "dri/swrast_dri.so");
        fs::create_directories(prefix / "share/glvnd/egl_vendor.d");
        std::ofstream(prefix / "share/glvnd/egl_vendor.d/50_mesa.json")
            << R"({"file_format_version": "1.0.0", "ICD": {"library_path": "libEGL_mesa.so.0"}})";
    }
    const Target t{8, 8, ColorFormat::Rgba8, DepthFormat::None, 1};
    DrawList list;
    list.target = t;
    list.draws.push_back(lower_left_triangle(t, {1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}));
    const auto scene = make_scene("mesa_prefix", list);
    const auto render_with = [&](const fs::path& p) {
        harness::BackendOptions o;
        o.kind = kKind;
        o.mesa_prefix = p;
        auto backend = harness::make_backend(o);
        return backend->render(scene);
    };
    const auto system = render_with({});
    ASSERT_EQ(system.status, RenderStatus::Ok) << system.message;
    const auto own = render_with(prefix);
    ASSERT_EQ(own.status, RenderStatus::Ok) << own.message;
    const std::string libs = own.provenance.at("libraries");
    EXPECT_NE(libs.find((lib / main_library).string()), std::string::npos) << libs;
    EXPECT_EQ(libs.find(original.string()), std::string::npos) << libs;
    EXPECT_NE(system.provenance.at("libraries").find(original.string()), std::string::npos)
        << system.provenance.at("libraries");
    if (kKind == harness::BackendKind::Egl) {
        EXPECT_NE(libs.find((lib / "dri/swrast_dri.so").string()), std::string::npos) << libs;
    }
    EXPECT_EQ(own.provenance.at("mesa_prefix"), fs::absolute(prefix).string());
    EXPECT_NE(own.provenance.at("gl_version").find("Mesa " + own.provenance.at("mesa_version")),
              std::string::npos);
    // The same pixels: it is the same Mesa.
    EXPECT_EQ(own.image.color8, system.image.color8);
    // A prefix without Mesa is bad input.
    EXPECT_THROW(render_with(prefix / "share"), harness::MesaPrefixError);
    fs::remove_all(prefix);
}

#if REFRASTER_TEST_EGL
// EGL devices: the worker lists what EGL_EXT_device_enumeration offers (here Mesa's software
// device), renders on the chosen one with the surfaceless platform's pixels, records the
// device in the provenance, and refuses a device that does not exist.
TEST(GlBackendEglDevice, ListsRendersOnAndRecordsTheDevice) {
    ::setenv("REFRASTER_WORKER_DIR", REFRASTER_TEST_WORKER_DIR, 0);
    harness::BackendOptions o;
    o.kind = harness::BackendKind::Egl;
    const auto devices = harness::list_egl_devices(o);
    ASSERT_FALSE(devices.empty());
    int software = -1;
    for (std::size_t i = 0; i < devices.size(); ++i) {
        EXPECT_EQ(devices[i].rfind(std::to_string(i) + ": ", 0), 0u) << devices[i];
        if (software < 0 && devices[i].find("EGL_MESA_device_software") != std::string::npos)
            software = static_cast<int>(i);
    }
    ASSERT_GE(software, 0) << "no software device";
    const Target t{8, 8, ColorFormat::Rgba8, DepthFormat::None, 1};
    DrawList list;
    list.target = t;
    list.draws.push_back(lower_left_triangle(t, {1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}));
    const auto scene = make_scene("egl_device", list);
    const auto surfaceless = harness::make_backend(o)->render(scene);
    ASSERT_EQ(surfaceless.status, RenderStatus::Ok) << surfaceless.message;
    EXPECT_EQ(surfaceless.provenance.at("egl_platform"), "surfaceless");
    o.egl_device = software;
    const auto on_device = harness::make_backend(o)->render(scene);
    ASSERT_EQ(on_device.status, RenderStatus::Ok) << on_device.message;
    EXPECT_EQ(on_device.provenance.at("egl_platform"), "device");
    EXPECT_EQ(on_device.provenance.at("egl_device"), std::to_string(software));
    EXPECT_NE(on_device.provenance.at("egl_device_extensions").find("EGL_MESA_device_software"),
              std::string::npos);
    EXPECT_EQ(on_device.provenance.at("renderer"), surfaceless.provenance.at("renderer"));
    EXPECT_EQ(on_device.image.color8, surfaceless.image.color8);
    // A device that does not exist: the worker cannot start, and says why.
    o.egl_device = static_cast<int>(devices.size()) + 3;
    const auto missing = harness::make_backend(o)->render(scene);
    EXPECT_NE(missing.status, RenderStatus::Ok);
    EXPECT_NE(missing.message.find("does not exist"), std::string::npos) << missing.message;
    // Not a backend with devices.
    o.kind = harness::BackendKind::OSMesa;
    o.egl_device = 0;
    EXPECT_THROW(harness::make_backend(o), harness::BackendOptionError);
}
// The command line: --egl-device list answers before anything else is required, and a device
// index that is not a number is bad input.
TEST(GlBackendEglDevice, CommandLine) {
    const std::string bin = std::string(REFRASTER_TEST_WORKER_DIR) + "/refraster";
    if (!std::filesystem::exists(bin)) GTEST_SKIP() << "no refraster binary beside the workers";
    FILE* p =
        ::popen(("'" + bin + "' conformance run --against egl --egl-device list").c_str(), "r");
    ASSERT_NE(p, nullptr);
    std::string out;
    char buf[1024];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    EXPECT_EQ(::pclose(p), 0);
    EXPECT_EQ(out.rfind("0: ", 0), 0u) << out;
    char tmpl[] = "/tmp/refraster-egl-device-XXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    const std::filesystem::path out_dir = std::filesystem::path(tmpl) / "out";
    EXPECT_EQ(std::system(("'" + bin +
                           "' conformance run --against egl --cases smoke.triangles --egl-device "
                           "first --output '" +
                           out_dir.string() + "' > /dev/null 2>&1")
                              .c_str()) >>
                  8,
              2);
    EXPECT_FALSE(std::filesystem::exists(out_dir));
    std::filesystem::remove_all(tmpl);
}
#endif
