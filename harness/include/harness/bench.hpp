// bench.hpp: `refraster bench`, the reference's speed against llvmpipe measured side by side.
//
// Implements: the benchmark workloads, generated in memory from a seed (no files): tiny
// (1,000,000 triangles of 2 to 10 pixels), medium (100,000 of 100 to 500 pixels) and full (200
// triangles covering the whole target), each flat and smooth, and medium and full with
// perspective (w from 1 to 8 across each triangle), on a 1024x1024 rgba8 target with z24 and
// the depth test `less`; their rendering by the reference and by OSMesa llvmpipe with
// LP_NUM_THREADS=0 and with its default threads, and by softpipe, each GL configuration in a
// worker of its own, warmed up by one render that is not timed (context, framebuffer objects,
// shaders, the first upload), then in interleaved rounds; the medians; every reference and
// llvmpipe render compared byte for byte with llvmpipe's single-threaded one of the same round;
// the reference's heap high-water mark; a table and the JSON of docs/performance.md.
//
// Times are those each renderer measures for itself, from clip-space float arrays to a
// finished, read-back framebuffer: the reference's refraster::render, a GL worker's
// upload, draws and glReadPixels (never the transfer between processes).
//
// Deliberately does not: compare softpipe's pixels (its rules differ from llvmpipe's;
// docs/conformance.md), or turn a time into a pass or a fail: speed is reported, never asserted.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "refraster/draw.hpp"
#include "refraster/profile.hpp"

namespace harness {

struct BenchWorkload {
    std::string name;  // tiny-flat, ..., full-perspective
    refraster::DrawList list;
    std::size_t triangles = 0;
};

// The workload names, in the order the table lists them.
const std::vector<std::string>& bench_workload_names();

// Throws std::invalid_argument for an unknown name. `scale` (0, 1] keeps that fraction of the
// triangles (for quick runs and tests); the full workloads use 1.
BenchWorkload make_bench_workload(const std::string& name, std::uint64_t seed, double scale = 1.0);

struct BenchOptions {
    std::vector<std::string> scenes;  // empty: every workload
    int rounds = 5;
    double scale = 1.0;
    std::uint64_t seed = 1;
    bool gl = true;  // also the GL configurations (needs the OSMesa worker)
    double timeout_seconds = 600.0;
    refraster::Profile profile;  // the reference's rules (llvmpipe-22.3 unless told otherwise)
};

// The split of the reference's time by stage, each the median over the rounds.
struct BenchSplit {
    double load = 0, setup = 0, raster = 0, fragment = 0;  // milliseconds
};

struct BenchRow {
    std::string name;
    std::size_t triangles = 0;
    double pixels = 0.0;  // covered by the triangles, counted by the reference's traversal
    double ref_ms = 0.0;
    std::optional<double> llvmpipe_t0_ms, llvmpipe_ms, softpipe_ms;
    double ref_heap_peak_mb = 0.0;
    BenchSplit split;
};

// Runs the benchmark, printing progress to `log`. Throws std::runtime_error when a render fails
// or differs from llvmpipe's single-threaded one (a benchmark of wrong pixels means nothing).
std::vector<BenchRow> run_bench(const BenchOptions& options, std::ostream& log);

std::string bench_table(const std::vector<BenchRow>& rows);
std::string bench_json(const std::vector<BenchRow>& rows);

// The heap high-water mark since the last reset, in bytes above what was in use then. The CLI
// reports every allocation and release here (tool/heap_meter.cpp replaces the global
// operator new and delete); a program without that reads 0.
void reset_heap_peak();
std::size_t heap_peak_bytes();
void note_heap_allocation(std::size_t bytes);
void note_heap_release(std::size_t bytes);

}  // namespace harness
