#include "harness/bench.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <ostream>
#include <random>
#include <sstream>
#include <stdexcept>

#include "../backends/thread_pin.hpp"
#include "harness/backend.hpp"
#include "harness/files.hpp"
#include "harness/scene.hpp"
#include "harness/scene_text.hpp"
#include "refraster/framebuffer.hpp"
#include "refraster/profile.hpp"
#include "refraster/renderer.hpp"

namespace harness {

namespace {

// What a workload draws.
enum class Kind : std::uint8_t {
    Triangles,  // one draw of independent triangles, each with one random depth
    Allpass,    // full-screen layers, each nearer than the one before: every layer passes
    Lines,      // independent lines, one draw per integer width
    Points,     // points, one draw per integer size
    Polygons,   // one polygon a draw, filled by a rule
};

struct Spec {
    Kind kind = Kind::Triangles;
    std::size_t count = 0;                  // primitives at scale 1
    double min_area = 0.0, max_area = 0.0;  // pixels; 0 for full-screen triangles
    std::uint32_t size = 1024;              // the target: size x size rgba8, z24
    refraster::ShadeModel shade = refraster::ShadeModel::Smooth;
    bool perspective = false;
    // Textured workloads: a 256x256 texture with generated mipmaps, wrapped with repeat, sampled
    // with this min filter and `mag` at about two texels a pixel, modulating the colour.
    std::optional<refraster::TextureFilter> texture = std::nullopt;
    refraster::TextureFilter mag = refraster::TextureFilter::Linear;
    std::uint32_t samples = 1;  // 4: a multisampled target, resolved as glBlitFramebuffer does
    // Lines: widths, points: sizes, whole pixels from `min_width` to `max_width`.
    int min_width = 1, max_width = 1;
    std::optional<refraster::FillRule> fill_rule = std::nullopt;  // polygons
};

std::optional<Spec> spec_of(const std::string& name) {
    using refraster::TextureFilter;
    constexpr auto flat = refraster::ShadeModel::Flat;
    const auto triangles = [](std::size_t count, double min_area, double max_area) {
        Spec s;
        s.count = count;
        s.min_area = min_area;
        s.max_area = max_area;
        return s;
    };
    const auto tiny = [&] { return triangles(1'000'000, 2.0, 10.0); };
    const auto medium = [&] { return triangles(100'000, 100.0, 500.0); };
    const auto full = [&] { return triangles(200, 0.0, 0.0); };
    const auto with = [](Spec s, auto&& change) {
        change(s);
        return s;
    };
    const auto shaded = [&](Spec s, refraster::ShadeModel m) {
        return with(s, [&](Spec& x) { x.shade = m; });
    };
    const auto perspective = [&](Spec s) { return with(s, [](Spec& x) { x.perspective = true; }); };
    const auto textured = [&](Spec s, TextureFilter min, TextureFilter mag) {
        return with(s, [&](Spec& x) {
            x.texture = min;
            x.mag = mag;
        });
    };
    const auto sampled4 = [&](Spec s) { return with(s, [](Spec& x) { x.samples = 4; }); };
    const auto kind = [&](Kind k, std::size_t count, int min_width, int max_width) {
        Spec s;
        s.kind = k;
        s.count = count;
        s.min_width = min_width;
        s.max_width = max_width;
        return s;
    };
    const auto polygons = [&](refraster::FillRule rule) {
        Spec s;
        s.kind = Kind::Polygons;
        s.count = 10'000;
        s.min_area = 100.0;
        s.max_area = 2000.0;
        s.fill_rule = rule;
        return s;
    };
    const auto allpass = [&](refraster::ShadeModel m) {
        return with(full(), [&](Spec& x) {
            x.kind = Kind::Allpass;
            x.shade = m;
        });
    };
    const auto sized = [&](Spec s, std::uint32_t size) {
        return with(s, [&](Spec& x) { x.size = size; });
    };
    static const std::map<std::string, Spec> specs{
        {"tiny-flat", shaded(tiny(), flat)},
        {"tiny-smooth", tiny()},
        {"medium-flat", shaded(medium(), flat)},
        {"medium-smooth", medium()},
        {"full-flat", shaded(full(), flat)},
        {"full-smooth", full()},
        {"medium-perspective", perspective(medium())},
        {"full-perspective", perspective(full())},
        {"medium-textured-bilinear",
         textured(medium(), TextureFilter::Linear, TextureFilter::Linear)},
        {"medium-textured-trilinear",
         textured(medium(), TextureFilter::LinearMipmapLinear, TextureFilter::Linear)},
        {"medium-textured-nearest",
         textured(medium(), TextureFilter::Nearest, TextureFilter::Nearest)},
        {"full-textured-bilinear", textured(full(), TextureFilter::Linear, TextureFilter::Linear)},
        {"full-textured-trilinear",
         textured(full(), TextureFilter::LinearMipmapLinear, TextureFilter::Linear)},
        {"full-textured-perspective",
         textured(perspective(full()), TextureFilter::Linear, TextureFilter::Linear)},
        {"medium-smooth-4x", sampled4(medium())},
        {"full-smooth-4x", sampled4(full())},
        {"lines", kind(Kind::Lines, 100'000, 1, 1)},
        {"wide-lines", kind(Kind::Lines, 100'000, 2, 10)},
        {"lines-4x", sampled4(kind(Kind::Lines, 100'000, 1, 3))},
        {"points", kind(Kind::Points, 100'000, 1, 8)},
        {"points-4x", sampled4(kind(Kind::Points, 100'000, 1, 8))},
        {"polygons-nonzero", polygons(refraster::FillRule::NonZero)},
        {"polygons-evenodd", polygons(refraster::FillRule::EvenOdd)},
        {"full-flat-allpass", allpass(flat)},
        {"full-smooth-allpass", allpass(refraster::ShadeModel::Smooth)},
        {"tiny-flat-4m", with(shaded(tiny(), flat), [](Spec& x) { x.count = 4'000'000; })},
        {"full-flat-2048", sized(shaded(full(), flat), 2048)},
        {"full-smooth-2048", sized(full(), 2048)},
    };
    const auto it = specs.find(name);
    if (it == specs.end()) return std::nullopt;
    return it->second;
}

constexpr std::string_view kSoftpipePrefix = "softpipe-";

refraster::Draw base_draw(const Spec& shape) {
    refraster::Draw d;
    const auto size = static_cast<std::int32_t>(shape.size);
    d.state.viewport = {0, 0, size, size};
    d.state.depth_test = refraster::CompareFunc::Less;
    d.state.shade = shape.shade;
    d.vertices.attributes = {{"color", 4}};
    return d;
}

void push_vertex(refraster::Draw& d, double x, double y, double z, double w, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (double c : {x * w, y * w, z * w, w}) d.vertices.data.push_back(static_cast<float>(c));
    for (int c = 0; c < 3; ++c) d.vertices.data.push_back(static_cast<float>(u(rng)));
    d.vertices.data.push_back(1.0f);
}

// Lines and points: `count` primitives of random places and colours (one random depth each),
// drawn by one draw per integer width (size), in increasing order.
void add_lines_or_points(refraster::DrawList& list, const Spec& shape, std::size_t count,
                         std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const bool lines = shape.kind == Kind::Lines;
    const int widths = shape.max_width - shape.min_width + 1;
    std::vector<refraster::Draw> draws;
    for (int k = 0; k < widths; ++k) {
        auto d = base_draw(shape);
        d.primitive = lines ? refraster::PrimitiveType::Lines : refraster::PrimitiveType::Points;
        const auto width = static_cast<float>(shape.min_width + k);
        (lines ? d.state.line_width : d.state.point_size) = width;
        draws.push_back(std::move(d));
    }
    const double size = shape.size;
    const auto ndc = [&](double v) { return v / size * 2.0 - 1.0; };
    for (std::size_t i = 0; i < count; ++i) {
        const auto k = std::min<std::size_t>(static_cast<std::size_t>(u(rng) * widths),
                                             static_cast<std::size_t>(widths - 1));
        auto& d = draws[k];
        const double x = u(rng) * size, y = u(rng) * size;
        const double z = 2.0 * u(rng) - 1.0;
        push_vertex(d, ndc(x), ndc(y), z, 1.0, rng);
        if (lines) {
            // From a few pixels to about 50, in any direction.
            const double length = 3.0 + 47.0 * u(rng);
            const double angle = 2.0 * std::numbers::pi * u(rng);
            push_vertex(d, ndc(x + length * std::cos(angle)), ndc(y + length * std::sin(angle)), z,
                        1.0, rng);
        }
    }
    for (auto& d : draws)
        if (!d.vertices.data.empty()) list.draws.push_back(std::move(d));
}

// Polygons: star-like outlines of 8 to 64 vertices around a random centre, their radii such
// that the disc they scatter over has from `min_area` to `max_area` pixels; every second one
// takes its vertices in a random order of angles, so that its outline crosses itself. One draw
// a polygon (a fill rule fills one polygon), each with one random depth.
void add_polygons(refraster::DrawList& list, const Spec& shape, std::size_t count,
                  std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double size = shape.size;
    const auto ndc = [&](double v) { return v / size * 2.0 - 1.0; };
    for (std::size_t i = 0; i < count; ++i) {
        auto d = base_draw(shape);
        d.primitive = refraster::PrimitiveType::Polygon;
        d.state.fill_rule = shape.fill_rule;
        const auto n = 8 + std::min<std::size_t>(static_cast<std::size_t>(u(rng) * 57), 56);
        const double area = shape.min_area + (shape.max_area - shape.min_area) * u(rng);
        const double radius = std::sqrt(area / std::numbers::pi);
        const double cx = u(rng) * size, cy = u(rng) * size;
        const double z = 2.0 * u(rng) - 1.0;
        const bool crossing = i % 2 == 1;
        std::vector<double> angles(n);
        for (std::size_t k = 0; k < n; ++k)
            angles[k] = crossing ? 2.0 * std::numbers::pi * u(rng)
                                 : 2.0 * std::numbers::pi * (static_cast<double>(k) + u(rng)) /
                                       static_cast<double>(n);
        d.vertices.data.reserve(n * 8);
        for (std::size_t k = 0; k < n; ++k) {
            // Alternate long and short spokes: a star.
            const double r = radius * (k % 2 == 0 ? 0.7 + 0.3 * u(rng) : 0.2 + 0.3 * u(rng));
            push_vertex(d, ndc(cx + r * std::cos(angles[k])), ndc(cy + r * std::sin(angles[k])), z,
                        1.0, rng);
        }
        list.draws.push_back(std::move(d));
    }
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
                                                "medium-textured-trilinear",
                                                "medium-textured-nearest",
                                                "full-textured-bilinear",
                                                "full-textured-trilinear",
                                                "full-textured-perspective",
                                                "medium-smooth-4x",
                                                "full-smooth-4x",
                                                "lines",
                                                "wide-lines",
                                                "lines-4x",
                                                "points",
                                                "points-4x",
                                                "polygons-nonzero",
                                                "polygons-evenodd",
                                                "full-flat-allpass",
                                                "full-smooth-allpass",
                                                "softpipe-medium-smooth",
                                                "softpipe-tiny-flat",
                                                "softpipe-medium-textured-bilinear"};
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

std::optional<std::string> bench_softpipe_counterpart(const std::string& name) {
    if (!name.starts_with(kSoftpipePrefix)) return std::nullopt;
    std::string rest = name.substr(kSoftpipePrefix.size());
    if (!spec_of(rest)) return std::nullopt;
    return rest;
}

BenchWorkload make_bench_workload(const std::string& name, std::uint64_t seed, double scale) {
    // A softpipe row draws its counterpart's scene, from the same seed.
    const auto softpipe_of = bench_softpipe_counterpart(name);
    const std::string& scene = softpipe_of ? *softpipe_of : name;
    const auto spec = spec_of(scene);
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
    w.primitive = shape.kind == Kind::Lines      ? "lines"
                  : shape.kind == Kind::Points   ? "points"
                  : shape.kind == Kind::Polygons ? "polygons"
                                                 : "triangles";
    w.list.target = {size, size, refraster::ColorFormat::Rgba8, refraster::DepthFormat::Z24,
                     shape.samples};
    w.list.clear.color = {0.0f, 0.0f, 0.0f, 1.0f};
    w.list.clear.depth = 1.0f;
    std::mt19937_64 rng(seed ^ std::hash<std::string>{}(scene));
    if (shape.kind == Kind::Lines || shape.kind == Kind::Points) {
        add_lines_or_points(w.list, shape, count, rng);
        return w;
    }
    if (shape.kind == Kind::Polygons) {
        add_polygons(w.list, shape, count, rng);
        return w;
    }
    refraster::Draw d = base_draw(shape);
    d.primitive = refraster::PrimitiveType::Triangles;
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
        refraster::TextureState ts;  // wrap: repeat in s and t
        ts.min_filter = *shape.texture;
        ts.mag_filter = shape.mag;
        d.state.texture = ts;
    }
    d.vertices.data.reserve(count * 3 * (textured ? 12 : 8));

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
        double z = 2.0 * u(rng) - 1.0;  // one depth a triangle: later ones pass or fail
        // Allpass: layer i at 1 - 2 (i + 1) / (count + 1) in NDC, each nearer than the last by
        // 1 / (count + 1) of the depth range, far more than z24's step: every layer passes.
        if (shape.kind == Kind::Allpass)
            z = 1.0 - 2.0 * static_cast<double>(i + 1) / static_cast<double>(count + 1);
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
    bool compared;    // byte-compared with llvmpipe_t0
    bool one_thread;  // runs on the bench's CPU (BenchOptions::pin)
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

// A render as the comparison sees it: the image (a 4x target's resolve) and, for a 4x target,
// every sample.
struct Rendered {
    refraster::Framebuffer image;
    refraster::Framebuffer samples;  // 0 x 0 for a single-sample target
};

// What differs between two renders ("image" or "samples"), or nothing when both are the same
// bytes.
std::optional<std::string> difference(const Rendered& a, const Rendered& b) {
    if (!(a.image == b.image)) return "image";
    if (!(a.samples == b.samples)) return "samples";
    return std::nullopt;
}

}  // namespace

SceneFile bench_scene_file(const std::string& name, const refraster::DrawList& list) {
    SceneFile f;
    f.name = name;
    f.target = list.target;
    f.clear = list.clear;
    const auto texture_name = [](std::size_t i) {
        // Zero-padded, so that the file's name order is the draw list's index order.
        const std::string n = std::to_string(i);
        return "t" + std::string(6 - std::min<std::size_t>(6, n.size()), '0') + n;
    };
    for (std::size_t i = 0; i < list.textures.size(); ++i)
        f.textures[texture_name(i)] = list.textures[i];
    bool polygons = false;
    for (const auto& d : list.draws) {
        SceneDraw sd;
        sd.primitive = d.primitive;
        sd.space = VertexSpace::Clip;
        sd.state = d.state;
        if (d.state.texture) sd.texture = texture_name(d.state.texture->texture);
        polygons = polygons || d.primitive == refraster::PrimitiveType::Polygon ||
                   d.state.fill_rule.has_value();
        const auto colour = d.vertices.attributes.size() > 0 ? d.vertices.attribute_offset(0) : 0;
        const auto texcoord = d.vertices.attributes.size() > 1 ? d.vertices.attribute_offset(1) : 0;
        sd.vertices.reserve(d.vertices.size());
        for (std::size_t v = 0; v < d.vertices.size(); ++v) {
            const auto rec = d.vertices.vertex(v);
            SceneVertex sv;
            sv.position_size = 4;
            for (std::size_t k = 0; k < 4; ++k) {
                sv.position[k] = rec[k];
                if (colour) sv.color[k] = rec[colour + k];
                if (texcoord) sv.texcoord[k] = rec[texcoord + k];
            }
            sd.vertices.push_back(sv);
        }
        sd.indices = d.indices;
        f.draws.push_back(std::move(sd));
    }
    if (polygons) f.requires_extensions.emplace_back("polygons");
    return f;
}

namespace {

// A whole process's wall and CPU time (its own and its waited-for children's, wait4's
// rusage), or the first line of what it wrote to stderr when it failed.
struct ProcessTime {
    double wall_ms = 0.0, cpu_ms = 0.0;
    std::string failure;  // empty: exit status 0
};

ProcessTime time_process(const std::vector<std::string>& argv,
                         const std::vector<std::string>& set_environment,
                         const std::filesystem::path& errors) {
    std::vector<std::string> env;
    for (char** e = environ; *e; ++e) {
        const std::string_view entry(*e);
        bool replaced = false;
        for (const auto& s : set_environment)
            replaced = replaced || entry.substr(0, s.find('=') + 1) == s.substr(0, s.find('=') + 1);
        if (!replaced) env.emplace_back(entry);
    }
    env.insert(env.end(), set_environment.begin(), set_environment.end());
    std::vector<char*> args, envp;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    for (const auto& e : env) envp.push_back(const_cast<char*>(e.c_str()));
    envp.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, errors.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0600);
    ProcessTime t;
    const auto t0 = std::chrono::steady_clock::now();
    pid_t pid = 0;
    const int spawned =
        posix_spawn(&pid, argv.front().c_str(), &actions, nullptr, args.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) {
        t.failure = argv.front() + ": cannot start: " + std::strerror(spawned);
        return t;
    }
    int status = 0;
    rusage usage{};
    while (wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
    }
    t.wall_ms = ms_since(t0);
    const auto ms = [](const timeval& v) {
        return static_cast<double>(v.tv_sec) * 1000.0 + static_cast<double>(v.tv_usec) / 1000.0;
    };
    t.cpu_ms = ms(usage.ru_utime) + ms(usage.ru_stime);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::ifstream in(errors);
        std::string line;
        std::getline(in, line);
        t.failure = (WIFEXITED(status) ? "exit " + std::to_string(WEXITSTATUS(status))
                                       : std::string("killed by a signal")) +
                    (line.empty() ? "" : ": " + line);
    }
    return t;
}

std::string file_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A directory of its own under the system's temporary one, removed with everything in it.
struct TemporaryDirectory {
    std::filesystem::path path;
    TemporaryDirectory() {
        std::string pattern =
            (std::filesystem::temp_directory_path() / "refraster-bench-XXXXXX").string();
        if (!mkdtemp(pattern.data()))
            throw std::runtime_error("bench: cannot make a temporary directory: " +
                                     std::string(std::strerror(errno)));
        path = pattern;
    }
    ~TemporaryDirectory() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
    TemporaryDirectory(const TemporaryDirectory&) = delete;
    TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
};

}  // namespace

BenchReport run_bench(const BenchOptions& options, std::ostream& log) {
    const std::vector<std::string> names = bench_run_names(options);
    for (const auto& n : names)
        (void)make_bench_workload(n, options.seed, 1e-9);  // unknown names fail first
    if (options.rounds < 1) throw std::invalid_argument("bench needs at least one round");

    BenchReport report;
    report.options = options;
    // The CPU every single-threaded render runs on: the reference's first configuration when
    // it has one thread, llvmpipe with LP_NUM_THREADS=0, softpipe and the process runs.
    std::optional<int> cpu;
    if (options.pin) {
        const std::vector<int> allowed = detail::allowed_cpus();
        if (allowed.empty()) throw std::runtime_error("bench: this process may run on no CPU");
        cpu = options.pin_cpu.value_or(allowed.front());
        {
            const detail::ThreadPin check(cpu);  // a CPU this process may not run on: bad input
        }
    }
    report.pinned_cpu = cpu.value_or(-1);
    // The CPU a render of `threads` threads runs on: the bench's for one thread, else any.
    const auto cpu_for = [&](unsigned threads) { return threads == 1 ? cpu : std::nullopt; };
    report.kernels =
        std::string(refraster::to_string(refraster::resolve_kernel_path(options.kernels)));
    report.cpu_flags = bench_cpu_flags();
    report.commit = host_provenance()["commit"];
    report.date = utc_now();

    // Whole processes: a scene file per workload in a directory of the run's own.
    std::unique_ptr<TemporaryDirectory> process_dir;
    if (options.process) {
        if (options.refraster_path.empty())
            throw std::invalid_argument("bench --process needs the refraster executable's path");
        const auto builtin = refraster::builtin_profile_names();
        if (std::find(builtin.begin(), builtin.end(), options.profile.name) == builtin.end() ||
            !(refraster::builtin_profile(options.profile.name) == options.profile))
            throw std::invalid_argument(
                "bench --process runs `refraster render --profile NAME`, "
                "so it needs a built-in profile, not \"" +
                options.profile.name + "\"");
        process_dir = std::make_unique<TemporaryDirectory>();
    }

    std::vector<GlConfig> configs;
    std::vector<std::unique_ptr<Backend>> backends;
    if (options.gl) {
        configs = {{"llvmpipe_t0", Driver::Llvmpipe, {"LP_NUM_THREADS=0"}, true, true},
                   {"llvmpipe", Driver::Llvmpipe, {}, true, false}};
        if (options.softpipe) configs.push_back({"softpipe", Driver::Softpipe, {}, false, true});
        for (const auto& c : configs) {
            BackendOptions o;
            o.kind = BackendKind::OSMesa;
            o.driver = c.driver;
            o.environment = c.environment;
            o.timeout_seconds = options.timeout_seconds;
            if (c.one_thread) o.cpu = cpu;
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
        // A softpipe row: the reference under softpipe's rules, compared with softpipe alone.
        const bool softpipe_row = bench_softpipe_counterpart(name).has_value();
        refraster::RenderOptions row_first = first;
        std::optional<refraster::RenderOptions> row_second = second;
        if (softpipe_row) {
            row_first.profile = refraster::softpipe_22_3_profile();
            if (row_second) row_second->profile = row_first.profile;
        }
        Scene scene;
        {
            auto w = make_bench_workload(name, options.seed, options.scale);
            scene.draw_list = std::move(w.list);
            scene.file.name = "bench." + name;
            BenchRow row;
            row.name = name;
            row.triangles = w.triangles;
            row.primitive = w.primitive;
            row.framebuffer_bytes = bench_framebuffer_bytes(scene.draw_list.target);
            row.vertex_bytes = bench_vertex_data_bytes(scene.draw_list);
            rows.push_back(row);
        }
        BenchRow& row = rows.back();
        // The reference's render as the GL backends return theirs: a 4x target's resolve as the
        // image and every sample beside it. The resolve is part of the timed render, as the
        // GL worker's glBlitFramebuffer is of its own.
        const auto render_ref = [&](const refraster::RenderOptions& ro, Rendered& out) {
            // One thread on the bench's CPU; more wherever the system puts them (the band
            // workers inherit the calling thread's affinity).
            const detail::ThreadPin pin(cpu_for(ro.threads));
            const auto s0 = std::chrono::steady_clock::now();
            const auto outcome = refraster::render(scene.draw_list, ro, out.image);
            if (out.image.samples > 1) {
                out.samples = std::move(out.image);
                out.image = refraster::resolve_samples(out.samples);
            }
            const double ms = ms_since(s0);
            if (outcome.status != refraster::RenderStatus::Ok)
                throw std::runtime_error("bench " + name + ": the reference (" + ro.profile.name +
                                         ", " + std::to_string(ro.threads) +
                                         " threads): " + outcome.message);
            return ms;
        };
        {
            // The pixels the primitives cover (before the depth test): what Mpix/s counts.
            refraster::RenderOptions count = row_first;
            count.stop_after = refraster::RenderStage::Raster;
            refraster::Framebuffer scratch;
            row.pixels =
                static_cast<double>(refraster::render(scene.draw_list, count, scratch).fragments);
        }
        log << name << ": " << row.triangles << " " << row.primitive << " covering " << std::fixed
            << std::setprecision(1) << row.pixels / 1e6 << " Mpx, generated in " << ms_since(t0)
            << " ms\n"
            << std::flush;
        // softpipe is timed only, and not on the scaling workloads (their point is the
        // reference's rate against its own at the standard size); a softpipe row runs softpipe
        // alone and compares it.
        std::vector<bool> active(configs.size(), true);
        for (std::size_t c = 0; c < configs.size(); ++c) {
            const bool softpipe = configs[c].label == "softpipe";
            active[c] = softpipe_row ? softpipe : !(softpipe && bench_scaling_counterpart(name));
        }
        // The configuration every other render of the row is compared with.
        const std::string judge = softpipe_row ? "softpipe" : "llvmpipe_t0";
        // Warm-up: one untimed render in every GL worker (context, framebuffer objects, shader
        // compilation, first upload).
        for (std::size_t c = 0; c < backends.size(); ++c) {
            if (!active[c]) continue;
            const auto r = backends[c]->render(scene);
            if (r.status == RenderStatus::NotSupported && configs[c].label == "softpipe" &&
                !softpipe_row) {
                // Timed only here: a scene softpipe cannot draw leaves its column empty.
                log << "  softpipe not timed: " << r.message << "\n";
                active[c] = false;
                continue;
            }
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
        // The scene file the process runs load, written once; a softpipe row has none (its
        // processes would be softpipe's, which the column does not compare).
        std::filesystem::path scene_path;
        if (process_dir && !softpipe_row) {
            scene_path = process_dir->path / (name + ".json");
            write_file_atomically(
                scene_path, scene_json_text(bench_scene_file("bench." + name, scene.draw_list),
                                            VertexForm::Base64));
        }
        std::vector<double> ref_proc_ms, ref_proc_cpu_ms, gl_proc_ms, gl_proc_cpu_ms;
        std::vector<double> ref_ms, ref2_ms;
        std::map<std::string, std::vector<double>> gl_ms;
        std::vector<std::vector<double>> stage_ms(4);
        std::size_t heap_peak = 0, heap2_peak = 0;
        for (int round = 0; round < options.rounds; ++round) {
            // Interleaved: every renderer once a round, so that the machine's load shifts
            // every column alike.
            Rendered ref;
            reset_heap_peak();
            ref_ms.push_back(render_ref(row_first, ref));
            heap_peak = std::max(heap_peak, heap_peak_bytes());
            std::optional<Rendered> ref2;
            if (row_second) {
                ref2.emplace();
                reset_heap_peak();
                ref2_ms.push_back(render_ref(*row_second, *ref2));
                heap2_peak = std::max(heap2_peak, heap_peak_bytes());
            }
            // The split: the first configuration stopped after each stage; a stage's time is
            // the difference of the medians.
            for (std::size_t k = 0; k + 1 < std::size(stages); ++k) {
                refraster::Framebuffer partial;
                refraster::RenderOptions ro = row_first;
                ro.stop_after = stages[k];
                const detail::ThreadPin pin(cpu_for(ro.threads));
                const auto s0 = std::chrono::steady_clock::now();
                (void)refraster::render(scene.draw_list, ro, partial);
                stage_ms[k].push_back(ms_since(s0));
            }
            stage_ms[3].push_back(ref_ms.back());
            std::optional<Rendered> judged;
            const std::string in_round = " in round " + std::to_string(round + 1);
            const std::string judge_words =
                softpipe_row ? "softpipe's" : "llvmpipe's (LP_NUM_THREADS=0)";
            for (std::size_t c = 0; c < backends.size(); ++c) {
                if (!active[c]) continue;
                auto r = backends[c]->render(scene);
                if (r.status != RenderStatus::Ok) throw failed(name, configs[c].label, r);
                // The worker's own time: its first GL call to the finished read-back, the
                // transfer between the processes left out (RenderResult::round_trip_seconds).
                gl_ms[configs[c].label].push_back(r.seconds * 1000.0);
                Rendered gl{std::move(r.image), std::move(r.samples)};
                if (configs[c].label == judge) {
                    judged = std::move(gl);
                    if (const auto what = difference(ref, *judged)) {
                        throw std::runtime_error("bench " + name + ": the reference's " + *what +
                                                 " (" + std::to_string(row_first.threads) +
                                                 " threads, " + row_first.profile.name +
                                                 ") differs from " + judge_words + in_round);
                    }
                    if (ref2) {
                        if (const auto what = difference(*ref2, *judged)) {
                            throw std::runtime_error("bench " + name + ": the reference's " +
                                                     *what + " (" +
                                                     std::to_string(row_second->threads) +
                                                     " threads, " + row_second->profile.name +
                                                     ") differs from " + judge_words + in_round);
                        }
                    }
                } else if (configs[c].compared && judged) {
                    if (const auto what = difference(gl, *judged)) {
                        throw std::runtime_error("bench " + name + ": llvmpipe's " + *what +
                                                 " with threads differs from "
                                                 "LP_NUM_THREADS=0" +
                                                 in_round);
                    }
                }
            }
            if (!scene_path.empty()) {
                // The reference as `ref` runs, llvmpipe as `llvmpipe t0`; the same PNG from both.
                const auto dir = process_dir->path;
                const std::string exe = options.refraster_path, file = scene_path.string();
                const std::string timeout = std::to_string(options.timeout_seconds);
                // Both processes, and llvmpipe's worker under the second, on the bench's CPU.
                const detail::ThreadPin pin(cpu_for(first.threads));
                const auto ref_run =
                    time_process({exe, "render", file, "--threads", std::to_string(first.threads),
                                  "--profile", first.profile.name, "--timeout", timeout, "--output",
                                  (dir / "ref.png").string()},
                                 {}, dir / "ref.stderr");
                const auto gl_run = time_process(
                    {exe, "render", file, "--backend", "osmesa", "--driver", "llvmpipe",
                     "--timeout", timeout, "--output", (dir / "llvmpipe.png").string()},
                    {"LP_NUM_THREADS=0"}, dir / "llvmpipe.stderr");
                const std::string& failure =
                    !ref_run.failure.empty() ? ref_run.failure : gl_run.failure;
                if (!failure.empty()) {
                    // Not a comparison: the in-process renders above were compared. A scene
                    // past the file format's limits (docs/limits.md) is refused by the loader.
                    log << "  process runs dropped: "
                        << (ref_run.failure.empty() ? "llvmpipe" : "ref") << ": " << failure
                        << "\n";
                    std::error_code ignored;
                    std::filesystem::remove(scene_path, ignored);
                    scene_path.clear();
                    ref_proc_ms.clear();
                    ref_proc_cpu_ms.clear();
                    gl_proc_ms.clear();
                    gl_proc_cpu_ms.clear();
                } else {
                    if (file_bytes(dir / "ref.png") != file_bytes(dir / "llvmpipe.png"))
                        throw std::runtime_error("bench " + name +
                                                 ": the PNG of `refraster render` differs from "
                                                 "the one of `--backend osmesa`" +
                                                 in_round);
                    ref_proc_ms.push_back(ref_run.wall_ms);
                    ref_proc_cpu_ms.push_back(ref_run.cpu_ms);
                    gl_proc_ms.push_back(gl_run.wall_ms);
                    gl_proc_cpu_ms.push_back(gl_run.cpu_ms);
                }
            }
            log << "  round " << round + 1 << ": ref " << ref_ms.back() << " ms";
            if (row_second)
                log << ", ref " << row_second->threads << "T " << ref2_ms.back() << " ms";
            for (std::size_t c = 0; c < configs.size(); ++c)
                if (active[c])
                    log << ", " << configs[c].label << " " << gl_ms[configs[c].label].back()
                        << " ms";
            if (!ref_proc_ms.empty() && !scene_path.empty())
                log << ", ref proc " << ref_proc_ms.back() << " ms, llvmpipe proc "
                    << gl_proc_ms.back() << " ms";
            log << "\n" << std::flush;
        }
        if (!scene_path.empty()) {
            // The tiny workloads' files are over 100 MB: one at a time on the disk.
            std::error_code ignored;
            std::filesystem::remove(scene_path, ignored);
        }
        row.ref_ms = median(ref_ms);
        if (row_second) row.ref2_ms = median(ref2_ms);
        row.ref_heap_peak_mb = static_cast<double>(heap_peak) / (1024.0 * 1024.0);
        if (row_second) row.ref2_heap_peak_mb = static_cast<double>(heap2_peak) / (1024.0 * 1024.0);
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
        if (!ref_proc_ms.empty()) {
            row.ref_process_ms = median(ref_proc_ms);
            row.ref_process_cpu_ms = median(ref_proc_cpu_ms);
            row.llvmpipe_process_ms = median(gl_proc_ms);
            row.llvmpipe_process_cpu_ms = median(gl_proc_cpu_ms);
        }
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

std::optional<double> BenchRow::process_speedup() const {
    if (!ref_process_ms || !llvmpipe_process_ms || !(*ref_process_ms > 0.0)) return std::nullopt;
    return *llvmpipe_process_ms / *ref_process_ms;
}

std::optional<double> BenchRow::speedup_vs_softpipe() const {
    if (!bench_softpipe_counterpart(name) || !softpipe_ms || !(ref_ms > 0.0)) return std::nullopt;
    return *softpipe_ms / ref_ms;
}

std::optional<double> BenchRow::speedup2_vs_softpipe() const {
    if (!bench_softpipe_counterpart(name) || !softpipe_ms || !ref2_ms || !(*ref2_ms > 0.0))
        return std::nullopt;
    return *softpipe_ms / *ref2_ms;
}

std::optional<double> bench_speed_target(const std::string& scene) {
    if (bench_softpipe_counterpart(scene)) return 5.0;
    if (scene == "tiny-flat" || scene == "tiny-smooth") return 3.0;
    static const std::map<std::string, double> targets{
        {"medium-flat", 2.0},
        {"medium-smooth", 2.0},
        {"medium-perspective", 2.0},
        {"full-flat", 2.0},
        {"full-smooth", 2.0},
        {"full-perspective", 2.0},
        {"medium-textured-bilinear", 1.5},
        {"medium-textured-trilinear", 1.5},
        {"medium-textured-nearest", 1.5},
        {"full-textured-bilinear", 1.5},
        {"full-textured-trilinear", 1.5},
        {"full-textured-perspective", 1.5},
        {"medium-smooth-4x", 2.0},
        {"full-smooth-4x", 2.0},
        {"lines-4x", 2.0},
        {"points-4x", 2.0},
        {"lines", 2.0},
        {"wide-lines", 2.0},
        {"points", 2.0},
        {"polygons-nonzero", 2.0},
        {"polygons-evenodd", 2.0},
        {"full-flat-allpass", 2.0},
        {"full-smooth-allpass", 2.0},
    };
    const auto it = targets.find(scene);
    if (it == targets.end()) return std::nullopt;
    return it->second;
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
            // A softpipe row is judged against softpipe, every other against llvmpipe.
            const bool softpipe = bench_softpipe_counterpart(r.name).has_value();
            targets.push_back({r.name, "speed", softpipe ? r.speedup_vs_softpipe() : r.speedup(),
                               *t, false, true});
            targets.push_back({r.name, "speed 2T",
                               softpipe ? r.speedup2_vs_softpipe() : r.speedup2(), *t, false,
                               false});
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
      << "; profile " << opt_in.profile.name << "; "
      << (report.pinned_cpu >= 0 ? "one thread on CPU " + std::to_string(report.pinned_cpu)
                                 : std::string("not pinned"))
      << "; cpu " << report.cpu_flags << "; commit " << report.commit << "; " << report.date;
    if (!report.gl_renderer.empty())
        o << "; " << report.gl_renderer << ", Mesa " << report.mesa_version;
    o << "\n\n";
    o << "| scene | primitives | Mpx | ref ms | ref Mprim/s | ref Mpix/s | ref 2T ms | llvmpipe "
         "t0 ms | Mprim/s | Mpix/s | llvmpipe ms | softpipe ms | ref / llvmpipe t0 | ref 2T / "
         "llvmpipe | ref / softpipe | ref proc ms | llvmpipe proc ms | ref proc / llvmpipe proc "
         "| rate ratio | ref heap MB | heap bound MB | heap | load | setup | raster | fragment |\n"
      << "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | "
         "---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: | ---: | "
         "---: | ---: |\n";
    const auto opt = [](const std::optional<double>& v, int digits = 1) {
        return v ? fixed(*v, digits) : std::string("-");
    };
    for (const auto& r : rows) {
        const double tris = static_cast<double>(r.triangles);
        const double heap = r.heap_peak_mb(), bound = r.heap_bound_mb();
        o << "| " << r.name << " | " << r.triangles << " " << r.primitive << " | "
          << fixed(r.pixels / 1e6, 1) << " | " << fixed(r.ref_ms, 1) << " | "
          << fixed(rate(tris, r.ref_ms), 2) << " | " << fixed(rate(r.pixels, r.ref_ms), 1) << " | "
          << opt(r.ref2_ms) << " | " << opt(r.llvmpipe_t0_ms) << " | "
          << (r.llvmpipe_t0_ms ? fixed(rate(tris, *r.llvmpipe_t0_ms), 2) : "-") << " | "
          << (r.llvmpipe_t0_ms ? fixed(rate(r.pixels, *r.llvmpipe_t0_ms), 1) : "-") << " | "
          << opt(r.llvmpipe_ms) << " | " << opt(r.softpipe_ms) << " | " << opt(r.speedup(), 2)
          << " | " << opt(r.speedup2(), 2) << " | " << opt(r.speedup_vs_softpipe(), 2) << " | "
          << opt(r.ref_process_ms) << " | " << opt(r.llvmpipe_process_ms) << " | "
          << opt(r.process_speedup(), 2) << " | " << opt(bench_rate_ratio(r, rows), 2) << " | "
          << fixed(heap, 1) << " | " << fixed(bound, 1) << " | "
          << (heap <= bound ? "within" : "over") << " | " << fixed(r.split.load, 1) << " | "
          << fixed(r.split.setup, 1) << " | " << fixed(r.split.raster, 1) << " | "
          << fixed(r.split.fragment, 1) << " |\n";
    }
    o << "\nref / llvmpipe t0: the reference's speed over single-threaded llvmpipe's (above 1: the "
         "reference is faster); ref 2T / llvmpipe: the second reference configuration's over "
         "llvmpipe's with its default threads; ref / softpipe: on a softpipe row, the reference's "
         "(softpipe-22.3 profile) over softpipe's; proc: a whole process from scene file to PNG "
         "(`--process`), the reference on one thread against llvmpipe with LP_NUM_THREADS=0; "
         "rate ratio: a scaling workload's rate (Mtri/s for tiny, Mpix/s for full) over its "
         "standard counterpart's; heap bound: twice the framebuffer plus the scene's vertex "
         "data. Medians; times in ms (GL: the worker's own clock, the transfer between processes "
         "excluded); the split is the reference's.\n";

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
                  {"process", o.process},
                  {"profile", o.profile.name},
                  {"kernels_asked", std::string(refraster::to_string(o.kernels))},
                  {"kernels", report.kernels},
                  {"threads", o.threads},
                  {"second_threads", o.second_threads},
                  {"pinned_cpu", report.pinned_cpu >= 0 ? nlohmann::ordered_json(report.pinned_cpu)
                                                        : nlohmann::ordered_json()}};
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
        s["primitive"] = r.primitive;
        s["triangles"] = r.triangles;  // the primitives, of the kind "primitive" says
        s["pixels"] = r.pixels;
        s["ref_ms"] = r.ref_ms;
        s["ref2_ms"] = opt(r.ref2_ms);
        s["llvmpipe_t0_ms"] = opt(r.llvmpipe_t0_ms);
        s["llvmpipe_ms"] = opt(r.llvmpipe_ms);
        s["softpipe_ms"] = opt(r.softpipe_ms);
        s["speedup_vs_llvmpipe_t0"] = opt(r.speedup());
        s["speedup_2t_vs_llvmpipe"] = opt(r.speedup2());
        s["speedup_vs_softpipe"] = opt(r.speedup_vs_softpipe());
        s["speedup_2t_vs_softpipe"] = opt(r.speedup2_vs_softpipe());
        s["ref_process_ms"] = opt(r.ref_process_ms);
        s["ref_process_cpu_ms"] = opt(r.ref_process_cpu_ms);
        s["llvmpipe_process_ms"] = opt(r.llvmpipe_process_ms);
        s["llvmpipe_process_cpu_ms"] = opt(r.llvmpipe_process_cpu_ms);
        s["process_speedup"] = opt(r.process_speedup());
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
