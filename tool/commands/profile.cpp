// profile [NAME]: a reference profile, built-in or from a file, with overrides applied, printed
// as JSON that loads back as a profile file.
#include <iostream>
#include <memory>

#include "commands/commands.hpp"
#include "harness/profile_io.hpp"

namespace tool {

Command add_profile_command(CLI::App& app) {
    auto a = std::make_shared<ProfileArgs>();
    auto* cmd = app.add_subcommand("profile", "Print a reference profile as JSON (a profile file)");
    cmd->add_option("name", a->profile, "Built-in name or profile file")->capture_default_str();
    cmd->add_option("--profile-set", a->overrides,
                    "Override one parameter: key=value (repeatable)");
    return {cmd, [a] {
                std::cout << harness::profile_to_json(a->load()) << "\n";
                return kExitOk;
            }};
}

}  // namespace tool
