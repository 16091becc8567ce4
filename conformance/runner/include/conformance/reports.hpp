// reports.hpp: what a conformance run leaves in its output directory, from its results.jsonl.
//
// Implements: results.csv and failures.csv in deqp-runner's format ("name,Status,seconds";
// failures lists every case that counts as failed, so that it can serve as the next run's
// baseline), results.json (every case's record and a summary), junit.xml (one testcase per
// case: failure for failed statuses, skipped for NotSupported), and an HTML report: index.html
// with counts per area, an inline SVG chart of error against run time over all cases and a
// table of cases, and cases/<case>.html with the case's images side by side (pixelated,
// zoomable), its numbers, its provenance and its explanation. No network: CSS and script
// inline, images by relative path.
//
// Every name, path and message a record holds reaches a page through the encoders of
// harness/encode.hpp (HTML text and attributes, JSON inside the case page's script, CSV fields,
// XML), and every report is built in memory before the first is written, so that a record the
// reports cannot read leaves the directory as it was.
//
// Deliberately does not: render anything; everything comes from the records and images the
// run wrote.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace conformance {

// One report: its path below the output directory ("index.html", "cases/NAME.html") and text.
struct ReportFile {
    std::string path;
    std::string text;
};

// Whether the output holds a file ("images/NAME.ref.png", "explain/NAME.svg"), for the links
// of the case pages.
using FileExists = std::function<bool(const std::string& relative)>;

// Every report of `lines` (results.jsonl's lines, in any order; empty ones skipped). Throws
// std::runtime_error naming `source` and the line of a record that is not one (record_check).
// `run_setup` is run.json's text (empty when there is none): its "inputs" (the baseline, skips
// and flakes files: each as given, its copy under inputs/, its hash and what it holds) are
// shown on the index, linked to the copies, and kept in results.json; a run.json that is not
// JSON throws, naming `run_source`.
std::vector<ReportFile> build_reports(const std::vector<std::string>& lines,
                                      const std::string& source, std::size_t selected_cases,
                                      const FileExists& exists, const std::string& run_setup = "",
                                      const std::string& run_source = "run.json");

// Writes each file atomically, every path checked to lie inside `output` (records.hpp) before
// the first is written.
void write_report_files(const std::filesystem::path& output, const std::vector<ReportFile>& files);

// The reports of output/results.jsonl (read within the bounds of records.hpp), written.
void write_reports(const std::filesystem::path& output, std::size_t selected_cases);

}  // namespace conformance
