// suite.hpp: the conformance run: the scenes under a root, selected, sharded, rendered by the
// reference and one GL backend, compared, judged against a baseline, streamed to
// DIR/results.jsonl as each case ends, and reported.
//
// Implements: case discovery (a case's name is its scene's path below the root, dotted,
// without ".json"; two files giving one name are an error), selection by globs, exclusion
// globs and case lists (dEQP style: one name per line, '#' comments), sharding (case i of the
// sorted selection runs on shard i % count; the index and count come from shard.hpp, and
// every record names its shard), baselines in deqp-runner's "name,Status" lines judged as
// deqp-runner judges them (ExpectedFail, UnexpectedPass, UnexpectedImprovement, and a re-run
// of every unexpected result to tell a Flake), its flakes files (KnownFlake), resuming a killed
// run from its results.jsonl (a half-written last line is dropped), a progress line on
// terminals, and the reports of reports.hpp.
//
// Deliberately does not: run cases in parallel (one GL worker per backend; parallelism is
// sharding across processes or machines).
#pragma once

#include <filesystem>
#include <iosfwd>
#include <map>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "harness/backend.hpp"
#include "harness/case_result.hpp"
#include "harness/scene.hpp"

namespace conformance {

struct CaseFile {
    std::string name;  // triangles.coverage.shared_edge_horizontal_ccw
    std::filesystem::path file;
};

// Scene files below `root`, sorted by case name; throws std::runtime_error when two files give
// the same case name.
std::vector<CaseFile> discover_cases(const std::filesystem::path& root);

std::string case_name_for(const std::filesystem::path& root, const std::filesystem::path& file);

// True when `name` matches any of the fnmatch globs (none: everything matches).
bool matches_any(const std::string& name, const std::vector<std::string>& globs);

// Reads a case list: one name or glob per line, '#' starts a comment.
std::vector<std::string> read_caselist(const std::filesystem::path& file);

// Reads a baseline: "name,Status[,...]" lines (deqp-runner's failures.csv or results.csv, in
// the words of deqp_runner.hpp: deqp-runner's own, an older deqp-runner's UnexpectedPass, and
// this project's NotSupported and InternalError), '#' comments and blank lines skipped. Maps
// each name to its word in deqp-runner's current spelling. Throws std::runtime_error naming
// the file and line of a line without a known word or of a case listed twice.
std::map<std::string, std::string> read_baseline(const std::filesystem::path& file);

// Applies the baseline to a case's result as deqp-runner does (deqp_runner_with_baseline):
// ExpectedFail, UnexpectedPass (a pass where a failure, crash, timeout or missing case was
// listed), UnexpectedImprovement (a fail or NotSupported where worse was listed); raw_status
// keeps the result the baseline changed. Without a baseline, or for a case it does not list,
// the result stands. Returns whether the verdict counts as failed.
bool apply_baseline(harness::CaseResult& r, const std::map<std::string, std::string>* baseline);

// deqp-runner's skips and flakes files: one regular expression a line (searched for anywhere
// in the case name, as deqp-runner's RegexSet does), '#' comments. Throws std::runtime_error
// naming the file and line of an expression that does not compile.
class NamePatterns {
  public:
    void add_file(const std::filesystem::path& file);
    // Where the first matching expression was written ("skips.txt:3"), or nullopt.
    std::optional<std::string> match(const std::string& name) const;
    bool empty() const { return patterns_.empty(); }
    std::size_t size() const { return patterns_.size(); }

  private:
    std::vector<std::pair<std::regex, std::string>> patterns_;
};

struct RunOptions {
    std::filesystem::path scenes_root;
    // How each scene file is loaded: the limits and the texture root (--texture-root).
    harness::SceneLimits scene_limits;
    std::vector<std::string> case_globs;
    std::vector<std::string> exclude_globs;
    std::optional<std::filesystem::path> caselist;
    std::optional<std::filesystem::path> baseline;
    // deqp-runner's --skips (cases left out of the selection before sharding) and --flakes
    // (a failure of a matching case is a Flake, with or without a baseline).
    std::vector<std::filesystem::path> skips;
    std::vector<std::filesystem::path> flakes;
    int shard_index = 0;
    int shard_count = 1;
    std::string shard_source = "none";  // what decided them (shard.hpp), in every record
    bool resume = false;
    bool progress = false;              // a live progress line (terminals only)
    harness::BackendOptions reference;  // ref by default
    harness::BackendOptions against;
    std::filesystem::path output;
    // --verdict gl: a case whose every differing pixel is a legal variation of GL's rules
    // passes; one with a violation fails naming it (harness/gl_verdict.hpp).
    bool gl_verdict = false;
};

struct RunSummary {
    std::size_t passed = 0;    // Pass
    std::size_t failed = 0;    // Fail, Crash, Timeout, InternalError, Unexpected*
    std::size_t skipped = 0;   // NotSupported
    std::size_t expected = 0;  // ExpectedFail: failed as the baseline lists
    std::size_t flaky = 0;     // Flake, KnownFlake: failed, then passed alone
    void add(harness::CaseStatus st);
    // "N passed, M failed, K skipped", then ", E failed as the baseline expects" and ", F
    // flaky" when there are any: the last line `run` and `merge` print. The counts add up to
    // the cases finished.
    std::string line() const;
};

// Runs the suite; throws std::runtime_error for a problem with the run itself (no scenes
// matched, a bad case list or baseline, output not writable, backend unavailable, a results
// directory that cannot be resumed), before writing anything.
//
// The run writes DIR/run.json, its setup (format, commit, both sides' backends, the reference
// profile and its rules, the verdict, baseline and flakes files' contents as hashes, the shard
// and the selected cases), before its first record. --resume refuses, naming the file and the
// record or key at fault: a directory without run.json (written before it existed: rerun
// without --resume), a run.json of another setup, and any record of a case outside the
// selection, of another shard, commit, profile, backend or driver, or of another run than the
// other records; the first case the resumed run renders must have the kept records' identity
// (record_check.hpp), checked before it is written. Without --resume, what an earlier run or
// merge wrote there is cleared first (clear_run_output).
RunSummary run_suite(const RunOptions& options, std::ostream& console);

// Removes what a run or merge wrote into `output` and nothing else: when `output` holds a
// results.jsonl or run.json, the reports (results.jsonl, results.csv, failures.csv,
// samples.csv, results.json, junit.xml, index.html, merge.txt, run.json) and, for every case
// results.jsonl records, cases/NAME.html, images/NAME.BACKEND.png|exr (its two backends),
// images/NAME.mask.png, images/NAME.samples.png, explain/NAME.svg and explain/NAME.txt; then
// cases/, images/ and explain/ when that leaves them empty. Throws std::runtime_error naming
// the line of a results.jsonl whose records cannot be read (a torn last line aside), leaving
// everything in place.
void clear_run_output(const std::filesystem::path& output);

}  // namespace conformance
