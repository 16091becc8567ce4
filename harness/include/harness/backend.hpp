// backend.hpp: the renderers a scene can be sent to, behind one interface.
//
// Implements: `Backend` (render a loaded scene into a Framebuffer), the statuses a render
// ends with, and the provenance recorded with every result.
//
// Deliberately does not: compare images or write files.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "harness/scene.hpp"
#include "refraster/error.hpp"
#include "refraster/framebuffer.hpp"
#include "refraster/profile.hpp"

namespace refraster {
struct RenderOptions;  // refraster/renderer.hpp
struct RenderOutcome;
}  // namespace refraster

namespace harness {

enum class BackendKind : std::uint8_t { Ref, OSMesa, Egl };

// The Mesa driver a GL backend renders with, by name. Two kinds, chosen two ways
// (docs/conformance.md, "Choosing the driver"):
//  - a Gallium software driver inside Mesa's swrast DRI driver and OSMesa, chosen with
//    GALLIUM_DRIVER: llvmpipe, softpipe;
//  - any other DRI driver, chosen by Mesa's loader with MESA_LOADER_DRIVER_OVERRIDE (egl only):
//    zink (GL on Vulkan; on lavapipe when LIBGL_ALWAYS_SOFTWARE=1), iris, radeonsi, ...
// Driver::Llvmpipe and the other known names convert implicitly, so a Driver reads like the
// enumeration it was.
class Driver {
  public:
    enum Known : std::uint8_t { Llvmpipe, Softpipe, Zink };
    Driver() : Driver(Llvmpipe) {}
    Driver(Known k);  // NOLINT(google-explicit-constructor): Driver d = Driver::Softpipe
    // Any name; whether this system has it is checked where a worker starts
    // (check_driver_available).
    explicit Driver(std::string name) : name_(std::move(name)) {}
    const std::string& name() const { return name_; }
    // llvmpipe or softpipe: chosen with GALLIUM_DRIVER, and the only drivers OSMesa has.
    bool gallium_software() const { return name_ == "llvmpipe" || name_ == "softpipe"; }
    friend bool operator==(const Driver&, const Driver&) = default;

