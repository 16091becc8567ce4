// bench.hpp: `refraster bench`, the reference's speed against llvmpipe measured side by side.
//
// Implements: the benchmark workloads, generated in memory from a seed (no files): tiny
// (1,000,000 triangles of 2 to 10 pixels), medium (100,000 of 100 to 500 pixels) and full (200
// triangles covering the whole target), each flat and smooth, medium and full with perspective
// (w from 1 to 8 across each triangle), textured (a mipmapped 256x256 texture, repeat; nearest,
// bilinear, trilinear filters), 4x multisampled, lines, wide lines and points (single-sample and
// 4x), polygons filled by the non-zero and even-odd rules, full-screen layers that all pass the
// depth test, and softpipe rows (a standard scene drawn under the softpipe-22.3 profile and
// compared with softpipe), on a 1024x1024 rgba8 target with z24 and the depth test `less`, and
// the scaling workloads (tiny-flat-4m, full-flat-2048, full-smooth-2048); their rendering by the
// reference (one configuration with BenchOptions::threads, a second with
// BenchOptions::second_threads, both on the kernel path asked for) and by OSMesa llvmpipe with
// LP_NUM_THREADS=0 and with its default threads, and by softpipe, each GL configuration in a
// worker of its own, warmed up by one render that is not timed (context, framebuffer objects,
// shaders, the first upload), then in interleaved rounds; the medians; every reference and
// llvmpipe render compared byte for byte with llvmpipe's single-threaded one of the same round
// (on a softpipe row, the reference's with softpipe's); the reference's heap high-water mark and
// its bound; the performance targets judged (speed ratios, linearity of the scaling workloads,
// heap); a table and the JSON of docs/performance.md.
//
// Times are those each renderer measures for itself, from clip-space float arrays to a
// finished, read-back framebuffer: the reference's refraster::render, a GL worker's
// upload, draws and glReadPixels (never the transfer between processes).
//
// Deliberately does not: compare softpipe's pixels on the rows drawn under llvmpipe's rules
// (its rules differ from llvmpipe's; docs/conformance.md), or turn a time into a failure: the
// targets are reported as met or missed, and the command still succeeds.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "harness/scene.hpp"
#include "refraster/draw.hpp"
#include "refraster/profile.hpp"
#include "refraster/renderer.hpp"

