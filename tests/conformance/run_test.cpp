// `refraster compare` and `refraster conformance run` end to end through OSMesa.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>

#include "harness/bench.hpp"
#include "harness/image_io.hpp"
#include "layered_scene.hpp"
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

// Reads results.csv and failures.csv as deqp-runner reads and writes them
// (RunnerResults::from_csv, write_results, write_failures): lines "name,Status,duration"
// sorted bytewise by name without a header, Status one of its RunnerStatus words, the duration
// as Rust prints an f32 (plain decimal, no exponent, no trailing zeros), and failures.csv the
// lines whose status is not a success, as "name,Status". Returns the statuses by name.
std::map<std::string, std::string> read_as_deqp_runner(const std::filesystem::path& dir) {
    const std::regex line_re(
        "([^,]+),(Pass|Fail|Crash|Skip|Flake|KnownFlake|Warn|Missing|ExpectedFail|Timeout|"
        "UnexpectedImprovement\\((Pass|Fail|Crash|Skip|Warn|Timeout)\\)),"
        "(0|[1-9][0-9]*)(\\.[0-9]*[1-9])?");
    const std::string results = testutil::read_text(dir / "results.csv");
    std::map<std::string, std::string> words;
    std::string expected_failures, previous;
    std::stringstream in(results);
    for (std::string line; std::getline(in, line);) {
        std::smatch m;
        EXPECT_TRUE(std::regex_match(line, m, line_re)) << "results.csv: " << line;
        if (m.empty()) continue;
        EXPECT_LT(previous, m[1].str()) << "results.csv is not sorted by name";
        previous = m[1];
        words[m[1]] = m[2];
        const std::string st = m[2];
        if (!(st == "Pass" || st == "Skip" || st == "Warn" || st == "Flake" || st == "KnownFlake" ||
              st == "ExpectedFail")) {
            expected_failures += m[1].str() + "," + st + "\n";
        }
    }
    EXPECT_TRUE(results.empty() || results.back() == '\n');
    EXPECT_EQ(testutil::read_text(dir / "failures.csv"), expected_failures);
    return words;
}

std::string last_line(const std::string& s) {
    auto t = s;
    while (!t.empty() && t.back() == '\n') t.pop_back();
    return t.substr(t.rfind('\n') + 1);
}

