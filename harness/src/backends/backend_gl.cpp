// backend_gl.cpp: see backend_gl.hpp. No GL here: this file is part of harness_core.
#include "backend_gl.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <thread>
#include <vector>

#include "driver_env.hpp"
#include "no_answer.hpp"
#include "thread_pin.hpp"
#include "wire.hpp"

namespace harness {

namespace {

constexpr const char* kWorkerDirVariable = "REFRASTER_WORKER_DIR";
// Creating a context (llvmpipe compiles its first shaders lazily) takes well under a second;
// a short per-scene timeout must not make every start-up fail.
constexpr double kMinStartupSeconds = 10.0;
// How long a worker that closed its pipe may take to finish exiting before it is killed.
constexpr auto kExitGrace = std::chrono::seconds(2);

const char* worker_name(BackendKind kind) {
    switch (kind) {
        case BackendKind::OSMesa:
            return "refraster-worker-osmesa";
        case BackendKind::Egl:
            return "refraster-worker-egl";
        case BackendKind::Ref:
            break;
    }
    throw std::invalid_argument("the reference renderer has no GL worker");
}

const char* driver_name(const Driver& d) {
    return d.name().c_str();
}

const char* kind_name(BackendKind k) {
    return k == BackendKind::Egl ? "egl" : "osmesa";
}

std::string describe_wait_status(int status) {
    if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        const char* abbrev = sigabbrev_np(sig);
        const char* text = strsignal(sig);
        return "killed by signal " + std::to_string(sig) + " (" +
               (abbrev ? std::string("SIG") + abbrev : std::string("?")) +
               (text ? std::string(", ") + text : std::string()) + ")";
    }
    if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
    return "ended with wait status " + std::to_string(status);
}

// Keeps a pipe end away from fds 0-2, which posix_spawn's dup2 onto 0 and 1 could clobber.
int above_stdio(int fd) {
    if (fd > STDERR_FILENO) return fd;
    const int moved = ::fcntl(fd, F_DUPFD_CLOEXEC, STDERR_FILENO + 1);
    const int saved = errno;
    ::close(fd);
    if (moved < 0) throw std::system_error(saved, std::generic_category(), "fcntl");
    return moved;
}

void set_nonblocking(int fd) {
    const int flags = ::fcntl(fd, F_GETFL);
    if (flags < 0 || ::fcntl(fd, F_SETFL, flags | O_NONBLOCK) < 0) {
        throw std::system_error(errno, std::generic_category(), "fcntl(O_NONBLOCK)");
    }
}

void close_fd(int& fd) {
    if (fd >= 0) ::close(fd);
    fd = -1;
}

// Milliseconds for poll(2): -1 without a deadline, rounded up so a wait never ends early.
int poll_timeout(const std::optional<std::chrono::steady_clock::time_point>& deadline) {
    if (!deadline) return -1;
    const auto left = *deadline - std::chrono::steady_clock::now();
    if (left <= std::chrono::steady_clock::duration::zero()) return 0;
    const auto ms = std::chrono::ceil<std::chrono::milliseconds>(left).count();
    return static_cast<int>(std::min<long long>(ms, 1 << 30));
}

// The DRI driver files this system (or the --mesa-prefix build) has, by driver name: every
// <name>_dri.so in LIBGL_DRIVERS_PATH when set, else in the usual Debian and FHS folders.
std::map<std::string, std::filesystem::path> dri_drivers(const std::vector<std::string>& env) {
    std::vector<std::filesystem::path> dirs;
    for (const auto& kv : env) {
        if (!kv.starts_with("LIBGL_DRIVERS_PATH=")) continue;
        std::string_view list(kv);
        list.remove_prefix(std::string_view("LIBGL_DRIVERS_PATH=").size());
        while (!list.empty()) {
            const auto end = list.find(':');
            if (end != 0) dirs.emplace_back(std::string(list.substr(0, end)));
            if (end == std::string_view::npos) break;
            list.remove_prefix(end + 1);
        }
    }
    if (dirs.empty()) {
        std::error_code ec;
        for (const auto& e : std::filesystem::directory_iterator("/usr/lib", ec)) {
            if (e.is_directory(ec) && std::filesystem::is_directory(e.path() / "dri", ec))
                dirs.push_back(e.path() / "dri");
        }
        dirs.insert(dirs.end(), {"/usr/lib/dri", "/usr/lib64/dri", "/usr/local/lib/dri"});
    }
    std::map<std::string, std::filesystem::path> found;
    for (const auto& dir : dirs) {
        std::error_code ec;
        for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
            const std::string file = e.path().filename().string();
            if (!file.ends_with("_dri.so")) continue;
            found.emplace(file.substr(0, file.size() - 7), e.path());
        }
    }
    return found;
}

