// refraster: the command-line front door. Every subcommand is a file under commands/ and a line
// of the table commands/commands.hpp; main declares them in the table's order, parses the
// command line and runs the one chosen.
//
// Exit codes are shared by every subcommand (command.hpp, README.md "Exit codes"). An error a
// command leaves to main is reported here, once: a refraster::Error with the exit code of its
// class, running out of memory as such, and anything else as an internal error.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>
#include <new>
#include <vector>

#include "command.hpp"
#include "commands/commands.hpp"
#include "harness/encode.hpp"
#include "options.hpp"

namespace {

int run(int argc, char** argv) {
    CLI::App app{"refraster: a bit-exact reference rasterizer and its comparison harness"};
    app.require_subcommand(1);
    // A braced list is evaluated in order, so --help lists the commands in the table's order.
    const std::vector<tool::Command> commands{
#define REFRASTER_ADD_COMMAND(name) tool::add_##name##_command(app),
        REFRASTER_COMMANDS(REFRASTER_ADD_COMMAND)
#undef REFRASTER_ADD_COMMAND
    };
    if (const auto rc = tool::list_egl_devices_if_asked(argc, argv)) return *rc;
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "refraster: " << harness::encode::terminal(e.what()) << " (see --help)\n";
        return tool::kExitBadInput;
    }
    for (const auto& command : commands) {
        if (command.app->parsed()) return command.run();
    }
    return tool::kExitBadInput;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const refraster::Error& e) {
        std::cerr << "refraster: " << harness::encode::terminal(e.what()) << "\n";
        return tool::exit_code(e.exit_class());
    } catch (const std::bad_alloc&) {
        std::cerr << "refraster: out of memory\n";
        return tool::kExitOutOfMemory;
    } catch (const std::exception& e) {
        std::cerr << "refraster: " << harness::encode::terminal(e.what()) << "\n";
        return tool::kExitBackendFailure;
    }
}
