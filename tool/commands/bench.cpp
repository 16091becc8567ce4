// bench: the reference timed against OSMesa llvmpipe and softpipe on generated workloads, with
// the performance targets judged (docs/performance.md). The exit code says whether it ran, not
// whether the targets were met.
#include "harness/bench.hpp"

#include <filesystem>
#include <iostream>
#include <memory>
#include <new>
#include <stdexcept>

#include "commands/commands.hpp"
#include "harness/encode.hpp"
#include "harness/files.hpp"

namespace tool {
namespace {

struct BenchArgs {
    std::string scenes;
    int rounds = 5;
    double scale = 1.0;
    std::uint64_t seed = 1;
    bool no_gl = false;
    bool no_softpipe = false;
    bool scaling = false;
    bool process = false;
    unsigned threads = 1;
    unsigned second_threads = 2;
    std::string kernels = "fastest";
    std::string pin_cpu = "auto";
    std::string json;
    ProfileArgs profile;
};

int run_bench(const BenchArgs& a) {
    harness::BenchOptions o;
    o.profile = a.profile.load();
    o.scenes = split_globs(a.scenes);
    o.rounds = a.rounds;
    o.scale = a.scale;
    o.seed = a.seed;
    o.gl = !a.no_gl;
    o.softpipe = !a.no_softpipe;
    o.scaling = a.scaling;
    o.process = a.process;
    if (a.process) {
        // The process runs start this very executable.
        std::error_code error;
        o.refraster_path = std::filesystem::read_symlink("/proc/self/exe", error).string();
        if (error) {
            std::cerr << "refraster bench: --process: cannot find this executable: "
                      << error.message() << "\n";
            return kExitBackendFailure;
        }
    }
    o.threads = a.threads;
    o.second_threads = a.second_threads;
    o.kernels = *harness::parse_kernel_path(a.kernels);  // CLI checks the name
    if (a.pin_cpu == "none") {
        o.pin = false;
    } else if (a.pin_cpu != "auto") {
        o.pin_cpu = std::stoi(a.pin_cpu);  // CLI checks it is a number
    }
    harness::BenchReport report;
    try {
        report = harness::run_bench(o, std::cerr);
    } catch (const std::invalid_argument& e) {
        std::cerr << "refraster bench: " << harness::encode::terminal(e.what()) << "\n";
        return kExitBadInput;
    } catch (const std::bad_alloc&) {
        throw;  // running out of memory: main reports it (exit 3)
    } catch (const std::exception& e) {
        std::cerr << "refraster bench: " << harness::encode::terminal(e.what()) << "\n";
        return kExitBackendFailure;
    }
    std::cout << harness::bench_table(report);
    if (!a.json.empty()) {
        try {
            harness::write_file_atomically(a.json, harness::bench_json(report));
        } catch (const std::bad_alloc&) {
            throw;  // running out of memory: main reports it (exit 3)
        } catch (const std::exception& e) {
            std::cerr << harness::encode::terminal(e.what()) << "\n";
            return kExitBadInput;
        }
    }
    return kExitOk;
}

}  // namespace

Command add_bench_command(CLI::App& app) {
    auto a = std::make_shared<BenchArgs>();
    auto* cmd = app.add_subcommand(
        "bench",
        "Time the reference (one thread, two) against OSMesa llvmpipe (one thread, default "
        "threads) and softpipe, and judge the performance targets");
    // The lists come from the harness, so the help names what a run measures.
    std::string standard, scaling;
    for (const auto& n : harness::bench_workload_names())
        standard += (standard.empty() ? "" : ", ") + n;
    for (const auto& n : harness::bench_scaling_workload_names())
        scaling += (scaling.empty() ? "" : ", ") + n;
    cmd->add_option("--scenes", a->scenes,
                    "Comma-separated workloads; by default the " +
                        std::to_string(harness::bench_workload_names().size()) +
                        " standard ones: " + standard + "; the scaling workloads: " + scaling);
    cmd->add_flag("--scaling", a->scaling,
                  "Also the scaling workloads (tiny-flat-4m, full-flat-2048, full-smooth-2048) "
                  "and their standard counterparts, for the rate ratio");
    cmd->add_option("--rounds", a->rounds, "Interleaved rounds; medians are reported")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    cmd->add_option("--scale", a->scale, "Fraction of each workload's triangles, for quick runs")
        ->check(CLI::Range(1e-6, 1.0))
        ->capture_default_str();
    cmd->add_option("--seed", a->seed, "Seed of the generated workloads")->capture_default_str();
    cmd->add_flag("--process", a->process,
                  "Also time whole processes from scene file to PNG: `refraster render` on the "
                  "reference and with --backend osmesa (LP_NUM_THREADS=0)");
    cmd->add_flag("--no-gl", a->no_gl, "Time the reference alone");
    cmd->add_flag("--no-softpipe", a->no_softpipe, "Leave softpipe out (llvmpipe only)");
    cmd->add_option("--threads", a->threads,
                    "The reference's threads, compared with llvmpipe LP_NUM_THREADS=0 (0: one "
                    "per core)")
        ->capture_default_str();
    cmd->add_option("--second-threads", a->second_threads,
                    "Threads of a second reference configuration, compared with llvmpipe's "
                    "default threads (0: leave it out)")
        ->capture_default_str();
    cmd->add_option("--kernels", a->kernels,
                    "The reference's fragment kernels: model, scalar, avx2, avx512 or fastest")
        ->check(CLI::IsMember({"model", "scalar", "avx2", "avx512", "fastest"}))
        ->capture_default_str();
    cmd->add_option("--pin-cpu", a->pin_cpu,
                    "The CPU every single-threaded render runs on (the reference on one thread, "
                    "llvmpipe LP_NUM_THREADS=0, softpipe, the process runs): a number, auto (the "
                    "lowest this process may use) or none")
        ->check(CLI::IsMember({"auto", "none"}) | CLI::Range(0, 1023))
        ->capture_default_str();
    cmd->add_option("--json", a->json, "Write the results as JSON here");
    add_profile_options(cmd, a->profile);
    return {cmd, [a] { return run_bench(*a); }};
}

}  // namespace tool