bool valid_driver_name(const std::string& name) {
    return !name.empty() && name.size() <= 64 && std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    });
}

// Refuses, as bad input, a driver this backend cannot load: a name that is no driver name, a
// driver other than llvmpipe and softpipe under OSMesa, a DRI driver this system lacks.
void check_driver_available(const BackendOptions& options) {
    const std::string& name = options.driver.name();
    if (!valid_driver_name(name))
        throw BackendOptionError("--driver " + name +
                                 ": not a driver name (lower-case letters, digits and _)");
    if (options.driver.gallium_software()) return;
    if (options.kind == BackendKind::OSMesa)
        throw BackendOptionError("--driver " + name +
                                 ": OSMesa renders with llvmpipe or softpipe only; " + name +
                                 " needs --against egl");
    auto env = driver_env::process_environment();
    env.insert(env.end(), options.environment.begin(), options.environment.end());
    const auto drivers = dri_drivers(env);
    if (drivers.count(name) != 0) return;
    std::string have = "llvmpipe, softpipe";
    for (const auto& [n, path] : drivers)
        if (n != "swrast" && n != "kms_swrast") have += ", " + n;
    throw BackendOptionError("--driver " + name + ": this system has no Mesa DRI driver " + name +
                             "_dri.so (drivers here: " + have + ")");
}

}  // namespace

std::vector<std::string> worker_driver_variables(const BackendOptions& options) {
    if (options.kind == BackendKind::Ref) return {};
    return driver_env::driver_variables(gl_worker_environment(
        options.driver, driver_env::process_environment(), options.environment));
}

Driver driver_from_environment(BackendKind kind, const std::vector<std::string>& environment) {
    const auto value = [&](std::string_view name) -> std::string {
        for (const auto& kv : environment)
            if (kv.size() > name.size() && kv.starts_with(name) && kv[name.size()] == '=')
                return kv.substr(name.size() + 1);
        return {};
    };
    if (kind == BackendKind::Egl) {
        const std::string loader = value("MESA_LOADER_DRIVER_OVERRIDE");
        if (!loader.empty() && loader != "swrast" && loader != "kms_swrast") return Driver(loader);
    }
    const std::string gallium = value("GALLIUM_DRIVER");
    return gallium.empty() ? Driver(Driver::Llvmpipe) : Driver(gallium);
}

std::vector<std::string> gl_worker_environment(const Driver& driver,
                                               const std::vector<std::string>& base,
                                               const std::vector<std::string>& extra) {
    const auto set_by = [](const std::vector<std::string>& list, std::string_view name) {
        return std::any_of(list.begin(), list.end(), [&](const std::string& kv) {
            return kv.size() > name.size() && kv.starts_with(name) && kv[name.size()] == '=';
        });
    };
    const auto name_of = [](const std::string& kv) { return kv.substr(0, kv.find('=')); };
    std::vector<std::string> env;
    for (const auto& kv : base) {
        const std::string name = name_of(kv);
        if (name == "GALLIUM_DRIVER" || name == "MESA_LOADER_DRIVER_OVERRIDE" ||
            set_by(extra, name))
            continue;
        env.push_back(kv);
    }
    if (driver.gallium_software()) {
        env.push_back("GALLIUM_DRIVER=" + driver.name());
    } else {
        env.push_back("MESA_LOADER_DRIVER_OVERRIDE=" + driver.name());
    }
    // Without it, EGL's loader takes a GPU's driver where there is one (whatever
    // GALLIUM_DRIVER says), and zink finds no Vulkan device on a machine without one; with it,
    // the software drivers run, and zink runs on lavapipe. LIBGL_ALWAYS_SOFTWARE=0 in the
    // environment keeps zink on a GPU.
    if (!set_by(base, "LIBGL_ALWAYS_SOFTWARE") && !set_by(extra, "LIBGL_ALWAYS_SOFTWARE"))
        env.emplace_back("LIBGL_ALWAYS_SOFTWARE=1");
    env.insert(env.end(), extra.begin(), extra.end());
    return env;
}

