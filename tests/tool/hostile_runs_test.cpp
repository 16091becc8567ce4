// `conformance run`, `--resume` and `merge` against hostile or careless inputs: scene paths and
// file names that would break a page, a CSV, junit.xml or the terminal, records whose names
// leave the output, records of another run, shard numbers out of range, results files that
// are devices or FIFOs, and a used output folder. The reference runs against itself (a tie
// rule flipped so that a case fails), so no GL is needed.
//
// REFRASTER_TEST_CLI, when set, names another refraster binary to run these against
// (test_util.hpp, refraster_bin).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "test_util.hpp"

namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

// A run of the CLI, ended after 60 s: a command that would block without bound (a FIFO read
// by an older build) fails the test instead of hanging it.
testutil::CliResult cli(const std::vector<std::string>& args) {
    return testutil::run_cli(args, testutil::kUnsetShardVariables + "timeout 60 ");
}

const char* kTie =
    R"({"format": "refraster-scene/1", "target": {"width": 8, "height": 8},
        "clear": {"color": [0, 0, 0, 1]}, "draws": [{"primitive": "triangles",
        "vertices": [{"position": [0, 0]}, {"position": [8, 0]}, {"position": [0, 8]}]}]})";
const char* kPlain =
    R"({"format": "refraster-scene/1", "target": {"width": 8, "height": 8},
        "clear": {"color": [0, 0, 0, 1]}, "draws": [{"primitive": "triangles",
        "vertices": [{"position": [0.25, 0.25]}, {"position": [7.25, 0.75]},
        {"position": [1.5, 7.75]}]}]})";

// ROOT/t/tie.json (fails with the tie rule flipped) and ROOT/t/plain.json (passes).
fs::path suite(const fs::path& root) {
    fs::create_directories(root / "t");
    std::ofstream(root / "t" / "tie.json") << kTie;
    std::ofstream(root / "t" / "plain.json") << kPlain;
    return root;
}

std::vector<std::string> run_args(const fs::path& scenes, const fs::path& out) {
    return {"conformance", "run",           "--scenes",           scenes.string(), "--against",
            "ref",         "--profile-set", "tie_rule=right-top", "--output",      out.string()};
}

std::vector<std::string> with(std::vector<std::string> args, std::vector<std::string> more) {
    args.insert(args.end(), more.begin(), more.end());
    return args;
}

std::vector<json> records(const fs::path& jsonl) {
    std::vector<json> v;
    std::istringstream in(testutil::read_text(jsonl));
    for (std::string l; std::getline(in, l);)
        if (!l.empty()) v.push_back(json::parse(l));
    return v;
}

void write_records(const fs::path& jsonl, const std::vector<json>& rs) {
    std::ofstream o(jsonl, std::ios::binary | std::ios::trunc);
    for (const auto& r : rs) o << r.dump() << "\n";
}

std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

// One line on stderr, with no control character but its newline.
void expect_one_clean_line(const std::string& err) {
    EXPECT_EQ(count(err, "\n"), 1u) << err;
    EXPECT_TRUE(std::none_of(err.begin(), err.end() - 1, [](char c) {
        return static_cast<unsigned char>(c) < 0x20;
    })) << err;
}

// No script of a page's own is ended early, and the markup a path carries is never markup.
void expect_script_intact(const std::string& page) {
    EXPECT_EQ(count(page, "<script"), count(page, "</script")) << page;
    EXPECT_EQ(page.find("<img src=x"), std::string::npos);
}

TEST(HostileRuns, ScenePathCannotEndTheCasePageScript) {
    testutil::TempDir dir;
    const fs::path root = suite(dir.path() / "<" / "script><img src=x onerror=alert(1)>");
    const fs::path out = dir.path() / "out";
    const auto r = cli(run_args(root, out));
    ASSERT_EQ(r.exit_code, 1) << r.out << r.err;
    const std::string page = testutil::read_text(out / "cases" / "t.tie.html");
    ASSERT_NE(page.find("explain-command"), std::string::npos)
        << "the case failed and is explained";
    expect_script_intact(page);

    // Through merge: a record's scene field.
    auto rs = records(out / "results.jsonl");
    for (auto& rec : rs) rec["scene"] = "/s/</script><img src=x onerror=alert(2)>/t.json";
    const fs::path shard = dir.path() / "shard";
    fs::create_directories(shard);
    write_records(shard / "results.jsonl", rs);
    const fs::path merged = dir.path() / "merged";
    const auto m = cli({"conformance", "merge", shard.string(), "--output", merged.string()});
    ASSERT_EQ(m.exit_code, 1) << m.out << m.err;  // merged whole; its case failed, as in the run
    expect_script_intact(testutil::read_text(merged / "cases" / "t.tie.html"));
}

