// refraster fingerprint (harness/fingerprint.hpp) against backends whose rules are known: the
// reference under every single-rule mutation of both driver profiles is fingerprinted back to
// exactly that profile, and rules a backend's pixels cannot decide are reported undecided.
// (Recovering llvmpipe-22.3 and softpipe-22.3 from OSMesa: tests/backends/softpipe_coverage_test.)
#include "harness/fingerprint.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "harness/backend.hpp"
#include "harness/profile_io.hpp"
#include "refraster/profile.hpp"
#include "refraster/renderer.hpp"

namespace {

std::unique_ptr<harness::Backend> reference(const refraster::Profile& p) {
    return harness::make_reference_backend(p);
}

const harness::RuleFinding* finding(const harness::FingerprintResult& r, const std::string& key) {
    for (const auto& f : r.rules)
        if (f.key == key) return &f;
    return nullptr;
}

struct Mutation {
    const char* base;
    const char* rule;  // key=value
};

class FingerprintMutation : public ::testing::TestWithParam<Mutation> {};

// Each rule flipped in turn: the fingerprint names every rule of the mutated profile, all
// decided, and each decided rule carries evidence.
TEST_P(FingerprintMutation, RecoversTheMutatedProfile) {
    refraster::Profile want = refraster::builtin_profile(GetParam().base);
    harness::apply_profile_overrides(want, {GetParam().rule});
    harness::name_by_rules(want);
    const auto backend = reference(want);
    const auto r = harness::fingerprint(*backend);
    EXPECT_TRUE(r.complete()) << harness::fingerprint_text(r);
    EXPECT_EQ(harness::profile_rules(r.profile), harness::profile_rules(want))
        << harness::fingerprint_text(r);
    EXPECT_EQ(r.profile.name, want.name);
    for (const auto& f : r.rules) {
        if (f.decided) {
            EXPECT_FALSE(f.evidence.empty()) << f.key;
        }
    }
}

// A test name of the rule: "tie_rule_right_top".
std::string mutation_name(const ::testing::TestParamInfo<Mutation>& info) {
    std::string s = info.param.rule;
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

// On a CPU with FMA, "auto" fuses; the flip is the other value.
const char* other_fma() {
    return refraster::host_has_fma() ? "viewport_fma=off" : "viewport_fma=on";
}

INSTANTIATE_TEST_SUITE_P(Llvmpipe, FingerprintMutation,
                         ::testing::Values(Mutation{"llvmpipe-22.3", "subpixel_bits=4"},
                                           Mutation{"llvmpipe-22.3", "subpixel_bits=6"},
                                           Mutation{"llvmpipe-22.3", "snap_rounding=half-away"},
                                           Mutation{"llvmpipe-22.3", "snap_rounding=truncate"},
                                           Mutation{"llvmpipe-22.3", "pixel_center_offset=0"},
                                           Mutation{"llvmpipe-22.3", "tie_rule=left-top"},
                                           Mutation{"llvmpipe-22.3", "tie_rule=right-bottom"},
                                           Mutation{"llvmpipe-22.3", "tie_rule=right-top"},
                                           Mutation{"llvmpipe-22.3", "clipping=guard-band"},
                                           Mutation{"llvmpipe-22.3", other_fma()},
                                           Mutation{"llvmpipe-22.3", "depth_rounding=truncate"},
                                           Mutation{"llvmpipe-22.3", "depth_clear=float"},
                                           Mutation{"llvmpipe-22.3", "color_rounding=truncate"},
                                           Mutation{"llvmpipe-22.3", "line_rule=bresenham"},
                                           Mutation{"llvmpipe-22.3", "point_rule=two-triangles"},
                                           Mutation{"llvmpipe-22.3", "offset_units_scale=2"},
                                           Mutation{"llvmpipe-22.3", "point_line_clipping=pixels"},
                                           Mutation{"llvmpipe-22.3", "texture_rho=approx"},
                                           Mutation{"llvmpipe-22.3", "texture_mip_blend=brilinear"},
                                           Mutation{"llvmpipe-22.3", "texture_filtering=float"}),
                         mutation_name);

INSTANTIATE_TEST_SUITE_P(Softpipe, FingerprintMutation,
                         ::testing::Values(Mutation{"softpipe-22.3", "viewport_fma=on"},
                                           Mutation{"softpipe-22.3", "clipping=guard-band"},
                                           Mutation{"softpipe-22.3", "depth_rounding=nearest"},
                                           Mutation{"softpipe-22.3", "depth_clear=float"},
                                           Mutation{"softpipe-22.3", "color_rounding=truncate"},
                                           Mutation{"softpipe-22.3", "line_rule=parallelogram"},
                                           Mutation{"softpipe-22.3", "point_rule=square"},
                                           Mutation{"softpipe-22.3", "offset_units_scale=0.5"},
                                           Mutation{"softpipe-22.3", "point_line_clipping=pixels"}),
                         mutation_name);

TEST(Fingerprint, BuiltInProfilesComeBackUnchanged) {
    for (const char* name : {"llvmpipe-22.3", "softpipe-22.3"}) {
        const auto backend = reference(refraster::builtin_profile(name));
        const auto r = harness::fingerprint(*backend);
        EXPECT_TRUE(r.complete()) << harness::fingerprint_text(r);
        EXPECT_EQ(r.profile, refraster::builtin_profile(name)) << harness::fingerprint_text(r);
        // The reference honours the draw state GL requires (softpipe's family draws no 4x).
        for (const auto& f : r.rules) {
            if (f.key == "edge_flags" ||
                (f.key == "multisample_enable" && std::string(name) == "llvmpipe-22.3")) {
                EXPECT_EQ(f.value, "honoured") << f.key << ": " << f.evidence;
            }
        }
    }
}

// A backend whose lines follow no rule the reference has (the reference's lines moved one
// pixel up) and which cannot draw rgba32f: the line rule and the fusion are undecided, with
// the reason, and every other rule is still decided.
class Unmodelled : public harness::Backend {
  public:
    Unmodelled() : inner_(reference(refraster::llvmpipe_22_3_profile())) {}
    harness::BackendKind kind() const override { return harness::BackendKind::Ref; }
    std::string name() const override { return "unmodelled"; }
    harness::RenderResult render(const harness::Scene& s) override {
        if (s.draw_list.target.color == refraster::ColorFormat::Rgba32f) {
            harness::RenderResult r;
            r.status = harness::RenderStatus::NotSupported;
            r.message = "no float targets";
            return r;
        }
        auto r = inner_->render(s);
        if (s.file.name == "lines") {
            auto& img = r.image;
            for (std::uint32_t y = img.height - 1; y > 0; --y)
                for (std::uint32_t x = 0; x < img.width; ++x)
                    for (std::size_t k = 0; k < 4; ++k)
                        img.color8[4 * img.index(x, y) + k] =
                            img.color8[4 * img.index(x, y - 1) + k];
        }
        return r;
    }

  private:
    std::unique_ptr<harness::Backend> inner_;
};

TEST(Fingerprint, UndecidableRulesAreReportedNotGuessed) {
    Unmodelled backend;
    const auto r = harness::fingerprint(backend);
    EXPECT_FALSE(r.complete());
    const auto* line = finding(r, "line_rule");
    ASSERT_NE(line, nullptr);
    EXPECT_FALSE(line->decided);
    EXPECT_EQ(line->value, "undecided");
    EXPECT_NE(line->evidence.find("no candidate reproduces"), std::string::npos) << line->evidence;
    const auto* fma = finding(r, "viewport_fma");
    ASSERT_NE(fma, nullptr);
    EXPECT_FALSE(fma->decided);
    EXPECT_NE(fma->evidence.find("draws none of the probes"), std::string::npos) << fma->evidence;
    for (const char* key : {"coverage", "tie_rule", "point_rule", "depth_rounding"}) {
        const auto* f = finding(r, key);
        ASSERT_NE(f, nullptr) << key;
        EXPECT_TRUE(f->decided) << key << ": " << f->evidence;
    }
}

// A backend whose rules differ per primitive class, as OpenGL 4.6 allows: scenes that draw only
// `cls` go through the reference under `cls_rules`, every other scene under llvmpipe-22.3.
class PerClass : public harness::Backend {
  public:
    PerClass(refraster::PrimitiveType cls, const std::vector<std::string>& cls_rules)
        : cls_(cls), inner_(reference(refraster::llvmpipe_22_3_profile())) {
        refraster::Profile p = refraster::llvmpipe_22_3_profile();
        harness::apply_profile_overrides(p, cls_rules);
        class_ = reference(p);
    }
    harness::BackendKind kind() const override { return harness::BackendKind::Ref; }
    std::string name() const override { return "per-class"; }
    harness::RenderResult render(const harness::Scene& s) override {
        const auto& d = s.draw_list.draws;
        const bool only = !d.empty() && std::all_of(d.begin(), d.end(), [&](const auto& x) {
            return x.primitive == cls_;
        });
        return (only ? class_ : inner_)->render(s);
    }

  private:
    refraster::PrimitiveType cls_;
    std::unique_ptr<harness::Backend> inner_, class_;
};

// Snapping and conversions decided from triangles are checked on lines and on points: a class
// that differs is named with the values that reproduce it and left undecided, while the
// triangles' rules stay decided and the other class agrees.
TEST(Fingerprint, EachPrimitiveClassIsCheckedAgainstTheRulesDecidedFromAnother) {
    struct Case {
        refraster::PrimitiveType cls;
        std::vector<std::string> rules;
        const char* differs;  // the finding that differs
        const char* agrees;   // one of the other class
        const char* named;    // in the evidence
    };
    for (const auto& c : {Case{refraster::PrimitiveType::Lines,
                               {"subpixel_bits=4"},
                               "line_snapping",
                               "point_snapping",
                               "subpixel_bits=4"},
                          Case{refraster::PrimitiveType::Points,
                               {"color_rounding=truncate"},
                               "point_precision",
                               "line_precision",
                               "color_rounding=truncate"}}) {
        PerClass backend(c.cls, c.rules);
        const auto r = harness::fingerprint(backend);
        EXPECT_FALSE(r.complete()) << harness::fingerprint_text(r);
        const auto* d = finding(r, c.differs);
        ASSERT_NE(d, nullptr) << c.differs;
        EXPECT_EQ(d->value, "differs") << d->evidence;
        EXPECT_FALSE(d->decided);
        EXPECT_NE(d->evidence.find(c.named), std::string::npos) << d->evidence;
        const auto* a = finding(r, c.agrees);
        ASSERT_NE(a, nullptr) << c.agrees;
        EXPECT_TRUE(a->decided) << a->evidence;
        EXPECT_EQ(a->value.rfind("as ", 0), 0u) << a->value;
        // The triangles' rules are the profile's.
        EXPECT_EQ(r.profile.gl.subpixel_bits, 8) << harness::fingerprint_text(r);
        EXPECT_EQ(r.profile.gl.color_rounding, refraster::Rounding::Nearest);
    }
}

// Point sprite origins (GL 14.4): a backend that keeps the first origin its worker drew with is
// order-dependent (seen only by swapping the origins in a fresh worker), one that always draws
// the default origin ignores the state, and the reference honours it.
class SpriteOrigin : public harness::Backend {
  public:
    enum class Fault { None, Sticky, Ignored };
    explicit SpriteOrigin(Fault f)
        : fault_(f), inner_(reference(refraster::llvmpipe_22_3_profile())) {}
    harness::BackendKind kind() const override { return harness::BackendKind::Ref; }
    std::string name() const override { return "sprites"; }
    harness::RenderResult render(const harness::Scene& s) override {
        harness::Scene changed = s;
        for (auto& d : changed.draw_list.draws) {
            if (!d.state.texture || !d.state.texture->coord_replace) continue;
            auto& origin = d.state.texture->point_coord_origin;
            if (fault_ == Fault::Ignored) origin = refraster::PointCoordOrigin::UpperLeft;
            if (fault_ == Fault::Sticky) {
                if (!first_) first_ = origin;
                origin = *first_;
            }
        }
        return inner_->render(changed);
    }

  private:
    Fault fault_;
    std::optional<refraster::PointCoordOrigin> first_;
    std::unique_ptr<harness::Backend> inner_;
};

TEST(Fingerprint, SpriteOriginsHonouredIgnoredOrOrderDependent) {
    using Fault = SpriteOrigin::Fault;
    const auto origin_of = [](Fault fault, bool with_fresh) {
        SpriteOrigin backend(fault);
        harness::FreshBackend fresh;
        if (with_fresh)
            fresh = [fault]() -> std::unique_ptr<harness::Backend> {
                return std::make_unique<SpriteOrigin>(fault);
            };
        const auto r = harness::fingerprint(backend, {}, fresh);
        const auto* f = finding(r, "point_sprite_origin");
        EXPECT_NE(f, nullptr);
        return f == nullptr ? std::string() : f->value + ": " + f->evidence;
    };
    EXPECT_EQ(origin_of(Fault::None, true).rfind("honoured: ", 0), 0u);
    EXPECT_EQ(origin_of(Fault::Sticky, true).rfind("order-dependent: ", 0), 0u)
        << origin_of(Fault::Sticky, true);
    EXPECT_EQ(origin_of(Fault::Ignored, true).rfind("ignored: ", 0), 0u);
    // Without a fresh worker a sticky origin looks ignored, and the finding says it may not be.
    const auto sticky_alone = origin_of(Fault::Sticky, false);
    EXPECT_EQ(sticky_alone.rfind("ignored: ", 0), 0u) << sticky_alone;
    EXPECT_NE(sticky_alone.find("first origin sticks"), std::string::npos) << sticky_alone;
}

// Textures: the reference's own sampler is found "as the profile"; a backend whose texels come
// out one step brighter (a filtering rule nobody modelled) leaves texture_sampling undecided,
// with the pixel, and the fingerprint incomplete.
class BrighterTexels : public harness::Backend {
  public:
    BrighterTexels() : inner_(reference(refraster::llvmpipe_22_3_profile())) {}
    harness::BackendKind kind() const override { return harness::BackendKind::Ref; }
    std::string name() const override { return "brighter texels"; }
    harness::RenderResult render(const harness::Scene& s) override {
        auto r = inner_->render(s);
        const bool textured =
            std::any_of(s.draw_list.draws.begin(), s.draw_list.draws.end(),
                        [](const auto& d) { return d.state.texture.has_value(); });
        if (textured && !s.draw_list.draws.front().state.texture->coord_replace) {
            for (auto& byte : r.image.color8)
                if (byte > 0 && byte < 255) ++byte;
        }
        return r;
    }

  private:
    std::unique_ptr<harness::Backend> inner_;
};

TEST(Fingerprint, TextureSamplingIsComparedNeverGuessed) {
    const auto own = harness::fingerprint(*reference(refraster::llvmpipe_22_3_profile()));
    const auto* f = finding(own, "texture_sampling");
    ASSERT_NE(f, nullptr);
    EXPECT_EQ(f->value, "as the profile") << f->evidence;
    EXPECT_TRUE(own.complete());
    BrighterTexels brighter;
    const auto other = harness::fingerprint(brighter);
    const auto* g = finding(other, "texture_sampling");
    ASSERT_NE(g, nullptr);
    EXPECT_EQ(g->value, "undecided");
    EXPECT_FALSE(g->decided);
    EXPECT_NE(g->evidence.find("probe textures pixel ("), std::string::npos) << g->evidence;
    EXPECT_FALSE(other.complete());
}

}  // namespace
