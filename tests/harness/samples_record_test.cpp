// A 4x case from renders to verdict, record and reports: the samples are compared as well as
// the resolve, the record carries them, and the conformance reports show them. The renders come
// from backends that return fixed framebuffers, so no renderer has to draw 4x yet.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "harness/case_result.hpp"
#include "harness/image_io.hpp"
#include "test_util.hpp"

namespace {

using json = nlohmann::json;
using refraster::ColorFormat;
using refraster::DepthFormat;
using refraster::Framebuffer;

// A backend that answers every render with the framebuffers it was given.
class FixedBackend : public harness::Backend {
  public:
    FixedBackend(std::string name, harness::RenderResult r, harness::RenderResult owners = {})
        : name_(std::move(name)), result_(std::move(r)), owners_(std::move(owners)) {}
    harness::BackendKind kind() const override { return harness::BackendKind::Ref; }
    std::string name() const override { return name_; }
    harness::RenderResult render(const harness::Scene&) override { return result_; }
    harness::RenderResult render_owners(const harness::Scene& s) override {
        if (owners_.image.width == 0) return Backend::render_owners(s);
        return owners_;
    }

  private:
    std::string name_;
    harness::RenderResult result_;
    harness::RenderResult owners_;
};

const std::string kScene4x = R"({"format": "refraster-scene/1", "name": "ms.case",
  "requires": ["multisample"], "target": {"width": 2, "height": 2, "samples": 4, "depth": "z24"},
  "clear": {"color": [0, 0, 0, 1]}, "draws": []})";

Framebuffer black4(std::uint32_t w, std::uint32_t h) {
    Framebuffer fb(w, h, ColorFormat::Rgba8, DepthFormat::Z24, 4);
    for (std::size_t i = 0; i < fb.pixel_count() * 4; ++i) {
        fb.color8[4 * i + 3] = 255;
        fb.depth[i] = 0xffffff;
    }
    return fb;
}

void set_sample(Framebuffer& fb, std::uint32_t x, std::uint32_t y, std::uint32_t s,
                std::array<std::uint8_t, 4> c) {
    std::copy(c.begin(), c.end(),
              fb.color8.begin() + static_cast<std::ptrdiff_t>(4 * fb.sample_index(x, y, s)));
}

harness::RenderResult result_of(const Framebuffer& ms) {
    harness::RenderResult r;
    r.samples = ms;
    r.image = refraster::resolve_samples(ms);
    r.seconds = 0.001;
    return r;
}

// Reference and actual whose resolves are equal and whose samples 0 and 1 of pixel (0, 1) are
// swapped.
struct SwappedSamples {
    Framebuffer ref = black4(2, 2);
    Framebuffer act = black4(2, 2);
    SwappedSamples() {
        set_sample(ref, 0, 1, 0, {240, 0, 0, 255});
        set_sample(act, 0, 1, 1, {240, 0, 0, 255});
    }
};