TEST(HostileRuns, SceneFileNamesThatWouldForgeOutputAreRefusedBeforeWriting) {
    for (const std::string& bad : {std::string("x\nPass forged_case"), std::string("x\x1b[2Jy"),
                                   std::string("a,b"), std::string(250, 'n')}) {
        testutil::TempDir dir;
        const fs::path root = suite(dir.path() / "scenes");
        std::ofstream(root / "t" / (bad + ".json")) << kPlain;
        const fs::path out = dir.path() / "out";
        const auto r = cli(run_args(root, out));
        EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
        EXPECT_EQ(r.out.find("forged_case"), std::string::npos) << r.out;
        expect_one_clean_line(r.err);
        EXPECT_NE(r.err.find("case name"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out / "results.jsonl")) << "nothing written";
    }
}

TEST(HostileRuns, ControlCharactersInPathsReachNoReportOrTerminalRaw) {
    testutil::TempDir dir;
    // A scene that does not load, under a root whose path holds ESC and a newline, and one whose
    // `name` (quoted in its InternalError message) holds an escape sequence and a forged line.
    const fs::path root = suite(dir.path() / "r\x1b[31m\nPass forged");
    std::ofstream(root / "t" / "broken.json") << "{ not json";
    std::ofstream(root / "t" / "named.json")
        << R"({"format": "refraster-scene/1", "name": "x\u001b[31mred\nPass forged",
              "target": {"width": 4, "height": 4}, "draws": []})";
    const fs::path out = dir.path() / "out";
    const auto r = cli(run_args(root, out));
    ASSERT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_EQ(r.out.find('\x1b'), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("\nPass forged"), std::string::npos) << r.out;
    const std::string junit = testutil::read_text(out / "junit.xml");
    ASSERT_NE(junit.find("t.broken"), std::string::npos);
    EXPECT_EQ(junit.find('\x1b'), std::string::npos) << "XML 1.0 forbids it";
    EXPECT_NE(junit.find("t.named"), std::string::npos);
    EXPECT_EQ(testutil::read_text(out / "cases" / "t.named.html").find('\x1b'), std::string::npos);
    const std::string csv = testutil::read_text(out / "results.csv");
    EXPECT_EQ(count(csv, "\n"), 4u) << csv;
    // The run merges as it is: the case that rendered nothing is of the same run as the others
    // (exit 1 as the run's: some cases failed).
    const auto m =
        cli({"conformance", "merge", out.string(), "--output", (dir.path() / "merged").string()});
    EXPECT_EQ(m.exit_code, 1) << m.out << m.err;
    EXPECT_NE(m.out.find(" passed, "), std::string::npos) << m.out;
    EXPECT_EQ(testutil::read_text(dir.path() / "merged" / "results.csv"), csv);
    EXPECT_EQ(m.out.find('\x1b'), std::string::npos) << m.out;
}

TEST(HostileRuns, MergeRefusesNamesOutsideTheOutputAndBadRecordsBeforeWriting) {
    testutil::TempDir dir;
    const fs::path root = suite(dir.path() / "scenes");
    const fs::path run = dir.path() / "run";
    ASSERT_EQ(cli(run_args(root, run)).exit_code, 1);
    const auto good = records(run / "results.jsonl");
    const fs::path shard = dir.path() / "shard", out = dir.path() / "deep" / "out";
    fs::create_directories(shard);
    const auto refused = [&](const std::function<void(std::vector<json>&)>& spoil,
                             const std::string& says) {
        auto rs = good;
        spoil(rs);
        write_records(shard / "results.jsonl", rs);
        const auto m = cli({"conformance", "merge", shard.string(), "--output", out.string()});
        EXPECT_EQ(m.exit_code, 2) << says << ": " << m.out << m.err;
        EXPECT_NE(m.err.find(says), std::string::npos) << m.err;
        expect_one_clean_line(m.err);
        EXPECT_FALSE(fs::exists(out)) << "nothing written for " << says;
    };
    refused([](auto& rs) { rs[0]["case"] = "../../escaped"; }, "case:");
    EXPECT_FALSE(fs::exists(dir.path() / "escaped.html"));
    refused([&](auto& rs) { rs[0]["case"] = (dir.path() / "absolute").string(); }, "case:");
    EXPECT_FALSE(fs::exists(dir.path() / "absolute.html"));
    refused(
        [](auto& rs) {
            rs[0]["case"] =
                "t.ti\x01"
                "e";
        },
        "case:");
    // A wrongly typed field: refused naming the line and the field, before any output.
    refused([](auto& rs) { rs[1]["actual"]["seconds"] = "fast"; },
            "results.jsonl:2: actual.seconds");
    refused([](auto& rs) { rs[0]["comparison"]["max_color"]["x"] = "left"; },
            "comparison.max_color.x");
    // Shard numbers out of range, checked before any work.
    refused(
        [](auto& rs) {
            for (auto& r : rs) r["shard"]["count"] = 2000000000;
        },
        "shard.count");
    refused(
        [](auto& rs) {
            for (auto& r : rs) r["shard"]["count"] = -5;
        },
        "shard.count");
    refused(
        [](auto& rs) {
            for (auto& r : rs) r["shard"]["count"] = 0;
        },
        "shard.count");
    refused(
        [](auto& rs) {
            for (auto& r : rs) r["shard"]["index"] = 7;
        },
        "shard.index");
}

