// `refraster conformance merge`: three shards merged give the unsharded run's results and
// reports (everything but the timings and the shard each record names), and shards that
// cannot be one run are refused before anything is written.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <regex>
#include <set>

#include "test_util.hpp"

namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

const std::string kClean = testutil::kUnsetShardVariables;

std::string bin() {
    return testutil::shell_quote(testutil::refraster_bin());
}

// The last line of a command's output, before the "rc=" line the helpers append.
std::string last_line(const std::string& text) {
    std::string t = text;
    while (!t.empty() && t.back() == '\n') t.pop_back();
    const auto nl = t.rfind('\n');
    return nl == std::string::npos ? t : t.substr(nl + 1);
}

// A run of the smoke cases with the reference's tie rule flipped, so that some fail and leave
// images and explain views. Returns the run's last line ("N passed, M failed, K skipped").
std::string run_shard(const std::string& vars, const fs::path& out,
                      const std::string& tie = "right-top") {
    const std::string cmd = kClean + vars + " " + bin() +
                            " conformance run --cases 'smoke.*,triangles.coverage.*' --against "
                            "ref --profile-set tie_rule=" +
                            tie + " --output " + testutil::shell_quote(out.string()) +
                            " 2> /dev/null; echo \"rc=$?\"";
    const std::string text = testutil::command_output(cmd);
    const auto at = text.rfind("rc=");
    // 1: some cases failed, which is what the test wants.
    const int rc = std::stoi(text.substr(at + 3));
    EXPECT_TRUE(rc == 0 || rc == 1) << cmd;
    return last_line(text.substr(0, at));
}

struct Cli {
    int code;
    std::string out;
};
Cli merge(const std::vector<fs::path>& shards, const fs::path& out) {
    std::string cmd = bin() + " conformance merge";
    for (const auto& s : shards) cmd += " " + testutil::shell_quote(s.string());
    cmd += " --output " + testutil::shell_quote(out.string()) + " 2>&1; echo \"rc=$?\"";
    const std::string text = testutil::command_output(cmd);
    const auto at = text.rfind("rc=");
    return {std::stoi(text.substr(at + 3)), text.substr(0, at)};
}

// The CSV without its seconds column.
std::string without_times(const std::string& csv) {
    return std::regex_replace(csv, std::regex(",[0-9.]+\n"), "\n");
}
std::string junit_without_times(const std::string& xml) {
    return std::regex_replace(xml, std::regex(" time=\"[^\"]*\""), "");
}
// A record without what differs between runs of the same cases: timings and the shard.
json record_core(json r) {
    r.erase("shard");
    for (const char* side : {"reference", "actual"})
        if (r.contains(side)) r[side].erase("seconds");
    return r;
}
std::vector<json> records(const fs::path& jsonl) {
    std::vector<json> v;
    std::istringstream in(testutil::read_text(jsonl));
    for (std::string l; std::getline(in, l);)
        if (!l.empty()) v.push_back(record_core(json::parse(l)));
    return v;
}
std::set<std::string> listing(const fs::path& dir) {
    std::set<std::string> s;
    if (fs::is_directory(dir))
        for (const auto& e : fs::directory_iterator(dir)) s.insert(e.path().filename().string());
    return s;
}

// A record whose largest colour difference holds NaN or infinite channels (rgba32f stores
// them) is written with "NaN", "Infinity" and "-Infinity", which the run, its reports and
// merge read back: before, the run ended with exit 2 and no report.
TEST(ConformanceMerge, NonFiniteChannelsRoundTrip) {
    testutil::TempDir dir;
    const fs::path out = dir.path() / "run";
    const std::string cmd = kClean + " " + bin() +
                            " conformance run --cases 'extreme.colour_*_rgba32f*' --against ref "
                            "--profile-set viewport_fma=off --output " +
                            testutil::shell_quote(out.string()) + " > /dev/null 2>&1";
    const int rc = std::system(cmd.c_str()) >> 8;
    ASSERT_EQ(rc, 1) << cmd;  // some cases fail, and the run ends normally
    EXPECT_TRUE(fs::exists(out / "index.html"));
    const std::string text = testutil::read_text(out / "results.jsonl");
    EXPECT_NE(text.find("\"NaN\""), std::string::npos) << text.substr(0, 2000);
    const auto m = merge({out}, dir.path() / "merged");
    EXPECT_TRUE(m.code == 0 || m.code == 1) << m.out;
    EXPECT_TRUE(fs::exists(dir.path() / "merged" / "index.html")) << m.out;
}

