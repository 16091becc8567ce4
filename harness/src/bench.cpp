#include "harness/bench.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <ostream>
#include <random>
#include <sstream>
#include <stdexcept>

#include "harness/backend.hpp"
#include "harness/scene.hpp"
#include "refraster/renderer.hpp"

namespace harness {

namespace {

constexpr std::uint32_t kSize = 1024;  // the target: kSize x kSize rgba8, z24

struct Shape {
    std::size_t count;
    double min_area, max_area;  // pixels; 0 for full-screen triangles
};

Shape shape_of(const std::string& size) {
    if (size == "tiny") return {1'000'000, 2.0, 10.0};
    if (size == "medium") return {100'000, 100.0, 500.0};
    return {200, 0.0, 0.0};  // full
}

}  // namespace

const std::vector<std::string>& bench_workload_names() {
    static const std::vector<std::string> names{
        "tiny-flat", "tiny-smooth", "medium-flat",        "medium-smooth",
        "full-flat", "full-smooth", "medium-perspective", "full-perspective"};
    return names;
}

BenchWorkload make_bench_workload(const std::string& name, std::uint64_t seed, double scale) {
    const auto& names = bench_workload_names();
    if (std::find(names.begin(), names.end(), name) == names.end()) {
        std::string list;
        for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
        throw std::invalid_argument("unknown bench scene \"" + name + "\" (scenes: " + list + ")");
    }
    if (!(scale > 0.0 && scale <= 1.0))
        throw std::invalid_argument("bench scale must be in (0, 1]");
    const std::string size = name.substr(0, name.find('-'));
    const std::string kind = name.substr(name.find('-') + 1);
    const Shape shape = shape_of(size);
    const auto count = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::llround(static_cast<double>(shape.count) * scale)));

    BenchWorkload w;
    w.name = name;
    w.triangles = count;
    w.list.target = {kSize, kSize, refraster::ColorFormat::Rgba8, refraster::DepthFormat::Z24, 1};
    w.list.clear.color = {0.0f, 0.0f, 0.0f, 1.0f};
    w.list.clear.depth = 1.0f;
    refraster::Draw d;
    d.primitive = refraster::PrimitiveType::Triangles;
    d.state.viewport = {0, 0, static_cast<std::int32_t>(kSize), static_cast<std::int32_t>(kSize)};
    d.state.depth_test = refraster::CompareFunc::Less;
    d.state.shade = kind == "flat" ? refraster::ShadeModel::Flat : refraster::ShadeModel::Smooth;
    d.vertices.attributes = {{"color", 4}};
    d.vertices.data.reserve(count * 3 * 8);

    std::mt19937_64 rng(seed ^ std::hash<std::string>{}(name));
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const bool perspective = kind == "perspective";
    for (std::size_t i = 0; i < count; ++i) {
        std::array<std::array<double, 2>, 3> win{};
        if (shape.max_area == 0.0) {
            // A triangle over the whole target (and beyond it, so that it is clipped).
            win = {{{-0.25 * kSize * u(rng), -0.25 * kSize * u(rng)},
                    {2.5 * kSize, -0.25 * kSize * u(rng)},
                    {-0.25 * kSize * u(rng), 2.5 * kSize}}};
        } else {
            // A random shape of the asked-for area around a random centre: two edge vectors of
            // random direction and aspect, scaled to the area, counter-clockwise.
            const double area = shape.min_area + (shape.max_area - shape.min_area) * u(rng);
            const double angle = 2.0 * std::numbers::pi * u(rng);
            const double spread = 0.4 + 2.0 * u(rng);  // the angle between the two edges
            const double aspect = 0.5 + 1.5 * u(rng);
            const double l1 = std::sqrt(2.0 * area / (aspect * std::sin(std::min(spread, 3.0))));
            const double l2 = aspect * l1;
            const double cx = u(rng) * kSize, cy = u(rng) * kSize;
            const std::array<double, 2> e1{l1 * std::cos(angle), l1 * std::sin(angle)};
            const std::array<double, 2> e2{l2 * std::cos(angle + spread),
                                           l2 * std::sin(angle + spread)};
            win = {{{cx - (e1[0] + e2[0]) / 3, cy - (e1[1] + e2[1]) / 3},
                    {cx + (2 * e1[0] - e2[0]) / 3, cy + (2 * e1[1] - e2[1]) / 3},
                    {cx + (2 * e2[0] - e1[0]) / 3, cy + (2 * e2[1] - e1[1]) / 3}}};
        }
        const double z = 2.0 * u(rng) - 1.0;  // one depth a triangle: later ones pass or fail
        for (int k = 0; k < 3; ++k) {
            // w from 1 to 8 across the triangle with perspective, 1 otherwise.
            const double wv = perspective ? 1.0 + 7.0 * u(rng) : 1.0;
            const double nx = win[static_cast<std::size_t>(k)][0] / kSize * 2.0 - 1.0;
            const double ny = win[static_cast<std::size_t>(k)][1] / kSize * 2.0 - 1.0;
            for (double c : {nx * wv, ny * wv, z * wv, wv})
                d.vertices.data.push_back(static_cast<float>(c));
            for (int c = 0; c < 3; ++c) d.vertices.data.push_back(static_cast<float>(u(rng)));
            d.vertices.data.push_back(1.0f);
        }
    }
    w.list.draws.push_back(std::move(d));
    return w;
}

