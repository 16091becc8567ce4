#include "harness/bench.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <ctime>
#include <iomanip>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <ostream>
#include <random>
#include <sstream>
#include <stdexcept>

#include "harness/backend.hpp"
#include "harness/scene.hpp"
#include "refraster/renderer.hpp"

namespace harness {

namespace {

struct Spec {
    std::size_t count;          // triangles at scale 1
    double min_area, max_area;  // pixels; 0 for full-screen triangles
    std::uint32_t size;         // the target: size x size rgba8, z24
    refraster::ShadeModel shade;
    bool perspective;
    // Textured workloads: a 256x256 texture with generated mipmaps, sampled with this min
    // filter (mag linear) at about two texels a pixel, modulating the colour.
    std::optional<refraster::TextureFilter> texture = std::nullopt;
};

std::optional<Spec> spec_of(const std::string& name) {
    constexpr auto flat = refraster::ShadeModel::Flat;
    constexpr auto smooth = refraster::ShadeModel::Smooth;
    static const std::map<std::string, Spec> specs{
        {"tiny-flat", {1'000'000, 2.0, 10.0, 1024, flat, false}},
        {"tiny-smooth", {1'000'000, 2.0, 10.0, 1024, smooth, false}},
        {"medium-flat", {100'000, 100.0, 500.0, 1024, flat, false}},
        {"medium-smooth", {100'000, 100.0, 500.0, 1024, smooth, false}},
        {"full-flat", {200, 0.0, 0.0, 1024, flat, false}},
        {"full-smooth", {200, 0.0, 0.0, 1024, smooth, false}},
        {"medium-perspective", {100'000, 100.0, 500.0, 1024, smooth, true}},
        {"full-perspective", {200, 0.0, 0.0, 1024, smooth, true}},
        {"medium-textured-bilinear",
         {100'000, 100.0, 500.0, 1024, smooth, false, refraster::TextureFilter::Linear}},
        {"medium-textured-trilinear",
         {100'000, 100.0, 500.0, 1024, smooth, false,
          refraster::TextureFilter::LinearMipmapLinear}},
        {"tiny-flat-4m", {4'000'000, 2.0, 10.0, 1024, flat, false}},
        {"full-flat-2048", {200, 0.0, 0.0, 2048, flat, false}},
        {"full-smooth-2048", {200, 0.0, 0.0, 2048, smooth, false}},
    };
    const auto it = specs.find(name);
    if (it == specs.end()) return std::nullopt;
    return it->second;
}

}  // namespace

const std::vector<std::string>& bench_workload_names() {
    static const std::vector<std::string> names{"tiny-flat",
                                                "tiny-smooth",
                                                "medium-flat",
                                                "medium-smooth",
                                                "full-flat",
                                                "full-smooth",
                                                "medium-perspective",
                                                "full-perspective",
                                                "medium-textured-bilinear",
                                                "medium-textured-trilinear"};
    return names;
}

const std::vector<std::string>& bench_scaling_workload_names() {
    static const std::vector<std::string> names{"tiny-flat-4m", "full-flat-2048",
                                                "full-smooth-2048"};
    return names;
}

std::optional<std::string> bench_scaling_counterpart(const std::string& name) {
    if (name == "tiny-flat-4m") return "tiny-flat";
    if (name == "full-flat-2048") return "full-flat";
    if (name == "full-smooth-2048") return "full-smooth";
    return std::nullopt;
}

BenchWorkload make_bench_workload(const std::string& name, std::uint64_t seed, double scale) {
    const auto spec = spec_of(name);
    if (!spec) {
        std::string list;
        for (const auto* names : {&bench_workload_names(), &bench_scaling_workload_names()})
            for (const auto& n : *names) list += (list.empty() ? "" : ", ") + n;
        throw std::invalid_argument("unknown bench scene \"" + name + "\" (scenes: " + list + ")");
    }
    if (!(scale > 0.0 && scale <= 1.0))
        throw std::invalid_argument("bench scale must be in (0, 1]");
    const Spec& shape = *spec;
    const std::uint32_t size = shape.size;
    const auto count = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::llround(static_cast<double>(shape.count) * scale)));

    BenchWorkload w;
    w.name = name;
    w.triangles = count;
    w.list.target = {size, size, refraster::ColorFormat::Rgba8, refraster::DepthFormat::Z24, 1};
    w.list.clear.color = {0.0f, 0.0f, 0.0f, 1.0f};
    w.list.clear.depth = 1.0f;
    refraster::Draw d;
    d.primitive = refraster::PrimitiveType::Triangles;
    d.state.viewport = {0, 0, static_cast<std::int32_t>(size), static_cast<std::int32_t>(size)};
    d.state.depth_test = refraster::CompareFunc::Less;
    d.state.shade = shape.shade;
    d.vertices.attributes = {{"color", 4}};
    const bool textured = shape.texture.has_value();
    if (textured) {
        d.vertices.attributes.push_back({"texcoord", 4});
        refraster::Texture t;
        refraster::TextureImage img;
        img.width = img.height = 256;
        img.rgba.resize(256 * 256 * 4);
        for (std::size_t i = 0; i < img.rgba.size(); ++i) {
            const std::size_t texel = i / 4;
            const std::size_t x = texel % 256, y = texel / 256;
            img.rgba[i] = static_cast<std::uint8_t>(((x ^ y) * (i % 4 + 3) + x * 7) & 0xff);
        }
        t.levels.push_back(std::move(img));
        t.generate_mipmaps = true;
        w.list.textures.push_back(std::move(t));
        refraster::TextureState ts;
        ts.min_filter = *shape.texture;
        d.state.texture = ts;
    }
    d.vertices.data.reserve(count * 3 * (textured ? 12 : 8));

    std::mt19937_64 rng(seed ^ std::hash<std::string>{}(name));
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const bool perspective = shape.perspective;
    for (std::size_t i = 0; i < count; ++i) {
        std::array<std::array<double, 2>, 3> win{};
        if (shape.max_area == 0.0) {
            // A triangle over the whole target (and beyond it, so that it is clipped).
            win = {{{-0.25 * size * u(rng), -0.25 * size * u(rng)},
                    {2.5 * size, -0.25 * size * u(rng)},
                    {-0.25 * size * u(rng), 2.5 * size}}};
        } else {
            // A random shape of the asked-for area around a random centre: two edge vectors of
            // random direction and aspect, scaled to the area, counter-clockwise.
            const double area = shape.min_area + (shape.max_area - shape.min_area) * u(rng);
            const double angle = 2.0 * std::numbers::pi * u(rng);
            const double spread = 0.4 + 2.0 * u(rng);  // the angle between the two edges
            const double aspect = 0.5 + 1.5 * u(rng);
            const double l1 = std::sqrt(2.0 * area / (aspect * std::sin(std::min(spread, 3.0))));
            const double l2 = aspect * l1;
            const double cx = u(rng) * size, cy = u(rng) * size;
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
            const double nx = win[static_cast<std::size_t>(k)][0] / size * 2.0 - 1.0;
            const double ny = win[static_cast<std::size_t>(k)][1] / size * 2.0 - 1.0;
            for (double c : {nx * wv, ny * wv, z * wv, wv})
                d.vertices.data.push_back(static_cast<float>(c));
            for (int c = 0; c < 3; ++c) d.vertices.data.push_back(static_cast<float>(u(rng)));
            d.vertices.data.push_back(1.0f);
            if (textured) {
                // About two texels of the 256x256 base level a pixel.
                const auto& p = win[static_cast<std::size_t>(k)];
                for (double c : {p[0] / 128.0, p[1] / 128.0, 0.0, 1.0})
                    d.vertices.data.push_back(static_cast<float>(c));
            }
        }
    }
    w.list.draws.push_back(std::move(d));
    return w;
}

std::size_t bench_framebuffer_bytes(const refraster::Target& target) {
    const std::size_t samples = std::size_t{target.width} * target.height * target.samples;
    const std::size_t colour = target.color == refraster::ColorFormat::Rgba8 ? 4 : 16;
    const std::size_t depth = target.depth == refraster::DepthFormat::None ? 0 : 4;
    return samples * (colour + depth);
}

std::size_t bench_vertex_data_bytes(const refraster::DrawList& list) {
    std::size_t bytes = 0;
    // Textures count as the scene's data too (every level given, the base of a generated chain).
    for (const auto& t : list.textures)
        for (const auto& l : t.levels) bytes += l.rgba.size();
    for (const auto& d : list.draws) {
        bytes += d.vertices.data.size() * sizeof(float);
        if (d.indices) bytes += d.indices->size() * sizeof(std::uint32_t);
    }
    return bytes;
}

std::size_t bench_heap_bound_bytes(const refraster::DrawList& list) {
    return 2 * bench_framebuffer_bytes(list.target) + bench_vertex_data_bytes(list);
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

std::optional<refraster::KernelPath> parse_kernel_path(std::string_view name) {
    for (const auto p :
         {refraster::KernelPath::Model, refraster::KernelPath::Scalar, refraster::KernelPath::Avx2,
          refraster::KernelPath::Avx512, refraster::KernelPath::Fastest}) {
        if (refraster::to_string(p) == name) return p;
    }
    return std::nullopt;
}

std::string bench_cpu_flags() {
    std::string flags;
#if defined(__x86_64__) || defined(__i386__)
    __builtin_cpu_init();
    if (__builtin_cpu_supports("fma")) flags += "fma ";
    if (__builtin_cpu_supports("avx2")) flags += "avx2 ";
    if (__builtin_cpu_supports("avx512f")) flags += "avx512f ";
    if (__builtin_cpu_supports("avx512bw")) flags += "avx512bw ";
    if (__builtin_cpu_supports("avx512dq")) flags += "avx512dq ";
    if (__builtin_cpu_supports("avx512vl")) flags += "avx512vl ";
#endif
    if (!flags.empty()) flags.pop_back();
    return flags;
}

namespace {

std::string utc_now() {
    const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    std::tm tm{};
    gmtime_r(&t, &tm);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return text;
}

// The workloads a run measures, in order, each once: the names asked for (or the standard
// ones), then with `scaling` each scaling workload after its counterpart.
std::vector<std::string> bench_run_names(const BenchOptions& options) {
    std::vector<std::string> names;
    const auto add = [&](const std::string& n) {
        if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
    };
    for (const auto& n :
         options.scenes.empty() && !options.scaling ? bench_workload_names() : options.scenes)
        add(n);
    if (options.scaling) {
        for (const auto& n : bench_scaling_workload_names()) {
            add(*bench_scaling_counterpart(n));
            add(n);
        }
    }
    return names;
}

}  // namespace

BenchReport run_bench(const BenchOptions& options, std::ostream& log) {
    const std::vector<std::string> names = bench_run_names(options);
    for (const auto& n : names)
        (void)make_bench_workload(n, options.seed, 1e-9);  // unknown names fail first
    if (options.rounds < 1) throw std::invalid_argument("bench needs at least one round");

    BenchReport report;
    report.options = options;
    report.kernels =
        std::string(refraster::to_string(refraster::resolve_kernel_path(options.kernels)));
    report.cpu_flags = bench_cpu_flags();
    report.commit = host_provenance()["commit"];
    report.date = utc_now();

    std::vector<GlConfig> configs;
    std::vector<std::unique_ptr<Backend>> backends;
    if (options.gl) {
        configs = {{"llvmpipe_t0", Driver::Llvmpipe, {"LP_NUM_THREADS=0"}, true},
                   {"llvmpipe", Driver::Llvmpipe, {}, true}};
        if (options.softpipe) configs.push_back({"softpipe", Driver::Softpipe, {}, false});
        for (const auto& c : configs) {
            BackendOptions o;
            o.kind = BackendKind::OSMesa;
            o.driver = c.driver;
            o.environment = c.environment;
            o.timeout_seconds = options.timeout_seconds;
            backends.push_back(make_backend(o));
        }
    }
    const refraster::RenderStage stages[] = {
        refraster::RenderStage::Load, refraster::RenderStage::Setup, refraster::RenderStage::Raster,
        refraster::RenderStage::Fragment};
    refraster::RenderOptions first;
    first.profile = options.profile;
    first.kernels = options.kernels;
    first.threads = options.threads;
    std::optional<refraster::RenderOptions> second;
    if (options.second_threads > 0) {
        second = first;
        second->threads = options.second_threads;
    }
    const auto failed = [](const std::string& name, const std::string& label,
                           const RenderResult& r) {
        return std::runtime_error("bench " + name + ": " + label + ": " +
                                  std::string(to_string(r.status)) + ": " + r.message);
    };

    std::vector<BenchRow>& rows = report.rows;
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
            row.framebuffer_bytes = bench_framebuffer_bytes(scene.draw_list.target);
            row.vertex_bytes = bench_vertex_data_bytes(scene.draw_list);
            rows.push_back(row);
        }
        BenchRow& row = rows.back();
        {
            // The pixels the triangles cover (before the depth test): what Mpix/s counts.
            refraster::RenderOptions count = first;
            count.stop_after = refraster::RenderStage::Raster;
            refraster::Framebuffer scratch;
            row.pixels =
                static_cast<double>(refraster::render(scene.draw_list, count, scratch).fragments);
        }
        log << name << ": " << row.triangles << " triangles covering " << std::fixed
            << std::setprecision(1) << row.pixels / 1e6 << " Mpx, generated in " << ms_since(t0)
            << " ms\n"
            << std::flush;
        // softpipe is timed only, and not on the scaling workloads (their point is the
        // reference's rate against its own at the standard size).
        std::vector<bool> active(configs.size(), true);
        for (std::size_t c = 0; c < configs.size(); ++c)
            active[c] = !(configs[c].label == "softpipe" && bench_scaling_counterpart(name));
        // Warm-up: one untimed render in every GL worker (context, framebuffer objects, shader
        // compilation, first upload).
        for (std::size_t c = 0; c < backends.size(); ++c) {
            if (!active[c]) continue;
            const auto r = backends[c]->render(scene);
            if (r.status != RenderStatus::Ok) throw failed(name, configs[c].label, r);
            if (configs[c].label == "llvmpipe_t0" && report.gl_renderer.empty()) {
                const auto value = [&](const char* key) {
                    const auto it = r.provenance.find(key);
                    return it == r.provenance.end() ? std::string() : it->second;
                };
                report.gl_renderer = value("renderer");
                report.gl_version = value("gl_version");
                report.mesa_version = value("mesa_version");
            }
        }
        std::vector<double> ref_ms, ref2_ms;
        std::map<std::string, std::vector<double>> gl_ms;
        std::vector<std::vector<double>> stage_ms(4);
        std::size_t heap_peak = 0, heap2_peak = 0;
        for (int round = 0; round < options.rounds; ++round) {
            // Interleaved: every renderer once a round, so that the machine's load shifts
            // every column alike.
            refraster::Framebuffer ref;
            reset_heap_peak();
            auto s0 = std::chrono::steady_clock::now();
            (void)refraster::render(scene.draw_list, first, ref);
            ref_ms.push_back(ms_since(s0));
            heap_peak = std::max(heap_peak, heap_peak_bytes());
            std::optional<refraster::Framebuffer> ref2;
            if (second) {
                ref2.emplace();
                reset_heap_peak();
                s0 = std::chrono::steady_clock::now();
                (void)refraster::render(scene.draw_list, *second, *ref2);
                ref2_ms.push_back(ms_since(s0));
                heap2_peak = std::max(heap2_peak, heap_peak_bytes());
            }
            // The split: the first configuration stopped after each stage; a stage's time is
            // the difference of the medians.
            for (std::size_t k = 0; k + 1 < std::size(stages); ++k) {
                refraster::Framebuffer partial;
                refraster::RenderOptions ro = first;
                ro.stop_after = stages[k];
                s0 = std::chrono::steady_clock::now();
                (void)refraster::render(scene.draw_list, ro, partial);
                stage_ms[k].push_back(ms_since(s0));
            }
            stage_ms[3].push_back(ref_ms.back());
            std::optional<refraster::Framebuffer> single;
            for (std::size_t c = 0; c < backends.size(); ++c) {
                if (!active[c]) continue;
                auto r = backends[c]->render(scene);
                if (r.status != RenderStatus::Ok) throw failed(name, configs[c].label, r);
                gl_ms[configs[c].label].push_back(r.seconds * 1000.0);
                const std::string in_round = " in round " + std::to_string(round + 1);
                if (configs[c].label == "llvmpipe_t0") {
                    single = std::move(r.image);
                    if (!(ref == *single)) {
                        throw std::runtime_error(
                            "bench " + name + ": the reference's image (" +
                            std::to_string(first.threads) +
                            " threads) differs from llvmpipe's (LP_NUM_THREADS=0)" + in_round);
                    }
                    if (ref2 && !(*ref2 == *single)) {
                        throw std::runtime_error(
                            "bench " + name + ": the reference's image (" +
                            std::to_string(second->threads) +
                            " threads) differs from llvmpipe's (LP_NUM_THREADS=0)" + in_round);
                    }
                } else if (configs[c].compared && single && !(r.image == *single)) {
                    throw std::runtime_error("bench " + name +
                                             ": llvmpipe with threads differs from "
                                             "LP_NUM_THREADS=0" +
                                             in_round);
                }
            }
            log << "  round " << round + 1 << ": ref " << ref_ms.back() << " ms";
            if (second) log << ", ref " << second->threads << "T " << ref2_ms.back() << " ms";
            for (std::size_t c = 0; c < configs.size(); ++c)
                if (active[c])
                    log << ", " << configs[c].label << " " << gl_ms[configs[c].label].back()
                        << " ms";
            log << "\n" << std::flush;
        }
        row.ref_ms = median(ref_ms);
        if (second) row.ref2_ms = median(ref2_ms);
        row.ref_heap_peak_mb = static_cast<double>(heap_peak) / (1024.0 * 1024.0);
        if (second) row.ref2_heap_peak_mb = static_cast<double>(heap2_peak) / (1024.0 * 1024.0);
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
    return report;
}

constexpr double kMiB = 1024.0 * 1024.0;

double BenchRow::heap_bound_mb() const {
    return static_cast<double>(2 * framebuffer_bytes + vertex_bytes) / kMiB;
}

double BenchRow::heap_peak_mb() const {
    return std::max(ref_heap_peak_mb, ref2_heap_peak_mb.value_or(0.0));
}

std::optional<double> BenchRow::speedup() const {
    if (!llvmpipe_t0_ms || !(ref_ms > 0.0)) return std::nullopt;
    return *llvmpipe_t0_ms / ref_ms;
}

std::optional<double> BenchRow::speedup2() const {
    if (!llvmpipe_ms || !ref2_ms || !(*ref2_ms > 0.0)) return std::nullopt;
    return *llvmpipe_ms / *ref2_ms;
}

std::optional<double> bench_speed_target(const std::string& scene) {
    if (scene == "tiny-flat" || scene == "tiny-smooth") return 3.0;
    if (scene == "medium-flat" || scene == "medium-smooth") return 2.0;
    if (scene == "full-flat") return 2.0;
    if (scene == "full-smooth" || scene == "medium-perspective" || scene == "full-perspective")
        return 1.5;
    return std::nullopt;
}

double bench_rate(const BenchRow& row) {
    if (!(row.ref_ms > 0.0)) return 0.0;
    const double count =
        row.name.starts_with("tiny") ? static_cast<double>(row.triangles) : row.pixels;
    return count / (row.ref_ms * 1000.0);
}

std::optional<double> bench_rate_ratio(const BenchRow& row, const std::vector<BenchRow>& rows) {
    const auto counterpart = bench_scaling_counterpart(row.name);
    if (!counterpart) return std::nullopt;
    for (const auto& r : rows) {
        if (r.name != *counterpart) continue;
        const double base = bench_rate(r);
        if (!(base > 0.0)) return std::nullopt;
        return bench_rate(row) / base;
    }
    return std::nullopt;
}

std::vector<BenchTarget> bench_targets(const std::vector<BenchRow>& rows) {
    std::vector<BenchTarget> targets;
    for (const auto& r : rows) {
        if (const auto t = bench_speed_target(r.name)) {
            targets.push_back({r.name, "speed", r.speedup(), *t, false, true});
            targets.push_back({r.name, "speed 2T", r.speedup2(), *t, false, false});
        }
        if (bench_scaling_counterpart(r.name)) {
            targets.push_back({r.name, "linearity", bench_rate_ratio(r, rows),
                               kBenchLinearityTarget, false, true});
        }
        targets.push_back({r.name, "heap", r.heap_peak_mb(), r.heap_bound_mb(), true, true});
    }
    return targets;
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

namespace {

std::string target_value(const BenchTarget& t) {
    return t.value ? fixed(*t.value, 2) : std::string("-");
}

std::string target_word(const BenchTarget& t) {
    return !t.value ? "not measured" : t.met() ? "met" : "missed";
}

std::string ref_label(unsigned threads) {
    return threads == 1   ? "1 thread"
           : threads == 0 ? "one thread per core"
                          : std::to_string(threads) + " threads";
}

}  // namespace

std::string bench_table(const BenchReport& report) {
    const auto& rows = report.rows;
    const auto& opt_in = report.options;
    std::ostringstream o;
    const auto rate = [](double count, double ms) {
        return ms > 0.0 ? count / (ms * 1000.0) : 0.0;
    };  // millions a second
    o << "kernels " << report.kernels << " (asked: " << refraster::to_string(opt_in.kernels)
      << "); ref: " << ref_label(opt_in.threads) << "; ref 2T: "
      << (opt_in.second_threads > 0 ? ref_label(opt_in.second_threads) : std::string("off"))
      << "; profile " << opt_in.profile.name << "; cpu " << report.cpu_flags << "; commit "
      << report.commit << "; " << report.date;
    if (!report.gl_renderer.empty())
        o << "; " << report.gl_renderer << ", Mesa " << report.mesa_version;
    o << "\n\n";
    o << "| scene | triangles | Mpx | ref ms | ref Mtri/s | ref Mpix/s | ref 2T ms | llvmpipe t0 "
         "ms "
         "| Mtri/s | Mpix/s | llvmpipe ms | softpipe ms | ref / llvmpipe t0 | ref 2T / llvmpipe "
         "| rate ratio | ref heap MB | heap bound MB | heap | load | setup | raster | fragment |\n"
      << "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | "
         "---: | ---: | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: |\n";
    const auto opt = [](const std::optional<double>& v, int digits = 1) {
        return v ? fixed(*v, digits) : std::string("-");
    };
    for (const auto& r : rows) {
        const double tris = static_cast<double>(r.triangles);
        const double heap = r.heap_peak_mb(), bound = r.heap_bound_mb();
        o << "| " << r.name << " | " << r.triangles << " | " << fixed(r.pixels / 1e6, 1) << " | "
          << fixed(r.ref_ms, 1) << " | " << fixed(rate(tris, r.ref_ms), 2) << " | "
          << fixed(rate(r.pixels, r.ref_ms), 1) << " | " << opt(r.ref2_ms) << " | "
          << opt(r.llvmpipe_t0_ms) << " | "
          << (r.llvmpipe_t0_ms ? fixed(rate(tris, *r.llvmpipe_t0_ms), 2) : "-") << " | "
          << (r.llvmpipe_t0_ms ? fixed(rate(r.pixels, *r.llvmpipe_t0_ms), 1) : "-") << " | "
          << opt(r.llvmpipe_ms) << " | " << opt(r.softpipe_ms) << " | " << opt(r.speedup(), 2)
          << " | " << opt(r.speedup2(), 2) << " | " << opt(bench_rate_ratio(r, rows), 2) << " | "
          << fixed(heap, 1) << " | " << fixed(bound, 1) << " | "
          << (heap <= bound ? "within" : "over") << " | " << fixed(r.split.load, 1) << " | "
          << fixed(r.split.setup, 1) << " | " << fixed(r.split.raster, 1) << " | "
          << fixed(r.split.fragment, 1) << " |\n";
    }
    o << "\nref / llvmpipe t0: the reference's speed over single-threaded llvmpipe's (above 1: the "
         "reference is faster); ref 2T / llvmpipe: the second reference configuration's over "
         "llvmpipe's with its default threads; rate ratio: a scaling workload's rate (Mtri/s for "
         "tiny, Mpix/s for full) over its standard counterpart's; heap bound: twice the "
         "framebuffer plus the scene's vertex data. Medians; times in ms; the split is the "
         "reference's.\n";

    // The summary: the required targets on one line, the 2-thread ratios (reported) on another.
    const auto targets = bench_targets(rows);
    std::size_t met = 0, required = 0, heap_rows = 0, heap_within = 0;
    std::string line, reported, heap_over;
    for (const auto& t : targets) {
        if (t.what == "heap") {
            ++heap_rows;
            if (t.met())
                ++heap_within;
            else
                heap_over += (heap_over.empty() ? "" : ", ") + t.scene;
        } else if (t.required) {
            line += (line.empty() ? "" : ", ") + t.scene +
                    (t.what == "linearity" ? " rate " : " ") + target_value(t) + "/" +
                    fixed(t.target, 1) + " " + target_word(t);
        } else {
            reported += (reported.empty() ? "" : ", ") + t.scene + " " + target_value(t) + "/" +
                        fixed(t.target, 1) + " " + target_word(t);
        }
        if (t.required) {
            ++required;
            if (t.met()) ++met;
        }
    }
    o << "\ntargets: " << line << (line.empty() ? "" : "; ") << "heap within bound on "
      << heap_within << " of " << heap_rows
      << (heap_over.empty() ? "" : " (over: " + heap_over + ")") << "; " << met << " of "
      << required << " met\n";
    if (!reported.empty()) o << "reported, not required (ref 2T / llvmpipe): " << reported << "\n";
    return o.str();
}

std::string bench_json(const BenchReport& report) {
    const auto& rows = report.rows;
    nlohmann::ordered_json j;
    const auto opt = [](const std::optional<double>& v) {
        return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json();
    };
    const auto& o = report.options;
    j["bench"] = {{"rounds", o.rounds},
                  {"scale", o.scale},
                  {"seed", o.seed},
                  {"scaling", o.scaling},
                  {"gl", o.gl},
                  {"softpipe", o.gl && o.softpipe},
                  {"profile", o.profile.name},
                  {"kernels_asked", std::string(refraster::to_string(o.kernels))},
                  {"kernels", report.kernels},
                  {"threads", o.threads},
                  {"second_threads", o.second_threads}};
    j["host"] = {{"cpu_flags", report.cpu_flags},
                 {"commit", report.commit},
                 {"date", report.date},
                 {"gl_renderer", report.gl_renderer},
                 {"gl_version", report.gl_version},
                 {"mesa_version", report.mesa_version}};
    auto& scenes = j["scenes"] = nlohmann::ordered_json::array();
    for (const auto& r : rows) {
        nlohmann::ordered_json s;
        s["name"] = r.name;
        s["triangles"] = r.triangles;
        s["pixels"] = r.pixels;
        s["ref_ms"] = r.ref_ms;
        s["ref2_ms"] = opt(r.ref2_ms);
        s["llvmpipe_t0_ms"] = opt(r.llvmpipe_t0_ms);
        s["llvmpipe_ms"] = opt(r.llvmpipe_ms);
        s["softpipe_ms"] = opt(r.softpipe_ms);
        s["speedup_vs_llvmpipe_t0"] = opt(r.speedup());
        s["speedup_2t_vs_llvmpipe"] = opt(r.speedup2());
        s["rate"] = bench_rate(r);
        s["rate_unit"] = r.name.starts_with("tiny") ? "Mtri/s" : "Mpix/s";
        const auto counterpart = bench_scaling_counterpart(r.name);
        s["counterpart"] =
            counterpart ? nlohmann::ordered_json(*counterpart) : nlohmann::ordered_json();
        s["rate_ratio"] = opt(bench_rate_ratio(r, rows));
        s["ref_heap_peak_mb"] = r.ref_heap_peak_mb;
        s["ref2_heap_peak_mb"] = opt(r.ref2_heap_peak_mb);
        s["framebuffer_bytes"] = r.framebuffer_bytes;
        s["vertex_bytes"] = r.vertex_bytes;
        s["heap_bound_mb"] = r.heap_bound_mb();
        s["heap_within_bound"] = r.heap_peak_mb() <= r.heap_bound_mb();
        s["split_ms"] = {{"load", r.split.load},
                         {"setup", r.split.setup},
                         {"raster", r.split.raster},
                         {"fragment", r.split.fragment}};
        scenes.push_back(s);
    }
    auto& t = j["targets"];
    std::size_t met = 0, missed = 0, unmeasured = 0;
    auto& checks = t["checks"] = nlohmann::ordered_json::array();
    for (const auto& target : bench_targets(rows)) {
        checks.push_back({{"scene", target.scene},
                          {"what", target.what},
                          {"value", opt(target.value)},
                          {"comparison", target.at_most ? "<=" : ">="},
                          {"target", target.target},
                          {"required", target.required},
                          {"met", target.met()}});
        if (!target.required) continue;
        if (!target.value)
            ++unmeasured;
        else if (target.met())
            ++met;
        else
            ++missed;
    }
    t["met"] = met;
    t["missed"] = missed;
    t["not_measured"] = unmeasured;
    t["all_met"] = missed == 0 && unmeasured == 0;
    return j.dump(1) + "\n";
}

}  // namespace harness
