// deqp-runner's words and rules (conformance/deqp_runner.hpp): the duration column against
// Rust's own formatting of f32 (vectors made with rustc by scripts/make_deqp_runner_vectors.sh),
// the baseline verdicts of RunnerStatus::with_baseline, and the status words both ways.
#include "conformance/deqp_runner.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "conformance/suite.hpp"
#include "harness/case_result.hpp"

namespace {

using conformance::deqp_runner_duration;

float from_bits(std::uint32_t bits) {
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

TEST(DeqpRunnerDuration, MatchesRustDisplayOfF32) {
    std::ifstream in(std::string(REFRASTER_SOURCE_DIR) +
                     "/tests/conformance/data/rust_f32_display.txt");
    ASSERT_TRUE(in) << "tests/conformance/data/rust_f32_display.txt";
    std::size_t checked = 0, wrong = 0;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        const auto space = line.find(' ');
        ASSERT_NE(space, std::string::npos) << line;
        const auto bits =
            static_cast<std::uint32_t>(std::stoul(line.substr(0, space), nullptr, 16));
        const std::string rust = line.substr(space + 1);
        const std::string ours = deqp_runner_duration(from_bits(bits));
        ++checked;
        if (ours != rust && ++wrong <= 10) {
            ADD_FAILURE() << "bits " << line.substr(0, space) << ": Rust prints " << rust
                          << ", this prints " << ours;
        }
    }
    EXPECT_GT(checked, 7000u);
    EXPECT_EQ(wrong, 0u);
}

TEST(DeqpRunnerDuration, HalfwayValuesRoundUpAsRustDoes) {
    // 1783756.25 lies halfway between the 8-digit 1783756.2 and 1783756.3, both of which
    // read back as it; Rust prints the upper, std::to_chars the even one.
    EXPECT_EQ(deqp_runner_duration(1783756.25f), "1783756.3");
    EXPECT_EQ(deqp_runner_duration(0.5f), "0.5");
    EXPECT_EQ(deqp_runner_duration(1.0f), "1");
    EXPECT_EQ(deqp_runner_duration(0.0f), "0");
    EXPECT_EQ(deqp_runner_duration(1e-7f), "0.0000001");
    EXPECT_EQ(deqp_runner_duration(1e20f), "100000000000000000000");
}

TEST(DeqpRunnerWords, ReadsEveryWordOfEveryVersion) {
    for (const char* w : {"Pass", "Fail", "Skip", "Crash", "Warn", "Timeout", "Flake", "KnownFlake",
                          "Missing", "ExpectedFail", "UnexpectedImprovement(Pass)",
                          "UnexpectedImprovement(Skip)", "UnexpectedImprovement(Timeout)"}) {
        EXPECT_EQ(conformance::deqp_runner_word(w).value_or("?"), w);
    }
    EXPECT_EQ(conformance::deqp_runner_word("UnexpectedPass").value_or("?"),
              "UnexpectedImprovement(Pass)");
    EXPECT_EQ(conformance::deqp_runner_word("NotSupported").value_or("?"), "Skip");
    EXPECT_EQ(conformance::deqp_runner_word("InternalError").value_or("?"), "Fail");
    for (const char* w : {"", "pass", "Maybe", "UnexpectedImprovement()",
                          "UnexpectedImprovement(Flake)", "UnexpectedImprovement(Pass"}) {
        EXPECT_FALSE(conformance::deqp_runner_word(w)) << w;
    }
}

TEST(DeqpRunnerWords, RecordsAreWrittenInDeqpRunnerWords) {
    using conformance::deqp_runner_status;
    EXPECT_EQ(deqp_runner_status("NotSupported", ""), "Skip");
    EXPECT_EQ(deqp_runner_status("InternalError", ""), "Fail");
    EXPECT_EQ(deqp_runner_status("UnexpectedPass", "Pass"), "UnexpectedImprovement(Pass)");
    EXPECT_EQ(deqp_runner_status("UnexpectedImprovement", "Fail"), "UnexpectedImprovement(Fail)");
    EXPECT_EQ(deqp_runner_status("UnexpectedImprovement", "InternalError"),
              "UnexpectedImprovement(Fail)");
    EXPECT_EQ(deqp_runner_status("UnexpectedImprovement", "NotSupported"),
              "UnexpectedImprovement(Skip)");
    EXPECT_EQ(deqp_runner_status("KnownFlake", "Fail"), "KnownFlake");
    EXPECT_EQ(deqp_runner_status("ExpectedFail", "Crash"), "ExpectedFail");
    // Every status this project records, in deqp-runner's words, is a success exactly when it
    // does not count as failed here: failures.csv and the exit code agree.
    for (auto st :
         {harness::CaseStatus::Pass, harness::CaseStatus::Fail, harness::CaseStatus::NotSupported,
          harness::CaseStatus::Crash, harness::CaseStatus::Timeout,
          harness::CaseStatus::InternalError, harness::CaseStatus::ExpectedFail,
          harness::CaseStatus::UnexpectedPass, harness::CaseStatus::UnexpectedImprovement,
          harness::CaseStatus::Flake, harness::CaseStatus::KnownFlake}) {
        const std::string word = deqp_runner_status(harness::to_string(st), "Fail");
        EXPECT_EQ(conformance::deqp_runner_is_success(word), !harness::counts_as_failure(st))
            << harness::to_string(st) << " as " << word;
    }
}

// RunnerStatus::with_baseline, every result dEQP reports against every word a baseline can
// hold. Columns: not listed, then kBaselines in order.
const std::vector<std::string> kBaselines = {"Pass",
                                             "Fail",
                                             "Skip",
                                             "Crash",
                                             "Timeout",
                                             "Warn",
                                             "Flake",
                                             "KnownFlake",
                                             "Missing",
                                             "ExpectedFail",
                                             "UnexpectedImprovement(Pass)"};

TEST(DeqpRunnerBaseline, EveryResultAgainstEveryListedWord) {
    const std::string ui = "UnexpectedImprovement";
    const std::map<std::string, std::vector<std::string>> expected = {
        {"Pass",
         {"Pass", "Pass", ui + "(Pass)", "Pass", ui + "(Pass)", ui + "(Pass)", "Pass", "Pass",
          "Pass", ui + "(Pass)", "Pass", "Pass"}},
        {"Fail",
         {"Fail", "Fail", "ExpectedFail", "Fail", ui + "(Fail)", ui + "(Fail)", "Fail", "Fail",
          "Fail", "Fail", "ExpectedFail", "Fail"}},
        {"Skip",
         {"Skip", "Skip", ui + "(Skip)", "Skip", ui + "(Skip)", ui + "(Skip)", "Skip", "Skip",
          "Skip", ui + "(Skip)", "Skip", "Skip"}},
        {"Crash",
         {"Crash", "Crash", "Crash", "Crash", "ExpectedFail", "Crash", "Crash", "Crash", "Crash",
          "Crash", "ExpectedFail", "Crash"}},
        {"Timeout",
         {"Timeout", "Timeout", "Timeout", "Timeout", "Timeout", "ExpectedFail", "Timeout",
          "Timeout", "Timeout", "Timeout", "Timeout", "Timeout"}},
        {"Warn",
         {"Warn", "Warn", ui + "(Warn)", "Warn", ui + "(Warn)", "Warn", "ExpectedFail", "Warn",
          "Warn", "Warn", "Warn", "Warn"}},
    };
    for (const auto& [result, row] : expected) {
        ASSERT_EQ(row.size(), kBaselines.size() + 1);
        EXPECT_EQ(conformance::deqp_runner_with_baseline(result, ""), row[0]) << result;
        for (std::size_t i = 0; i < kBaselines.size(); ++i) {
            EXPECT_EQ(conformance::deqp_runner_with_baseline(result, kBaselines[i]), row[i + 1])
                << result << " against a baseline of " << kBaselines[i];
        }
    }
}

harness::CaseResult result(const std::string& name, harness::CaseStatus st) {
    harness::CaseResult r;
    r.name = name;
    r.status = st;
    return r;
}

TEST(DeqpRunnerBaseline, ApplyBaselineKeepsTheResultAsRawStatus) {
    using harness::CaseStatus;
    const std::map<std::string, std::string> baseline = {{"a.fails", "Fail"},
                                                         {"a.crashes", "Crash"},
                                                         {"a.missing", "Missing"},
                                                         {"a.any", "ExpectedFail"}};
    struct Case {
        std::string name;
        CaseStatus result, verdict;
        bool failed;
    };
    for (const Case& c : std::vector<Case>{
             {"a.fails", CaseStatus::Fail, CaseStatus::ExpectedFail, false},
             {"a.fails", CaseStatus::InternalError, CaseStatus::ExpectedFail, false},
             {"a.fails", CaseStatus::Pass, CaseStatus::UnexpectedPass, true},
             {"a.fails", CaseStatus::NotSupported, CaseStatus::UnexpectedImprovement, true},
             {"a.fails", CaseStatus::Crash, CaseStatus::Crash, true},
             {"a.crashes", CaseStatus::Crash, CaseStatus::ExpectedFail, false},
             {"a.crashes", CaseStatus::Fail, CaseStatus::UnexpectedImprovement, true},
             {"a.missing", CaseStatus::Pass, CaseStatus::UnexpectedPass, true},
             {"a.missing", CaseStatus::Fail, CaseStatus::Fail, true},
             {"a.any", CaseStatus::Crash, CaseStatus::ExpectedFail, false},
             {"a.any", CaseStatus::Timeout, CaseStatus::Timeout, true},
             {"a.any", CaseStatus::Pass, CaseStatus::Pass, false},
             {"a.unlisted", CaseStatus::Pass, CaseStatus::Pass, false},
             {"a.unlisted", CaseStatus::Fail, CaseStatus::Fail, true},
         }) {
        auto r = result(c.name, c.result);
        const bool failed = conformance::apply_baseline(r, &baseline);
        const std::string what = c.name + " " + std::string(harness::to_string(c.result));
        EXPECT_EQ(r.status, c.verdict) << what << " became " << harness::to_string(r.status);
        EXPECT_EQ(failed, c.failed) << what;
        if (c.verdict != c.result) {
            ASSERT_TRUE(r.raw_status) << what;
            EXPECT_EQ(*r.raw_status, c.result) << what;
        } else {
            EXPECT_FALSE(r.raw_status) << what;
        }
    }
    // Without a baseline nothing changes.
    auto r = result("a.fails", CaseStatus::Fail);
    EXPECT_TRUE(conformance::apply_baseline(r, nullptr));
    EXPECT_EQ(r.status, CaseStatus::Fail);
}

}  // namespace