TEST(CompareCli, DriverMismatchWritesRecordAndMask) {
    testutil::TempDir dir;
    const auto scene = dir.write("tie.json", kTieScene);
    const auto r = testutil::run_cli(
        {"compare", scene.string(), "--reference", "osmesa", "--reference-driver", "softpipe",
         "--against", "osmesa", "--driver", "llvmpipe", "--json", (dir.path() / "r.json").string(),
         "--diff", (dir.path() / "mask.png").string()});
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
    const auto r =
        testutil::run_cli({"compare", scene.string(), "--reference", "egl", "--against", "osmesa"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out.rfind("Pass tie", 0), 0u) << r.out;
}

TEST(ConformanceRun, SmokeSuiteStreamsResultsAndSummarises) {
    testutil::TempDir dir;
    const auto out = dir.path() / "run";
    const auto r = testutil::run_cli({"conformance", "run", "--cases", "smoke.*", "--against",
                                      "osmesa", "--output", out.string()});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(
        std::regex_match(last_line(r.out), std::regex(R"(\d+ passed, \d+ failed, \d+ skipped)")))
        << r.out;
    const auto lines = read_jsonl(out / "results.jsonl");
    ASSERT_EQ(lines.size(), 8u);
    EXPECT_EQ(lines[0]["case"], "smoke.blending");
    for (const auto& l : lines) {
        EXPECT_NE(l["status"], "Crash");
        EXPECT_EQ(l["actual"]["status"], "Ok") << l.dump();
        EXPECT_TRUE(std::filesystem::exists(
            out / "images" / (l["case"].get<std::string>() + ".osmesa-llvmpipe.png")));
    }
}

// Every link and image of the report resolves from the output folder it was written to, here
// one three levels below a temporary directory (before, the index linked ../../docs/, which
// holds only from the source tree's out/conformance/).
TEST(HtmlReport, EveryLinkResolvesFromAnyOutputFolder) {
    testutil::TempDir dir;
    const auto out = dir.path() / "a" / "b" / "c";
    const auto r = testutil::run_cli(
        {"conformance", "run", "--cases", "smoke.*,triangles.coverage.square*", "--against", "ref",
         "--profile-set", "tie_rule=right-top", "--output", out.string()});
    ASSERT_EQ(r.exit_code, 1) << r.err;  // some cases fail: case pages and images are linked
    std::vector<std::filesystem::path> pages{out / "index.html"};
    for (const auto& e : std::filesystem::directory_iterator(out / "cases"))
        if (e.path().extension() == ".html") pages.push_back(e.path());
    ASSERT_GT(pages.size(), 1u);
    const std::regex attr(R"re((?:href|src)="([^"]*)")re");
    std::size_t checked = 0;
    for (const auto& page : pages) {
        const std::string html = testutil::read_text(page);
        for (std::sregex_iterator it(html.begin(), html.end(), attr), end; it != end; ++it) {
            std::string target = (*it)[1].str();
            if (target.empty() || target[0] == '#' || target.rfind("data:", 0) == 0 ||
                target.rfind("http:", 0) == 0 || target.rfind("https:", 0) == 0 ||
                target.rfind("javascript:", 0) == 0)
                continue;
            target = target.substr(0, target.find_first_of("#?"));
            for (std::size_t at; (at = target.find("&amp;")) != std::string::npos;)
                target.replace(at, 5, "&");
            EXPECT_TRUE(std::filesystem::exists(page.parent_path() / target))
                << page.filename() << " links " << target;
            ++checked;
        }
    }
    EXPECT_GT(checked, 10u);
    // A summary says why the failures failed: the flipped tie rule's cases grouped under the
    // rule explain names, linked; and the worst cases by mismatched pixels.
    {
        const std::string idx = testutil::read_text(out / "index.html");
        const auto table = idx.find("id=\"failures-by-verdict\"");
        ASSERT_NE(table, std::string::npos);
        EXPECT_TRUE(std::regex_search(
            idx.substr(table, idx.find("</table>", table) - table),
            std::regex(
                R"(<td>coverage: tie rule</td><td class="num">\d+</td><td><a href="cases/)")))
            << idx.substr(table, 800);
        EXPECT_NE(idx.find("id=\"worst-cases\"><li><a href=\"cases/"), std::string::npos);
    }
    // The case table lists the failures first (the run has both).
    const std::string index = testutil::read_text(out / "index.html");
    const std::regex row(R"re(<tr data-status="([A-Za-z]+)")re");
    std::vector<std::string> order;
    for (std::sregex_iterator it(index.begin(), index.end(), row), end; it != end; ++it)
        order.push_back((*it)[1].str());
    ASSERT_FALSE(order.empty());
    const auto first_pass = std::find(order.begin(), order.end(), "Pass");
    ASSERT_NE(first_pass, order.end());
    EXPECT_NE(first_pass, order.begin());
    EXPECT_EQ(std::find(first_pass, order.end(), "Fail"), order.end())
        << "a Fail row after a Pass row";
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
            EXPECT_NE(lines[i]["message"].get<std::string>().find("smoke/depth.json"),
                      std::string::npos)
                << lines[i]["message"];
        } else {
            EXPECT_EQ(lines[i]["actual"]["status"], "Ok") << lines[i].dump();
        }
    }
    EXPECT_EQ(crashes, 1);
}

// A failure that depends on what the worker drew before: the worker answers its 3rd scene with
// one pixel changed, as stale state would. Run alone in a fresh worker the case passes, so it is
// a Flake saying so, and its explanation is the failing render's (a later render of the same
// worker agrees with the reference, and explaining from it would say so).
TEST(ConformanceRun, AFailureThatPassesAloneIsAnOrderDependentFlake) {
    testutil::TempDir dir;
    const auto out = dir.path() / "run";
    const std::string cmd = "REFRASTER_WORKER_STALE_AT=3 " +
                            testutil::shell_quote(std::string(REFRASTER_BIN_DIR) + "/refraster") +
                            " conformance run --cases 'smoke.*' --against osmesa --output " +
                            testutil::shell_quote(out.string()) + " > /dev/null 2>&1";
    const int status = std::system(cmd.c_str());
    EXPECT_EQ(WEXITSTATUS(status), 0);  // a Flake counts as passed
    const auto lines = read_jsonl(out / "results.jsonl");
    ASSERT_EQ(lines.size(), 8u);
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (i != 2) {
            EXPECT_EQ(lines[i]["status"], "Pass") << lines[i].dump();
            continue;
        }
        const json& l = lines[i];
        EXPECT_EQ(l["status"], "Flake") << l.dump();
        EXPECT_EQ(l.value("raw_status", ""), "Fail") << l.dump();
        EXPECT_EQ(l["alone"]["status"], "Pass") << l.dump();
        EXPECT_EQ(l["alone"]["mismatched_pixels"], 0) << l.dump();
        EXPECT_NE(l["message"].get<std::string>().find("order dependent"), std::string::npos);
        ASSERT_TRUE(l.contains("explanation")) << l.dump();
        EXPECT_EQ(l["explanation"]["pixel"], json::array({0, 0})) << l.dump();
        EXPECT_EQ(l["explanation"]["verdict"].get<std::string>().find("agree"), std::string::npos)
            << l.dump();
    }
}

TEST(ConformanceRun, NoMatchingCaseIsAUsageError) {
    testutil::TempDir dir;
    const auto r = testutil::run_cli(
        {"conformance", "run", "--cases", "no.such.*", "--output", (dir.path() / "run").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(testutil::count_lines(r.err), 1u);
}

std::map<std::string, std::string> statuses(const std::filesystem::path& jsonl) {
    std::map<std::string, std::string> m;
    for (const auto& l : read_jsonl(jsonl))
        m[l["case"].get<std::string>()] = l["status"].get<std::string>();
    return m;
}

std::string bin() {
    return testutil::shell_quote(std::string(REFRASTER_BIN_DIR) + "/refraster");
}

TEST(ConformanceRun, SigkillThenResumeGivesTheUninterruptedResults) {
    testutil::TempDir dir;
    const auto full = dir.path() / "full";
    const auto killed = dir.path() / "killed";
    const std::string sel = " --cases 'triangles.*,lines.*' --against osmesa --output ";
    ASSERT_EQ(std::system((bin() + " conformance run" + sel + testutil::shell_quote(full.string()) +
                           " > /dev/null")
                              .c_str()) >>
                  8,
              0);
    // Kill a second run with SIGKILL once it has written some results.
    const std::string cmd =
        bin() + " conformance run" + sel + testutil::shell_quote(killed.string()) +
        " > /dev/null & pid=$!; while [ ! -s " +
        testutil::shell_quote((killed / "results.jsonl").string()) + " ] || [ $(wc -l < " +
        testutil::shell_quote((killed / "results.jsonl").string()) +
        ") -lt 20 ]; do sleep 0.01; done; kill -9 $pid; wait $pid";
    std::system(cmd.c_str());
    const auto partial = read_jsonl(killed / "results.jsonl");
    EXPECT_GE(partial.size(), 20u);
    EXPECT_LT(partial.size(), statuses(full / "results.jsonl").size());
    // Cut the last line in half, as a kill in the middle of a write would.
    std::string kept;
    {
        const auto text = testutil::read_text(killed / "results.jsonl");
        const std::string cut = text.substr(0, text.size() - 40);
        kept = cut.substr(0, cut.rfind('\n') + 1);
        std::ofstream(killed / "results.jsonl", std::ios::trunc) << cut;
    }
    const std::size_t kept_cases =
        static_cast<std::size_t>(std::count(kept.begin(), kept.end(), '\n'));
    const auto out = dir.path() / "resume.txt";
    const int rc =
        std::system((bin() + " conformance run" + sel + testutil::shell_quote(killed.string()) +
                     " --resume > " + testutil::shell_quote(out.string()))
                        .c_str());
    EXPECT_EQ(rc >> 8, 0);
    const auto console = testutil::read_text(out);
    EXPECT_NE(console.find("resume: kept " + std::to_string(kept_cases) + " finished cases"),
              std::string::npos)
        << console;
    EXPECT_NE(console.find("cut a torn last line"), std::string::npos) << console;
    // Every finished record is kept byte for byte (same timings, same provenance): the resumed
    // file starts with exactly the complete lines the killed run wrote; only the rest is new.
    const auto resumed = testutil::read_text(killed / "results.jsonl");
    EXPECT_EQ(resumed.substr(0, kept.size()), kept);
    // The cases the resumed run printed are exactly the ones not kept.
    std::size_t printed = 0;
    std::stringstream lines(console);
    for (std::string l; std::getline(lines, l);) printed += l.rfind("Pass ", 0) == 0 ? 1u : 0u;
    EXPECT_EQ(printed + kept_cases, statuses(full / "results.jsonl").size());
    EXPECT_EQ(statuses(killed / "results.jsonl"), statuses(full / "results.jsonl"));
    EXPECT_EQ(read_jsonl(killed / "results.jsonl").size(),
              read_jsonl(full / "results.jsonl").size());  // none twice
}

TEST(ConformanceRun, ResumeRefusesAFileNoKillCouldLeave) {
    testutil::TempDir dir;
    const auto out = dir.path() / "out";
    const std::vector<std::string> run{"conformance", "run",      "--cases",
                                       "smoke.*",     "--output", out.string()};
    ASSERT_EQ(testutil::run_cli(run).exit_code, 0);
    const auto good = testutil::read_text(out / "results.jsonl");
    auto resume = run;
    resume.push_back("--resume");
    // A complete line in the middle that is not a record.
    std::ofstream(out / "results.jsonl", std::ios::trunc) << "not json\n" << good;
    auto r = testutil::run_cli(resume);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("results.jsonl:1: not a result record"), std::string::npos) << r.err;
    EXPECT_EQ(testutil::read_text(out / "results.jsonl"), "not json\n" + good);  // left alone
    // A case recorded twice.
    std::ofstream(out / "results.jsonl", std::ios::trunc)
        << good << good.substr(0, good.find('\n') + 1);
    r = testutil::run_cli(resume);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("recorded twice"), std::string::npos) << r.err;
    // Records of another comparison: the same scenes under another profile.
    std::ofstream(out / "results.jsonl", std::ios::trunc) << good;
    resume.insert(resume.end(), {"--profile-set", "tie_rule=right-top"});
    r = testutil::run_cli(resume);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("refusing to resume"), std::string::npos) << r.err;
    EXPECT_EQ(testutil::read_text(out / "results.jsonl"), good);
}

// A run's records name their implementation: resuming under another driver, or under a
// variable that changes the driver's results (GALLIVM_PERF changes texture results), is
// refused before anything is written.
TEST(ConformanceRun, ResumeRefusesAnotherDriverOrDriverEnvironment) {
    testutil::TempDir dir;
    const auto out = dir.path() / "out";
    const std::vector<std::string> run{"conformance",     "run",      "--cases",
                                       "smoke.triangles", "--output", out.string()};
    ASSERT_EQ(testutil::run_cli(run, "env -u GALLIVM_PERF ").exit_code, 0);
    const auto good = testutil::read_text(out / "results.jsonl");
    // Drop the record, as a kill before its case finished would.
    std::ofstream(out / "results.jsonl", std::ios::trunc) << "";
    auto resume = run;
    resume.push_back("--resume");
    auto r = testutil::run_cli(resume, "env GALLIVM_PERF=nopt ");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("GALLIVM_PERF=nopt"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("refusing to resume"), std::string::npos) << r.err;
    auto softpipe = resume;
    softpipe.insert(softpipe.end(), {"--driver", "softpipe"});
    r = testutil::run_cli(softpipe, "env -u GALLIVM_PERF ");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("osmesa-softpipe"), std::string::npos) << r.err;
    EXPECT_EQ(testutil::read_text(out / "results.jsonl"), "");
    // The same implementation resumes.
    r = testutil::run_cli(resume, "env -u GALLIVM_PERF ");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_FALSE(good.empty());
}

