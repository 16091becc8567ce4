// command.hpp: what a subcommand of the tool is made of, the exit codes every subcommand
// shares, and the reporting steps several of them take.
//
// Exit codes (README.md, "Exit codes"): 0 success, 1 images differ beyond `expect` (or a
// conformance case failed), 2 bad input or usage, 3 backend failure (crash, timeout, internal
// error, out of memory), 4 NotSupported. 2 and 3 are the classes a refraster::Error carries.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "harness/backend.hpp"
#include "harness/scene.hpp"
#include "options.hpp"
#include "refraster/error.hpp"
#include "refraster/profile.hpp"

namespace tool {

constexpr int kExitOk = 0;
constexpr int kExitMismatch = 1;
constexpr int kExitBadInput = static_cast<int>(refraster::ExitClass::BadInput);
constexpr int kExitBackendFailure = static_cast<int>(refraster::ExitClass::BackendFailure);
constexpr int kExitNotSupported = 4;
// Running out of memory is a run failure: the one line `refraster: out of memory` (main.cpp).
constexpr int kExitOutOfMemory = kExitBackendFailure;

// The exit code of an error's class: the class's value is the code.
constexpr int exit_code(refraster::ExitClass c) {
    return static_cast<int>(c);
}

// A subcommand once declared: its node in the command line (parsed() when the command line
// chose it) and what runs it after parsing, returning the exit code. `run` owns the variables
// the command's options were bound to, so that they live as long as the parser.
struct Command {
    CLI::App* app = nullptr;
    std::function<int()> run;
};

// The scene, loaded under `scene` (--texture-root), or nullopt after printing its one-line
// SceneError (bad input).
std::optional<harness::Scene> load_or_report(const std::string& path, const SceneArgs& scene);

// The backend, or nullptr after reporting a backend that cannot start (a backend failure).
// Bad input (a profile, --egl-device or --mesa-prefix that cannot work) is thrown, for main to
// report.
std::unique_ptr<harness::Backend> backend_or_report(const BackendArgs& a, const std::string& scene);

// The reference's profile and, when `want_backend`, the GL backend of `against` (whose own
// profile options describe the reference). Returns an exit code when the backend cannot be had,
// after reporting it; a bad profile is thrown.
std::optional<int> profile_and_backend(const BackendArgs& against, const std::string& scene,
                                       bool want_backend, refraster::Profile& profile,
                                       std::unique_ptr<harness::Backend>& backend);

// 0 for Ok, 4 for NotSupported, 3 for any failure.
int exit_code_for(harness::RenderStatus s);

}  // namespace tool
