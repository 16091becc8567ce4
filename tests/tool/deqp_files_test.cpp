// deqp-runner's skips and flakes files in `conformance run`: skipped cases are left out of the
// selection, failures of known flakes are KnownFlake, and an expression that does not compile is
// refused naming its file and line.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "test_util.hpp"

namespace {

namespace fs = std::filesystem;

struct RunOutput {
    int code;
    std::string out;
    std::map<std::string, nlohmann::json> records;
};

// The smoke and coverage cases with the reference's tie rule flipped: some fail.
RunOutput run(const std::vector<std::string>& extra, const fs::path& out) {
    std::string cmd =
        testutil::shell_quote(std::string(REFRASTER_BIN_DIR) + "/refraster") +
        " conformance run --cases 'smoke.*,triangles.coverage.*' --against ref --profile-set "
        "tie_rule=right-top --output " +
        testutil::shell_quote(out.string());
    for (const auto& e : extra) cmd += " " + testutil::shell_quote(e);
    cmd += " 2>&1; echo \"rc=$?\"";
    const std::string text = testutil::command_output(cmd);
    RunOutput r{std::stoi(text.substr(text.rfind("rc=") + 3)), text, {}};
    if (fs::exists(out / "results.jsonl")) {
        std::istringstream in(testutil::read_text(out / "results.jsonl"));
        for (std::string l; std::getline(in, l);) {
            const auto j = nlohmann::json::parse(l);
            r.records[j["case"].get<std::string>()] = j;
        }
    }
    return r;
}

TEST(DeqpFiles, SkipsLeaveCasesOut) {
    testutil::TempDir dir;
    const auto skips = dir.write("skips.txt", "# deqp-runner style\nsmoke\\.triangle_\n\nlines$\n");
    const RunOutput all = run({}, dir.path() / "all");
    const RunOutput some = run({"--skips", skips.string()}, dir.path() / "some");
    ASSERT_TRUE(all.records.count("smoke.triangle_fan") && all.records.count("smoke.lines"));
    EXPECT_FALSE(some.records.count("smoke.triangle_fan"));
    EXPECT_FALSE(some.records.count("smoke.triangle_strip"));
    EXPECT_FALSE(some.records.count("smoke.lines"));
    EXPECT_TRUE(some.records.count("smoke.triangles"));  // "triangle_" does not match it
    EXPECT_EQ(some.records.size(), all.records.size() - 3);
}

TEST(DeqpFiles, FlakesTurnFailuresIntoKnownFlake) {
    testutil::TempDir dir;
    const RunOutput all = run({}, dir.path() / "all");
    std::string failing;
    for (const auto& [name, r] : all.records)
        if (r["status"] == "Fail") failing = name;
    ASSERT_FALSE(failing.empty()) << all.out;
    std::string flakes_text;
    for (const auto& [name, r] : all.records)
        if (r["status"] == "Fail") flakes_text += "^" + name + "$\n";
    const auto flakes = dir.write("flakes.txt", flakes_text);
    const RunOutput f = run({"--flakes", flakes.string()}, dir.path() / "flaky");
    EXPECT_EQ(f.code, 0) << f.out;  // nothing counts as failed any more
    EXPECT_EQ(f.records.at(failing)["status"], "KnownFlake");
    EXPECT_EQ(f.records.at(failing)["raw_status"], "Fail");
    EXPECT_NE(f.records.at(failing)["message"].get<std::string>().find("known flake (flakes.txt:"),
              std::string::npos);
    // deqp-runner's word for it, and no longer a failure.
    EXPECT_NE(
        testutil::read_text(dir.path() / "flaky" / "results.csv").find(failing + ",KnownFlake,"),
        std::string::npos);
    EXPECT_EQ(testutil::read_text(dir.path() / "flaky" / "failures.csv"), "");
    // A passing case is untouched by a pattern that matches it.
    for (const auto& [name, r] : all.records) {
        if (r["status"] == "Pass") {
            EXPECT_EQ(f.records.at(name)["status"], "Pass") << name;
        }
    }
}

TEST(DeqpFiles, BadExpressionIsRefused) {
    testutil::TempDir dir;
    const auto bad = dir.write("flakes.txt", "smoke\\.ok\nsmoke.(unclosed\n");
    const RunOutput r = run({"--flakes", bad.string()}, dir.path() / "out");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("flakes.txt:2"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir.path() / "out" / "results.jsonl"));
}

}  // namespace