// Scenes of our own under DIR/scenes/t: one the reference gets wrong under tie_rule=right-top,
// one it gets right, and with `msaa` one that needs an extension nothing implements
// (NotSupported).
std::filesystem::path write_small_suite(const std::filesystem::path& dir, bool msaa = true) {
    const auto scenes = dir / "scenes" / "t";
    std::filesystem::create_directories(scenes);
    std::ofstream(scenes / "tie.json")
        << R"({"format": "refraster-scene/1", "name": "t.tie", "description": "d",
      "target": {"width": 8, "height": 8}, "clear": {"color": [0, 0, 0, 1]},
      "draws": [{"primitive": "triangles", "vertices": [{"position": [0, 0]}, {"position": [8, 0]}, {"position": [0, 8]}]}]})";
    std::ofstream(scenes / "plain.json")
        << R"({"format": "refraster-scene/1", "name": "t.plain", "description": "d",
      "target": {"width": 8, "height": 8}, "clear": {"color": [0, 0, 0, 1]},
      "draws": [{"primitive": "triangles", "vertices": [{"position": [0.25, 0.25]}, {"position": [7.25, 0.75]}, {"position": [1.5, 7.75]}]}]})";
    if (msaa)
        std::ofstream(scenes / "msaa.json")
            << R"({"format": "refraster-scene/1", "name": "t.msaa", "description": "d",
      "requires": ["x-future"], "target": {"width": 8, "height": 8, "samples": 4}, "draws": []})";
    return dir / "scenes";
}

