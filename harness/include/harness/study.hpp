// study.hpp: `refraster study`: error against run time for the reference's precision choices,
// for supersampled antialiasing, and on stiff and extreme cases, measured against exact answers.
//
// Implements three studies, each a table (one row per variant and workload family, or per
// variant and sweep step, with the seed) and a figure:
// - precision: coverage under sub-pixel snapping at 4 to 16 bits and under unsnapped float32,
//   float64 and exact setup; fused and unfused attribute interpolation; z16, z24 and z32f
//   depth; on seeded families of triangles; against the exact coverage oracle (the `gl-exact`
//   profile's predicates) and exact attribute and depth values;
// - antialiasing: supersampling at 1, 4, 16 and 64 samples per pixel in several patterns,
//   resolved with box, tent and Gaussian filters, against the exact area coverage of each pixel
//   (rational arithmetic) and the exactly integrated filtered coverage;
// - stability: families swept towards their limits (area to 0, w to 0, coordinates to the
//   snapping budget, nearly parallel edges, depth slopes to the z24 step), error against the
//   sweep parameter, one curve per variant, with the llvmpipe model's own monotonicity.
// The meaning of every column and the conclusions drawn from them: docs/precision-study.md.
//
// Deliberately does not: write files (the tool does), time anything with a GL driver, or
// decide which variant is best (the reader does, from the Pareto front the figure marks).
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "refraster/error.hpp"

namespace harness {

struct StudyOptions {
    std::uint64_t seed = 1;
    bool quick = false;  // small sizes, for CI: seconds instead of minutes
    // Progress lines ("precision: family medium, variant snap-8 (12/54)"); may be empty.
    std::function<void(const std::string&)> progress;
};

// A finished study: the CSV's text (a header line, then one line per row) and the SVG's.
struct StudyOutput {
    std::string name;  // "precision", "antialiasing", "stability"
    std::string csv;
    std::string svg;
    // One line per number worth quoting, for the tool to print (and the docs to quote):
    // "snap-8: 0 holes, 0 double hits on 412 shared edges".
    std::vector<std::string> summary;
    // The decision table, in Markdown: for each error target, the cheapest choice that meets
    // it and its time as a ratio with the range its timing rounds allow (a study that times
    // nothing tabulates what it measured instead, one row per case).
    std::string decisions;
    // A few sentences the numbers support, written for a reader.
    std::vector<std::string> conclusions;
    // Where the numbers come from (filled by run_study): study, seed, quick, commit, CPU flags,
    // kernels' compile flags, UTC date, seconds the study took.
    std::vector<std::pair<std::string, std::string>> provenance;
};

// summary.md: the decision table, the conclusions, the command that reproduces them, the
// provenance and every summary line.
std::string study_summary_markdown(const StudyOutput& out, const std::string& command);

class StudyError : public refraster::Error {
  public:
    explicit StudyError(const std::string& message)
        : refraster::Error(refraster::ExitClass::BadInput, message) {}
};

StudyOutput run_precision_study(const StudyOptions& options);
StudyOutput run_antialiasing_study(const StudyOptions& options);
StudyOutput run_stability_study(const StudyOptions& options);

// The study names the tool accepts, in order.
std::vector<std::string> study_names();
// By name; throws StudyError for an unknown name.
StudyOutput run_study(const std::string& name, const StudyOptions& options);

}  // namespace harness