std::filesystem::path gl_worker_path(BackendKind kind, const std::filesystem::path& worker_dir) {
    const char* name = worker_name(kind);
    if (!worker_dir.empty()) return worker_dir / name;
    if (const char* dir = std::getenv(kWorkerDirVariable); dir && *dir) {
        return std::filesystem::path(dir) / name;
    }
    std::error_code ec;
    const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) return std::filesystem::path(name);
    // A build tree keeps the workers beside the tool; an installation puts them under
    // libexec/refraster beside bin/ (the CMake package, docs/library.md).
    const auto beside = self.parent_path() / name;
    const auto installed = self.parent_path().parent_path() / "libexec" / "refraster" / name;
    if (::access(beside.c_str(), X_OK) != 0 && ::access(installed.c_str(), X_OK) == 0) {
        return installed;
    }
    return beside;
}

GlWorkerBackend::GlWorkerBackend(const BackendOptions& options)
    : options_(options), worker_path_(gl_worker_path(options.kind, options.worker_dir)) {
    check_driver_available(options_);
    if (::access(worker_path_.c_str(), X_OK) != 0) {
        throw std::runtime_error("GL worker " + worker_path_.string() +
                                 " is not an executable file (set " + kWorkerDirVariable +
                                 " or BackendOptions::worker_dir to the directory that holds it)");
    }
    ::signal(SIGPIPE, SIG_IGN);
}

GlWorkerBackend::~GlWorkerBackend() {
    if (pid_ < 0) return;
    // End of stream on its stdin is the worker's cue to tear its context down and exit.
    close_fd(to_worker_);
    const auto until = Clock::now() + kExitGrace;
    int status = 0;
    while (::waitpid(pid_, &status, WNOHANG) == 0 && Clock::now() < until) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    kill_worker();
}

std::string GlWorkerBackend::name() const {
    return std::string(kind_name(options_.kind)) + "-" + driver_name(options_.driver);
}

