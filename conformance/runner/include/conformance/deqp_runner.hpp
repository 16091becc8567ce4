// deqp_runner.hpp: the words and rules of deqp-runner (Mesa's CI test runner, v0.20), so that
// its files and this project's can stand in for each other.
//
// Implements: deqp-runner's status words (RunnerStatus, including `UnexpectedImprovement(X)`
// and `KnownFlake`) and this project's statuses written in them; its success rule (which
// statuses a failures.csv lists); how a result and a baseline's word combine into a verdict
// (RunnerStatus::with_baseline, written out as a table in docs/conformance.md); and the
// duration column of results.csv, which deqp-runner prints with Rust's `{}` for an f32: the
// shortest decimal that reads back as the same f32, never with an exponent.
//
// Deliberately does not: read or write files (suite.cpp and reports.cpp do), or run dEQP.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace conformance {

// A status word of deqp-runner's, or of an older deqp-runner (`UnexpectedPass`), or of this
// project's results.jsonl (`NotSupported`, `InternalError`), in deqp-runner's current
// spelling: Pass, Fail, Skip, Crash, Warn, Flake, KnownFlake, Missing, ExpectedFail, Timeout,
// or UnexpectedImprovement(Pass|Fail|Skip|Crash|Warn|Timeout). nullopt for anything else.
std::optional<std::string> deqp_runner_word(std::string_view word);

// A results.jsonl status (and the raw status a baseline changed, empty when none) written in
// deqp-runner's words: NotSupported is Skip, InternalError is Fail, UnexpectedPass is
// UnexpectedImprovement(Pass), UnexpectedImprovement is UnexpectedImprovement(its raw status).
std::string deqp_runner_status(std::string_view status, std::string_view raw_status);

// The one word the console, the CSVs and JUnit give a status: deqp-runner's for a baseline's
// verdicts (UnexpectedImprovement(Pass), not UnexpectedPass), this project's otherwise
// (NotSupported and InternalError say more than Skip and Fail; results.csv maps them).
std::string reported_status(std::string_view status, std::string_view raw_status);

// deqp-runner's RunnerStatus::is_success: Pass, Skip, Warn, Flake, KnownFlake, ExpectedFail.
bool deqp_runner_is_success(std::string_view word);

// RunnerStatus::with_baseline: the verdict, in deqp-runner's words, on a result (Pass, Fail,
// Skip, Crash, Warn or Timeout) that the baseline lists as `baseline` (a deqp_runner_word, or
// empty when the baseline does not list the case).
std::string deqp_runner_with_baseline(std::string_view result, std::string_view baseline);

// The duration column: Rust's Display of an f32, e.g. 0.1 is "0.1", 1 is "1", 1e-7 is
// "0.0000001" and 1e20 is "100000000000000000000".
std::string deqp_runner_duration(float seconds);

}  // namespace conformance