TEST(ConformanceMerge, EqualsTheUnshardedRun) {
    testutil::TempDir dir;
    std::vector<fs::path> shards;
    for (int i = 0; i < 3; ++i) {
        shards.push_back(dir.path() / ("s" + std::to_string(i)));
        run_shard("GTEST_SHARD_INDEX=" + std::to_string(i) + " GTEST_TOTAL_SHARDS=3",
                  shards.back());
    }
    const fs::path whole = dir.path() / "whole", merged = dir.path() / "merged";
    const std::string summary = run_shard("", whole);
    // Given in any order. It ends as the run does: the same summary line, and exit 1 for the
    // failures (a CI job's last step can gate on it).
    const Cli m = merge({shards[2], shards[0], shards[1]}, merged);
    EXPECT_EQ(m.code, 1) << m.out;
    EXPECT_NE(m.out.find("merged 3 of 3 shards"), std::string::npos) << m.out;
    EXPECT_NE(summary.find(" passed, "), std::string::npos) << summary;
    EXPECT_EQ(last_line(m.out), summary) << m.out;
    const auto text = [](const fs::path& p) { return testutil::read_text(p); };
    EXPECT_FALSE(text(whole / "failures.csv").empty());  // the comparison has failures to merge
    EXPECT_EQ(text(merged / "failures.csv"), text(whole / "failures.csv"));
    EXPECT_EQ(without_times(text(merged / "results.csv")),
              without_times(text(whole / "results.csv")));
    EXPECT_EQ(junit_without_times(text(merged / "junit.xml")),
              junit_without_times(text(whole / "junit.xml")));
    EXPECT_EQ(text(merged / "samples.csv"), text(whole / "samples.csv"));
    EXPECT_EQ(records(merged / "results.jsonl"), records(whole / "results.jsonl"));
    const json mj = json::parse(text(merged / "results.json"));
    const json wj = json::parse(text(whole / "results.json"));
    EXPECT_EQ(mj["summary"], wj["summary"]);
    ASSERT_EQ(mj["cases"].size(), wj["cases"].size());
    for (const char* sub : {"images", "explain", "cases"}) {
        EXPECT_FALSE(listing(whole / sub).empty()) << sub;
        EXPECT_EQ(listing(merged / sub), listing(whole / sub)) << sub;
    }
    for (const auto& f : listing(whole / "images"))
        EXPECT_EQ(text(merged / "images" / f), text(whole / "images" / f)) << f;
    EXPECT_TRUE(fs::exists(merged / "index.html"));
}

TEST(ConformanceMerge, NamesMissingShardsAndReportsTheRest) {
    testutil::TempDir dir;
    const fs::path s0 = dir.path() / "s0", s2 = dir.path() / "s2";
    run_shard("CI_NODE_INDEX=1 CI_NODE_TOTAL=3", s0);
    run_shard("CI_NODE_INDEX=3 CI_NODE_TOTAL=3", s2);
    const Cli m = merge({s0, s2}, dir.path() / "merged");
    EXPECT_EQ(m.code, 1) << m.out;
    EXPECT_NE(m.out.find("missing: shard 1 of 3"), std::string::npos) << m.out;
    EXPECT_NE(last_line(m.out).find("; 1 of 3 shards missing"), std::string::npos) << m.out;
    EXPECT_NE(testutil::read_text(dir.path() / "merged" / "merge.txt").find("missing: shard 1"),
              std::string::npos);
    EXPECT_EQ(records(dir.path() / "merged" / "results.jsonl").size(),
              records(s0 / "results.jsonl").size() + records(s2 / "results.jsonl").size());
}

TEST(ConformanceMerge, RefusesShardsThatAreNotOneRun) {
    testutil::TempDir dir;
    const fs::path s0 = dir.path() / "s0", s1 = dir.path() / "s1", other = dir.path() / "other";
    const fs::path half = dir.path() / "half";
    run_shard("GTEST_SHARD_INDEX=0 GTEST_TOTAL_SHARDS=2", s0);
    run_shard("GTEST_SHARD_INDEX=1 GTEST_TOTAL_SHARDS=2", s1);
    run_shard("GTEST_SHARD_INDEX=1 GTEST_TOTAL_SHARDS=2", other, "left-top");
    run_shard("GTEST_SHARD_INDEX=1 GTEST_TOTAL_SHARDS=3", half);
    const fs::path out = dir.path() / "out";
    const auto refused = [&](const std::vector<fs::path>& in, const std::string& says) {
        const Cli m = merge(in, out);
        EXPECT_EQ(m.code, 2) << m.out;
        EXPECT_NE(m.out.find(says), std::string::npos) << m.out;
        EXPECT_EQ(m.out.find('\n'), m.out.size() - 1) << "one line: " << m.out;
        EXPECT_FALSE(fs::exists(out)) << "nothing written for " << says;
    };
    refused({s0, s0}, "are both shard 0 of 2");
    refused({s0, other}, "another run than");
    refused({s0, half}, "of 3, but");
    refused({s0, s1, s1}, "both shard 1 of 2");
    // A torn last record (a killed shard).
    const fs::path torn = dir.path() / "torn";
    fs::create_directories(torn);
    const std::string full = testutil::read_text(s1 / "results.jsonl");
    std::ofstream(torn / "results.jsonl", std::ios::binary) << full.substr(0, full.size() - 10);
    refused({s0, torn}, "torn");
    refused({s0, dir.path() / "nowhere"}, "cannot read");
    // The output must not be a shard.
    const Cli m = merge({s0, s1}, s1);
    EXPECT_EQ(m.code, 2);
    EXPECT_NE(m.out.find("the output is one of the shards"), std::string::npos) << m.out;
}

}  // namespace