namespace {

std::atomic<std::size_t> g_heap_current{0};
std::atomic<std::size_t> g_heap_peak{0};
std::atomic<std::size_t> g_heap_base{0};

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct GlConfig {
    std::string label;  // llvmpipe_t0, llvmpipe, softpipe
    Driver driver;
    std::vector<std::string> environment;
    bool compared;  // byte-compared with llvmpipe_t0
};

double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

std::vector<BenchRow> run_bench(const BenchOptions& options, std::ostream& log) {
    const std::vector<std::string> names =
        options.scenes.empty() ? bench_workload_names() : options.scenes;
    for (const auto& n : names)
        (void)make_bench_workload(n, options.seed, 1e-6);  // unknown names fail first
    if (options.rounds < 1) throw std::invalid_argument("bench needs at least one round");

    std::vector<GlConfig> configs;
    std::vector<std::unique_ptr<Backend>> backends;
    if (options.gl) {
        configs = {{"llvmpipe_t0", Driver::Llvmpipe, {"LP_NUM_THREADS=0"}, true},
                   {"llvmpipe", Driver::Llvmpipe, {}, true},
                   {"softpipe", Driver::Softpipe, {}, false}};
        for (const auto& c : configs) {
            BackendOptions o;
            o.kind = BackendKind::OSMesa;
            o.driver = c.driver;
            o.environment = c.environment;
            o.timeout_seconds = options.timeout_seconds;
            backends.push_back(make_backend(o));
        }
    }
    const refraster::Profile& profile = options.profile;
    const refraster::RenderStage stages[] = {
        refraster::RenderStage::Load, refraster::RenderStage::Setup, refraster::RenderStage::Raster,
        refraster::RenderStage::Fragment};

    std::vector<BenchRow> rows;
    for (const auto& name : names) {
        auto t0 = std::chrono::steady_clock::now();
        Scene scene;
        {
            auto w = make_bench_workload(name, options.seed, options.scale);
            scene.draw_list = std::move(w.list);
            scene.file.name = "bench." + name;
            BenchRow row;
            row.name = name;
            row.triangles = w.triangles;
            rows.push_back(row);
        }
        BenchRow& row = rows.back();
        {
            // The pixels the triangles cover (before the depth test): what Mpix/s counts.
            refraster::RenderOptions count;
            count.profile = options.profile;
            count.stop_after = refraster::RenderStage::Raster;
            refraster::Framebuffer scratch;
            row.pixels =
                static_cast<double>(refraster::render(scene.draw_list, count, scratch).fragments);
        }
        log << name << ": " << row.triangles << " triangles covering " << std::fixed
            << std::setprecision(1) << row.pixels / 1e6 << " Mpx, generated in " << ms_since(t0)
            << " ms\n"
            << std::flush;
        // Warm-up: one untimed render in every GL worker (context, framebuffer objects, shader
        // compilation, first upload).
        for (std::size_t c = 0; c < backends.size(); ++c) {
            const auto r = backends[c]->render(scene);
            if (r.status != RenderStatus::Ok) {
                throw std::runtime_error("bench " + name + ": " + configs[c].label + ": " +
                                         std::string(to_string(r.status)) + ": " + r.message);
            }
        }
        std::vector<double> ref_ms;
        std::map<std::string, std::vector<double>> gl_ms;
        std::vector<std::vector<double>> stage_ms(4);
        std::size_t heap_peak = 0;
        for (int round = 0; round < options.rounds; ++round) {
            // Interleaved: every renderer once a round, so that the machine's load shifts
            // every column alike.
            refraster::Framebuffer ref;
            reset_heap_peak();
            refraster::RenderOptions ro;
            ro.profile = profile;
            auto s0 = std::chrono::steady_clock::now();
            (void)refraster::render(scene.draw_list, ro, ref);
            ref_ms.push_back(ms_since(s0));
            heap_peak = std::max(heap_peak, heap_peak_bytes());
            // The split: the same render stopped after each stage; a stage's time is the
            // difference of the medians.
            for (std::size_t k = 0; k + 1 < std::size(stages); ++k) {
                refraster::Framebuffer partial;
                ro.stop_after = stages[k];
                s0 = std::chrono::steady_clock::now();
                (void)refraster::render(scene.draw_list, ro, partial);
                stage_ms[k].push_back(ms_since(s0));
            }
            stage_ms[3].push_back(ref_ms.back());
            std::optional<refraster::Framebuffer> single;
            for (std::size_t c = 0; c < backends.size(); ++c) {
                auto r = backends[c]->render(scene);
                if (r.status != RenderStatus::Ok) {
                    throw std::runtime_error("bench " + name + ": " + configs[c].label + ": " +
                                             std::string(to_string(r.status)) + ": " + r.message);
                }
                gl_ms[configs[c].label].push_back(r.seconds * 1000.0);
                if (configs[c].label == "llvmpipe_t0") {
                    single = std::move(r.image);
                    if (!(ref == *single)) {
                        throw std::runtime_error("bench " + name +
                                                 ": the reference's image differs from llvmpipe's "
                                                 "(LP_NUM_THREADS=0) in round " +
                                                 std::to_string(round + 1));
                    }
                } else if (configs[c].compared && single && !(r.image == *single)) {
                    throw std::runtime_error(
                        "bench " + name +
                        ": llvmpipe with threads differs from LP_NUM_THREADS=0 in round " +
                        std::to_string(round + 1));
                }
            }
            log << "  round " << round + 1 << ": ref " << ref_ms.back() << " ms";
            for (const auto& c : configs)
                log << ", " << c.label << " " << gl_ms[c.label].back() << " ms";
            log << "\n" << std::flush;
        }
        row.ref_ms = median(ref_ms);
        row.ref_heap_peak_mb = static_cast<double>(heap_peak) / (1024.0 * 1024.0);
        double before = 0.0;
        double* split[] = {&row.split.load, &row.split.setup, &row.split.raster,
                           &row.split.fragment};
        for (std::size_t k = 0; k < 4; ++k) {
            const double m = median(stage_ms[k]);
            *split[k] = std::max(0.0, m - before);
            before = std::max(before, m);
        }
        if (gl_ms.count("llvmpipe_t0")) row.llvmpipe_t0_ms = median(gl_ms["llvmpipe_t0"]);
        if (gl_ms.count("llvmpipe")) row.llvmpipe_ms = median(gl_ms["llvmpipe"]);
        if (gl_ms.count("softpipe")) row.softpipe_ms = median(gl_ms["softpipe"]);
    }
    return rows;
}

namespace {

std::string fixed(double v, int digits) {
    std::ostringstream o;
    o << std::fixed << std::setprecision(digits) << v;
    return o.str();
}

}  // namespace

void note_heap_allocation(std::size_t bytes) {
    const std::size_t now = g_heap_current.fetch_add(bytes, std::memory_order_relaxed) + bytes;
    std::size_t peak = g_heap_peak.load(std::memory_order_relaxed);
    while (now > peak && !g_heap_peak.compare_exchange_weak(peak, now, std::memory_order_relaxed)) {
    }
}

void note_heap_release(std::size_t bytes) {
    g_heap_current.fetch_sub(bytes, std::memory_order_relaxed);
}

void reset_heap_peak() {
    const std::size_t now = g_heap_current.load(std::memory_order_relaxed);
    g_heap_base.store(now, std::memory_order_relaxed);
    g_heap_peak.store(now, std::memory_order_relaxed);
}

std::size_t heap_peak_bytes() {
    return g_heap_peak.load(std::memory_order_relaxed) -
           g_heap_base.load(std::memory_order_relaxed);
}

std::string bench_table(const std::vector<BenchRow>& rows) {
    std::ostringstream o;
    const auto rate = [](double count, double ms) {
        return ms > 0.0 ? count / (ms * 1000.0) : 0.0;
    };  // millions a second
    o << "| scene | triangles | Mpx | ref ms | ref Mtri/s | ref Mpix/s | llvmpipe t0 ms | Mtri/s | "
         "Mpix/s | llvmpipe ms | "
         "softpipe ms | ref / llvmpipe t0 | ref heap MB | load | setup | raster | fragment |\n"
      << "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | "
         "---: | ---: | ---: | ---: | ---: |\n";
    const auto opt = [](const std::optional<double>& v) {
        return v ? fixed(*v, 1) : std::string("-");
    };
    for (const auto& r : rows) {
        const double tris = static_cast<double>(r.triangles);
        o << "| " << r.name << " | " << r.triangles << " | " << fixed(r.pixels / 1e6, 1) << " | "
          << fixed(r.ref_ms, 1) << " | " << fixed(rate(tris, r.ref_ms), 2) << " | "
          << fixed(rate(r.pixels, r.ref_ms), 1) << " | " << opt(r.llvmpipe_t0_ms) << " | "
          << (r.llvmpipe_t0_ms ? fixed(rate(tris, *r.llvmpipe_t0_ms), 2) : "-") << " | "
          << (r.llvmpipe_t0_ms ? fixed(rate(r.pixels, *r.llvmpipe_t0_ms), 1) : "-") << " | "
          << opt(r.llvmpipe_ms) << " | " << opt(r.softpipe_ms) << " | "
          << (r.llvmpipe_t0_ms && r.ref_ms > 0 ? fixed(*r.llvmpipe_t0_ms / r.ref_ms, 2)
                                               : std::string("-"))
          << " | " << fixed(r.ref_heap_peak_mb, 1) << " | " << fixed(r.split.load, 1) << " | "
          << fixed(r.split.setup, 1) << " | " << fixed(r.split.raster, 1) << " | "
          << fixed(r.split.fragment, 1) << " |\n";
    }
    o << "\nref / llvmpipe t0: the reference's speed over single-threaded llvmpipe's (above 1: the "
         "reference is "
         "faster). Medians; times in ms; the split is the reference's.\n";
    return o.str();
}

std::string bench_json(const std::vector<BenchRow>& rows) {
    nlohmann::ordered_json j;
    auto& scenes = j["scenes"] = nlohmann::ordered_json::array();
    const auto opt = [](const std::optional<double>& v) {
        return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json();
    };
    for (const auto& r : rows) {
        nlohmann::ordered_json s;
        s["name"] = r.name;
        s["triangles"] = r.triangles;
        s["pixels"] = r.pixels;
        s["ref_ms"] = r.ref_ms;
        s["llvmpipe_t0_ms"] = opt(r.llvmpipe_t0_ms);
        s["llvmpipe_ms"] = opt(r.llvmpipe_ms);
        s["softpipe_ms"] = opt(r.softpipe_ms);
        s["speedup_vs_llvmpipe_t0"] = r.llvmpipe_t0_ms && r.ref_ms > 0
                                          ? nlohmann::ordered_json(*r.llvmpipe_t0_ms / r.ref_ms)
                                          : nlohmann::ordered_json();
        s["ref_heap_peak_mb"] = r.ref_heap_peak_mb;
        s["split_ms"] = {{"load", r.split.load},
                         {"setup", r.split.setup},
                         {"raster", r.split.raster},
                         {"fragment", r.split.fragment}};
        scenes.push_back(s);
    }
    return j.dump(1) + "\n";
}

}  // namespace harness