TEST(ConformanceRun, BaselineExpectedFailAndUnexpectedPass) {
    testutil::TempDir dir;
    // Scenes of our own: one the reference gets wrong on purpose (tie rule flipped by profile)
    // and one it gets right.
    write_small_suite(dir.path(), false);
    std::ofstream(dir.path() / "baseline.csv") << "# known failures\nt.tie,Fail\nt.plain,Fail\n";
    const auto out = dir.path() / "out";
    const auto r =
        testutil::run_cli({"conformance", "run", "--scenes", (dir.path() / "scenes").string(),
                           "--baseline", (dir.path() / "baseline.csv").string(), "--profile-set",
                           "tie_rule=right-top", "--output", out.string()});
    const auto st = statuses(out / "results.jsonl");
    EXPECT_EQ(st.at("t.tie"), "ExpectedFail");
    EXPECT_EQ(st.at("t.plain"), "UnexpectedPass");
    EXPECT_EQ(r.exit_code, 1);  // an unexpected pass fails the run: the baseline is stale
    // One word for the status everywhere (deqp-runner's), and the expected failure counted as
    // what it is, not as passed.
    EXPECT_NE(r.out.find("UnexpectedImprovement(Pass) t.plain"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("UnexpectedPass"), std::string::npos) << r.out;
    EXPECT_EQ(last_line(r.out), "0 passed, 1 failed, 0 skipped, 1 failed as the baseline expects")
        << r.out;
    const auto index = testutil::read_text(out / "index.html");
    EXPECT_NE(index.find("<tr><td>t</td><td class=\"num\">0</td><td class=\"num\">1</td><td "
                         "class=\"num\">0</td><td class=\"num\">1</td><td class=\"num\">0</td>"),
              std::string::npos)
        << index.substr(index.find("id=\"areas\""), 600);
    EXPECT_EQ(testutil::read_text(out / "failures.csv"), "t.plain,UnexpectedImprovement(Pass)\n");
    EXPECT_NE(testutil::read_text(out / "results.csv").find("t.tie,ExpectedFail,"),
              std::string::npos);
    const auto junit = testutil::read_text(out / "junit.xml");
    EXPECT_NE(junit.find("<failure type=\"UnexpectedImprovement(Pass)\""), std::string::npos);
    EXPECT_NE(junit.find("tests=\"2\" failures=\"1\""), std::string::npos);
}

TEST(ConformanceRun, CsvsSpeakDeqpRunnerAndBaselinesAcceptIt) {
    testutil::TempDir dir;
    const auto scenes = write_small_suite(dir.path());
    const auto first = dir.path() / "first";
    auto r = testutil::run_cli({"conformance", "run", "--scenes", scenes.string(), "--profile-set",
                                "tie_rule=right-top", "--output", first.string()});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    const auto csv = testutil::read_text(first / "results.csv");
    EXPECT_NE(csv.find("t.msaa,Skip,"), std::string::npos)
        << csv;  // deqp-runner's word for NotSupported
    EXPECT_EQ(csv.find("NotSupported"), std::string::npos) << csv;
    EXPECT_NE(csv.find("t.tie,Fail,"), std::string::npos) << csv;
    EXPECT_EQ(statuses(first / "results.jsonl").at("t.msaa"),
              "NotSupported");  // the precise status stays
    EXPECT_EQ(testutil::read_text(first / "failures.csv"), "t.tie,Fail\n");
    EXPECT_EQ(read_as_deqp_runner(first).size(), 3u);
    // The run's own results.csv, durations and all, is a baseline: now nothing is unexpected.
    const auto second = dir.path() / "second";
    r = testutil::run_cli({"conformance", "run", "--scenes", scenes.string(), "--profile-set",
                           "tie_rule=right-top", "--baseline", (first / "results.csv").string(),
                           "--output", second.string()});
    EXPECT_EQ(r.exit_code, 0) << r.err << r.out;
    EXPECT_EQ(statuses(second / "results.jsonl").at("t.tie"), "ExpectedFail");
    // deqp-runner's other words: ExpectedFail (any failure), Skip, and a comment.
    std::ofstream(dir.path() / "b.csv")
        << "# from an older run\nt.tie,ExpectedFail\nt.msaa,Skip\nt.plain,Pass,0.1\n";
    const auto third = dir.path() / "third";
    r = testutil::run_cli({"conformance", "run", "--scenes", scenes.string(), "--profile-set",
                           "tie_rule=right-top", "--baseline", (dir.path() / "b.csv").string(),
                           "--output", third.string()});
    EXPECT_EQ(r.exit_code, 0) << r.err << r.out;
    EXPECT_NE(testutil::read_text(third / "results.csv").find("t.tie,ExpectedFail,"),
              std::string::npos);
    EXPECT_EQ(read_as_deqp_runner(third).at("t.tie"), "ExpectedFail");
    // A fail where the baseline lists a crash, and a pass where it lists a missing case, are
    // improvements to record in it, as deqp-runner words them; both fail the run.
    std::ofstream(dir.path() / "c.csv") << "t.tie,Crash\nt.plain,Missing\n";
    const auto fourth = dir.path() / "fourth";
    r = testutil::run_cli({"conformance", "run", "--scenes", scenes.string(), "--profile-set",
                           "tie_rule=right-top", "--baseline", (dir.path() / "c.csv").string(),
                           "--output", fourth.string()});
    EXPECT_EQ(r.exit_code, 1) << r.err << r.out;
    const auto words = read_as_deqp_runner(fourth);
    EXPECT_EQ(words.at("t.tie"), "UnexpectedImprovement(Fail)");
    EXPECT_EQ(words.at("t.plain"), "UnexpectedImprovement(Pass)");
    EXPECT_EQ(words.at("t.msaa"), "Skip");
    const auto st4 = statuses(fourth / "results.jsonl");
    EXPECT_EQ(st4.at("t.tie"), "UnexpectedImprovement");
    EXPECT_EQ(st4.at("t.plain"), "UnexpectedPass");
    // An unknown word names the file and line.
    std::ofstream(dir.path() / "bad.csv") << "t.tie,Fail\nt.plain,Maybe\n";
    r = testutil::run_cli({"conformance", "run", "--scenes", scenes.string(), "--baseline",
                           (dir.path() / "bad.csv").string(), "--output",
                           (dir.path() / "x").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("bad.csv:2: expected name,Status"), std::string::npos) << r.err;
}

TEST(ConformanceRun, CasePageExplainCommandReproducesTheCase) {
    testutil::TempDir dir;
    const auto scenes = write_small_suite(dir.path());
    const auto out = dir.path() / "out";
    const auto r =
        testutil::run_cli({"conformance", "run", "--scenes", scenes.string(), "--cases", "t.tie",
                           "--against", "osmesa", "--driver", "llvmpipe", "--profile-set",
                           "tie_rule=right-top", "--output", out.string()});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    const auto page = testutil::read_text(out / "cases" / "t.tie.html");
    const std::regex code("<code id=\"explain-command\">([^<]*)</code>");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(page, m, code)) << page;
    const std::string cmd = m[1].str();
    EXPECT_NE(cmd.find("--against osmesa --driver llvmpipe --profile llvmpipe-22.3 --profile-set "
                       "tie_rule=right-top"),
              std::string::npos)
        << cmd;
    // Run it as printed: it reproduces the failing pixel and names the rule the run named.
    ASSERT_EQ(cmd.rfind("refraster ", 0), 0u);
    const auto log = dir.path() / "explain.txt";
    const int rc =
        std::system((bin() + cmd.substr(9) + " > " + testutil::shell_quote(log.string())).c_str());
    EXPECT_EQ(rc >> 8, 1);  // the pixel differs
    const auto text = testutil::read_text(log);
    EXPECT_NE(text.find("verdict: coverage: "), std::string::npos) << text;
    EXPECT_NE(text.find("tie rule: "), std::string::npos) << text;
    EXPECT_NE(page.find("coverage, tie rule"), std::string::npos);
    // The index names the profile that ran.
    EXPECT_NE(testutil::read_text(out / "index.html")
                  .find("Reference profile <b>llvmpipe-22.3+tie_rule=right-top</b>"),
              std::string::npos);
}

TEST(Bench, TablesJsonAndRefusesWrongPixels) {
    // A small fraction of every workload, one round: the table, the JSON of
    // docs/performance.md, and the comparison with llvmpipe that makes a wrong reference fail.
    testutil::TempDir dir;
    const auto json_path = dir.path() / "bench.json";
    auto r = testutil::run_cli(
        {"bench", "--scale", "0.002", "--rounds", "2", "--json", json_path.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("| full-perspective |"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("| medium-textured-trilinear |"), std::string::npos) << r.out;
    const auto j = json::parse(testutil::read_text(json_path));
    // Every workload of the default run (docs/performance.md, "What it measures").
    ASSERT_EQ(j["scenes"].size(), harness::bench_workload_names().size());
    for (const auto& s : j["scenes"]) {
        const auto name = s["name"].get<std::string>();
        // The softpipe rows are timed against softpipe alone; softpipe draws no 4x target.
        std::vector<const char*> timed{"ref_ms"};
        if (name.rfind("softpipe-", 0) == 0) {
            timed.insert(timed.end(), {"softpipe_ms", "speedup_vs_softpipe"});
            EXPECT_TRUE(s["llvmpipe_t0_ms"].is_null()) << name;
        } else {
            timed.insert(timed.end(), {"llvmpipe_t0_ms", "llvmpipe_ms", "speedup_vs_llvmpipe_t0"});
            if (name.find("-4x") == std::string::npos) timed.push_back("softpipe_ms");
        }
        for (const char* k : timed) EXPECT_GT(s[k].get<double>(), 0.0) << name << " " << k;
        EXPECT_GT(s["ref_heap_peak_mb"].get<double>(), 4.0)
            << s["name"];  // at least the 1024x1024 colour buffer
        double split = 0;
        for (const char* k : {"load", "setup", "raster", "fragment"})
            split += s["split_ms"][k].get<double>();
        EXPECT_GT(split, 0.0) << s["name"];
        EXPECT_GT(s["pixels"].get<double>(), 0.0) << s["name"];
    }
    r = testutil::run_cli({"bench", "--scenes", "medium-flat", "--scale", "0.01", "--rounds", "1",
                           "--profile-set", "snap_rounding=truncate"});
    EXPECT_EQ(r.exit_code, 3);
    EXPECT_NE(r.err.find("differs from llvmpipe's"), std::string::npos) << r.err;
    r = testutil::run_cli({"bench", "--scenes", "huge-flat"});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("unknown bench scene \"huge-flat\""), std::string::npos) << r.err;
}

TEST(ConformanceRun, ShardsPartitionTheSelection) {
    testutil::TempDir dir;
    std::map<std::string, std::string> all;
    std::size_t total = 0;
    for (int i = 0; i < 3; ++i) {
        const auto out = dir.path() / ("s" + std::to_string(i));
        const std::string cmd =
            "GTEST_SHARD_INDEX=" + std::to_string(i) + " GTEST_TOTAL_SHARDS=3 " + bin() +
            " conformance run --cases 'smoke.*,points.*' --against osmesa --output " +
            testutil::shell_quote(out.string()) + " > /dev/null";
        EXPECT_EQ(std::system(cmd.c_str()) >> 8, 0);
        const auto st = statuses(out / "results.jsonl");
        total += st.size();
        EXPECT_GE(st.size(), 9u);
        for (const auto& [k, v] : st)
            EXPECT_TRUE(all.emplace(k, v).second) << k << " ran on two shards";
    }
    const auto whole = dir.path() / "whole";
    EXPECT_EQ(std::system((bin() + " conformance run --cases 'smoke.*,points.*' --output " +
                           testutil::shell_quote(whole.string()) + " > /dev/null")
                              .c_str()) >>
                  8,
              0);
    EXPECT_EQ(all, statuses(whole / "results.jsonl"));
    EXPECT_EQ(total, all.size());
}

TEST(ConformanceRun, CaselistAndExclude) {
    testutil::TempDir dir;
    std::ofstream(dir.path() / "list.txt")
        << "# a dEQP-style case list\nsmoke.triangles\nsmoke.depth  # trailing "
           "comment\npoints.size_*\n";
    const auto out = dir.path() / "out";
    const auto r =
        testutil::run_cli({"conformance", "run", "--caselist", (dir.path() / "list.txt").string(),
                           "--exclude", "points.size_1*", "--output", out.string()});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const auto st = statuses(out / "results.jsonl");
    EXPECT_TRUE(st.count("smoke.triangles"));
    EXPECT_TRUE(st.count("smoke.depth"));
    EXPECT_TRUE(st.count("points.size_2"));
    EXPECT_FALSE(st.count("points.size_1_5"));
    EXPECT_FALSE(st.count("smoke.lines"));
}

TEST(ConformanceRun, DuplicateCaseNamesAreRefused) {
    testutil::TempDir dir;
    std::filesystem::create_directories(dir.path() / "a");
    const std::string scene =
        R"({"format": "refraster-scene/1", "target": {"width": 4, "height": 4}, "draws": []})";
    std::ofstream(dir.path() / "a" / "b.json") << scene;
    std::ofstream(dir.path() / "a.b.json") << scene;
    const auto r = testutil::run_cli({"conformance", "run", "--scenes", dir.path().string(),
                                      "--output", (dir.path() / "out").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("duplicate case name a.b"), std::string::npos) << r.err;
}

}  // namespace

namespace {

nlohmann::json explain(const std::string& scene, const std::string& pixel,
                       const std::vector<std::string>& extra) {
    std::vector<std::string> args{
        "explain", std::string(REFRASTER_SOURCE_DIR) + "/conformance/scenes/" + scene, "--pixel",
        pixel, "--json"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = testutil::run_cli(args);
    return nlohmann::json::parse(r.out);
}

TEST(Explain, FlippedTieRuleFailuresNameTheTieRule) {
    // Every failing pixel of a tie-heavy scene under the flipped rule is explained by the tie rule.
    testutil::TempDir dir;
    const auto scene = std::string(REFRASTER_SOURCE_DIR) +
                       "/conformance/scenes/triangles/coverage/square_through_centres.json";
    const auto r = testutil::run_cli({"compare", scene, "--profile-set", "tie_rule=right-top",
                                      "--diff", (dir.path() / "m.png").string()});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    const auto mask = harness::read_color_image(dir.path() / "m.png");
    int explained = 0;
    for (std::uint32_t y = 0; y < mask.height; ++y) {
        for (std::uint32_t x = 0; x < mask.width; ++x) {
            if (mask.color8[4 * mask.index(x, y)] != 255) continue;  // dark grey: equal
            const auto j = explain("triangles/coverage/square_through_centres.json",
                                   std::to_string(x) + "," + std::to_string(y),
                                   {"--profile-set", "tie_rule=right-top"});
            EXPECT_EQ(j["rule"], "tie rule") << x << "," << y << ": " << j["verdict"];
            EXPECT_FALSE(j["agree"].get<bool>());
            ++explained;
        }
    }
    // The square lights (10..19)^2 under left-bottom and (11..20)^2 under right-top: 19 + 19
    // pixels of difference.
    EXPECT_EQ(explained, 38);
}

TEST(Explain, SnappingMismatchIsNotATie) {
    // Half-away rounding moves the left edge at 10.5 + 1/512 off the centres: a mismatch at
    // column 10 with no centre exactly on a reference edge.
    const auto j = explain("triangles/coverage/left_edge_plus_1_512.json", "10,15",
                           {"--profile-set", "snap_rounding=half-away"});
    EXPECT_FALSE(j["agree"].get<bool>());
    EXPECT_NE(j["rule"], "tie rule");
    EXPECT_EQ(j["rule"], "snapping");
}

TEST(Explain, AgreementAndSvg) {
    testutil::TempDir dir;
    const auto svg = dir.path() / "n.svg";
    const auto r = testutil::run_cli(
        {"explain", std::string(REFRASTER_SOURCE_DIR) + "/conformance/scenes/smoke/triangles.json",
         "--pixel", "3,2", "--svg", svg.string()});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("verdict: the reference and the backend agree at (3, 2)"),
              std::string::npos)
        << r.out;
    const auto text = testutil::read_text(svg);
    EXPECT_NE(text.find("<svg"), std::string::npos);
    EXPECT_NE(text.find("<polygon"), std::string::npos);  // the triangle's snapped edges
    const auto bad = testutil::run_cli(
        {"explain", std::string(REFRASTER_SOURCE_DIR) + "/conformance/scenes/smoke/triangles.json",
         "--pixel", "99,2"});
    EXPECT_EQ(bad.exit_code, 2);  // bad input, like every other
    EXPECT_EQ(testutil::count_lines(bad.err), 1u);
    EXPECT_NE(bad.err.find("triangles.json: --pixel 99,2: outside the 8x8 target"),
              std::string::npos)
        << bad.err;
}

}  // namespace

namespace {

TEST(Reduce, TwoThousandTrianglesDownToTheSharedEdge) {
    // 1,998 small triangles away from pixel-centre ties (random float corners), plus two that
    // share an edge through pixel centres. With the tie rule flipped, the reference parts from
    // llvmpipe on that edge; reduce must keep the mismatch and end with at most 2 triangles.
    testutil::TempDir dir;
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    nlohmann::json vertices = nlohmann::json::array();
    for (int i = 0; i < 1998; ++i) {
        const float cx = 2 + 60 * u(rng), cy = 2 + 60 * u(rng);
        for (int k = 0; k < 3; ++k) {
            vertices.push_back({{"position", {cx + 3 * u(rng) - 1.5f, cy + 3 * u(rng) - 1.5f}},
                                {"color", {u(rng), u(rng), u(rng), 1.0f}}});
        }
    }
    for (auto p : {std::array<float, 2>{8.5f, 20.5f},
                   {40.5f, 20.5f},
                   {24.5f, 4.5f},
                   {40.5f, 20.5f},
                   {8.5f, 20.5f},
                   {24.5f, 44.5f}}) {
        vertices.push_back({{"position", {p[0], p[1]}}, {"color", {1, 1, 1, 1}}});
    }
    const nlohmann::json scene = {
        {"format", "refraster-scene/1"},
        {"target", {{"width", 64}, {"height", 64}}},
        {"clear", {{"color", {0, 0, 0, 1}}}},
        {"draws",
         {{{"primitive", "triangles"}, {"vertices", vertices}, {"state", {{"shade", "flat"}}}}}}};
    const auto in = dir.write("big.json", scene.dump());
    const auto out = dir.path() / "min.json";
    const auto r = testutil::run_cli(
        {"reduce", in.string(), "--profile-set", "tie_rule=right-top", "-o", out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    EXPECT_NE(r.out.find("signature: coverage: tie rule (a coverage difference that explain puts "
                         "down to tie rule"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("step 1:"), std::string::npos);
    // A coordinate step names the coordinate and its grid.
    EXPECT_TRUE(std::regex_search(
        r.out, std::regex(R"(step \d+: draws\[\d+\]\.vertices\[\d+\]\.position [xy] -?[0-9.]+ -> )"
                          R"(-?[0-9.]+ \(to a multiple of [0-9.e-]+\))")))
        << r.out;
    const auto reduced = nlohmann::json::parse(testutil::read_text(out));
    // The reduced scene records what it was reduced against.
    EXPECT_NE(reduced["description"].get<std::string>().find(", against "), std::string::npos)
        << reduced["description"];
    std::size_t triangles = 0;
    for (const auto& d : reduced["draws"]) triangles += d["vertices"].size() / 3;
    EXPECT_GE(triangles, 1u);
    EXPECT_LE(triangles, 2u);
    // The reduced scene is valid and still fails the same way.
    const auto c =
        testutil::run_cli({"compare", out.string(), "--profile-set", "tie_rule=right-top"});
    EXPECT_EQ(c.exit_code, 1) << c.err << c.out;
}

TEST(Reduce, KeepsTheChosenPixelAndIsNamedAfterItsFile) {
    // Two triangles apart, each with a diagonal through pixel centres: under a flipped tie rule
    // both mismatch. Keeping a pixel of the second must keep the second triangle, whatever the
    // pixel of largest difference; the scene is named after its output file.
    testutil::TempDir dir;
    const std::string scene = R"({"format": "refraster-scene/1", "name": "two.triangles",
      "target": {"width": 32, "height": 16}, "clear": {"color": [0, 0, 0, 1]},
      "draws": [{"primitive": "triangles", "vertices": [
        {"position": [0, 0]}, {"position": [8, 0]}, {"position": [0, 8]},
        {"position": [16, 0]}, {"position": [32, 0]}, {"position": [16, 16]}]}]})";
    const auto in = dir.write("two.json", scene);
    const auto out = dir.path() / "second_only.json";
    // A pixel where the second triangle mismatches, from the error mask.
    const auto cmp =
        testutil::run_cli({"compare", in.string(), "--profile-set", "tie_rule=right-top", "--diff",
                           (dir.path() / "m.png").string()});
    ASSERT_EQ(cmp.exit_code, 1) << cmp.err;
    const auto mask = harness::read_color_image(dir.path() / "m.png");
    int px = -1, py = -1;
    for (std::uint32_t y = 0; y < mask.height && px < 0; ++y) {
        for (std::uint32_t x = 16; x < mask.width; ++x) {
            if (mask.color8[4 * mask.index(x, y)] == 255) {
                px = static_cast<int>(x);
                py = static_cast<int>(y);
                break;
            }
        }
    }
    ASSERT_GE(px, 16) << "the second triangle mismatches somewhere";
    const std::string pixel = std::to_string(px) + "," + std::to_string(py);
    auto r = testutil::run_cli({"reduce", in.string(), "--profile-set", "tie_rule=right-top",
                                "--pixel", pixel, "-o", out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    const auto reduced = nlohmann::json::parse(testutil::read_text(out));
    EXPECT_EQ(reduced["name"], "second_only");
    ASSERT_EQ(reduced["draws"].size(), 1u);
    ASSERT_EQ(reduced["draws"][0]["vertices"].size(), 3u);
    EXPECT_GE(reduced["draws"][0]["vertices"][0]["position"][0].get<float>(),
              16.0f);  // the second triangle
    const auto e = testutil::run_cli({"explain", out.string(), "--pixel", pixel, "--profile-set",
                                      "tie_rule=right-top", "--json"});
    EXPECT_EQ(e.exit_code, 1) << e.err;
    const auto ej = nlohmann::json::parse(e.out);
    EXPECT_EQ(ej["rule"], "tie rule");
    // The JSON carries what the text says: the GL verdict, and which implementation drew the
    // backend's side.
    EXPECT_NE(ej.value("gl_verdict", "").find("legal"), std::string::npos) << e.out;
    EXPECT_TRUE(ej["backend"]["provenance"].contains("renderer")) << e.out;
    // A class the scene does not show cannot be kept; bad pixels are bad input.
    r = testutil::run_cli({"reduce", in.string(), "--profile-set", "tie_rule=right-top", "--class",
                           "depth", "-o", (dir.path() / "d.json").string()});
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "d.json"));
    r = testutil::run_cli(
        {"reduce", in.string(), "--pixel", "40,1", "-o", (dir.path() / "p.json").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("outside the 32x16 target"), std::string::npos) << r.err;
}

// A backend that runs out of --timeout ends the reduction as a backend failure (exit 3, the
// backend's Timeout message), not as "the scene matches the backend" (exit 2); nothing is
// written. (The reference's own renders are bounded the same way: Cli.TimeoutStopsTheReference*.)
TEST(Reduce, ATimeoutIsABackendFailure) {
    testutil::TempDir dir;
    const auto in = dir.write("heavy.json", testutil::layered_scene(2048, 400));
    const auto out = dir.path() / "min.json";
    const auto r =
        testutil::run_cli({"reduce", in.string(), "--timeout", "0.5", "-o", out.string()});
    EXPECT_EQ(r.exit_code, 3) << r.err << r.out;
    EXPECT_EQ(testutil::count_lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("gave no answer within 0.500000 s for " + in.string()), std::string::npos)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace

namespace {

using testutil::chromium_dom;
using testutil::layout_probe;

std::string dump_dom(const std::filesystem::path& page, const std::filesystem::path& profile_dir,
                     const std::string& window = "1280,900") {
    return chromium_dom(page, profile_dir, window);
}

// The explain picture, laid out by Chromium: nothing past a 1,280 px window and no two text boxes
// overlapping (the verdict used to be one line cut at the right edge, and the legend's entries
// ran into each other); every primitive and every snapped edge labelled as the text names them;
// both sides' values in the captions.
TEST(HtmlReport, ChromiumExplainPictureFitsAndLabelsWhatTheTextNames) {
    testutil::TempDir dir;
    const std::string scene = std::string(REFRASTER_SOURCE_DIR) +
                              "/conformance/scenes/triangles/coverage/square_through_centres.json";
    for (const char* pixel : {"10,10", "0,0", "12,20"}) {
        SCOPED_TRACE(pixel);
        const auto svg = dir.path() / (std::string("e") + pixel[0] + pixel[1] + ".svg");
        const auto r = testutil::run_cli({"explain", scene, "--pixel", pixel, "--profile-set",
                                          "tie_rule=right-top", "--svg", svg.string()});
        ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.err;
        const std::string text = testutil::read_text(svg);
        const auto count = [&](const std::string& what) {
            std::size_t n = 0;
            for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
                ++n;
            return n;
        };
        EXPECT_EQ(count("class=\"edge-label\""), count("class=\"edge-direction\""));
        EXPECT_EQ(count("class=\"primitive-label\""),
                  count("class=\"snapped\"") + count("class=\"unsnapped\""));
        EXPECT_NE(text.find("): reference "), std::string::npos);
        EXPECT_NE(text.find("; backend "), std::string::npos);
        // The backend's colours too: at a differing pixel its cell is split, its lower-right
        // half the backend's (the flipped tie rule makes (10, 10) differ).
        if (std::string(pixel) == "10,10") {
            EXPECT_GT(count("class=\"backend-half\""), 0u) << text.substr(0, 400);
        }
        const auto page = dir.path() / (svg.stem().string() + ".html");
        std::ofstream(page) << "<!DOCTYPE html><html><body style=\"margin:8px\">" << text
                            << "</body></html>\n";
        const std::string probe = layout_probe(page, dir.path() / "chrome");
        ASSERT_NE(probe, "no probe") << "(is the chromium package installed?)";
        EXPECT_NE(probe.find("outside=0 "), std::string::npos) << probe;
        EXPECT_NE(probe.find("overlaps=0 "), std::string::npos) << probe;
    }
}

// The index and a failing case's page fit a 1,280 px window: nothing reaches past its right
// edge (the profile's rule string and the case table used to), and no two text boxes overlap.
TEST(HtmlReport, ChromiumLayoutFitsA1280PixelWindow) {
    testutil::TempDir dir;
    const auto out = dir.path() / "run";
    const auto r = testutil::run_cli(
        {"conformance", "run", "--cases", "smoke.*,triangles.coverage.square*", "--profile-set",
         "tie_rule=right-top", "--profile-set", "offset_units_scale=2", "--output", out.string()});
    ASSERT_EQ(r.exit_code, 1) << r.err;
    for (const auto& page :
         {out / "index.html", out / "cases" / "triangles.coverage.square_through_centres.html"}) {
        const std::string probe = layout_probe(page, dir.path() / "chrome");
        ASSERT_NE(probe, "no probe") << page << " (is the chromium package installed?)";
        EXPECT_NE(probe.find("client=1280"), std::string::npos) << probe;
        EXPECT_NE(probe.find("outside=0 "), std::string::npos) << page << ": " << probe;
        EXPECT_NE(probe.find("overlaps=0 "), std::string::npos) << page << ": " << probe;
    }
    // The hovered pixel's explain command sits right under the images, above the mask legend
    // and the provenance tables.
    const std::string page =
        testutil::read_text(out / "cases" / "triangles.coverage.square_through_centres.html");
    const auto command = page.find("id=\"pixel-command\"");
    ASSERT_NE(command, std::string::npos);
    EXPECT_LT(command, page.find("id=\"mask-legend\""));
    EXPECT_LT(command, page.find("Reference provenance"));
}

TEST(HtmlReport, ChromiumShowsSummaryChartImagesAndNumbers) {
    testutil::TempDir dir;
    const auto out = dir.path() / "run";
    const auto r =
        testutil::run_cli({"conformance", "run", "--cases", "smoke.*,triangles.coverage.square*",
                           "--profile-set", "tie_rule=right-top", "--output", out.string()});
    ASSERT_EQ(r.exit_code, 1) << r.err;  // the flipped tie rule fails the squares
    const auto index = dump_dom(out / "index.html", dir.path() / "chrome");
    ASSERT_FALSE(index.empty()) << "chromium produced no DOM (is the chromium package installed?)";
    EXPECT_NE(index.find("id=\"summary\""), std::string::npos);
    EXPECT_NE(index.find("id=\"error-chart\""), std::string::npos);
    EXPECT_NE(index.find("<circle"), std::string::npos);
    EXPECT_NE(index.find("href=\"cases/triangles.coverage.square_through_centres.html\""),
              std::string::npos);
    EXPECT_NE(index.find(">triangles.coverage<"), std::string::npos);  // counts per area
    // The chart's axes carry ticks with units, and a legend counts the statuses.
    EXPECT_NE(index.find("class=\"tick-x\""), std::string::npos);
    EXPECT_NE(index.find("class=\"tick-y\""), std::string::npos);
    // 38 mismatched pixels against none: a decade and more, so a log scale with its decades.
    EXPECT_NE(index.find("data-y-scale=\"log\""), std::string::npos);
    EXPECT_NE(index.find("mismatched pixels (log scale, 0 at the bottom)"), std::string::npos);
    EXPECT_NE(index.find("text-anchor=\"end\">10</text>"), std::string::npos);
    EXPECT_NE(index.find("render time, reference + backend"), std::string::npos);
    EXPECT_NE(index.find("id=\"chart-legend\""), std::string::npos);
    EXPECT_NE(index.find(">Fail (2)<"), std::string::npos);
    EXPECT_NE(index.find(">Pass (8)<"), std::string::npos);
    // The table's script ran (it counts the rows it shows), and the failing rows carry their
    // verdict and pixel classes.
    EXPECT_NE(index.find("10 of 10 cases shown"), std::string::npos);
    EXPECT_NE(index.find("coverage: tie rule"), std::string::npos);
    EXPECT_NE(index.find("<option>Fail</option>"), std::string::npos);
    // A link to a view of the table: the failing cases only, the most mismatched pixels first.
    const auto view =
        dump_dom(out.string() + "/index.html#status=Fail&sort=-3", dir.path() / "chrome");
    EXPECT_NE(view.find("2 of 10 cases shown"), std::string::npos);
    EXPECT_NE(view.find("aria-sort=\"descending\""), std::string::npos);
    const auto filtered =
        dump_dom(out.string() + "/index.html#filter=strip", dir.path() / "chrome");
    EXPECT_NE(filtered.find("1 of 10 cases shown"), std::string::npos);  // smoke.triangle_strip
    // Sorted by name descending, the last case comes first.
    const auto sorted = dump_dom(out.string() + "/index.html#sort=-0", dir.path() / "chrome");
    const auto first_row = sorted.find("id=\"cases\"");
    ASSERT_NE(first_row, std::string::npos);
    EXPECT_LT(sorted.find("triangles.coverage.square_through_centres_cw", first_row),
              sorted.find("smoke.blending", first_row));
    // JUnit: every case says its verdict, its numbers and its page.
    const auto junit = testutil::read_text(out / "junit.xml");
    EXPECT_NE(junit.find("Fail: 38 mismatched pixels (missing 19, extra 19, colour only 0"),
              std::string::npos)
        << junit;
    EXPECT_NE(junit.find("verdict: coverage: tie rule"), std::string::npos);
    EXPECT_NE(junit.find("case page: cases/triangles.coverage.square_through_centres.html"),
              std::string::npos);
    EXPECT_NE(junit.find("Pass: 0 mismatched pixels"), std::string::npos);
    const auto page = dump_dom(out / "cases" / "triangles.coverage.square_through_centres.html",
                               dir.path() / "chrome");
    EXPECT_NE(page.find("id=\"case-status\""), std::string::npos);
    EXPECT_NE(page.find(">Fail<"), std::string::npos);
    EXPECT_NE(page.find("id=\"case-numbers\""), std::string::npos);
    EXPECT_NE(page.find(">38<"), std::string::npos);  // mismatched pixels
    EXPECT_NE(page.find("src=\"../images/triangles.coverage.square_through_centres.ref.png\""),
              std::string::npos);
    EXPECT_NE(page.find("src=\"../images/triangles.coverage.square_through_centres.mask.png\""),
              std::string::npos);
    // The zoom script ran and scaled the 32-pixel images eightfold.
    EXPECT_NE(page.find("width: 256px"), std::string::npos);
    EXPECT_NE(page.find("refraster explain"), std::string::npos);
    // 8-bit values print as whole numbers; the mask legend names every class.
    EXPECT_NE(page.find("reference (0, 0, 0, 255), backend (255, 255, 255, 255)"),
              std::string::npos);
    EXPECT_EQ(page.find("255.0"), std::string::npos);
    for (const char* cls :
         {"equal:", "missing:", "extra:", "another primitive", "colour only:", "depth only:"}) {
        EXPECT_NE(page.find(cls), std::string::npos) << cls;
    }
    // The explain view was written and is linked.
    EXPECT_NE(page.find("href=\"../explain/triangles.coverage.square_through_centres.svg\""),
              std::string::npos);
    const auto svg =
        testutil::read_text(out / "explain" / "triangles.coverage.square_through_centres.svg");
    EXPECT_NE(svg.find("<svg"), std::string::npos);
    EXPECT_NE(testutil::read_text(out / "explain" / "triangles.coverage.square_through_centres.txt")
                  .find("verdict"),
              std::string::npos);
}

// The case page at a pixel (#pixel=X,Y, what the pointer does): the readout names the pixel
// in GL's coordinates, the explain command is for that pixel, and a screenshot shows the
// outline at the same place in each of the three images, side by side.
TEST(HtmlReport, ChromiumCasePageOutlinesThePixelInEveryImage) {
    testutil::TempDir dir;
    const auto out = dir.path() / "run";
    const auto r = testutil::run_cli({"conformance", "run", "--cases",
                                      "triangles.coverage.square_through_centres", "--profile-set",
                                      "tie_rule=right-top", "--output", out.string()});
    ASSERT_EQ(r.exit_code, 1) << r.err;
    const auto page_path = out / "cases" / "triangles.coverage.square_through_centres.html";
    const std::string at = page_path.string() + "#pixel=12,20";
    const auto page = dump_dom(at, dir.path() / "chrome");
    ASSERT_FALSE(page.empty());
    EXPECT_NE(page.find("pixel (12, 20)"), std::string::npos);
    EXPECT_NE(page.find("--pixel 12,20"), std::string::npos);
    EXPECT_NE(page.find("display: block"), std::string::npos);  // the outlines are shown
    // The readout gives both sides' values there, as the images hold them.
    {
        const auto value = [&](const char* who) {
            const auto img = harness::read_color_image(
                out / "images" /
                (std::string("triangles.coverage.square_through_centres.") + who + ".png"));
            const std::size_t i = 4 * img.index(12, 20);
            return std::to_string(img.color8[i]) + ", " + std::to_string(img.color8[i + 1]) + ", " +
                   std::to_string(img.color8[i + 2]) + ", " + std::to_string(img.color8[i + 3]);
        };
        EXPECT_NE(page.find("pixel (12, 20): reference " + value("ref")), std::string::npos)
            << page.substr(page.find("pixel-readout"), 300);
        EXPECT_NE(page.find("; backend " + value("osmesa-llvmpipe")), std::string::npos)
            << page.substr(page.find("pixel-readout"), 300);
    }

    const auto shot = dir.path() / "case.png";
    const std::string cmd =
        "timeout 120 chromium --headless --no-sandbox --disable-gpu --no-first-run "
        "--user-data-dir=" +
        testutil::shell_quote((dir.path() / "chrome").string()) +
        " --virtual-time-budget=2000 --window-size=1200,900 --hide-scrollbars --screenshot=" +
        testutil::shell_quote(shot.string()) + " " + testutil::shell_quote("file://" + at) +
        " > /dev/null 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    const auto img = harness::read_color_image(shot);
    ASSERT_GT(img.width, 0u);
    // The outline colour (#00e5ff): in three places side by side, each 8 screen pixels a
    // side plus its 2-pixel border, all on the same rows.
    std::vector<std::uint32_t> xs;
    std::uint32_t top = img.height, bottom = 0;
    for (std::uint32_t y = 0; y < img.height; ++y) {
        for (std::uint32_t x = 0; x < img.width; ++x) {
            const auto* p = &img.color8[4 * (std::size_t{y} * img.width + x)];
            if (p[0] < 40 && p[1] > 200 && p[2] > 230) {
                xs.push_back(x);
                top = std::min(top, y);
                bottom = std::max(bottom, y);
            }
        }
    }
    ASSERT_FALSE(xs.empty()) << "no outline in the screenshot";
    std::sort(xs.begin(), xs.end());
    int groups = 1;
    for (std::size_t i = 1; i < xs.size(); ++i) groups += xs[i] - xs[i - 1] > 20 ? 1 : 0;
    EXPECT_EQ(groups, 3);
    EXPECT_LE(bottom - top, 14u);  // one row of outlines, 8 px plus borders
    // The mask's magenta (missing) and red (extra) are on screen too.
    bool magenta = false, red = false;
    for (std::size_t i = 0; i + 3 < img.color8.size(); i += 4) {
        const auto* p = &img.color8[i];
        magenta = magenta || (p[0] > 240 && p[1] < 20 && p[2] > 240);
        red = red || (p[0] > 240 && p[1] < 20 && p[2] < 20);
    }
    EXPECT_TRUE(magenta);
    EXPECT_TRUE(red);

    // The explain view the page links, drawn by Chromium: the explained pixel outlined in
    // magenta in both panels (unsnapped, snapped), side by side, and a primitive's outline.
    const auto view_shot = dir.path() / "explain.png";
    const std::string view_cmd =
        "timeout 120 chromium --headless --no-sandbox --disable-gpu --no-first-run "
        "--user-data-dir=" +
        testutil::shell_quote((dir.path() / "chrome").string()) +
        " --window-size=900,700 --hide-scrollbars --screenshot=" +
        testutil::shell_quote(view_shot.string()) + " " +
        testutil::shell_quote(
            "file://" +
            (out / "explain" / "triangles.coverage.square_through_centres.svg").string()) +
        " > /dev/null 2>&1";
    ASSERT_EQ(std::system(view_cmd.c_str()), 0);
    const auto view = harness::read_color_image(view_shot);
    std::vector<std::uint32_t> outline_x;
    bool primitive = false;
    for (std::uint32_t y = 0; y < view.height; ++y) {
        for (std::uint32_t x = 0; x < view.width; ++x) {
            const auto* p = &view.color8[4 * (std::size_t{y} * view.width + x)];
            if (p[0] > 240 && p[1] < 20 && p[2] > 240) outline_x.push_back(x);
            primitive =
                primitive ||
                (p[0] < 20 && p[1] > 150 && p[1] < 190 && p[2] > 50 && p[2] < 90) ||  // #00a844
                (p[0] < 60 && p[1] > 80 && p[1] < 120 && p[2] > 240);                 // #2962ff
        }
    }
    ASSERT_FALSE(outline_x.empty());
    std::sort(outline_x.begin(), outline_x.end());
    int panels = 1;
    for (std::size_t i = 1; i < outline_x.size(); ++i)
        panels += outline_x[i] - outline_x[i - 1] > 100 ? 1 : 0;
    EXPECT_GE(panels, 2);  // both panels (the legend's swatch may add one)
    EXPECT_TRUE(primitive);
}

}  // namespace

namespace {

TEST(ConformanceRun, HungWorkerIsATimeoutAndTheRunGoesOn) {
    testutil::TempDir dir;
    const auto out = dir.path() / "run";
    const std::string cmd =
        "REFRASTER_WORKER_HANG_AT=2 " + bin() +
        " conformance run --cases 'smoke.*' --against osmesa --timeout 1 --output " +
        testutil::shell_quote(out.string()) + " > /dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()) >> 8, 1);
    const auto lines = read_jsonl(out / "results.jsonl");
    ASSERT_EQ(lines.size(), 8u);
    int timeouts = 0;
    for (const auto& l : lines) timeouts += l["status"] == "Timeout";
    EXPECT_EQ(timeouts, 1);
    EXPECT_EQ(lines[1]["status"], "Timeout");
    EXPECT_NE(testutil::read_text(out / "failures.csv").find(",Timeout"), std::string::npos);
}

TEST(ConformanceRun, ProgressLineOnATerminalOnly) {
    testutil::TempDir dir;
    // `script` gives the run a terminal.
    const std::string run = bin() + " conformance run --cases 'smoke.*' --output " +
                            testutil::shell_quote((dir.path() / "a").string());
    const std::string cmd = "CI= script -qec " + testutil::shell_quote(run) +
                            " /dev/null < /dev/null > " +
                            testutil::shell_quote((dir.path() / "tty.txt").string()) + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()) >> 8, 0);
    const auto tty = testutil::read_text(dir.path() / "tty.txt");
    EXPECT_NE(tty.find("[8/8]"), std::string::npos) << tty;
    EXPECT_NE(tty.find("ETA"), std::string::npos);
    EXPECT_NE(tty.find("8 passed, 0 failed, 0 skipped"), std::string::npos);
    // Not a terminal: one line per case, no progress.
    const auto plain = testutil::run_cli(
        {"conformance", "run", "--cases", "smoke.*", "--output", (dir.path() / "b").string()});
    EXPECT_EQ(plain.out.find("ETA"), std::string::npos);
    EXPECT_NE(plain.out.find("Pass smoke.triangles\n"), std::string::npos);
    // Nothing differs: the chart's pixel axis is linear (0 and 1), not a log scale of nothing.
    const auto index = testutil::read_text(dir.path() / "b" / "index.html");
    EXPECT_NE(index.find("data-y-scale=\"linear\""), std::string::npos);
    EXPECT_EQ(index.find("(log scale, 0 at the bottom)"), std::string::npos);
}

}  // namespace

namespace {

// --timeout bounds the reference's side of a case as it bounds the worker's: a scene that
// would take the reference a minute is a Timeout after half a second, the reference's own status
// says so, and the run goes on to the next case.
TEST(ConformanceRun, SlowReferenceIsATimeoutAndTheRunGoesOn) {
    testutil::TempDir dir;
    const auto scenes = dir.path() / "scenes";
    std::filesystem::create_directories(scenes / "slow");
    {
        // A scene is named after its path.
        std::ofstream(scenes / "slow" / "a_layers.json")
            << testutil::layered_scene(2048, 400, "slow.a_layers");
        std::string tie = kTieScene;
        const std::string name = R"("name": "tie")";
        tie.replace(tie.find(name), name.size(), R"("name": "slow.b_tie")");
        std::ofstream(scenes / "slow" / "b_tie.json") << tie;
    }
    const auto out = dir.path() / "run";
    const auto r =
        testutil::run_cli({"conformance", "run", "--scenes", scenes.string(), "--against", "osmesa",
                           "--threads", "2", "--timeout", "0.5", "--output", out.string()});
    EXPECT_EQ(r.exit_code, 1) << r.err;
    const auto lines = read_jsonl(out / "results.jsonl");
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(lines[0]["status"], "Timeout") << lines[0].dump();
    EXPECT_EQ(lines[0]["reference"]["status"], "Timeout") << lines[0].dump();
    EXPECT_NE(lines[0]["reference"]["message"].get<std::string>().find(
                  "gave no answer within 0.500000 s"),
              std::string::npos)
        << lines[0].dump();
    EXPECT_EQ(lines[1]["status"], "Pass") << lines[1].dump();  // the run went on
    EXPECT_NE(testutil::read_text(out / "failures.csv").find(",Timeout"), std::string::npos);
    // The report's chart draws the timeout as one, a cross on the top edge that links to the
    // case, never as a dot at 0 mismatched pixels.
    const auto index = testutil::read_text(out / "index.html");
    EXPECT_NE(index.find("<a href=\"cases/slow.a_layers.html\"><path class=\"timeout\""),
              std::string::npos)
        << index;
    EXPECT_NE(index.find("<a href=\"cases/slow.b_tie.html\"><circle"), std::string::npos);
}

}  // namespace