namespace harness {

struct BenchWorkload {
    std::string name;  // tiny-flat, ..., full-perspective, tiny-flat-4m, ...
    refraster::DrawList list;
    std::size_t triangles = 0;            // the primitives: triangles, lines, points or polygons
    std::string primitive = "triangles";  // triangles, lines, points, polygons
};

// The workload names, in the order the table lists them: the standard ones, which a bench runs
// when it is given no names.
const std::vector<std::string>& bench_workload_names();

// The scaling workloads, for the linearity target: the generator of a standard workload with
// four times the triangles (tiny-flat-4m: 4,000,000 of tiny-flat's) or four times the pixels
// (full-flat-2048, full-smooth-2048: full-flat's and full-smooth's 200 triangles on a 2048x2048
// target). Each is judged by its rate (Mtri/s for tiny, Mpix/s for full) over its standard
// counterpart's in the same run. Not in the default list; `--scaling` adds them.
const std::vector<std::string>& bench_scaling_workload_names();

// The standard workload a scaling workload is measured against (tiny-flat-4m: tiny-flat),
// or nothing for a standard workload.
std::optional<std::string> bench_scaling_counterpart(const std::string& name);

// The scene a softpipe row draws (softpipe-medium-smooth: medium-smooth), or nothing for
// another row. Such a row renders its counterpart's scene (the same seed, the same bytes) with
// the reference under the softpipe-22.3 profile, compares it with softpipe's and is timed
// against softpipe; llvmpipe does not run on it.
std::optional<std::string> bench_softpipe_counterpart(const std::string& name);

// Throws std::invalid_argument for an unknown name. `scale` (0, 1] keeps that fraction of the
// triangles, at least one (for quick runs and tests).
BenchWorkload make_bench_workload(const std::string& name, std::uint64_t seed, double scale = 1.0);

// The scene file of a draw list, for the whole-process runs (BenchOptions::process):
// clip-space positions exactly as the list holds them, the textures named by index, and
// "polygons" required when a draw needs it, so that loading the file's text gives the same
// draw list back.
SceneFile bench_scene_file(const std::string& name, const refraster::DrawList& list);

// The heap bound of the performance target: twice the framebuffer (colour and depth, every
// sample) plus the scene's vertex data (every draw's floats and indices), in bytes.
std::size_t bench_framebuffer_bytes(const refraster::Target& target);
std::size_t bench_vertex_data_bytes(const refraster::DrawList& list);
std::size_t bench_heap_bound_bytes(const refraster::DrawList& list);

struct BenchOptions {
    std::vector<std::string> scenes;  // empty: every standard workload
    bool scaling = false;             // also the scaling workloads and their standard counterparts
    int rounds = 5;
    double scale = 1.0;
    std::uint64_t seed = 1;
    bool gl = true;        // also the GL configurations (needs the OSMesa worker)
    bool softpipe = true;  // with gl: also softpipe (timed only; slow on the tiny workloads)
    // Also time whole processes, `refraster render SCENE --output OUT.png` for the reference
    // and with `--backend osmesa` (LP_NUM_THREADS=0) for llvmpipe, on a scene file written once
    // a workload; needs `refraster_path`.
    bool process = false;
    std::string refraster_path;  // the refraster executable the process runs start
    double timeout_seconds = 600.0;
    refraster::Profile profile;  // the reference's rules (llvmpipe-22.3 unless told otherwise)
    refraster::KernelPath kernels = refraster::KernelPath::Fastest;
    // The reference's threads (RenderOptions::threads; 0: one per core), compared with
    // llvmpipe with LP_NUM_THREADS=0.
    unsigned threads = 1;
    // A second reference configuration with this many threads, timed in the same rounds and
    // compared with llvmpipe's default threads; 0 leaves it out.
    unsigned second_threads = 2;
    // Every single-threaded render (the first configuration with one thread, llvmpipe with
    // LP_NUM_THREADS=0, softpipe, the process runs) on one CPU: `pin_cpu`, or the lowest one
    // this process may run on. The CPUs of a shared machine differ in speed; a ratio of two
    // renders on different CPUs would measure the CPUs.
    bool pin = true;
    std::optional<int> pin_cpu;
};

// The split of the reference's time by stage, each the median over the rounds.
struct BenchSplit {
    double load = 0, setup = 0, raster = 0, fragment = 0;  // milliseconds
};

struct BenchRow {
    std::string name;
    std::size_t triangles = 0;            // primitives, of the kind `primitive` says
    std::string primitive = "triangles";  // triangles, lines, points, polygons
    double pixels = 0.0;  // covered by the triangles, counted by the reference's traversal
    double ref_ms = 0.0;  // the reference with BenchOptions::threads
    std::optional<double> ref2_ms;  // the reference with BenchOptions::second_threads
    std::optional<double> llvmpipe_t0_ms, llvmpipe_ms, softpipe_ms;
    // With BenchOptions::process: a whole `refraster render` process from the scene file to the
    // PNG, the reference on one thread and llvmpipe with LP_NUM_THREADS=0, wall and CPU time of
    // the child (its own and its waited-for children's), medians.
    std::optional<double> ref_process_ms, llvmpipe_process_ms;
    std::optional<double> ref_process_cpu_ms, llvmpipe_process_cpu_ms;
    double ref_heap_peak_mb = 0.0;  // the high-water mark of one render, the first configuration
    std::optional<double> ref2_heap_peak_mb;  // the same for the second configuration
    std::size_t framebuffer_bytes = 0;        // colour and depth of the target
    std::size_t vertex_bytes = 0;             // the scene's floats and indices
    BenchSplit split;