  private:
    std::string name_;
};

enum class RenderStatus : std::uint8_t {
    Ok,
    NotSupported,   // the renderer cannot draw what the scene asks
    Crash,          // the worker process died
    Timeout,        // the worker did not answer in time
    InternalError,  // anything else that went wrong in the backend
};

std::string_view to_string(BackendKind k);
const std::string& to_string(const Driver& d);
std::string_view to_string(RenderStatus s);

// Where a result came from. Keys are stable names (renderer, gl_version, mesa_version,
// driver, cpu_flags, profile, commit, ...); values are free text.
using Provenance = std::map<std::string, std::string>;

struct RenderResult {
    RenderStatus status = RenderStatus::Ok;
    std::string message;  // one line, when status != Ok
    // What the scene's target shows: for a 4x target, the resolve (glBlitFramebuffer's
    // colour; depth and owners of sample 0).
    refraster::Framebuffer image;
    // Every sample of a 4x target (samples == 4, colour, depth and, when asked for, owners a
    // sample); empty (0 x 0) for a single-sample target.
    refraster::Framebuffer samples;
    Provenance provenance;
    // Time spent rendering, as the renderer measured it: for a GL worker its own clock from
    // the first GL call to the finished read-back, the transfer between processes excluded.
    double seconds = 0.0;
    // A worker backend's round trip from sending the scene to the decoded reply (the render
    // plus the piping of the vertices and images); 0 for an in-process backend.
    double round_trip_seconds = 0.0;
};

class Backend {
  public:
    virtual ~Backend() = default;
    virtual BackendKind kind() const = 0;
    virtual std::string name() const = 0;  // e.g. "ref", "osmesa-llvmpipe"
    virtual RenderResult render(const Scene& scene) = 0;
    // The same render with Framebuffer::owner filled: which primitive wrote each pixel last
    // (a second pass for GL backends, with an integer attachment written from
    // gl_PrimitiveID). NotSupported where the backend cannot tell.
    virtual RenderResult render_owners(const Scene& scene) {
        (void)scene;
        RenderResult r;
        r.status = RenderStatus::NotSupported;
        r.message = name() + " cannot report primitive owners";
        return r;
    }
};

struct BackendOptions {
    BackendKind kind = BackendKind::Ref;
    Driver driver = Driver::Llvmpipe;
    // Per scene, every backend: a GL worker that has not answered by then is killed, a reference
    // render still running is stopped (refraster::RenderOptions::deadline); either way the
    // result is RenderStatus::Timeout. 0 or less: no limit.
    double timeout_seconds = 60.0;
    // NAME=value variables for a GL worker's environment (LP_NUM_THREADS=0), recorded in its
    // provenance like the driver's own.
    std::vector<std::string> environment;
    // The reference's rules (ref only), and the key=value overrides applied to the named
    // profile, recorded with every result.
    refraster::Profile profile;
    std::string profile_source = "built-in";  // "built-in" or the profile file's path
    std::vector<std::string> profile_overrides;
    // Threads the reference shades with (refraster::RenderOptions::threads; 0: one per core).
    // The bytes are the same for any count.
    unsigned threads = 0;
    // GL backends: the directory holding the worker executables. Empty: REFRASTER_WORKER_DIR,
    // else beside the running program, else ../libexec/refraster from it.
    std::filesystem::path worker_dir;
    // GL backends: a Mesa build of one's own, installed under this prefix; empty: the
    // system's. The workers load libOSMesa, libEGL and the DRI drivers from it
    // (mesa_prefix_environment) and record the libraries they loaded.
    std::filesystem::path mesa_prefix;
    // egl only: render on device N of EGL_EXT_device_enumeration's list (the software device
    // here, a GPU where there is one) instead of the surfaceless platform; the device's index,
    // extensions and DRM node go into the provenance.
    std::optional<int> egl_device;
    // GL backends: the worker (and every thread it starts) runs on this CPU alone, as the
    // calling thread's affinity set at the start says it may (`refraster bench` times a
    // single-threaded driver on the CPU it times the reference on). nullopt: wherever the
    // system puts it.
    std::optional<int> cpu;
};

// Backend options that cannot work (a device on a backend without devices): bad input, not a
// backend failure.
class BackendOptionError : public refraster::Error {
  public:
    explicit BackendOptionError(const std::string& message)
        : refraster::Error(refraster::ExitClass::BadInput, message) {}
};

// A --mesa-prefix that holds no Mesa.
class MesaPrefixError : public BackendOptionError {
  public:
    using BackendOptionError::BackendOptionError;
};

// The EGL devices the egl worker enumerates (EGL_EXT_device_enumeration), one line each:
// "N: <device extensions>[; <DRM node>]". Throws std::runtime_error when the worker cannot run.
std::vector<std::string> list_egl_devices(const BackendOptions& options);

// The worker environment that makes the dynamic loader, Mesa's DRI loader and glvnd take Mesa
// from `prefix`: LD_LIBRARY_PATH with the prefix's library directory first (lib/<multiarch>,
// lib64 or lib, the first holding libOSMesa.so* or libEGL_mesa.so*) before `current`,
// LIBGL_DRIVERS_PATH its dri/ directory, __EGL_VENDOR_LIBRARY_FILENAMES the prefix's Mesa
// vendor file (share/glvnd/egl_vendor.d), each only when present, and REFRASTER_MESA_PREFIX
// for the provenance. Throws MesaPrefixError naming the prefix when it holds no Mesa library.
std::vector<std::string> mesa_prefix_environment(const std::filesystem::path& prefix,
                                                 const std::string& current_ld_library_path);

// The environment a GL worker rendering with `driver` starts with: `base` (NAME=value) without
// the variables that choose a driver (GALLIUM_DRIVER, MESA_LOADER_DRIVER_OVERRIDE) or that
// `extra` sets; then the driver's choice: GALLIUM_DRIVER=llvmpipe or softpipe,
// MESA_LOADER_DRIVER_OVERRIDE=<name> for any other; then LIBGL_ALWAYS_SOFTWARE=1 unless base or
// extra set it (the software drivers, and zink on lavapipe, even where a GPU is); then `extra`.
std::vector<std::string> gl_worker_environment(const Driver& driver,
                                               const std::vector<std::string>& base,
                                               const std::vector<std::string>& extra);

// What a GL backend's workers will start with (gl_worker_environment of this process's
// environment and options.environment) among the variables that choose a driver or change its
// results: MESA_*, LIBGL_*, GALLIUM_*, GALLIVM_*, LP_*, SOFTPIPE_*, VK_*, ZINK_*, glvnd's
// vendor choice (__EGL_VENDOR_LIBRARY_*, __GLX_VENDOR_LIBRARY_*) and EGL_PLATFORM; sorted.
// Empty for the reference.
std::vector<std::string> worker_driver_variables(const BackendOptions& options);

// The driver the environment (NAME=value) chooses for a backend of `kind` when none is named:
// egl: MESA_LOADER_DRIVER_OVERRIDE (unless it names the swrast loader), else GALLIUM_DRIVER;
// osmesa: GALLIUM_DRIVER; llvmpipe when neither is set, or empty.
Driver driver_from_environment(BackendKind kind, const std::vector<std::string>& environment);

// Throws std::runtime_error when the backend was not built into this binary, and
// BackendOptionError for a driver the backend cannot load (a DRI driver the system lacks, or
// any but llvmpipe and softpipe under OSMesa).
std::unique_ptr<Backend> make_backend(const BackendOptions& options);

// The reference under `profile`, shading with `threads` (its bytes are the same for any count).
std::unique_ptr<Backend> make_reference_backend(const refraster::Profile& profile,
                                                unsigned threads = 1);

// Provenance common to every backend: the project's commit and the CPU's FMA/AVX2 flags.
Provenance host_provenance();

// One render of the reference for `scene` under a timeout of its own, as the reference backend
// renders under BackendOptions::timeout_seconds: `options` with a deadline `timeout_seconds`
// from now (none for 0 or less). explain, reduce and the GL verdict render the reference this
// way, each render timed on its own. Past the deadline every shading thread returns and this
// throws refraster::RenderStopped whose message is a backend's Timeout message ("the reference
// (PROFILE) gave no answer within S s for SCENE (stopped)").
refraster::RenderOutcome render_reference_within(const Scene& scene,
                                                 refraster::RenderOptions options,
                                                 double timeout_seconds,
                                                 refraster::Framebuffer& out);

}  // namespace harness