GlWorkerBackend::Deadline GlWorkerBackend::deadline_after(double seconds) const {
    if (!(seconds > 0.0) || !std::isfinite(seconds)) return std::nullopt;
    return Clock::now() +
           std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

Provenance GlWorkerBackend::base_provenance() {
    if (!host_provenance_) host_provenance_ = host_provenance();
    Provenance p = *host_provenance_;
    p["backend"] = kind_name(options_.kind);
    p["driver"] = driver_name(options_.driver);
    for (const auto& [k, v] : worker_provenance_) p.insert_or_assign(k, v);
    return p;
}

RenderResult GlWorkerBackend::failure(RenderStatus status, std::string message) {
    RenderResult r;
    r.status = status;
    r.message = std::move(message);
    r.provenance = base_provenance();
    return r;
}

void GlWorkerBackend::close_pipes() {
    close_fd(to_worker_);
    close_fd(from_worker_);
}

void GlWorkerBackend::kill_worker() {
    close_pipes();
    if (pid_ < 0) return;
    ::kill(pid_, SIGKILL);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
}

std::string GlWorkerBackend::reap_worker() {
    close_pipes();
    if (pid_ < 0) return "not running";
    const pid_t pid = pid_;
    const auto until = Clock::now() + kExitGrace;
    int status = 0;
    for (;;) {
        const pid_t r = ::waitpid(pid, &status, WNOHANG);
        if (r == pid) {
            pid_ = -1;
            return describe_wait_status(status);
        }
        if (r < 0 && errno != EINTR) {
            // Someone else reaped it (SIGCHLD ignored, for instance): nothing more to learn.
            pid_ = -1;
            return "ended (exit status unavailable)";
        }
        if (Clock::now() >= until) {
            kill_worker();
            return "closed its pipe but did not exit (killed)";
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

std::optional<RenderResult> GlWorkerBackend::ensure_worker() {
    if (pid_ >= 0) return std::nullopt;
    if (startup_failure_) return failure(RenderStatus::InternalError, *startup_failure_);
    worker_provenance_.clear();

    int request[2] = {-1, -1};
    int reply[2] = {-1, -1};
    auto close_all = [&] {
        for (int* fd : {&request[0], &request[1], &reply[0], &reply[1]}) close_fd(*fd);
    };
    posix_spawn_file_actions_t actions;
    posix_spawnattr_t attr;
    bool have_actions = false;
    bool have_attr = false;
    try {
        if (::pipe2(request, O_CLOEXEC) != 0 || ::pipe2(reply, O_CLOEXEC) != 0) {
            throw std::system_error(errno, std::generic_category(), "pipe2");
        }
        for (int* fd : {&request[0], &request[1], &reply[0], &reply[1]}) *fd = above_stdio(*fd);

        // The child's stdin reads requests and its stdout writes replies; dup2 clears
        // close-on-exec on the copies only, so no other worker inherits these pipes.
        posix_spawn_file_actions_init(&actions);
        have_actions = true;
        posix_spawn_file_actions_adddup2(&actions, request[0], STDIN_FILENO);
        posix_spawn_file_actions_adddup2(&actions, reply[1], STDOUT_FILENO);
        // The worker starts with default signal handling (our SIGPIPE is ignored, and an
        // ignored disposition would survive exec) and nothing blocked.
        posix_spawnattr_init(&attr);
        have_attr = true;
        sigset_t defaults;
        sigemptyset(&defaults);
        sigaddset(&defaults, SIGPIPE);
        sigset_t none;
        sigemptyset(&none);
        posix_spawnattr_setsigdefault(&attr, &defaults);
        posix_spawnattr_setsigmask(&attr, &none);
        posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);

        std::string program = worker_path_.string();
        std::vector<char*> argv{program.data(), nullptr};
        // The REFRASTER_WORKER_KILL_AT, _HANG_AT and _STALE_AT test hooks reach only the first
        // worker, so that a run sees exactly the one crash, hang or stale answer it asked for,
        // not one per replacement.
        std::vector<std::string> base = driver_env::process_environment();
        if (workers_started_ != 0) {
            std::erase_if(base, [](const std::string& kv) {
                return kv.starts_with("REFRASTER_WORKER_KILL_AT=") ||
                       kv.starts_with("REFRASTER_WORKER_HANG_AT=") ||
                       kv.starts_with("REFRASTER_WORKER_STALE_AT=");
            });
        }
        std::vector<std::string> env =
            gl_worker_environment(options_.driver, base, options_.environment);
        std::vector<char*> envp;
        envp.reserve(env.size() + 1);
        for (auto& e : env) envp.push_back(e.data());
        envp.push_back(nullptr);

        pid_t pid = -1;
        // The child inherits the spawning thread's affinity: pinned for the spawn alone, so
        // that no thread of the worker ever runs elsewhere.
        const detail::ThreadPin pin(options_.cpu);
        const int rc =
            ::posix_spawn(&pid, program.c_str(), &actions, &attr, argv.data(), envp.data());
        if (rc != 0) throw std::system_error(rc, std::generic_category(), "posix_spawn");
        pid_ = pid;
        ++workers_started_;
        close_fd(request[0]);
        close_fd(reply[1]);
        to_worker_ = request[1];
        from_worker_ = reply[0];
        request[1] = reply[0] = -1;
        set_nonblocking(to_worker_);
        set_nonblocking(from_worker_);
    } catch (const std::exception& e) {
        close_all();
        if (have_actions) posix_spawn_file_actions_destroy(&actions);
        if (have_attr) posix_spawnattr_destroy(&attr);
        if (pid_ >= 0) kill_worker();
        return failure(RenderStatus::InternalError,
                       "cannot start " + worker_path_.string() + ": " + e.what());
    }
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);

    // The worker announces itself once its context exists.
    const double startup = options_.timeout_seconds > 0.0
                               ? std::max(options_.timeout_seconds, kMinStartupSeconds)
                               : 0.0;
    std::uint32_t type = 0;
    std::vector<std::uint8_t> payload;
    std::string error;
    const Io io = receive(type, payload, deadline_after(startup), error);
    const std::string who = worker_path_.filename().string();
    if (io == Io::TimedOut) {
        kill_worker();
        return failure(RenderStatus::Timeout,
                       who + " did not start within " + std::to_string(startup) + " s");
    }
    if (io == Io::Died) {
        const std::string how = reap_worker();
        return failure(RenderStatus::Crash, who + " " + how + " while starting" +
                                                (error.empty() ? "" : " (" + error + ")"));
    }
    if (type != static_cast<std::uint32_t>(wire::FrameType::Hello)) {
        kill_worker();
        return failure(RenderStatus::InternalError,
                       who + " sent frame type " + std::to_string(type) + " instead of Hello");
    }
    RenderResult hello;
    try {
        hello = wire::decode_result(payload);
    } catch (const wire::WireError& e) {
        kill_worker();
        return failure(RenderStatus::InternalError, who + ": bad Hello: " + e.what());
    }
    if (hello.status != RenderStatus::Ok) {
        reap_worker();
        startup_failure_ = who + " (" + driver_name(options_.driver) +
                           ") cannot create its context: " + hello.message;
        return failure(RenderStatus::InternalError, *startup_failure_);
    }
    // A label must name the driver that rendered: a worker whose GL runs another driver than
    // the one asked for (the loader fell back, a GPU's driver was taken) is refused.
    const auto loaded = hello.provenance.find("driver");
    if (loaded != hello.provenance.end() && loaded->second != options_.driver.name()) {
        kill_worker();
        const auto renderer = hello.provenance.find("renderer");
        startup_failure_ = who + " was asked for " + options_.driver.name() + " but Mesa loaded " +
                           loaded->second + " (GL_RENDERER \"" +
                           (renderer == hello.provenance.end() ? "" : renderer->second) + "\")";
        return failure(RenderStatus::InternalError, *startup_failure_);
    }
    worker_provenance_ = std::move(hello.provenance);
    return std::nullopt;
}

GlWorkerBackend::Io GlWorkerBackend::send(std::uint32_t type, std::vector<std::uint8_t> payload,
                                          Deadline deadline) {
    wire::FrameWriter writer(static_cast<wire::FrameType>(type), std::move(payload));
    for (;;) {
        try {
            if (writer.write_some(to_worker_)) return Io::Ok;
        } catch (const wire::WireError&) {
            return Io::Died;  // EPIPE: the worker's end is closed
        }
        pollfd p{to_worker_, POLLOUT, 0};
        const int n = ::poll(&p, 1, poll_timeout(deadline));
        if (n < 0 && errno != EINTR) return Io::Died;
        if (n == 0) return Io::TimedOut;
    }
}

GlWorkerBackend::Io GlWorkerBackend::receive(std::uint32_t& type,
                                             std::vector<std::uint8_t>& payload, Deadline deadline,
                                             std::string& error) {
    wire::FrameReader reader;
    for (;;) {
        pollfd p{from_worker_, POLLIN, 0};
        const int n = ::poll(&p, 1, poll_timeout(deadline));
        if (n < 0) {
            if (errno == EINTR) continue;
            error = std::string("poll: ") + std::strerror(errno);
            return Io::Died;
        }
        if (n == 0) return Io::TimedOut;
        try {
            // Drain what is there before polling again: large images arrive in many pieces.
            for (int i = 0; i < 64; ++i) {
                const auto progress = reader.read_some(from_worker_);
                if (progress == wire::FrameReader::Progress::Complete) {
                    wire::Frame f = reader.take();
                    type = f.type;
                    payload = std::move(f.payload);
                    return Io::Ok;
                }
                if (progress == wire::FrameReader::Progress::Eof) return Io::Died;
            }
        } catch (const wire::WireError& e) {
            error = e.what();
            return Io::Died;
        }
    }
}

RenderResult GlWorkerBackend::render_frame(const Scene& scene, bool owners) {
    const std::string label = scene_label(scene);
    if (!scene.unsupported_extensions.empty()) {
        std::string list;
        for (const auto& e : scene.unsupported_extensions)
            list += (list.empty() ? "" : ", ") + escape_for_message(e);
        return failure(RenderStatus::NotSupported,
                       label + ": requires unsupported extension(s) " + list);
    }
    if (auto r = ensure_worker()) {
        r->message = label + ": " + r->message;
        return *r;
    }
    const std::string who = worker_path_.filename().string() + " (pid " + std::to_string(pid_) +
                            ", " + driver_name(options_.driver) + ")";

    std::vector<std::uint8_t> request;
    try {
        request = wire::encode_draw_list(scene.draw_list);
    } catch (const std::exception& e) {
        return failure(RenderStatus::InternalError, label + ": cannot encode: " + e.what());
    }

    const auto start = Clock::now();
    const Deadline deadline = deadline_after(options_.timeout_seconds);
    auto timed_out = [&] {
        kill_worker();
        return failure(RenderStatus::Timeout,
                       no_answer_message(who, options_.timeout_seconds, label, "killed"));
    };
    auto died = [&](const std::string& detail) {
        const std::string how = reap_worker();
        return failure(RenderStatus::Crash, who + " " + how + " while rendering " + label +
                                                (detail.empty() ? "" : " (" + detail + ")"));
    };

    Io io = send(static_cast<std::uint32_t>(owners ? wire::FrameType::RenderOwners
                                                   : wire::FrameType::Render),
                 std::move(request), deadline);
    if (io == Io::TimedOut) return timed_out();
    if (io == Io::Died) return died("");

    std::uint32_t type = 0;
    std::vector<std::uint8_t> payload;
    std::string error;
    io = receive(type, payload, deadline, error);
    if (io == Io::TimedOut) return timed_out();
    if (io == Io::Died) return died(error);
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();

    if (type != static_cast<std::uint32_t>(wire::FrameType::Reply)) {
        kill_worker();
        return failure(RenderStatus::InternalError,
                       who + " sent frame type " + std::to_string(type) + " for " + label);
    }
    RenderResult r;
    try {
        // The payload is given up as the images are copied out of it.
        r = wire::decode_result(std::move(payload));
    } catch (const wire::WireError& e) {
        kill_worker();
        return failure(RenderStatus::InternalError,
                       who + ": bad reply for " + label + ": " + e.what());
    }
    // r.seconds stays the worker's own render time; the round trip is kept beside it.
    r.round_trip_seconds = seconds;
    Provenance p = base_provenance();
    for (auto& [k, v] : r.provenance) p.insert_or_assign(k, std::move(v));
    r.provenance = std::move(p);
    if (r.status != RenderStatus::Ok) {
        r.message = label + ": " + r.message;
        return r;
    }

    const auto& t = scene.draw_list.target;
    // `samples` values a pixel: the image has one, the sample set t.samples.
    const auto shape_ok = [&](const refraster::Framebuffer& fb, std::uint32_t samples) {
        const std::size_t n = std::size_t{t.width} * t.height * samples;
        return fb.width == t.width && fb.height == t.height && fb.samples == samples &&
               fb.color_format == t.color && fb.depth_format == t.depth &&
               fb.color8.size() == (t.color == refraster::ColorFormat::Rgba8 ? n * 4 : 0) &&
               fb.color32f.size() == (t.color == refraster::ColorFormat::Rgba32f ? n * 4 : 0) &&
               fb.depth.size() == (t.depth == refraster::DepthFormat::None ? 0 : n) &&
               fb.owner.size() == (owners ? n : 0);
    };
    if (!shape_ok(r.image, 1)) {
        return failure(RenderStatus::InternalError,
                       who + " returned an image that does not match the target of " + label);
    }
    const bool samples_ok =
        t.samples == 1 ? r.samples == refraster::Framebuffer{} : shape_ok(r.samples, t.samples);
    if (!samples_ok) {
        return failure(RenderStatus::InternalError,
                       who + " returned samples that do not match the " +
                           std::to_string(t.samples) + "x target of " + label);
    }
    return r;
}

bool GlWorkerBackend::send_debug_frame(std::uint32_t type) {
    if (ensure_worker()) return false;
    return send(type, {}, deadline_after(kMinStartupSeconds)) == Io::Ok;
}

bool GlWorkerBackend::debug_crash_worker() {
    return send_debug_frame(static_cast<std::uint32_t>(wire::FrameType::Crash));
}

bool GlWorkerBackend::debug_hang_worker() {
    return send_debug_frame(static_cast<std::uint32_t>(wire::FrameType::Hang));
}

std::unique_ptr<Backend> make_gl_backend(const BackendOptions& options) {
    return std::make_unique<GlWorkerBackend>(options);
}

std::vector<std::string> list_egl_devices(const BackendOptions& options) {
    const std::filesystem::path worker = gl_worker_path(BackendKind::Egl, options.worker_dir);
    std::string cmd;
    for (const auto& kv : options.environment) cmd += "'" + kv + "' ";
    cmd = (cmd.empty() ? "" : "env " + cmd) + "'" + worker.string() + "' --list-devices";
    FILE* p = ::popen(cmd.c_str(), "r");
    if (p == nullptr) throw std::runtime_error(worker.string() + ": cannot start");
    std::string out;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    const int status = ::pclose(p);
    if (status != 0)
        throw std::runtime_error(worker.string() + " --list-devices failed" +
                                 (out.empty() ? "" : ": " + out));
    std::vector<std::string> lines;
    std::size_t at = 0;
    while (at < out.size()) {
        const std::size_t end = out.find('\n', at);
        lines.push_back(out.substr(at, end - at));
        if (end == std::string::npos) break;
        at = end + 1;
    }
    return lines;
}

}  // namespace harness
