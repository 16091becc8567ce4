#include "options.hpp"

#include <unistd.h>

#include <charconv>
#include <cstdlib>
#include <iostream>
#include <new>
#include <sstream>

#include "command.hpp"
#include "harness/encode.hpp"
#include "harness/profile_io.hpp"

namespace tool {

refraster::Profile ProfileArgs::load() const {
    auto p = harness::load_profile(profile);
    harness::apply_profile_overrides(p, overrides);
    return p;
}

std::string ProfileArgs::source() const {
    return harness::profile_source(profile);
}

void add_threads_option(CLI::App* cmd, unsigned& threads) {
    cmd->add_option("--threads", threads,
                    "Threads the reference shades with (0: one per core; the bytes are the "
                    "same for any count)")
        ->capture_default_str()
        ->check(CLI::Range(0u, 256u));
}

void add_profile_options(CLI::App* cmd, ProfileArgs& a) {
    cmd->add_option("--profile", a.profile,
                    "Reference profile: a built-in name or a profile JSON file")
        ->capture_default_str();
    cmd->add_option("--profile-set", a.overrides,
                    "Override one profile parameter: key=value (repeatable)");
}

harness::BackendOptions BackendArgs::options() const {
    harness::BackendOptions o;
    o.threads = threads;
    o.profile = profile.load();
    o.profile_source = profile.source();
    o.profile_overrides = profile.overrides;
    o.kind = backend == "osmesa" ? harness::BackendKind::OSMesa
             : backend == "egl"  ? harness::BackendKind::Egl
                                 : harness::BackendKind::Ref;
    if (driver.empty()) {
        std::vector<std::string> env;
        for (char** e = environ; e && *e; ++e) env.emplace_back(*e);
        o.driver = harness::driver_from_environment(o.kind, env);
    } else {
        o.driver = harness::Driver(driver);
    }
    o.timeout_seconds = timeout;
    o.mesa_prefix = mesa_prefix;
    if (!egl_device.empty() && egl_device != "list") {
        int n = -1;
        const auto [p, ec] =
            std::from_chars(egl_device.data(), egl_device.data() + egl_device.size(), n);
        if (ec != std::errc() || p != egl_device.data() + egl_device.size() || n < 0)
            throw harness::BackendOptionError("--egl-device " + egl_device +
                                              ": not a device index or 'list'");
        o.egl_device = n;
    }
    return o;
}

void add_backend_option(CLI::App* cmd, const std::string& name, std::string& backend,
                        const std::string& help, std::vector<std::string> choices) {
    cmd->add_option(name, backend, help)
        ->check(CLI::IsMember(std::move(choices)))
        ->capture_default_str();
}

void add_driver_options(CLI::App* cmd, BackendArgs& a) {
    cmd->add_option("--driver", a.driver,
                    "Mesa driver for osmesa and egl: llvmpipe, softpipe, or (egl) any DRI driver "
                    "this system has, zink included (default: MESA_LOADER_DRIVER_OVERRIDE or "
                    "GALLIUM_DRIVER, else llvmpipe)");
    cmd->add_option("--timeout", a.timeout,
                    "Seconds a backend (the reference or a GL worker) may take for one scene; "
                    "past it the scene is a Timeout (exit 3)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_option("--mesa-prefix", a.mesa_prefix,
                    "A Mesa build installed under DIR: the GL workers load libOSMesa, libEGL and "
                    "the DRI drivers from it (default $MESA_PREFIX; else the system's)")
        ->envname("MESA_PREFIX");
    cmd->add_option("--egl-device", a.egl_device,
                    "egl: render on EGL device N (EGL_EXT_device_enumeration) instead of the "
                    "surfaceless platform; 'list' prints the devices");
}

std::optional<int> list_egl_devices_if_asked(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg != "--egl-device=list" &&
            !(arg == "--egl-device" && i + 1 < argc && std::string(argv[i + 1]) == "list"))
            continue;
        BackendArgs egl{"egl"};
        if (const char* prefix = std::getenv("MESA_PREFIX")) egl.mesa_prefix = prefix;
        for (int j = 1; j + 1 < argc; ++j)
            if (std::string(argv[j]) == "--mesa-prefix") egl.mesa_prefix = argv[j + 1];
        try {
            harness::BackendOptions o = egl.options();
            if (!o.mesa_prefix.empty()) {
                const char* ld = std::getenv("LD_LIBRARY_PATH");
                o.environment = harness::mesa_prefix_environment(o.mesa_prefix, ld ? ld : "");
            }
            for (const auto& line : harness::list_egl_devices(o)) std::cout << line << "\n";
            return kExitOk;
        } catch (const harness::BackendOptionError&) {
            throw;  // bad input: main reports it
        } catch (const std::bad_alloc&) {
            throw;  // running out of memory: main reports it (exit 3)
        } catch (const std::exception& e) {
            std::cerr << "refraster: --egl-device list: " << harness::encode::terminal(e.what())
                      << "\n";
            return kExitBackendFailure;
        }
    }
    return std::nullopt;
}

std::optional<std::array<int, 2>> parse_pixel(const std::string& text) {
    int x = 0;
    int y = 0;
    char comma = 0;
    std::istringstream ps(text);
    if (!(ps >> x >> comma >> y) || comma != ',' || !ps.eof()) return std::nullopt;
    return std::array<int, 2>{x, y};
}

bool inside(const refraster::Target& t, const std::array<int, 2>& p) {
    return p[0] >= 0 && p[1] >= 0 && static_cast<std::uint32_t>(p[0]) < t.width &&
           static_cast<std::uint32_t>(p[1]) < t.height;
}

std::vector<std::string> split_globs(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string g; std::getline(ss, g, ',');) {
        if (!g.empty()) out.push_back(g);
    }
    return out;
}

harness::SceneLimits SceneArgs::limits() const {
    harness::SceneLimits l;
    l.texture_root = texture_root;
    return l;
}

void add_scene_options(CLI::App* cmd, SceneArgs& a) {
    cmd->add_option("--texture-root", a.texture_root,
                    "A folder the scene's texture files may also lie under (after resolving "
                    "symlinks); by default only the scene's own folder (docs/scene-format.md)")
        ->check(CLI::ExistingDirectory);
}

std::filesystem::path default_scenes_root() {
    if (std::filesystem::is_directory("conformance/scenes")) return "conformance/scenes";
    return std::filesystem::path(REFRASTER_SOURCE_DIR) / "conformance/scenes";
}

}  // namespace tool