    // Twice the framebuffer plus the vertex data (bench_heap_bound_bytes), in MB.
    double heap_bound_mb() const;
    // The larger of both configurations' high-water marks, in MB.
    double heap_peak_mb() const;
    // llvmpipe t0's median over the reference's (above 1: the reference is faster).
    std::optional<double> speedup() const;
    // llvmpipe's (default threads) median over the second configuration's.
    std::optional<double> speedup2() const;
    // llvmpipe's whole-process median over the reference's.
    std::optional<double> process_speedup() const;
    // softpipe's median over the reference's, and over the second configuration's: on a
    // softpipe row (bench_softpipe_counterpart) only.
    std::optional<double> speedup_vs_softpipe() const;
    std::optional<double> speedup2_vs_softpipe() const;
};

// One performance target and whether this run meets it.
struct BenchTarget {
    std::string scene;
    std::string what;             // "speed", "speed 2T", "linearity", "heap"
    std::optional<double> value;  // the measured ratio or MB; nothing when not measured
    double target = 0.0;
    bool at_most = false;  // heap: value <= target; otherwise value >= target
    bool required = true;  // "speed 2T" is reported, not required
    bool met() const { return value && (at_most ? *value <= target : *value >= target); }
};

// The speed target of a standard workload, the reference on one thread against llvmpipe on one
// thread (a softpipe row: against softpipe): tiny 3; medium and full flat, smooth and
// perspective 2; textured 1.5; 4x, lines, wide lines, points, polygons and allpass 2; softpipe
// rows 5; nothing for the scaling workloads.
std::optional<double> bench_speed_target(const std::string& scene);
inline constexpr double kBenchLinearityTarget = 0.9;

// Every target the rows can be judged on: speed (and speed 2T, reported) for each standard
// workload with a target, linearity for each scaling workload whose counterpart ran, heap for
// every row.
std::vector<BenchTarget> bench_targets(const std::vector<BenchRow>& rows);

// The rate a row is judged on for linearity: Mtri/s for tiny workloads, Mpix/s otherwise.
double bench_rate(const BenchRow& row);
// A scaling row's rate over its counterpart's, when both are among the rows.
std::optional<double> bench_rate_ratio(const BenchRow& row, const std::vector<BenchRow>& rows);

struct BenchReport {
    BenchOptions options;
    std::string kernels;  // the resolved path (to_string(resolve_kernel_path(options.kernels)))
    std::string cpu_flags;
    std::string commit;
    std::string date;  // UTC, ISO 8601
    // llvmpipe's GL_RENDERER, GL_VERSION and Mesa's package version, when a GL worker ran.
    std::string gl_renderer, gl_version, mesa_version;
    int pinned_cpu = -1;  // the CPU of the single-threaded renders; -1: not pinned
    std::vector<BenchRow> rows;
};

// The CPU flags the kernels choose by: fma, avx2, avx512f, avx512bw, avx512dq, avx512vl.
std::string bench_cpu_flags();

// The name of a kernel path (model, scalar, avx2, avx512, fastest), or nothing.
std::optional<refraster::KernelPath> parse_kernel_path(std::string_view name);

// Runs the benchmark, printing progress to `log`. Throws std::runtime_error when a render fails
// or differs from llvmpipe's single-threaded one (a benchmark of wrong pixels means nothing).
BenchReport run_bench(const BenchOptions& options, std::ostream& log);

// The Markdown table, the options and host line above it and the targets summary below it.
std::string bench_table(const BenchReport& report);
// Everything: options, host, every row's times, ratios, heap and bound, split, and `targets`.
std::string bench_json(const BenchReport& report);

// The heap high-water mark since the last reset, in bytes above what was in use then. The CLI
// reports every allocation and release here (tool/heap_meter.cpp replaces the global
// operator new and delete); a program without that reads 0.
void reset_heap_peak();
std::size_t heap_peak_bytes();
void note_heap_allocation(std::size_t bytes);
void note_heap_release(std::size_t bytes);

}  // namespace harness