TEST(SampleVerdict, ResolvedEqualButSamplesDifferFails) {
    const auto scene = harness::load_scene_text(kScene4x, "ms.json");
    ASSERT_TRUE(scene.unsupported_extensions.empty());
    const SwappedSamples f;
    FixedBackend ref("ref", result_of(f.ref));
    FixedBackend act("fixed", result_of(f.act));
    const auto r = harness::run_case(scene, "ms.case", ref, act);
    ASSERT_TRUE(r.comparison.has_value());
    ASSERT_TRUE(r.sample_comparison.has_value());
    EXPECT_EQ(r.comparison->mismatched_pixels, 0u);
    EXPECT_TRUE(r.comparison->within_expect);
    EXPECT_EQ(r.sample_comparison->mismatched_samples, 2u);
    EXPECT_EQ(r.status, harness::CaseStatus::Fail);
    EXPECT_NE(r.message.find("2 of 16 samples mismatched"), std::string::npos) << r.message;
    EXPECT_EQ(harness::pixel_of_largest_difference(r), (std::array<int, 2>{0, 1}));

    const auto j = json::parse(harness::to_json_line(r));
    const auto& c = j["comparison"];
    EXPECT_EQ(c["mismatched_pixels"], 0);
    EXPECT_EQ(c["samples"], 4);
    EXPECT_EQ(c["mismatched_samples"], 2);
    EXPECT_EQ(c["pixels_with_mismatched_samples"], 1);
    ASSERT_EQ(c["per_sample"].size(), 4u);
    EXPECT_EQ(c["per_sample"][0]["mismatched"], 1);
    EXPECT_EQ(c["per_sample"][0]["missing"], 1);
    EXPECT_EQ(c["per_sample"][1]["mismatched"], 1);
    EXPECT_EQ(c["per_sample"][1]["extra"], 1);
    EXPECT_EQ(c["per_sample"][2]["mismatched"], 0);
    EXPECT_EQ(c["max_sample_color"]["sample"], 0);
    EXPECT_EQ(c["max_sample_color"]["x"], 0);
    EXPECT_EQ(c["max_sample_color"]["y"], 1);
    EXPECT_EQ(c["max_sample_color"]["amount"], 240);
    EXPECT_EQ(c["samples_classified_by"], "clear colour");
    EXPECT_FALSE(c.contains("max_color"));  // the resolves agree
    EXPECT_FALSE(c.contains("max_depth"));  // a 4x target's depth is compared per sample
}

TEST(SampleVerdict, EqualSamplesPassAndDepthCountsOnce) {
    const auto scene = harness::load_scene_text(kScene4x, "ms.json");
    auto a = black4(2, 2);
    auto b = a;
    b.depth[b.sample_index(1, 1, 0)] = 7;  // sample 0: also the resolve's depth
    FixedBackend ref("ref", result_of(a));
    FixedBackend act("fixed", result_of(b));
    auto r = harness::run_case(scene, "ms.case", ref, act);
    EXPECT_EQ(r.status, harness::CaseStatus::Fail);
    EXPECT_EQ(r.comparison->mismatched_pixels, 0u);
    EXPECT_EQ(r.sample_comparison->mismatched_samples, 1u);
    EXPECT_EQ(r.sample_comparison->max_depth->sample, 0u);
    EXPECT_EQ(harness::pixel_of_largest_difference(r), (std::array<int, 2>{1, 1}));
    const auto j = json::parse(harness::to_json_line(r));
    EXPECT_EQ(j["comparison"]["depth_only"], 0);
    EXPECT_EQ(j["comparison"]["max_sample_depth"]["amount"], 0xffffff - 7);

    FixedBackend same("fixed", result_of(a));
    r = harness::run_case(scene, "ms.case", ref, same);
    EXPECT_EQ(r.status, harness::CaseStatus::Pass);
    EXPECT_EQ(r.sample_comparison->mismatched_samples, 0u);
    EXPECT_FALSE(harness::pixel_of_largest_difference(r).has_value());
}

TEST(SampleVerdict, ExpectBoundsSamplesToo) {
    const SwappedSamples f;
    for (const auto& [budget, status] :
         {std::pair{1, harness::CaseStatus::Fail}, std::pair{2, harness::CaseStatus::Pass}}) {
        std::string text = kScene4x;
        text.replace(
            text.find(R"("draws")"), 7,
            R"("expect": {"max_mismatched_pixels": )" + std::to_string(budget) + R"(}, "draws")");
        const auto scene = harness::load_scene_text(text, "ms.json");
        FixedBackend ref("ref", result_of(f.ref));
        FixedBackend act("fixed", result_of(f.act));
        EXPECT_EQ(harness::run_case(scene, "ms.case", ref, act).status, status) << budget;
    }
}

