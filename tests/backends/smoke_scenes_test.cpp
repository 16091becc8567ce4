// The smoke scenes through the GL backends, checked against pixels derived by hand from each
// scene's description (every edge chosen so that no pixel centre is in doubt), and OSMesa
// against EGL byte for byte.
#include <gtest/gtest.h>

#include <functional>

#include "harness/backend.hpp"
#include "harness/scene.hpp"

namespace {

using Rgba = std::array<std::uint8_t, 4>;
using Expected = std::function<Rgba(std::uint32_t x, std::uint32_t y)>;

constexpr Rgba kBlack{0, 0, 0, 255};
constexpr Rgba kRed{255, 0, 0, 255};
constexpr Rgba kGreen{0, 255, 0, 255};
constexpr Rgba kBlue{0, 0, 255, 255};
constexpr Rgba kYellow{255, 255, 0, 255};
constexpr Rgba kCyan{0, 255, 255, 255};
constexpr Rgba kWhite{255, 255, 255, 255};

bool in(std::uint32_t v, std::uint32_t lo, std::uint32_t hi) {
    return v >= lo && v <= hi;
}

struct SmokeCase {
    std::string file;
    Expected color;
    std::function<std::uint32_t(std::uint32_t, std::uint32_t)> depth;  // empty: no depth
};

std::vector<SmokeCase> smoke_cases() {
    return {
        {"triangles",
         [](auto x, auto y) { return in(x, 2, 5) && in(y, 1, 4) ? kRed : kBlack; },
         {}},
        {"triangle_strip",
         [](auto x, auto y) { return in(x, 1, 6) && in(y, 2, 3) ? kGreen : kBlack; },
         {}},
        {"triangle_fan",
         [](auto x, auto y) { return in(x, 1, 6) && in(y, 1, 6) ? kBlue : kBlack; },
         {}},
        {"depth",
         [](auto x, auto y) {
             if (x <= 5 && y <= 5) return kRed;
             return x >= 2 && y >= 2 ? kGreen : kBlack;
         },
         // Fragment depth RNE(fl(z * (2^24-1))): 0.25 -> 4194303.75 -> 4194304 and
         // 0.75 -> 12582911.25 -> 12582911; the clear value 1.0 -> 16777215.
         [](auto x, auto y) -> std::uint32_t {
             if (x <= 5 && y <= 5) return 4194304u;
             return x >= 2 && y >= 2 ? 12582911u : 16777215u;
         }},
        {"clip_space", [](auto x, auto y) { return x <= 5 && in(y, 2, 5) ? kWhite : kBlack; }, {}},
        {"lines",
         [](auto x, auto y) {
             if (x == 6 && y <= 5) return kCyan;
             return y == 3 && in(x, 1, 5) ? kYellow : kBlack;
         },
         {}},
        {"points",
         [](auto x, auto y) {
             if (x == 2 && y == 2) return kRed;
             if (in(x, 4, 6) && in(y, 4, 6)) return kGreen;
             return in(x, 1, 2) && in(y, 5, 6) ? kBlue : kBlack;
         },
         {}},
        {"blending",
         [](auto x, auto y) {
             if (x >= 6 && y >= 6) return kWhite;
             if (x <= 1) return kRed;
             if (x <= 3) return kYellow;
             return x <= 5 ? kGreen : kBlack;
         },
         {}},
    };
}

std::vector<harness::BackendKind> built_backends() {
    std::vector<harness::BackendKind> k;
#ifdef REFRASTER_HAVE_OSMESA
    k.push_back(harness::BackendKind::OSMesa);
#endif
#ifdef REFRASTER_HAVE_EGL
    k.push_back(harness::BackendKind::Egl);
#endif
    return k;
}

harness::Scene load(const std::string& name) {
    return harness::load_scene(std::filesystem::path(REFRASTER_SOURCE_DIR) /
                               "conformance/scenes/smoke" / (name + ".json"));
}

class SmokeScenes : public ::testing::TestWithParam<harness::BackendKind> {};

TEST_P(SmokeScenes, MatchHandDerivedPixels) {
    harness::BackendOptions o;
    o.kind = GetParam();
    auto backend = harness::make_backend(o);
    for (const auto& c : smoke_cases()) {
        SCOPED_TRACE(c.file);
        const auto scene = load(c.file);
        const auto r = backend->render(scene);
        ASSERT_EQ(r.status, harness::RenderStatus::Ok) << r.message;
        const auto& fb = r.image;
        ASSERT_EQ(fb.width, 8u);
        ASSERT_EQ(fb.height, 8u);
        int wrong = 0;
        for (std::uint32_t y = 0; y < 8; ++y) {
            for (std::uint32_t x = 0; x < 8; ++x) {
                const auto i = 4 * fb.index(x, y);
                const Rgba got{fb.color8[i], fb.color8[i + 1], fb.color8[i + 2], fb.color8[i + 3]};
                const Rgba want = c.color(x, y);
                if (got != want && ++wrong <= 4) {
                    ADD_FAILURE() << "pixel (" << x << ", " << y << "): got " << int{got[0]} << ","
                                  << int{got[1]} << "," << int{got[2]} << "," << int{got[3]}
                                  << " want " << int{want[0]} << "," << int{want[1]} << ","
                                  << int{want[2]} << "," << int{want[3]};
                }
                if (c.depth) {
                    EXPECT_EQ(fb.depth.at(fb.index(x, y)), c.depth(x, y))
                        << "depth at (" << x << ", " << y << ")";
                }
            }
        }
        EXPECT_EQ(wrong, 0);
    }
}

std::string backend_name(const ::testing::TestParamInfo<harness::BackendKind>& p) {
    return std::string(harness::to_string(p.param));
}

INSTANTIATE_TEST_SUITE_P(Gl, SmokeScenes, ::testing::ValuesIn(built_backends()), backend_name);

#if defined(REFRASTER_HAVE_OSMESA) && defined(REFRASTER_HAVE_EGL)
// The two GL paths render the same FBO through the same driver: every smoke scene must agree
// byte for byte, colour and depth, for llvmpipe and softpipe alike.
TEST(SmokeScenesAcrossBackends, OSMesaAndEglByteEqual) {
    for (auto driver : {harness::Driver::Llvmpipe, harness::Driver::Softpipe}) {
        harness::BackendOptions o;
        o.driver = driver;
        o.kind = harness::BackendKind::OSMesa;
        auto osmesa = harness::make_backend(o);
        o.kind = harness::BackendKind::Egl;
        auto egl = harness::make_backend(o);
        for (const auto& c : smoke_cases()) {
            SCOPED_TRACE(c.file + " " + std::string(harness::to_string(driver)));
            const auto scene = load(c.file);
            const auto a = osmesa->render(scene);
            const auto b = egl->render(scene);
            ASSERT_EQ(a.status, harness::RenderStatus::Ok) << a.message;
            ASSERT_EQ(b.status, harness::RenderStatus::Ok) << b.message;
            EXPECT_EQ(a.image.color8, b.image.color8);
            EXPECT_EQ(a.image.depth, b.image.depth);
            EXPECT_NE(a.provenance.at("renderer").find(std::string(harness::to_string(driver))),
                      std::string::npos)
                << a.provenance.at("renderer");
        }
    }
}
#endif

}  // namespace
