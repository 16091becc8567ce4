// deqp-runner's skips and flakes files in `conformance run`: skipped cases are left out of the
// selection, failures of known flakes are KnownFlake, and an expression that does not compile is
// refused naming its file and line; the baseline, skips and flakes files a run used are
// recorded in run.json, copied under inputs/, shown on the index and carried by a merge.
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

TEST(DeqpFiles, TheRunRecordsCopiesAndShowsItsInputFiles) {
    testutil::TempDir dir;
    const auto skips = dir.write("my-skips.txt", "smoke\\.triangle_\n# two cases\n");
    const auto flakes = dir.write("my-flakes.txt", "^nothing$\n^nothing either$\n");
    const auto baseline = dir.write("known.csv", "smoke.lines,Fail\nsmoke.points,Fail\n");
    const fs::path out = dir.path() / "out";
    const RunOutput r = run(
        {"--skips", skips.string(), "--flakes", flakes.string(), "--baseline", baseline.string()},
        out);
    ASSERT_TRUE(fs::exists(out / "run.json")) << r.out;
    const auto setup = nlohmann::json::parse(testutil::read_text(out / "run.json"));
    const auto& in = setup.at("inputs");
    EXPECT_EQ(in.at("baseline").at("file"), baseline.string());
    EXPECT_EQ(in.at("baseline").at("cases"), 2);
    EXPECT_EQ(in.at("skips").at(0).at("patterns"), 1);
    EXPECT_EQ(in.at("skips").at(0).at("skipped_cases"), 2);  // triangle_fan and triangle_strip
    EXPECT_EQ(in.at("flakes").at(0).at("patterns"), 2);
    // The copies hold the files' bytes as the run read them.
    EXPECT_EQ(testutil::read_text(out / "inputs" / "baseline.csv"), testutil::read_text(baseline));
    EXPECT_EQ(testutil::read_text(out / "inputs" / "skips-1.txt"), testutil::read_text(skips));
    EXPECT_EQ(testutil::read_text(out / "inputs" / "flakes-1.txt"), testutil::read_text(flakes));
    const std::string index = testutil::read_text(out / "index.html");
    const auto at = index.find("id=\"run-inputs\"");
    ASSERT_NE(at, std::string::npos);
    const std::string inputs = index.substr(at, index.find("</p>", at) - at);
    EXPECT_NE(inputs.find("<a href=\"inputs/baseline.csv\">"), std::string::npos) << inputs;
    EXPECT_NE(inputs.find("known.csv"), std::string::npos) << inputs;
    EXPECT_NE(inputs.find("2 cases listed"), std::string::npos) << inputs;
    EXPECT_NE(inputs.find("2 cases left out"), std::string::npos) << inputs;
    EXPECT_NE(inputs.find("<a href=\"inputs/flakes-1.txt\">"), std::string::npos) << inputs;
    EXPECT_NE(testutil::read_text(out / "results.json").find("\"inputs\""), std::string::npos);

    // A merge of the run carries its inputs.
    const fs::path merged = dir.path() / "merged";
    testutil::command_output(testutil::shell_quote(std::string(REFRASTER_BIN_DIR) + "/refraster") +
                             " conformance merge " + testutil::shell_quote(out.string()) +
                             " --output " + testutil::shell_quote(merged.string()) + " 2>&1");
    EXPECT_EQ(testutil::read_text(merged / "inputs" / "baseline.csv"),
              testutil::read_text(baseline));
    EXPECT_NE(testutil::read_text(merged / "index.html").find("<a href=\"inputs/skips-1.txt\">"),
              std::string::npos);

    // A run into the same folder without them leaves no copy behind, and says so.
    run({}, out);
    EXPECT_FALSE(fs::exists(out / "inputs"));
    EXPECT_NE(testutil::read_text(out / "index.html").find("No baseline, skips or flakes file."),
              std::string::npos);
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