TEST(SampleVerdict, OwnerPassClassesEverySample) {
    const auto scene = harness::load_scene_text(kScene4x, "ms.json");
    const SwappedSamples f;
    auto ro = result_of(f.ref);
    auto ao = result_of(f.act);
    ro.samples.owner.assign(16, 0);
    ao.samples.owner.assign(16, 0);
    ro.samples.owner[f.ref.sample_index(0, 1, 0)] = refraster::owner_id(0, 0);
    ao.samples.owner[f.act.sample_index(0, 1, 1)] = refraster::owner_id(0, 0);
    FixedBackend ref("ref", result_of(f.ref), ro);
    FixedBackend act("fixed", result_of(f.act), ao);
    const auto r = harness::run_case(scene, "ms.case", ref, act);
    EXPECT_TRUE(r.sample_comparison->classified_by_owners);
    EXPECT_EQ(r.sample_comparison->missing, 1u);
    EXPECT_EQ(r.sample_comparison->extra, 1u);
    // The resolved image's owners are sample 0's.
    EXPECT_EQ(r.reference->image.owner[r.reference->image.index(0, 1)], refraster::owner_id(0, 0));
    EXPECT_EQ(r.actual->image.owner[r.actual->image.index(0, 1)], 0u);
    EXPECT_EQ(json::parse(harness::to_json_line(r))["comparison"]["samples_classified_by"],
              "primitive owners");
}

TEST(SampleVerdict, ASideWithoutSamplesIsAnInternalError) {
    const auto scene = harness::load_scene_text(kScene4x, "ms.json");
    const auto ms = black4(2, 2);
    auto no_samples = result_of(ms);
    no_samples.samples = Framebuffer{};
    FixedBackend ref("ref", result_of(ms));
    FixedBackend act("fixed", no_samples);
    const auto r = harness::run_case(scene, "ms.case", ref, act);
    EXPECT_EQ(r.status, harness::CaseStatus::InternalError);
    EXPECT_EQ(r.message, "fixed: returned no samples of the 4x target, so they cannot be compared");
    EXPECT_FALSE(r.comparison.has_value());
}

// A single-sample record is as it was: no sample fields.
TEST(SampleVerdict, SingleSampleRecordsHoldNoSampleFields) {
    const auto scene = harness::load_scene_text(
        R"({"format": "refraster-scene/1", "target": {"width": 2, "height": 1}, "draws": []})",
        "one.json");
    Framebuffer a(2, 1, ColorFormat::Rgba8, DepthFormat::None);
    auto b = a;
    b.color8[0] = 9;
    harness::RenderResult ra;
    ra.image = a;
    harness::RenderResult rb;
    rb.image = b;
    FixedBackend ref("ref", ra);
    FixedBackend act("fixed", rb);
    const auto r = harness::run_case(scene, "one", ref, act);
    EXPECT_EQ(r.status, harness::CaseStatus::Fail);
    EXPECT_FALSE(r.sample_comparison.has_value());
    const auto c = json::parse(harness::to_json_line(r))["comparison"];
    for (const char* k : {"samples", "mismatched_samples", "per_sample", "max_sample_color",
                          "max_sample_depth", "samples_classified_by"}) {
        EXPECT_FALSE(c.contains(k)) << k;
    }
    EXPECT_EQ(c["mismatched_pixels"], 1);
}

