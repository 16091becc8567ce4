// case_result.hpp: one scene rendered by two backends and compared: the unit every command
// that reports (compare, conformance run) is built from.
//
// Implements: the case statuses of dEQP (Pass, Fail, NotSupported, Crash, Timeout,
// InternalError), running one case, and its JSON record (one line of results.jsonl).
//
// Deliberately does not: write images or decide exit codes.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "harness/backend.hpp"
#include "harness/compare.hpp"
#include "harness/scene.hpp"

namespace harness {

enum class CaseStatus : std::uint8_t {
    Pass,
    Fail,
    NotSupported,
    Crash,
    Timeout,
    InternalError,
    // Against a baseline:
    ExpectedFail,           // failed as the baseline says it does
    UnexpectedPass,         // passed where the baseline lists a failure
    UnexpectedImprovement,  // failed or was not supported where the baseline lists worse
                            // (raw_status says which)
    Flake,                  // an unexpected result that did not repeat on the re-run
    KnownFlake,             // a failure of a case a flakes file lists
};

std::string_view to_string(CaseStatus s);
std::optional<CaseStatus> case_status_from_string(std::string_view s);
// Fail, Crash, Timeout, InternalError, UnexpectedPass, UnexpectedImprovement.
bool counts_as_failure(CaseStatus s);

struct CaseResult {
    std::string name;
    std::string scene_path;
    CaseStatus status = CaseStatus::InternalError;
    std::optional<CaseStatus> raw_status;  // before the baseline, when one changed it
    std::string message;                   // one line: why, for anything but Pass
    Expect expect;
    std::string reference_name;
    std::string actual_name;
    std::optional<RenderResult> reference;
    std::optional<RenderResult> actual;
    // The resolved images (for a 4x target colour only, compare_resolved) and, for a 4x
    // target, every sample (compare_samples). The case passes only when both are within the
    // scene's expect.
    std::optional<Comparison> comparison;
    std::optional<SampleComparison> sample_comparison;
    // For a failure: the pixel of largest difference and the rule that explains it.
    std::optional<std::array<int, 2>> explained_pixel;
    std::string explanation;
    std::string explanation_difference;  // coverage, colour, depth, sample
    std::string explanation_rule;
    // The whole explanation of that pixel (explain.hpp), as text and as the SVG teaching view;
    // written beside the report by the conformance runner, not part of the JSON line.
    std::string explanation_text;
    std::string explanation_svg;
    // With GL verdicts (gl_verdict.hpp): the verdict's summary of a differing image; a case
    // whose differences are all legal variations passes with it as its message.
    std::string gl_verdict;
    // The shard of the run that produced it (conformance/shard.hpp): index, count and what
    // decided them ("gitlab", "flags", ...); empty outside a conformance run.
    std::optional<std::array<int, 2>> shard;
    std::string shard_source;
    // A failure run again alone, by a backend of its own (a fresh worker), in a conformance
    // run: that run's status and differing pixels. A case that fails after other cases but
    // passes alone depends on what its worker drew before: its status is Flake (raw_status the
    // failure), and its explanation is the failing render's.
    std::optional<CaseStatus> alone_status;
    std::size_t alone_mismatched_pixels = 0;
};

// Renders `scene` through both backends and compares actual against reference: the image, and
// for a 4x target also every sample (a side that returns no samples for a 4x target is an
// InternalError).
CaseResult run_case(const Scene& scene, const std::string& case_name, Backend& reference,
                    Backend& actual);

// A case that could not run at all (its scene did not load).
CaseResult case_error(const std::string& case_name, const std::string& scene_path,
                      const std::string& message);

// The pixel a failure is explained at: the resolved image's largest colour difference, else
// the samples' largest colour difference, else the largest depth difference (the image's, or
// for a 4x target the samples'). nullopt when nothing differs.
std::optional<std::array<int, 2>> pixel_of_largest_difference(const CaseResult& r);

// One JSON object, on one line, without a trailing newline. For a 4x target the comparison
// also holds samples, mismatched_samples, pixels_with_mismatched_samples, per_sample (one
// object a sample: sample, mismatched, missing, extra, other_primitive, color_only,
// depth_only), samples_classified_by, and max_sample_color / max_sample_depth (with x, y and
// sample); single-sample records hold none of these.
std::string to_json_line(const CaseResult& r);

}  // namespace harness
