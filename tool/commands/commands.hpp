// commands.hpp: the table of subcommands, in the order --help lists them.
//
// A subcommand is one file, tool/commands/NAME.cpp, defining add_NAME_command (declared below),
// and one line of this table; tool/CMakeLists.txt builds every file here, and main declares the
// commands from the table.
#pragma once

#include <CLI/CLI.hpp>

#include "command.hpp"

#define REFRASTER_COMMANDS(X) \
    X(render)                 \
    X(compare)                \
    X(conformance)            \
    X(explain)                \
    X(reduce)                 \
    X(bench)                  \
    X(fingerprint)            \
    X(profile)                \
    X(generate)               \
    X(teach)                  \
    X(study)                  \
    X(check)

namespace tool {

// Declares the command, its options and its subcommands on `app`.
#define REFRASTER_DECLARE_COMMAND(name) Command add_##name##_command(CLI::App& app);
REFRASTER_COMMANDS(REFRASTER_DECLARE_COMMAND)
#undef REFRASTER_DECLARE_COMMAND

}  // namespace tool
