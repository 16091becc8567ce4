// backend_gl.hpp: the OSMesa and EGL backends, each a persistent worker process.
//
// Implements: GlWorkerBackend, which starts refraster-worker-osmesa or refraster-worker-egl
// (its environment choosing the driver: gl_worker_environment, backend.hpp), refuses a worker
// whose GL runs another driver than the one asked for, keeps it for every later scene, and speaks
// the frame protocol of wire.hpp over two pipes. A worker that dies is reported as
// RenderStatus::Crash naming the scene and the signal; one that does not answer within
// BackendOptions::timeout_seconds is killed and reported as RenderStatus::Timeout. Either way
// the next render starts a fresh worker. The reply of a 4x target carries every sample
// (RenderResult::samples) beside the resolved image; a reply whose image or samples do not
// have the target's shape is an InternalError. GL lives only in the workers: a crash in Mesa cannot
// take the harness down, and OSMesa and glvnd (which export the same gl* symbols) never share
// an address space.
//
// Where the worker executables are: the directory named by REFRASTER_WORKER_DIR if set,
// otherwise the directory of the running executable.
//
// Deliberately does not: render anything itself, share one worker between threads (a
// GlWorkerBackend is used by one thread at a time; make one per thread), or retry a scene.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "harness/backend.hpp"

namespace harness {

class GlWorkerBackend : public Backend {
  public:
    // options.kind must be OSMesa or Egl (std::invalid_argument otherwise). Throws
    // std::runtime_error when the worker executable does not exist. Ignores SIGPIPE for the
    // whole process: a dead worker must show up as EPIPE, not kill the harness.
    explicit GlWorkerBackend(const BackendOptions& options);
    ~GlWorkerBackend() override;
    GlWorkerBackend(const GlWorkerBackend&) = delete;
    GlWorkerBackend& operator=(const GlWorkerBackend&) = delete;

    BackendKind kind() const override { return options_.kind; }
    std::string name() const override;  // "osmesa-llvmpipe", "egl-softpipe", ...
    // RenderResult::seconds is the round trip to the worker (request sent to reply
    // decoded); starting a worker is not counted. A timeout_seconds <= 0 waits forever;
    // start-up always gets at least 10 s.
    RenderResult render(const Scene& scene) override { return render_frame(scene, false); }
    RenderResult render_owners(const Scene& scene) override { return render_frame(scene, true); }

    const std::filesystem::path& worker_path() const { return worker_path_; }
    // The running worker's process id, -1 when none is running.
    pid_t worker_pid() const { return pid_; }

    // Test hooks: start a worker if none runs, then make it abort() or sleep forever on
    // receipt. The next render() reports Crash or Timeout. False if the frame could not be
    // sent (no worker could be started). For runs through the CLI, REFRASTER_WORKER_KILL_AT=N
    // in the environment makes the first worker SIGKILL itself on its Nth scene.
    bool debug_crash_worker();
    bool debug_hang_worker();

  private:
    using Clock = std::chrono::steady_clock;
    using Deadline = std::optional<Clock::time_point>;
    enum class Io : std::uint8_t { Ok, Died, TimedOut };

    RenderResult render_frame(const Scene& scene, bool owners);
    std::optional<RenderResult> ensure_worker();
    bool send_debug_frame(std::uint32_t type);
    Io send(std::uint32_t type, std::vector<std::uint8_t> payload, Deadline deadline);
    Io receive(std::uint32_t& type, std::vector<std::uint8_t>& payload, Deadline deadline,
               std::string& error);
    // Waits for an exited worker (killing it if it lingers) and describes how it ended.
    std::string reap_worker();
    void kill_worker();
    void close_pipes();
    Deadline deadline_after(double seconds) const;
    Provenance base_provenance();
    RenderResult failure(RenderStatus status, std::string message);

    BackendOptions options_;
    std::filesystem::path worker_path_;
    pid_t pid_ = -1;
    int to_worker_ = -1;
    int from_worker_ = -1;
    Provenance worker_provenance_;  // from the last worker's Hello
    std::optional<Provenance> host_provenance_;
    // A worker that said it cannot create its context will say so again: remembered so that
    // thousands of scenes do not each pay for a doomed start-up.
    std::optional<std::string> startup_failure_;
    unsigned workers_started_ = 0;
};

// The factory harness::make_backend calls for BackendKind::OSMesa and BackendKind::Egl.
std::unique_ptr<Backend> make_gl_backend(const BackendOptions& options);

// Where the worker executable of `kind` is looked for (see the file comment).
std::filesystem::path gl_worker_path(BackendKind kind,
                                     const std::filesystem::path& worker_dir = {});

}  // namespace harness