TEST(HostileRuns, ResultsFilesMustBeRegularFiles) {
    testutil::TempDir dir;
    const fs::path out = dir.path() / "out";
    // A device that never ends, and a FIFO nobody writes.
    const fs::path zero = dir.path() / "zero", fifo = dir.path() / "fifo";
    fs::create_directories(zero);
    fs::create_symlink("/dev/zero", zero / "results.jsonl");
    fs::create_directories(fifo);
    ASSERT_EQ(::mkfifo((fifo / "results.jsonl").c_str(), 0600), 0);
    for (const fs::path& shard : {zero, fifo}) {
        const auto m = cli({"conformance", "merge", shard.string(), "--output", out.string()});
        EXPECT_EQ(m.exit_code, 2) << shard << ": " << m.out << m.err;
        EXPECT_NE(m.err.find("not a regular file"), std::string::npos) << m.err;
        EXPECT_FALSE(fs::exists(out));
    }
    // A resumed run's results.jsonl.
    const fs::path root = suite(dir.path() / "scenes");
    const fs::path run = dir.path() / "run";
    ASSERT_EQ(cli(run_args(root, run)).exit_code, 1);
    fs::remove(run / "results.jsonl");
    ASSERT_EQ(::mkfifo((run / "results.jsonl").c_str(), 0600), 0);
    const auto r = cli(with(run_args(root, run), {"--resume"}));
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << r.err;
}

TEST(HostileRuns, ResumeRefusesRecordsOfAnotherRun) {
    testutil::TempDir dir;
    const fs::path root = suite(dir.path() / "scenes");
    const fs::path out = dir.path() / "out";
    const auto args = run_args(root, out);
    ASSERT_EQ(cli(args).exit_code, 1);
    const auto good = records(out / "results.jsonl");
    ASSERT_EQ(good.size(), 2u);
    const auto refused = [&](const std::function<void(std::vector<json>&)>& spoil,
                             const std::vector<std::string>& more, const std::string& says) {
        auto rs = good;
        spoil(rs);
        write_records(out / "results.jsonl", rs);
        const std::string before = testutil::read_text(out / "results.jsonl");
        const auto r = cli(with(with(args, more), {"--resume"}));
        EXPECT_EQ(r.exit_code, 2) << says << ": " << r.out << r.err;
        EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
        expect_one_clean_line(r.err);
        EXPECT_EQ(testutil::read_text(out / "results.jsonl"), before) << "left alone: " << says;
    };
    const auto keep = [](auto&) {};
    // Names that leave the output, cases the tree does not hold, a name corrupted.
    refused([](auto& rs) { rs[0]["case"] = "../../x"; }, {}, "results.jsonl:1: case:");
    EXPECT_FALSE(fs::exists(dir.path() / "x.html"));
    refused([](auto& rs) { rs[0]["case"] = "t.gone"; }, {}, "not in this run's selection");
    refused(
        [](auto& rs) {
            rs[1]["case"] =
                "t.pl\x7f"
                "ain";
        },
        {}, "results.jsonl:2: case:");
    // Another commit: the kept records would sit beside new ones under another commit.
    refused(
        [](auto& rs) {
            rs.pop_back();
            for (auto& r : rs) r["reference"]["provenance"]["commit"] = "0000000old";
        },
        {}, "commit 0000000old");
    // Another selection, shard setup or profile than the run in the directory.
    refused(keep, {"--cases", "t.tie"}, "selection");
    refused(keep, {"--shard-index", "0", "--shard-count", "2"}, "shard");
    refused(keep, {"--profile-set", "tie_rule=left-top"}, "reference");
    // Another implementation: found by the first case the resumed run renders, before it is
    // written.
    refused(
        [](auto& rs) {
            rs.pop_back();
            for (auto& r : rs) r["actual"]["provenance"]["renderer"] = "another renderer";
        },
        {}, "renderer");
    // A file from before run.json existed.
    write_records(out / "results.jsonl", good);
    fs::remove(out / "run.json");
    const auto old = cli(with(args, {"--resume"}));
    EXPECT_EQ(old.exit_code, 2) << old.out << old.err;
    EXPECT_NE(old.err.find("run again without --resume"), std::string::npos) << old.err;
}

