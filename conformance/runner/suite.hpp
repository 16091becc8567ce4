// suite.hpp: the conformance run: every scene under a root, rendered by the reference and one
// GL backend, compared, and streamed to DIR/results.jsonl as each case ends.
//
// Implements: case discovery (a case's name is its scene's path below the root, dotted, without
// ".json"), selection by glob, the run loop with per-case images, and the console summary whose
// last line is "N passed, N failed, N skipped".
//
// Deliberately does not (yet): baselines, shards, resume, HTML/JUnit reports.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "harness/backend.hpp"

namespace conformance {

struct CaseFile {
    std::string name;  // triangles.coverage.shared_edge_h
    std::filesystem::path file;
};

// Scene files below `root`, sorted by case name. `globs` (fnmatch patterns on the case name)
// keep a case that matches any of them; empty keeps every case.
std::vector<CaseFile> discover_cases(const std::filesystem::path& root,
                                     const std::vector<std::string>& globs);

std::string case_name_for(const std::filesystem::path& root, const std::filesystem::path& file);

struct RunOptions {
    std::filesystem::path scenes_root;
    std::vector<std::string> case_globs;
    harness::BackendOptions reference;  // ref by default
    harness::BackendOptions against;
    std::filesystem::path output;
};

struct RunSummary {
    std::size_t passed = 0;
    std::size_t failed = 0;
    std::size_t skipped = 0;
};

// Runs the suite; throws std::runtime_error for a problem with the run itself (no scenes
// matched, output not writable, backend unavailable).
RunSummary run_suite(const RunOptions& options, std::ostream& console);

}  // namespace conformance
