// options.hpp: the options several subcommands share, declared once: the reference's profile
// and threads, the backend and what drives it (driver, timeout, Mesa prefix, EGL device), and
// the option values more than one command parses (pixels, case globs, the scene root).
#pragma once

#include <CLI/CLI.hpp>
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "harness/backend.hpp"
#include "harness/scene.hpp"
#include "refraster/draw.hpp"
#include "refraster/profile.hpp"

namespace tool {

// The reference's profile, shared by the subcommands that run it.
struct ProfileArgs {
    std::string profile = "llvmpipe-22.3";
    std::vector<std::string> overrides;

    // Throws refraster::ProfileError.
    refraster::Profile load() const;
    std::string source() const;
};

// --profile and --profile-set.
void add_profile_options(CLI::App* cmd, ProfileArgs& a);
// --threads, the reference's.
void add_threads_option(CLI::App* cmd, unsigned& threads);

// Options naming a backend, shared by the subcommands.
struct BackendArgs {
    explicit BackendArgs(std::string b) : backend(std::move(b)) {}
    std::string backend;
    std::string driver;  // empty: the environment's choice (harness::driver_from_environment)
    double timeout = 60.0;
    std::string mesa_prefix;  // a Mesa build of one's own (GL backends)
    std::string egl_device;   // egl: a device index, or "list"
    ProfileArgs profile;
    unsigned threads = 0;  // the reference's; 0: one per core

    // Throws refraster::ProfileError and harness::BackendOptionError (bad input).
    harness::BackendOptions options() const;
};

// The option choosing the backend (--backend, --against, --reference): one of `choices`.
void add_backend_option(CLI::App* cmd, const std::string& name, std::string& backend,
                        const std::string& help, std::vector<std::string> choices);
// --driver, --timeout, --mesa-prefix and --egl-device.
void add_driver_options(CLI::App* cmd, BackendArgs& a);

// `--egl-device list` anywhere on the command line: prints the EGL devices and returns the exit
// code, whichever command asked and whatever else it requires (parsing would insist on a scene
// or an output first). --mesa-prefix (or MESA_PREFIX) still applies. nullopt when not asked.
std::optional<int> list_egl_devices_if_asked(int argc, char** argv);

// "X,Y" as two integers; nullopt when it is not of that form.
std::optional<std::array<int, 2>> parse_pixel(const std::string& text);
bool inside(const refraster::Target& t, const std::array<int, 2>& p);

// "a,b,,c" as {"a", "b", "c"}.
std::vector<std::string> split_globs(const std::string& s);

// How scene files are loaded, shared by every subcommand that loads them: --texture-root DIR,
// a folder a scene's texture files may lie under besides the scene's own folder
// (docs/scene-format.md, "Texture files").
struct SceneArgs {
    std::string texture_root;

    harness::SceneLimits limits() const;
};
// --texture-root.
void add_scene_options(CLI::App* cmd, SceneArgs& a);

// conformance/scenes of the working directory, else of the source tree the tool was built from.
std::filesystem::path default_scenes_root();

}  // namespace tool