TEST(HostileRuns, RunIntoAUsedFolderClearsWhatTheEarlierRunWroteAndNothingElse) {
    testutil::TempDir dir;
    const fs::path root = suite(dir.path() / "scenes");
    const fs::path out = dir.path() / "out";
    ASSERT_EQ(cli(run_args(root, out)).exit_code, 1);
    ASSERT_TRUE(fs::exists(out / "cases" / "t.tie.html"));
    ASSERT_TRUE(fs::exists(out / "images" / "t.tie.mask.png"));
    std::ofstream(out / "notes.txt") << "mine";
    std::ofstream(out / "images" / "mine.png") << "mine";
    const auto r = cli(with(run_args(root, out), {"--cases", "t.plain"}));
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    std::set<std::string> cases;
    for (const auto& e : fs::directory_iterator(out / "cases"))
        cases.insert(e.path().filename().string());
    EXPECT_EQ(cases, std::set<std::string>{"t.plain.html"});
    EXPECT_FALSE(fs::exists(out / "images" / "t.tie.mask.png"));
    EXPECT_FALSE(fs::exists(out / "explain" / "t.tie.svg"));
    EXPECT_EQ(testutil::read_text(out / "notes.txt"), "mine");
    EXPECT_EQ(testutil::read_text(out / "images" / "mine.png"), "mine");
    EXPECT_EQ(records(out / "results.jsonl").size(), 1u);
}

TEST(HostileRuns, NoOutputFolderLeadsOutOfTheOutput) {
    testutil::TempDir dir;
    const fs::path root = suite(dir.path() / "scenes");
    const fs::path out = dir.path() / "out", elsewhere = dir.path() / "elsewhere";
    ASSERT_EQ(cli(run_args(root, out)).exit_code, 1);
    // cases/ replaced by a link to a folder of someone else's, holding a file of a case's name.
    fs::create_directories(elsewhere);
    std::ofstream(elsewhere / "t.tie.html") << "mine";
    fs::remove_all(out / "cases");
    fs::create_directory_symlink(elsewhere, out / "cases");
    const std::string before = testutil::read_text(out / "results.jsonl");
    for (const bool resume : {false, true}) {
        auto args = run_args(root, out);
        if (resume) args.push_back("--resume");
        const auto r = cli(args);
        EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
        EXPECT_NE(r.err.find("not a directory"), std::string::npos) << r.err;
        EXPECT_EQ(testutil::read_text(elsewhere / "t.tie.html"), "mine");
        EXPECT_FALSE(fs::exists(elsewhere / "t.plain.html"));
        EXPECT_EQ(testutil::read_text(out / "results.jsonl"), before);
    }
    // A merge into it.
    const fs::path shard = dir.path() / "shard";
    fs::create_directories(shard);
    std::ofstream(shard / "results.jsonl") << before;
    const auto m = cli({"conformance", "merge", shard.string(), "--output", out.string()});
    EXPECT_EQ(m.exit_code, 2) << m.out << m.err;
    EXPECT_NE(m.err.find("not a directory"), std::string::npos) << m.err;
    EXPECT_EQ(testutil::read_text(elsewhere / "t.tie.html"), "mine");
    EXPECT_EQ(testutil::read_text(out / "results.jsonl"), before);
}

TEST(HostileRuns, ExplainEchoesABadPixelEscaped) {
    testutil::TempDir dir;
    const fs::path scene = dir.write("s.json", kPlain);
    const auto r = cli({"explain", scene.string(), "--pixel", "\xff\n1,2\x1b"});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    expect_one_clean_line(r.err);
    EXPECT_NE(r.err.find("\\xFF\\n1,2\\x1B"), std::string::npos) << r.err;
}

}  // namespace
