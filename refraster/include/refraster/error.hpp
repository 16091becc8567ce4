// error.hpp: refraster::Error, the one base of the project's refusals, and the class of failure
// each one reports.
//
// Implements: ExitClass, whose values are the command-line tool's exit codes for a failure
// (README.md, "Exit codes"); Error, a std::runtime_error that carries its ExitClass. Every
// error type that reaches a user (a bad scene, profile, option, shard or output; a broken
// worker stream) derives from Error with its class, so that whoever reports it (the tool's
// main, a program of one's own) can tell bad input from a backend failure without knowing
// every type, and the exit code of a type is stated where the type is.
//
// Deliberately does not: cover outcomes that are not errors (images that differ: 1; a renderer
// that does not support a scene: 4), nor running out of memory (std::bad_alloc), which the tool
// reports as such, with BackendFailure's code 3: a run that could not finish.
#pragma once

#include <stdexcept>
#include <string>

namespace refraster {

// The class of a failure, valued as the tool's exit code for it.
enum class ExitClass : int {
    // Bad input or usage: a scene, profile, option or output the user can fix. Nothing partial
    // is left behind.
    BadInput = 2,
    // A backend failed: a worker crashed, timed out, or its stream broke. Also the tool's code
    // for a run that ran out of memory.
    BackendFailure = 3,
};

class Error : public std::runtime_error {
  public:
    Error(ExitClass exit_class, const std::string& message)
        : std::runtime_error(message), exit_class_(exit_class) {}
    Error(ExitClass exit_class, const char* message)
        : std::runtime_error(message), exit_class_(exit_class) {}

    ExitClass exit_class() const noexcept { return exit_class_; }

  private:
    ExitClass exit_class_;
};

}  // namespace refraster
