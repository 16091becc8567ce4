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
// Deliberately does not: render anything; everything comes from the records and images the
// run wrote.
#pragma once

#include <filesystem>

namespace conformance {

void write_reports(const std::filesystem::path& output, std::size_t selected_cases);

}  // namespace conformance
