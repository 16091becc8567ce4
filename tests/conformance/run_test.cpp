// `refraster compare` and `refraster conformance run` end to end through OSMesa.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <regex>

#include "harness/image_io.hpp"
#include "test_util.hpp"

namespace {

using json = nlohmann::json;

// llvmpipe and softpipe give the pixel centres on this triangle's diagonal to different
// triangles (llvmpipe: left/bottom edges own ties; softpipe in an FBO: right/bottom): the
// hypotenuse is a right edge, so llvmpipe leaves its 8 centres out and softpipe draws them.
const char* kTieScene = R"({"format": "refraster-scene/1", "name": "tie",
 "description": "half-viewport triangle whose diagonal passes through 8 pixel centres",
 "target": {"width": 8, "height": 8}, "clear": {"color": [0, 0, 0, 1]},
 "draws": [{"primitive": "triangles",
            "vertices": [{"position": [0, 0]}, {"position": [8, 0]}, {"position": [0, 8]}]}]})";

std::vector<json> read_jsonl(const std::filesystem::path& p) {
    std::vector<json> v;
    std::stringstream s(testutil::read_text(p));
    for (std::string line; std::getline(s, line);) v.push_back(json::parse(line));
    return v;
}

std::string last_line(const std::string& s) {
    auto t = s;
    while (!t.empty() && t.back() == '\n') t.pop_back();
    return t.substr(t.rfind('\n') + 1);
}

TEST(CompareCli, DriverMismatchWritesRecordAndMask) {
    testutil::TempDir dir;
    const auto scene = dir.write("tie.json", kTieScene);
    const auto r = testutil::run_cli({"compare", scene.string(), "--reference", "osmesa",
                                      "--reference-driver", "softpipe", "--against", "osmesa",
                                      "--driver", "llvmpipe", "--json",
                                      (dir.path() / "r.json").string(), "--diff",
                                      (dir.path() / "mask.png").string()});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    const auto rec = json::parse(testutil::read_text(dir.path() / "r.json"));
    EXPECT_EQ(rec["status"], "Fail");
    EXPECT_EQ(rec["comparison"]["mismatched_pixels"], 8);
    EXPECT_EQ(rec["comparison"]["missing"], 8);  // softpipe drew them, llvmpipe did not
    EXPECT_EQ(rec["comparison"]["max_color"]["amount"], 255);
    EXPECT_EQ(rec["reference"]["provenance"]["driver"], "softpipe");
    EXPECT_EQ(rec["actual"]["provenance"]["driver"], "llvmpipe");
    for (const char* key : {"renderer", "gl_version", "mesa_version", "cpu_flags", "commit"}) {
        EXPECT_TRUE(rec["actual"]["provenance"].contains(key)) << key;
    }
    const auto mask = harness::read_color_image(dir.path() / "mask.png");
    for (std::uint32_t i = 0; i < 8; ++i) {
        // The diagonal's centres (i + 0.5, 7 - i + 0.5) lie on x + y = 8.
        const auto p = 4 * mask.index(i, 7 - i);
        EXPECT_EQ(mask.color8[p], 255);
        EXPECT_EQ(mask.color8[p + 1], 0);
        EXPECT_EQ(mask.color8[p + 2], 255);
    }
    EXPECT_TRUE(std::filesystem::exists(dir.path() / "mask.osmesa-softpipe.png"));
    EXPECT_TRUE(std::filesystem::exists(dir.path() / "mask.osmesa-llvmpipe.png"));
}

TEST(CompareCli, SameDriverPasses) {
    testutil::TempDir dir;
    const auto scene = dir.write("tie.json", kTieScene);
    const auto r = testutil::run_cli({"compare", scene.string(), "--reference", "egl", "--against", "osmesa"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out.rfind("Pass tie", 0), 0u) << r.out;
}

TEST(ConformanceRun, SmokeSuiteStreamsResultsAndSummarises) {
    testutil::TempDir dir;
    const auto out = dir.path() / "run";
    const auto r = testutil::run_cli({"conformance", "run", "--cases", "smoke.*", "--against",
                                      "osmesa", "--output", out.string()});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(std::regex_match(last_line(r.out), std::regex(R"(\d+ passed, \d+ failed, \d+ skipped)")))
        << r.out;
    const auto lines = read_jsonl(out / "results.jsonl");
    ASSERT_EQ(lines.size(), 8u);
    EXPECT_EQ(lines[0]["case"], "smoke.blending");
    for (const auto& l : lines) {
        EXPECT_NE(l["status"], "Crash");
        EXPECT_EQ(l["actual"]["status"], "Ok") << l.dump();
        EXPECT_TRUE(std::filesystem::exists(out / "images" / (l["case"].get<std::string>() + ".osmesa-llvmpipe.png")));
    }
}

TEST(ConformanceRun, KilledWorkerIsACrashAndTheRunGoesOn) {
    testutil::TempDir dir;
    const auto out = dir.path() / "run";
    // The worker SIGKILLs itself on receiving its 3rd scene.
    const std::string cmd = "REFRASTER_WORKER_KILL_AT=3 " +
                            testutil::shell_quote(std::string(REFRASTER_BIN_DIR) + "/refraster") +
                            " conformance run --cases 'smoke.*' --against osmesa --output " +
                            testutil::shell_quote(out.string()) + " > /dev/null 2>&1";
    const int status = std::system(cmd.c_str());
    EXPECT_EQ(WEXITSTATUS(status), 1);  // a Crash counts as a failure
    const auto lines = read_jsonl(out / "results.jsonl");
    ASSERT_EQ(lines.size(), 8u);  // every case ran
    int crashes = 0;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (lines[i]["status"] == "Crash") {
            ++crashes;
            EXPECT_EQ(i, 2u);
            EXPECT_NE(lines[i]["message"].get<std::string>().find("smoke/depth.json"), std::string::npos)
                << lines[i]["message"];
        } else {
            EXPECT_EQ(lines[i]["actual"]["status"], "Ok") << lines[i].dump();
        }
    }
    EXPECT_EQ(crashes, 1);
}

TEST(ConformanceRun, NoMatchingCaseIsAUsageError) {
    testutil::TempDir dir;
    const auto r = testutil::run_cli({"conformance", "run", "--cases", "no.such.*", "--output",
                                      (dir.path() / "run").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(testutil::count_lines(r.err), 1u);
}

}  // namespace
