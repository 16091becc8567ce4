// refraster: the command-line front door. Every subcommand is a file under commands/ and a line
// of the table commands/commands.hpp; main declares them in the table's order, parses the
// command line and runs the one chosen.
//
// Exit codes are shared by every subcommand (command.hpp, README.md "Exit codes"). An error a
// command leaves to main is reported here, once: a refraster::Error with the exit code of its
// class, running out of memory as such, and anything else as an internal error.
//
// Running out of memory ends the run with the one line `refraster: out of memory` and exit code
// 3 wherever it happens: a std::bad_alloc that reaches main, and one that would otherwise end
// the process through std::terminate (thrown out of a noexcept function or a destructor, or out
// of a thread's body, or out of a library's initialisation before main) alike; a thread that
// cannot be started for want of memory counts as running out of it. Threads of the project's own
// catch their exceptions and hand them to the thread that waits for them
// (refraster/src/stages/band_workers.cpp); the terminate handler is the last resort for any other
// path.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <new>
#include <system_error>
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

// The line and exit code of running out of memory, written without allocating.
[[noreturn]] void exit_out_of_memory() noexcept {
    static constexpr char kLine[] = "refraster: out of memory\n";
    std::fflush(stdout);
    [[maybe_unused]] const auto written = ::write(STDERR_FILENO, kLine, sizeof kLine - 1);
    std::_Exit(tool::kExitOutOfMemory);
}

// Whether `e` is the system refusing memory: std::bad_alloc, or a thread that could not be
// started for want of memory for its stack (EAGAIN, ENOMEM).
bool is_out_of_memory(const std::exception_ptr& e) {
    try {
        std::rethrow_exception(e);
    } catch (const std::bad_alloc&) {
        return true;
    } catch (const std::system_error& s) {
        return s.code() == std::errc::resource_unavailable_try_again ||
               s.code() == std::errc::not_enough_memory;
    } catch (...) {
    }
    return false;
}

std::terminate_handler previous_terminate = nullptr;

// std::terminate with running out of memory in flight (an exception that left a noexcept
// function, a destructor or a thread's body, or a library's initialisation before main) is
// reported as such, not as a crash.
[[noreturn]] void on_terminate() noexcept {
    if (const std::exception_ptr e = std::current_exception()) {
        if (is_out_of_memory(e)) exit_out_of_memory();
    }
    if (previous_terminate != nullptr) previous_terminate();
    std::abort();
}

// Installed before any library's initialisation runs (the executable's preinit array runs
// before the initialisers of the shared libraries it loads; some start threads there).
void install_terminate_handler(int, char**, char**) {
    previous_terminate = std::set_terminate(on_terminate);
}
[[gnu::section(".preinit_array"),
  gnu::used]] void (*const preinit_terminate_handler)(int, char**,
                                                      char**) = &install_terminate_handler;

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const refraster::Error& e) {
        std::cerr << "refraster: " << harness::encode::terminal(e.what()) << "\n";
        return tool::exit_code(e.exit_class());
    } catch (const std::bad_alloc&) {
        exit_out_of_memory();
    } catch (const std::system_error& e) {
        if (is_out_of_memory(std::current_exception())) exit_out_of_memory();
        std::cerr << "refraster: " << e.what() << "\n";
        return tool::kExitBackendFailure;
    } catch (const std::exception& e) {
        std::cerr << "refraster: " << harness::encode::terminal(e.what()) << "\n";
        return tool::kExitBackendFailure;
    }
}