// The reports of a run that resumes into a 4x case's record: the record is kept byte for
// byte, and results.csv, samples.csv, junit.xml, index.html and the case page show the samples
// and the sample mask. The run is the reference against itself, so no GL is needed.
TEST(SampleReports, ResumedRunReportsTheSamples) {
    testutil::TempDir dir;
    const auto scenes = dir.path() / "scenes";
    std::filesystem::create_directories(scenes / "ms");
    std::ofstream(scenes / "ms" / "case.json") << kScene4x;
    std::ofstream(scenes / "ms" / "plain.json")
        << R"({"format": "refraster-scene/1", "name": "ms.plain", "description": "one pixel",
              "target": {"width": 1, "height": 1}, "draws": []})";

    const auto scene = harness::load_scene_text(kScene4x, "ms.json");
    const SwappedSamples f;
    FixedBackend ref("ref", result_of(f.ref));
    FixedBackend act("ref", result_of(f.act));
    auto r = harness::run_case(scene, "ms.case", ref, act);
    // A real run of the same cases sets the directory up (run.json, which a resume must
    // match); its ms.case record is then replaced by this one, with the real record's shard
    // and provenance, as a run of these backends would have written it.
    const auto out = dir.path() / "out";
    const std::vector<std::string> run_args{"conformance", "run", "--scenes", scenes.string(),
                                            "--against",   "ref", "--output", out.string()};
    ASSERT_EQ(testutil::run_cli(run_args).exit_code, 0);
    nlohmann::json real;
    {
        std::istringstream in(testutil::read_text(out / "results.jsonl"));
        for (std::string l; std::getline(in, l);) {
            if (nlohmann::json::parse(l)["case"] == "ms.case") real = nlohmann::json::parse(l);
        }
    }
    ASSERT_TRUE(real.is_object());
    r.shard = std::array<int, 2>{0, 1};
    r.shard_source = real["shard"]["source"].get<std::string>();
    for (auto* side : {&r.reference, &r.actual}) {
        (*side)->provenance.clear();
        const char* key = side == &r.reference ? "reference" : "actual";
        for (const auto& [k, v] : real[key]["provenance"].items())
            (*side)->provenance[k] = v.get<std::string>();
    }
    const std::string record = harness::to_json_line(r) + "\n";
    std::ofstream(out / "results.jsonl", std::ios::binary | std::ios::trunc) << record;
    harness::write_color_image(r.sample_comparison->mask, out / "images" / "ms.case.samples.png");

    auto resume_args = run_args;
    resume_args.push_back("--resume");
    const auto run = testutil::run_cli(resume_args);
    ASSERT_EQ(run.exit_code, 1) << run.out << run.err;
    EXPECT_NE(run.out.find("resume: kept 1 finished case"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("1 passed, 1 failed, 0 skipped"), std::string::npos) << run.out;
    const std::string jsonl = testutil::read_text(out / "results.jsonl");
    EXPECT_EQ(jsonl.rfind(record, 0), 0u);  // kept byte for byte

    EXPECT_NE(testutil::read_text(out / "results.csv").find("ms.case,Fail,"), std::string::npos);
    const std::string samples = testutil::read_text(out / "samples.csv");
    EXPECT_EQ(samples.rfind("name,status,mismatched_pixels,mismatched_samples,", 0), 0u);
    EXPECT_NE(samples.find("\nms.case,Fail,0,2,1,1,1,0,0,240,0,1,0,,,,\n"), std::string::npos)
        << samples;
    EXPECT_EQ(samples.find("ms.plain"), std::string::npos);  // single-sample: no row

    const std::string junit = testutil::read_text(out / "junit.xml");
    EXPECT_NE(junit.find("<system-out>Fail: 0 mismatched pixels (missing 0, extra 0, colour only "
                         "0, depth only 0, other primitive 0); 2 mismatched samples in 1 pixels "
                         "(by sample 0: 1, 1: 1, 2: 0, 3: 0); max sample colour error 240 at (0, "
                         "1) sample 0\ncase page: cases/ms.case.html</system-out>"),
              std::string::npos)
        << junit;

    const std::string index = testutil::read_text(out / "index.html");
    EXPECT_NE(index.find(">mismatched samples</th>"), std::string::npos);
    const std::string page = testutil::read_text(out / "cases" / "ms.case.html");
    EXPECT_NE(page.find("id=\"sample-mask\""), std::string::npos);
    EXPECT_NE(page.find("../images/ms.case.samples.png"), std::string::npos);
    EXPECT_NE(page.find("id=\"per-sample\""), std::string::npos);
    EXPECT_NE(page.find("max sample colour error</th><td class=\"num\">240 at (0, 1) sample 0"),
              std::string::npos);
    EXPECT_NE(page.find("the largest sample difference is at pixel (0, 1), sample 0"),
              std::string::npos);
    EXPECT_EQ(page.find("Every pixel agrees"), std::string::npos);
    const std::string plain = testutil::read_text(out / "cases" / "ms.plain.html");
    EXPECT_EQ(plain.find("sample-mask"), std::string::npos);
    EXPECT_EQ(plain.find("sample-numbers"), std::string::npos);
}

}  // namespace
