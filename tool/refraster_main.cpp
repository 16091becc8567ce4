// refraster: the command-line front door. Subcommands share one set of exit codes:
//   0 success, 1 images differ beyond `expect` (or a conformance case failed),
//   2 bad input or usage, 3 backend failure (crash, timeout, internal error), 4 NotSupported.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>

#include "conformance/merge.hpp"
#include "conformance/shard.hpp"
#include "conformance/suite.hpp"
#include "harness/backend.hpp"
#include "harness/bench.hpp"
#include "harness/case_result.hpp"
#include "harness/explain.hpp"
#include "harness/extreme_scenes.hpp"
#include "harness/files.hpp"
#include "harness/fingerprint.hpp"
#include "harness/gl_verdict.hpp"
#include "harness/image_hash.hpp"
#include "harness/image_io.hpp"
#include "harness/profile_io.hpp"
#include "harness/reduce.hpp"
#include "harness/scene.hpp"
#include "harness/scene_text.hpp"
#include "harness/study.hpp"
#include "harness/teach.hpp"
#include "harness/teach_page.hpp"

namespace {

constexpr int kExitOk = 0;
constexpr int kExitMismatch = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitBackendFailure = 3;
constexpr int kExitNotSupported = 4;

// The reference's profile, shared by the subcommands that run it.
struct ProfileArgs {
    std::string profile = "llvmpipe-22.3";
    std::vector<std::string> overrides;

    // Throws refraster::ProfileError.
    refraster::Profile load() const {
        auto p = harness::load_profile(profile);
        harness::apply_profile_overrides(p, overrides);
        return p;
    }
    std::string source() const { return harness::profile_source(profile); }
};

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

// Options naming a backend, shared by the subcommands.
struct BackendArgs {
    explicit BackendArgs(std::string b) : backend(std::move(b)) {}
    std::string backend;
    std::string driver = "llvmpipe";
    double timeout = 60.0;
    std::string mesa_prefix;  // a Mesa build of one's own (GL backends)
    std::string egl_device;   // egl: a device index, or "list"
    ProfileArgs profile;
    unsigned threads = 0;  // the reference's; 0: one per core

    harness::BackendOptions options() const {
        harness::BackendOptions o;
        o.threads = threads;
        o.profile = profile.load();
        o.profile_source = profile.source();
        o.profile_overrides = profile.overrides;
        o.kind = backend == "osmesa" ? harness::BackendKind::OSMesa
                 : backend == "egl"  ? harness::BackendKind::Egl
                                     : harness::BackendKind::Ref;
        o.driver = driver == "softpipe" ? harness::Driver::Softpipe : harness::Driver::Llvmpipe;
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
};

void add_driver_options(CLI::App* cmd, BackendArgs& a) {
    cmd->add_option("--driver", a.driver, "Mesa driver for osmesa and egl")
        ->check(CLI::IsMember({"llvmpipe", "softpipe"}))
        ->capture_default_str();
    cmd->add_option("--timeout", a.timeout, "Seconds a GL backend may take for one scene")
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

std::optional<harness::Scene> load_or_report(const std::string& path) {
    try {
        return harness::load_scene(path);
    } catch (const harness::SceneError& e) {
        std::cerr << e.what() << "\n";
        return std::nullopt;
    }
}

// nullptr after reporting; `bad_profile` tells a usage error (exit 2) from a backend that
// cannot start (exit 3).
std::unique_ptr<harness::Backend> backend_or_report(const BackendArgs& a, const std::string& scene,
                                                    bool& bad_profile) {
    bad_profile = false;
    try {
        return harness::make_backend(a.options());
    } catch (const refraster::ProfileError& e) {
        std::cerr << "refraster: " << e.what() << "\n";
        bad_profile = true;
        return nullptr;
    } catch (const harness::BackendOptionError& e) {
        std::cerr << "refraster: " << e.what() << "\n";
        bad_profile = true;
        return nullptr;
    } catch (const std::exception& e) {
        std::cerr << scene << ": backend " << a.backend << ": " << e.what() << "\n";
        return nullptr;
    }
}

int exit_code_for(harness::RenderStatus s) {
    switch (s) {
        case harness::RenderStatus::Ok:
            return kExitOk;
        case harness::RenderStatus::NotSupported:
            return kExitNotSupported;
        default:
            return kExitBackendFailure;
    }
}

// ---- render ------------------------------------------------------------------------------

struct RenderArgs {
    std::string scene;
    BackendArgs backend{"ref"};
    std::string output;
    std::string samples_output;  // PREFIX: PREFIX.s0.png .. PREFIX.s3.png for a 4x target
};

int run_render(const RenderArgs& a) {
    const auto scene = load_or_report(a.scene);
    if (!scene) return kExitBadInput;
    const std::filesystem::path out(a.output);
    const auto want_ext = harness::image_extension(scene->file.target.color);
    if (out.extension() != want_ext) {
        std::cerr << a.output << ": the target is " << to_string(scene->file.target.color)
                  << ", so the output must end in " << want_ext << "\n";
        return kExitBadInput;
    }
    const std::uint32_t samples = scene->file.target.samples;
    if (!a.samples_output.empty() && samples == 1) {
        std::cerr << a.scene
                  << ": --samples-output needs a multisampled target; target.samples is 1\n";
        return kExitBadInput;
    }
    if (!a.samples_output.empty() &&
        (a.samples_output.back() == '/' || std::filesystem::is_directory(a.samples_output))) {
        std::cerr << a.samples_output << ": --samples-output takes a file name prefix (PREFIX.s0"
                  << want_ext << " ...), not a directory\n";
        return kExitBadInput;
    }
    bool bad_profile = false;
    auto backend = backend_or_report(a.backend, a.scene, bad_profile);
    if (!backend) return bad_profile ? kExitBadInput : kExitBackendFailure;
    const harness::RenderResult r = backend->render(*scene);
    if (r.status != harness::RenderStatus::Ok) {
        std::cerr << a.scene << ": " << to_string(r.status) << " in " << backend->name() << ": "
                  << r.message << "\n";
        return exit_code_for(r.status);
    }
    // The image and every sample's, all or none.
    std::vector<harness::ImageToWrite> images{{&r.image, out}};
    std::vector<refraster::Framebuffer> planes;
    std::vector<std::filesystem::path> sample_paths;
    if (!a.samples_output.empty()) {
        if (r.samples.samples != samples || r.samples.width != r.image.width ||
            r.samples.height != r.image.height) {
            std::cerr << a.scene << ": " << backend->name() << " returned no samples of the "
                      << samples << "x target, so --samples-output has nothing to write\n";
            return kExitBackendFailure;
        }
        sample_paths =
            harness::sample_image_paths(a.samples_output, samples, scene->file.target.color);
        for (std::uint32_t k = 0; k < samples; ++k) {
            planes.push_back(refraster::sample_plane(r.samples, k));
        }
        for (std::uint32_t k = 0; k < samples; ++k)
            images.emplace_back(&planes[k], sample_paths[k]);
    }
    try {
        harness::write_color_images(images);
    } catch (const std::exception& e) {
        std::cerr << e.what() << "\n";
        return kExitBadInput;
    }
    std::cout << "wrote " << out.string() << " (" << backend->name() << ", " << r.image.width << "x"
              << r.image.height << ")";
    if (!sample_paths.empty()) {
        std::cout << " and " << samples << " samples: " << sample_paths.front().string() << " .. "
                  << sample_paths.back().string();
    }
    std::cout << "\n";
    return kExitOk;
}

// ---- compare -----------------------------------------------------------------------------

struct CompareArgs {
    std::string scene;
    BackendArgs reference{"ref"};
    BackendArgs against{"osmesa"};
    std::string reference_driver;  // empty: the same as --driver
    std::string json;
    std::string diff;
};

// Writes the mask to `diff` and both images beside it: OUT.<backend>.png, and for a 4x target
// the sample mask as OUT.samples.png; all or none.
void write_diff_images(const harness::CaseResult& r, const std::filesystem::path& diff) {
    const auto beside = [&](const std::string& what, std::string_view ext) {
        auto p = diff;
        p.replace_filename(diff.stem().string() + "." + what + std::string(ext));
        return p;
    };
    std::vector<harness::ImageToWrite> images{{&r.comparison->mask, diff}};
    for (const auto& [rr, who] :
         {std::pair{&*r.reference, r.reference_name}, std::pair{&*r.actual, r.actual_name}}) {
        images.emplace_back(&rr->image,
                            beside(who, harness::image_extension(rr->image.color_format)));
    }
    if (r.sample_comparison && !r.sample_comparison->size_mismatch) {
        images.emplace_back(&r.sample_comparison->mask, beside("samples", ".png"));
    }
    harness::write_color_images(images);
}

int run_compare(CompareArgs a) {
    const auto scene = load_or_report(a.scene);
    if (!scene) return kExitBadInput;
    if (!a.diff.empty() && std::filesystem::path(a.diff).extension() != ".png") {
        std::cerr << a.diff << ": the error mask is written as .png\n";
        return kExitBadInput;
    }
    if (a.reference_driver.empty()) a.reference_driver = a.against.driver;
    a.reference.driver = a.reference_driver;
    a.reference.timeout = a.against.timeout;
    a.against.profile = a.reference.profile;
    a.against.threads = a.reference.threads;
    bool bad_ref = false;
    bool bad_act = false;
    auto ref = backend_or_report(a.reference, a.scene, bad_ref);
    auto act = ref ? backend_or_report(a.against, a.scene, bad_act) : nullptr;
    if (!ref || !act) return bad_ref || bad_act ? kExitBadInput : kExitBackendFailure;
    const std::string name = scene->file.name.empty()
                                 ? std::filesystem::path(a.scene).stem().string()
                                 : scene->file.name;
    const harness::CaseResult r = harness::run_case(*scene, name, *ref, *act);
    try {
        if (!a.json.empty()) {
            harness::write_file_atomically(a.json, harness::to_json_line(r) + "\n");
        }
        if (!a.diff.empty() && r.comparison && !r.comparison->size_mismatch) {
            write_diff_images(r, a.diff);
        }
    } catch (const std::exception& e) {
        std::cerr << e.what() << "\n";
        return kExitBadInput;
    }
    std::cout << to_string(r.status) << " " << r.name << " (" << r.reference_name << " vs "
              << r.actual_name << ")";
    if (r.comparison) std::cout << ": " << r.comparison->summary();
    if (r.sample_comparison) std::cout << "; " << r.sample_comparison->summary();
    std::cout << "\n";
    switch (r.status) {
        case harness::CaseStatus::Pass:
            return kExitOk;
        case harness::CaseStatus::Fail:
            return kExitMismatch;
        case harness::CaseStatus::NotSupported:
            std::cerr << a.scene << ": NotSupported: " << r.message << "\n";
            return kExitNotSupported;
        default:
            std::cerr << a.scene << ": " << to_string(r.status) << ": " << r.message << "\n";
            return kExitBackendFailure;
    }
}

// ---- conformance run ---------------------------------------------------------------------

struct ConformanceArgs {
    std::string cases;
    std::string exclude;
    std::string caselist;
    std::string baseline;
    std::string scenes;
    std::optional<int> shard_index;
    std::optional<int> shard_count;
    std::vector<std::string> skips;
    std::vector<std::string> flakes;
    bool resume = false;
    BackendArgs against{"osmesa"};
    ProfileArgs profile;
    unsigned threads = 0;
    std::string output;
    std::string verdict = "exact";
};

std::vector<std::string> split_globs(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string g; std::getline(ss, g, ',');) {
        if (!g.empty()) out.push_back(g);
    }
    return out;
}

std::filesystem::path default_scenes_root() {
    if (std::filesystem::is_directory("conformance/scenes")) return "conformance/scenes";
    return std::filesystem::path(REFRASTER_SOURCE_DIR) / "conformance/scenes";
}

int run_conformance(const ConformanceArgs& a) {
    conformance::RunOptions o;
    o.scenes_root = a.scenes.empty() ? default_scenes_root() : std::filesystem::path(a.scenes);
    o.case_globs = split_globs(a.cases);
    o.exclude_globs = split_globs(a.exclude);
    if (!a.caselist.empty()) o.caselist = a.caselist;
    if (!a.baseline.empty()) o.baseline = a.baseline;
    try {
        const conformance::Shard shard = conformance::resolve_shard(
            a.shard_index, a.shard_count, conformance::process_environment());
        o.shard_index = shard.index;
        o.shard_count = shard.count;
        o.shard_source = shard.source;
    } catch (const conformance::ShardError& e) {
        std::cerr << "refraster conformance run: " << e.what() << "\n";
        return kExitBadInput;
    }
    o.skips.assign(a.skips.begin(), a.skips.end());
    o.flakes.assign(a.flakes.begin(), a.flakes.end());
    o.resume = a.resume;
    o.gl_verdict = a.verdict == "gl";
    const char* ci = std::getenv("CI");
    o.progress = ::isatty(STDOUT_FILENO) != 0 && !(ci != nullptr && std::string(ci) == "true");
    o.output = a.output;
    try {
        BackendArgs ref{"ref"};
        ref.profile = a.profile;
        ref.threads = a.threads;
        o.reference = ref.options();
        o.against = a.against.options();
        const auto s = conformance::run_suite(o, std::cout);
        return s.failed == 0 ? kExitOk : kExitMismatch;
    } catch (const std::exception& e) {
        std::cerr << "refraster conformance run: " << e.what() << "\n";
        return kExitBadInput;
    }
}

// ---- explain -----------------------------------------------------------------------------

// The reference's profile and the GL backend of `against` (whose own profile options describe
// the reference). Returns an exit code when either cannot be had, after reporting it.
std::optional<int> profile_and_backend(const BackendArgs& against, const std::string& scene,
                                       bool want_backend, refraster::Profile& profile,
                                       std::unique_ptr<harness::Backend>& backend) {
    try {
        profile = against.profile.load();
    } catch (const refraster::ProfileError& e) {
        std::cerr << "refraster: " << e.what() << "\n";
        return kExitBadInput;
    }
    if (!want_backend) return std::nullopt;
    bool bad = false;
    BackendArgs gl = against;
    gl.profile = ProfileArgs{};
    backend = backend_or_report(gl, scene, bad);
    if (!backend) return bad ? kExitBadInput : kExitBackendFailure;
    return std::nullopt;
}

// "X,Y" as two integers; nullopt when it is not of that form.
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

struct ExplainArgs {
    std::string scene;
    std::string pixel;
    bool json = false;
    std::string svg;
    BackendArgs against{"osmesa"};
    bool no_backend = false;
    int sample = -1;  // -1: the resolved pixel
};

int run_explain(ExplainArgs a) {
    const auto scene = load_or_report(a.scene);
    if (!scene) return kExitBadInput;
    const auto pixel = parse_pixel(a.pixel);
    if (!pixel) {
        std::cerr << "refraster explain: --pixel " << a.pixel << ": expected X,Y\n";
        return kExitBadInput;
    }
    const int x = (*pixel)[0];
    const int y = (*pixel)[1];
    const auto& target = scene->draw_list.target;
    if (!inside(target, *pixel)) {
        std::cerr << a.scene << ": --pixel " << a.pixel << ": outside the " << target.width << "x"
                  << target.height << " target\n";
        return kExitBadInput;
    }
    if (a.sample >= 0 && target.samples != 4) {
        std::cerr << a.scene << ": --sample " << a.sample << ": the target has " << target.samples
                  << " sample" << (target.samples == 1 ? "" : "s")
                  << " (--sample needs a 4x target)\n";
        return kExitBadInput;
    }
    refraster::Profile profile;
    std::unique_ptr<harness::Backend> backend;
    if (const auto rc = profile_and_backend(a.against, a.scene, !a.no_backend, profile, backend))
        return *rc;
    try {
        const auto e = harness::explain_pixel(*scene, profile, x, y, backend.get(), a.sample);
        std::cout << (a.json ? harness::explanation_json(e) + "\n" : harness::explanation_text(e));
        // Whether GL allows the backend's pixel (gl_verdict.hpp), for a differing pixel.
        if (!a.json && !e.agree && e.backend && e.backend->status == harness::RenderStatus::Ok) {
            const auto v = harness::gl_verdict(*scene, profile, e.reference_image, e.backend->image,
                                               std::array<int, 2>{x, y});
            std::cout << "GL: " << v.at_pixel << "\n";
        }
        if (!a.svg.empty()) harness::write_file_atomically(a.svg, harness::explanation_svg(e));
        return e.agree ? kExitOk : kExitMismatch;
    } catch (const std::exception& ex) {
        std::cerr << a.scene << ": " << ex.what() << "\n";
        return kExitBackendFailure;
    }
}

// ---- reduce ------------------------------------------------------------------------------

struct ReduceArgs {
    std::string scene;
    std::string output;
    std::string pixel;
    std::string difference;
    BackendArgs against{"osmesa"};
};

int run_reduce(const ReduceArgs& a) {
    const auto scene = load_or_report(a.scene);
    if (!scene) return kExitBadInput;
    harness::MismatchToKeep keep;
    keep.difference = a.difference;
    if (!a.pixel.empty()) {
        keep.pixel = parse_pixel(a.pixel);
        if (!keep.pixel) {
            std::cerr << "refraster reduce: --pixel " << a.pixel << ": expected X,Y\n";
            return kExitBadInput;
        }
        if (!inside(scene->draw_list.target, *keep.pixel)) {
            std::cerr << a.scene << ": --pixel " << a.pixel << ": outside the "
                      << scene->draw_list.target.width << "x" << scene->draw_list.target.height
                      << " target\n";
            return kExitBadInput;
        }
    }
    refraster::Profile profile;
    std::unique_ptr<harness::Backend> backend;
    if (const auto rc = profile_and_backend(a.against, a.scene, true, profile, backend)) return *rc;
    try {
        const auto r =
            harness::reduce_scene(scene->file, a.scene, profile, *backend, std::cout, keep);
        auto reduced = r.scene;
        // The reduced scene is a scene of its own: named after its file, as a scene under
        // conformance/scenes is named after its path.
        reduced.name = std::filesystem::path(a.output).stem().string();
        reduced.description = "Reduced from " + a.scene + " (" +
                              std::to_string(r.primitives_before) + " -> " +
                              std::to_string(r.primitives_after) + " primitives), keeping a " +
                              r.signature + " mismatch" +
                              (keep.pixel                ? " at pixel " + a.pixel
                               : keep.difference.empty() ? ""
                                                         : " of class " + keep.difference) +
                              " under profile " + profile.name + ".";
        const std::string text = harness::scene_to_json(reduced);
        (void)harness::load_scene_text(text, a.output);  // what is written is a valid scene
        harness::write_file_atomically(a.output, text);
        std::cout << "wrote " << a.output << "\n";
        return kExitOk;
    } catch (const harness::SceneError& e) {
        std::cerr << "refraster reduce: internal error, the reduced scene is invalid: " << e.what()
                  << "\n";
        return kExitBackendFailure;
    } catch (const std::exception& e) {
        std::cerr << "refraster reduce: " << e.what() << "\n";
        return kExitBadInput;
    }
}

// ---- conformance hashes ------------------------------------------------------------------

// One line per scene, "case hash", of the reference's render (or its status when it does not
// render): the golden file conformance/expectations/ref-hashes.txt.
int run_hashes(const std::string& scenes, const ProfileArgs& profile) {
    try {
        BackendArgs ref{"ref"};
        ref.profile = profile;
        // Fused arithmetic wherever llvmpipe fuses, whatever this CPU has: std::fma gives the
        // same result everywhere, so the hashes do not depend on the host.
        ref.profile.overrides.insert(ref.profile.overrides.begin(), "viewport_fma=on");
        auto backend = harness::make_backend(ref.options());
        const auto root = scenes.empty() ? default_scenes_root() : std::filesystem::path(scenes);
        std::cout << "# refraster reference image hashes (FNV-1a 64 of decoded colour and depth), "
                     "profile "
                  << ref.profile.load().name << "\n"
                  << "# regenerate: build/bin/refraster conformance hashes > "
                     "conformance/expectations/ref-hashes.txt\n";
        for (const auto& c : conformance::discover_cases(root)) {
            const auto r = backend->render(harness::load_scene(c.file));
            std::cout << c.name << " "
                      << (r.status == harness::RenderStatus::Ok
                              ? harness::render_hash(r.image, r.samples)
                              : std::string(harness::to_string(r.status)))
                      << "\n";
        }
        return kExitOk;
    } catch (const std::exception& e) {
        std::cerr << "refraster conformance hashes: " << e.what() << "\n";
        return kExitBadInput;
    }
}

// ---- bench -------------------------------------------------------------------------------

struct BenchArgs {
    std::string scenes;
    int rounds = 5;
    double scale = 1.0;
    std::uint64_t seed = 1;
    bool no_gl = false;
    bool no_softpipe = false;
    bool scaling = false;
    unsigned threads = 1;
    unsigned second_threads = 2;
    std::string kernels = "fastest";
    std::string json;
    ProfileArgs profile;
};

int run_bench(const BenchArgs& a) {
    harness::BenchOptions o;
    try {
        o.profile = a.profile.load();
    } catch (const refraster::ProfileError& e) {
        std::cerr << "refraster: " << e.what() << "\n";
        return kExitBadInput;
    }
    o.scenes = split_globs(a.scenes);
    o.rounds = a.rounds;
    o.scale = a.scale;
    o.seed = a.seed;
    o.gl = !a.no_gl;
    o.softpipe = !a.no_softpipe;
    o.scaling = a.scaling;
    o.threads = a.threads;
    o.second_threads = a.second_threads;
    o.kernels = *harness::parse_kernel_path(a.kernels);  // CLI checks the name
    harness::BenchReport report;
    try {
        report = harness::run_bench(o, std::cerr);
    } catch (const std::invalid_argument& e) {
        std::cerr << "refraster bench: " << e.what() << "\n";
        return kExitBadInput;
    } catch (const std::exception& e) {
        std::cerr << "refraster bench: " << e.what() << "\n";
        return kExitBackendFailure;
    }
    std::cout << harness::bench_table(report);
    if (!a.json.empty()) {
        try {
            harness::write_file_atomically(a.json, harness::bench_json(report));
        } catch (const std::exception& e) {
            std::cerr << e.what() << "\n";
            return kExitBadInput;
        }
    }
    return kExitOk;
}

}  // namespace

// ---- conformance merge ----------------------------------------------------------------------

// merge SHARD_DIR... --output DIR: exit 0 when every shard is there, 1 when some are missing
// (the report of the others is written and says so), 2 for shards that cannot be one run.
int run_merge(const std::vector<std::string>& shards, const std::string& output) {
    std::vector<std::filesystem::path> dirs(shards.begin(), shards.end());
    try {
        const auto summary = conformance::merge_shards(dirs, output, std::cout);
        std::cout << "report: " << (std::filesystem::path(output) / "index.html").string() << "\n";
        return summary.missing_shards.empty() ? kExitOk : kExitMismatch;
    } catch (const conformance::MergeError& e) {
        std::cerr << "refraster conformance merge: " << e.what() << "\n";
        return kExitBadInput;
    } catch (const std::exception& e) {
        std::cerr << "refraster conformance merge: " << output << ": " << e.what() << "\n";
        return kExitBadInput;
    }
}

// ---- study ----------------------------------------------------------------------------------

struct StudyArgs {
    std::string name;
    std::string output;
    std::uint64_t seed = 1;
    bool quick = false;
    bool quiet = false;
};

// study NAME --output DIR: runs the study, then writes study.csv, study.svg and summary.md into
// DIR, each file whole or not at all; prints the conclusions.
int run_study_command(const StudyArgs& a) {
    const std::filesystem::path dir(a.output);
    std::error_code ec;
    if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec)) {
        std::cerr << a.output << ": --output names a file, not a directory\n";
        return kExitBadInput;
    }
    harness::StudyOptions o;
    o.seed = a.seed;
    o.quick = a.quick;
    if (!a.quiet) o.progress = [](const std::string& line) { std::cerr << line << "\n"; };
    harness::StudyOutput out;
    try {
        out = harness::run_study(a.name, o);
    } catch (const harness::StudyError& e) {
        std::cerr << "refraster study: " << e.what() << "\n";
        return kExitBadInput;
    }
    std::string command = "refraster study " + a.name + " --output " + a.output;
    if (a.seed != 1) command += " --seed " + std::to_string(a.seed);
    if (a.quick) command += " --quick";
    try {
        std::filesystem::create_directories(dir);
        harness::write_file_atomically(dir / "study.csv", out.csv);
        harness::write_file_atomically(dir / "study.svg", out.svg);
        harness::write_file_atomically(dir / "summary.md",
                                       harness::study_summary_markdown(out, command));
    } catch (const std::exception& e) {
        std::cerr << a.output << ": " << e.what() << "\n";
        return kExitBadInput;
    }
    for (const std::string& line : out.summary) std::cout << line << "\n";
    std::cout << "wrote " << (dir / "study.csv").string() << ", study.svg and summary.md\n";
    return kExitOk;
}

// ---- teach ----------------------------------------------------------------------------------

struct TeachArgs {
    std::string scene;
    std::string algorithm;
    std::string against = "ref";  // ref, or a GL backend: gl (OSMesa), osmesa, egl
    BackendArgs backend{"ref"};
    std::string output;
    int zoom = 8;
};

// An image of `w` x `h` pixels, each a `zoom` x `zoom` block of colour(x, y).
template <class Color>
refraster::Framebuffer zoomed(int w, int h, int zoom, Color&& color) {
    refraster::Framebuffer fb(static_cast<std::uint32_t>(w * zoom),
                              static_cast<std::uint32_t>(h * zoom), refraster::ColorFormat::Rgba8,
                              refraster::DepthFormat::None, 1);
    for (int y = 0; y < h * zoom; ++y) {
        for (int x = 0; x < w * zoom; ++x) {
            const std::array<std::uint8_t, 4> c = color(x / zoom, y / zoom);
            const std::size_t i =
                fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
            std::copy(c.begin(), c.end(), fb.color8.begin() + static_cast<long>(4 * i));
        }
    }
    return fb;
}

int run_teach(TeachArgs a) {
    const auto scene = load_or_report(a.scene);
    if (!scene) return kExitBadInput;
    if (scene->file.target.samples != 1) {
        std::cerr << a.scene << ": target.samples: teach compares single-sample targets, got "
                  << scene->file.target.samples << "\n";
        return kExitBadInput;
    }
    a.backend.backend = a.against == "gl" ? "osmesa" : a.against;
    bool bad_profile = false;
    auto backend = backend_or_report(a.backend, a.scene, bad_profile);
    if (!backend) return bad_profile ? kExitBadInput : kExitBackendFailure;
    // The owner pass: which primitive lit each pixel, so that coverage is known even where a
    // colour equals the clear colour.
    const harness::RenderResult gl = backend->render_owners(*scene);
    if (gl.status != harness::RenderStatus::Ok) {
        std::cerr << a.scene << ": " << to_string(gl.status) << " in " << backend->name() << ": "
                  << gl.message << "\n";
        return exit_code_for(gl.status);
    }
    harness::TeachResult r;
    try {
        r = harness::teach(*scene, a.algorithm, gl.image);
    } catch (const harness::TeachError& e) {
        std::cerr << a.scene << ": " << e.what() << "\n";
        return kExitBadInput;
    }
    const auto prov = [&](const char* key) {
        const auto it = gl.provenance.find(key);
        return it == gl.provenance.end() ? std::string("?") : it->second;
    };
    const std::string source = a.against == "ref"
                                   ? "the reference rasterizer, profile " + prov("profile")
                                   : backend->name() + " (" + prov("renderer") + ")";
    const auto data = harness::teach_json(r, *scene, a.scene, source);
    const std::filesystem::path dir(a.output);
    const int w = r.width;
    const auto at = [&](const std::vector<std::uint8_t>& rgba, int x, int y) {
        const std::size_t i = 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                   static_cast<std::size_t>(x));
        return std::array<std::uint8_t, 4>{rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
    };
    std::vector<int> diff(static_cast<std::size_t>(w) * static_cast<std::size_t>(r.height), 0);
    for (const auto& d : r.differences) {
        diff[static_cast<std::size_t>(d.y * w + d.x)] = d.algorithm > 0.0 && d.algorithm < 1.0 ? 3
                                                        : d.algorithm > 0.0 ? (d.gl ? 4 : 1)
                                                                            : 2;
    }
    const auto algorithm_png =
        zoomed(w, r.height, a.zoom, [&](int x, int y) { return at(r.algorithm_rgba, x, y); });
    const auto gl_png =
        zoomed(w, r.height, a.zoom, [&](int x, int y) { return at(r.gl_rgba, x, y); });
    // The difference mask, in the page's colours: orange lit by the algorithm only, blue by
    // GL only, yellow a partial weight or another primitive seen, dark grey equal (lighter where
    // both light the pixel).
    const auto mask_png = zoomed(w, r.height, a.zoom, [&](int x, int y) {
        const std::size_t i = static_cast<std::size_t>(y * w + x);
        switch (diff[i]) {
            case 1:
                return std::array<std::uint8_t, 4>{255, 109, 0, 255};
            case 2:
                return std::array<std::uint8_t, 4>{41, 121, 255, 255};
            case 3:
            case 4:
                return std::array<std::uint8_t, 4>{255, 214, 0, 255};
            default:
                break;
        }
        return r.gl_lit[i] ? std::array<std::uint8_t, 4>{90, 90, 90, 255}
                           : std::array<std::uint8_t, 4>{40, 40, 40, 255};
    });
    try {
        std::filesystem::create_directories(dir);
        harness::write_color_images({{&algorithm_png, dir / "algorithm.png"},
                                     {&gl_png, dir / "gl.png"},
                                     {&mask_png, dir / "differences.png"}});
        harness::write_file_atomically(dir / "teach.json", data.dump(1) + "\n");
        harness::write_file_atomically(dir / "index.html", harness::teach_page_html(data));
    } catch (const std::exception& e) {
        std::cerr << a.output << ": " << e.what() << "\n";
        return kExitBadInput;
    }
    std::cout << r.title << " on " << scene->file.name << " against " << source << ": " << r.summary
              << "; " << r.steps.size() << " steps\n";
    std::cout << "wrote " << (dir / "index.html").string() << "\n";
    return kExitOk;
}

// ---- check, generate many-triangles --------------------------------------------------------

// check SCENE.json [--rounds N]: loads the scene as every subcommand does and says what it
// holds and how long loading took (the best of N loads): the loader's speed in MB of file a
// second (docs/performance.md, "Loading").
int run_check(const std::string& path, int rounds) {
    double best = 0;
    std::optional<harness::Scene> scene;
    for (int r = 0; r < rounds; ++r) {
        scene.reset();  // one scene in memory at a time
        const auto start = std::chrono::steady_clock::now();
        scene = load_or_report(path);
        const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!scene) return kExitBadInput;
        best = r == 0 ? s : std::min(best, s);
    }
    std::uint64_t vertices = 0;
    for (const auto& d : scene->draw_list.draws) vertices += d.vertices.size();
    const auto work = harness::estimate_work(scene->draw_list);
    const auto bytes = std::filesystem::file_size(path);
    std::printf("%s: %zu draws, %llu vertices, %llu primitives, %llu estimated fragments",
                path.c_str(), scene->draw_list.draws.size(),
                static_cast<unsigned long long>(vertices),
                static_cast<unsigned long long>(work.primitives),
                static_cast<unsigned long long>(work.fragments));
    if (!scene->draw_list.textures.empty()) {
        std::uint64_t texel_bytes = 0;
        for (const auto& t : scene->draw_list.textures) {
            for (const auto& level : t.levels) texel_bytes += level.rgba.size();
        }
        std::printf(", %zu textures (%llu bytes of texels given)", scene->draw_list.textures.size(),
                    static_cast<unsigned long long>(texel_bytes));
    }
    std::printf("\n");
    std::printf("loaded %llu bytes in %.3f s (best of %d): %.1f MB/s\n",
                static_cast<unsigned long long>(bytes), best, rounds,
                static_cast<double>(bytes) / 1e6 / best);
    return scene->unsupported_extensions.empty() ? kExitOk : kExitNotSupported;
}

int run_generate_many(std::uint64_t triangles, std::uint64_t seed, const std::string& form,
                      const std::string& output) {
    const harness::VertexForm f = form == "values"   ? harness::VertexForm::Values
                                  : form == "base64" ? harness::VertexForm::Base64
                                                     : harness::VertexForm::Plain;
    const std::string text =
        harness::scene_json_text(harness::many_triangles_scene(triangles, seed), f);
    // Complete or absent: written beside the output, then renamed over it.
    const std::filesystem::path out(output);
    const std::filesystem::path tmp = out.string() + ".partial";
    {
        std::ofstream o(tmp, std::ios::binary);
        o.write(text.data(), static_cast<std::streamsize>(text.size()));
        if (!o) {
            std::cerr << output << ": cannot write\n";
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
            return kExitBadInput;
        }
    }
    std::filesystem::rename(tmp, out);
    std::cerr << output << ": " << text.size() << " bytes\n";
    return kExitOk;
}

// fingerprint: infer a backend's rules from the probe scenes (harness/fingerprint.hpp), print
// them with their evidence, write the profile (-o) and, with --json, every finding.
struct FingerprintArgs {
    BackendArgs against{"osmesa"};
    std::string output;
    std::string json;
};

int cmd_fingerprint(const FingerprintArgs& a) {
    bool bad_profile = false;
    auto backend = backend_or_report(a.against, "fingerprint", bad_profile);
    if (!backend) return bad_profile ? kExitBadInput : kExitBackendFailure;
    harness::FingerprintResult r;
    try {
        r = harness::fingerprint(
            *backend, [](const std::string& s) { std::cerr << "fingerprint: " << s << "\n"; });
    } catch (const std::exception& e) {
        std::cerr << "fingerprint: " << e.what() << "\n";
        return kExitBackendFailure;
    }
    std::cout << harness::fingerprint_text(r);
    const auto write = [](const std::string& path, const std::string& text) {
        const std::string tmp = path + ".tmp";
        {
            std::ofstream o(tmp, std::ios::binary);
            o << text << "\n";
            if (!o) {
                std::cerr << path << ": cannot write\n";
                std::error_code ec;
                std::filesystem::remove(tmp, ec);
                return false;
            }
        }
        std::filesystem::rename(tmp, path);
        return true;
    };
    if (!write(a.output, harness::profile_to_json(r.profile))) return kExitBadInput;
    if (!a.json.empty() && !write(a.json, harness::fingerprint_json(r))) return kExitBadInput;
    std::cerr << a.output << ": profile " << r.profile.name << "\n";
    // Undecided rules are a finding, not a failure of the tool: the profile is written, and the
    // exit code says that it is incomplete.
    return r.complete() ? kExitOk : kExitMismatch;
}

int main(int argc, char** argv) {
    CLI::App app{"refraster: a bit-exact reference rasterizer and its comparison harness"};
    app.require_subcommand(1);

    RenderArgs render;
    auto* rcmd = app.add_subcommand("render", "Render one scene file through one backend");
    rcmd->add_option("scene", render.scene, "Scene file (format refraster-scene/1)")->required();
    rcmd->add_option("--backend", render.backend.backend, "Renderer: ref, osmesa or egl")
        ->check(CLI::IsMember({"ref", "osmesa", "egl"}))
        ->capture_default_str();
    add_driver_options(rcmd, render.backend);
    add_profile_options(rcmd, render.backend.profile);
    add_threads_option(rcmd, render.backend.threads);
    rcmd->add_option("-o,--output", render.output,
                     "Output image: .png for rgba8 targets, .exr for rgba32f")
        ->required();
    rcmd->add_option("--samples-output", render.samples_output,
                     "For a 4x target, also each sample's image: PREFIX.s0.png .. PREFIX.s3.png "
                     "(.exr for rgba32f)");

    CompareArgs compare;
    auto* ccmd = app.add_subcommand(
        "compare", "Render one scene through the reference and a GL backend and compare pixels");
    ccmd->add_option("scene", compare.scene, "Scene file (format refraster-scene/1)")->required();
    ccmd->add_option("--against", compare.against.backend, "Backend compared with the reference")
        ->check(CLI::IsMember({"ref", "osmesa", "egl"}))
        ->capture_default_str();
    ccmd->add_option("--reference", compare.reference.backend,
                     "Backend taken as the truth (ref, or a GL backend to compare two drivers)")
        ->check(CLI::IsMember({"ref", "osmesa", "egl"}))
        ->capture_default_str();
    add_driver_options(ccmd, compare.against);
    add_profile_options(ccmd, compare.reference.profile);
    add_threads_option(ccmd, compare.reference.threads);
    ccmd->add_option("--reference-driver", compare.reference_driver,
                     "Mesa driver of a GL --reference (default: --driver)")
        ->check(CLI::IsMember({"llvmpipe", "softpipe"}));
    ccmd->add_option("--json", compare.json, "Write the result record (JSON) here");
    ccmd->add_option(
        "--diff", compare.diff,
        "Write the error mask here (.png), both images beside it as NAME.<backend>.png and, "
        "for a 4x target, the sample mask as NAME.samples.png");

    ConformanceArgs conf;
    auto* conf_cmd = app.add_subcommand("conformance", "The conformance suite");
    conf_cmd->require_subcommand(1);
    std::vector<std::string> merge_shards;
    std::string merge_output;
    auto* merge_cmd = conf_cmd->add_subcommand(
        "merge", "One run's results and reports from the output directories of its shards");
    merge_cmd->add_option("shards", merge_shards, "The shards' output directories")->required();
    merge_cmd->add_option("--output", merge_output, "Directory for the merged run")->required();
    auto* run_cmd = conf_cmd->add_subcommand("run", "Run the scenes against a GL backend");
    run_cmd->add_option("--cases", conf.cases, "Comma-separated globs on case names (smoke.*)");
    run_cmd->add_option("--exclude", conf.exclude, "Comma-separated globs of cases to leave out");
    run_cmd
        ->add_option("--caselist", conf.caselist,
                     "File of case names or globs, one a line, '#' comments")
        ->check(CLI::ExistingFile);
    run_cmd
        ->add_option(
            "--baseline", conf.baseline,
            "Expected failures, deqp-runner style name,Status lines (a previous failures.csv)")
        ->check(CLI::ExistingFile);
    run_cmd
        ->add_option("--skips", conf.skips,
                     "deqp-runner skips file: regular expressions, one a line, of cases to "
                     "leave out (repeatable)")
        ->check(CLI::ExistingFile);
    run_cmd
        ->add_option("--flakes", conf.flakes,
                     "deqp-runner flakes file: regular expressions of cases whose failures are "
                     "Flake (repeatable)")
        ->check(CLI::ExistingFile);
    run_cmd
        ->add_option("--shard-index", conf.shard_index,
                     "This shard, 0-based (default: from GTEST_SHARD_INDEX, GitLab's "
                     "CI_NODE_INDEX, Kubernetes' JOB_COMPLETION_INDEX or Slurm's "
                     "SLURM_ARRAY_TASK_ID; else 0)")
        ->check(CLI::NonNegativeNumber);
    run_cmd
        ->add_option("--shard-count", conf.shard_count,
                     "Number of shards (default: GTEST_TOTAL_SHARDS, CI_NODE_TOTAL, "
                     "REFRASTER_SHARD_COUNT, SLURM_ARRAY_TASK_COUNT; else 1)")
        ->check(CLI::PositiveNumber);
    run_cmd->add_flag("--resume", conf.resume,
                      "Continue a run killed part way, keeping its finished cases");
    run_cmd->add_option("--scenes", conf.scenes, "Scene root (default conformance/scenes)");
    run_cmd->add_option("--against", conf.against.backend, "GL backend compared with the reference")
        ->check(CLI::IsMember({"ref", "osmesa", "egl"}))
        ->capture_default_str();
    add_driver_options(run_cmd, conf.against);
    add_profile_options(run_cmd, conf.profile);
    run_cmd
        ->add_option("--verdict", conf.verdict,
                     "exact: any difference from the profile fails; gl: differences GL allows "
                     "(sub-pixel precision, tie rule, clipping, line and point rules, "
                     "interpolation precision) pass and violations fail, the rule named")
        ->check(CLI::IsMember({"exact", "gl"}))
        ->capture_default_str();
    add_threads_option(run_cmd, conf.threads);
    std::string hash_scenes;
    ProfileArgs hash_profile;
    auto* hash_cmd =
        conf_cmd->add_subcommand("hashes", "Print the reference's image hash for every scene");
    hash_cmd->add_option("--scenes", hash_scenes, "Scene root (default conformance/scenes)");
    add_profile_options(hash_cmd, hash_profile);
    run_cmd->add_option("--output", conf.output, "Directory for results.jsonl and images")
        ->required();

    ExplainArgs explain;
    auto* xcmd = app.add_subcommand(
        "explain", "Trace every decision about one pixel, and where the backend parts");
    xcmd->add_option("scene", explain.scene, "Scene file (format refraster-scene/1)")->required();
    xcmd->add_option("--pixel", explain.pixel,
                     "The pixel, X,Y in window coordinates (row 0 at the bottom)")
        ->required();
    xcmd->add_flag("--json", explain.json, "Print the trace and verdict as JSON");
    xcmd->add_option("--svg", explain.svg,
                     "Draw the pixel's neighbourhood at subpixel zoom into this SVG file");
    xcmd->add_option("--against", explain.against.backend, "GL backend whose bytes to compare")
        ->check(CLI::IsMember({"osmesa", "egl"}))
        ->capture_default_str();
    xcmd->add_flag("--no-backend", explain.no_backend, "Trace the reference alone");
    xcmd->add_option("--sample", explain.sample,
                     "On a 4x target, explain sample S (0..3) of the pixel instead of its resolve")
        ->check(CLI::Range(0, 3));
    add_driver_options(xcmd, explain.against);
    add_profile_options(xcmd, explain.against.profile);

    ReduceArgs reduce;
    auto* dcmd =
        app.add_subcommand("reduce", "Shrink a failing scene while it keeps the same mismatch");
    dcmd->add_option("scene", reduce.scene, "Scene file that mismatches")->required();
    dcmd->add_option("-o,--output", reduce.output,
                     "Where to write the reduced scene (.json); it is named after the file")
        ->required();
    dcmd->add_option("--pixel", reduce.pixel,
                     "Keep the mismatch at this pixel, X,Y (default: the largest difference)");
    dcmd->add_option("--class", reduce.difference, "Keep the largest mismatch of this class")
        ->check(CLI::IsMember({"coverage", "colour", "depth"}));
    dcmd->add_option("--against", reduce.against.backend, "GL backend")
        ->check(CLI::IsMember({"osmesa", "egl"}))
        ->capture_default_str();
    add_driver_options(dcmd, reduce.against);
    add_profile_options(dcmd, reduce.against.profile);

    BenchArgs bench;
    auto* bcmd = app.add_subcommand(
        "bench",
        "Time the reference (one thread, two) against OSMesa llvmpipe (one thread, default "
        "threads) and softpipe, and judge the performance targets");
    bcmd->add_option("--scenes", bench.scenes,
                     "Comma-separated workloads (default the standard eight): tiny-flat, "
                     "tiny-smooth, medium-flat, medium-smooth, full-flat, full-smooth, "
                     "medium-perspective, full-perspective; the scaling workloads "
                     "tiny-flat-4m, full-flat-2048, full-smooth-2048");
    bcmd->add_flag("--scaling", bench.scaling,
                   "Also the scaling workloads (tiny-flat-4m, full-flat-2048, full-smooth-2048) "
                   "and their standard counterparts, for the rate ratio");
    bcmd->add_option("--rounds", bench.rounds, "Interleaved rounds; medians are reported")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    bcmd->add_option("--scale", bench.scale,
                     "Fraction of each workload's triangles, for quick runs")
        ->check(CLI::Range(1e-6, 1.0))
        ->capture_default_str();
    bcmd->add_option("--seed", bench.seed, "Seed of the generated workloads")
        ->capture_default_str();
    bcmd->add_flag("--no-gl", bench.no_gl, "Time the reference alone");
    bcmd->add_flag("--no-softpipe", bench.no_softpipe, "Leave softpipe out (llvmpipe only)");
    bcmd->add_option("--threads", bench.threads,
                     "The reference's threads, compared with llvmpipe LP_NUM_THREADS=0 (0: one "
                     "per core)")
        ->capture_default_str();
    bcmd->add_option("--second-threads", bench.second_threads,
                     "Threads of a second reference configuration, compared with llvmpipe's "
                     "default threads (0: leave it out)")
        ->capture_default_str();
    bcmd->add_option("--kernels", bench.kernels,
                     "The reference's fragment kernels: model, scalar, avx2, avx512 or fastest")
        ->check(CLI::IsMember({"model", "scalar", "avx2", "avx512", "fastest"}))
        ->capture_default_str();
    bcmd->add_option("--json", bench.json, "Write the results as JSON here");
    add_profile_options(bcmd, bench.profile);

    FingerprintArgs fp;
    auto* fcmd = app.add_subcommand(
        "fingerprint",
        "Infer a backend's rules from probe scenes and write a profile the reference loads");
    fcmd->add_option("--against", fp.against.backend,
                     "Backend to fingerprint (ref: the reference under --profile)")
        ->check(CLI::IsMember({"ref", "osmesa", "egl"}))
        ->capture_default_str();
    add_driver_options(fcmd, fp.against);
    add_profile_options(fcmd, fp.against.profile);
    fcmd->add_option("-o,--output", fp.output, "The inferred profile (JSON)")->required();
    fcmd->add_option("--json", fp.json, "Every finding with its evidence (JSON)");

    ProfileArgs show;
    auto* pcmd =
        app.add_subcommand("profile", "Print a reference profile as JSON (a profile file)");
    pcmd->add_option("name", show.profile, "Built-in name or profile file")->capture_default_str();
    pcmd->add_option("--profile-set", show.overrides,
                     "Override one parameter: key=value (repeatable)");

    // generate extreme --seed N --output DIR: the seeded stiff and extreme scenes
    // (harness/extreme_scenes.hpp), one DIR/<kind>.json per kind.
    std::uint64_t gen_seed = 1;
    std::string gen_output;
    auto* gen_cmd = app.add_subcommand("generate", "Write generated scenes");
    gen_cmd->require_subcommand(1);
    auto* gen_extreme =
        gen_cmd->add_subcommand("extreme", "Stiff and extreme scenes, one file per kind");
    gen_extreme->add_option("--seed", gen_seed, "Seed of the generator")->capture_default_str();
    gen_extreme->add_option("--output", gen_output, "Directory for the scene files")->required();

    // generate many-triangles --triangles N [--form F] [--seed S] --output FILE
    std::uint64_t many_count = 1'000'000;
    std::string many_form = "plain";
    auto* gen_many = gen_cmd->add_subcommand(
        "many-triangles", "One scene of many small triangles, in a chosen vertex form");
    gen_many->add_option("--triangles", many_count, "Number of triangles")
        ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{100'000'000}))
        ->capture_default_str();
    gen_many
        ->add_option("--form", many_form,
                     "plain (vertices), values or base64 (extension vertex_arrays)")
        ->check(CLI::IsMember({"plain", "values", "base64"}))
        ->capture_default_str();
    gen_many->add_option("--seed", gen_seed, "Seed of the generator")->capture_default_str();
    gen_many->add_option("--output", gen_output, "The scene file")->required();

    std::string check_scene;
    int check_rounds = 1;
    TeachArgs teach;
    auto* tcmd = app.add_subcommand(
        "teach", "Run a textbook algorithm on a scene beside GL's rules and write a teaching page");
    tcmd->add_option("scene", teach.scene, "Scene file (format refraster-scene/1)")->required();
    std::vector<std::string> algorithm_names;
    std::string algorithm_help = "The algorithm:";
    for (const auto& info : harness::teach_algorithms()) {
        algorithm_names.emplace_back(info.name);
        algorithm_help += "\n  " + std::string(info.name) + ": " + std::string(info.title) + " (" +
                          std::string(info.takes) + ")";
    }
    tcmd->add_option("--algorithm", teach.algorithm, algorithm_help)
        ->required()
        ->check(CLI::IsMember(algorithm_names));
    tcmd->add_option("--against", teach.against,
                     "GL's rules from the reference (ref) or a GL backend (gl: OSMesa, osmesa, "
                     "egl)")
        ->check(CLI::IsMember({"ref", "gl", "osmesa", "egl"}))
        ->capture_default_str();
    tcmd->add_option("--output", teach.output,
                     "Directory for index.html, teach.json and the images algorithm.png, gl.png, "
                     "differences.png")
        ->required();
    tcmd->add_option("--zoom", teach.zoom, "Screen pixels a pixel in the PNG images")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    add_driver_options(tcmd, teach.backend);
    add_profile_options(tcmd, teach.backend.profile);

    StudyArgs study;
    auto* scmd =
        app.add_subcommand("study",
                           "Measure error against run time for precision choices, antialiasing and "
                           "stiff cases, against exact answers (docs/precision-study.md)");
    scmd->add_option("study", study.name, "precision, antialiasing or stability")
        ->required()
        ->check(CLI::IsMember(harness::study_names()));
    scmd->add_option("--output", study.output, "Directory for study.csv, study.svg, summary.md")
        ->required();
    scmd->add_option("--seed", study.seed, "Seed of the workloads")->capture_default_str();
    scmd->add_flag("--quick", study.quick, "Small sizes (seconds, for CI)");
    scmd->add_flag("--quiet", study.quiet, "No progress lines on stderr");

    auto* check_cmd = app.add_subcommand(
        "check", "Load a scene, say what it holds and how fast it loaded (MB/s)");
    check_cmd->add_option("scene", check_scene, "Scene file")->required();
    check_cmd->add_option("--rounds", check_rounds, "Loads; the best time is reported")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();

    // --egl-device list: the devices, whichever command asked and whatever else it requires
    // (before parsing, which would insist on a scene or an output first). --mesa-prefix (or
    // MESA_PREFIX) still applies.
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
        } catch (const harness::BackendOptionError& e) {
            std::cerr << "refraster: " << e.what() << "\n";
            return kExitBadInput;
        } catch (const std::exception& e) {
            std::cerr << "refraster: --egl-device list: " << e.what() << "\n";
            return kExitBackendFailure;
        }
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "refraster: " << e.what() << " (see --help)\n";
        return kExitBadInput;
    }
    if (gen_many->parsed()) return run_generate_many(many_count, gen_seed, many_form, gen_output);
    if (check_cmd->parsed()) return run_check(check_scene, check_rounds);
    if (tcmd->parsed()) return run_teach(teach);
    if (scmd->parsed()) return run_study_command(study);
    if (gen_extreme->parsed())
        return harness::write_extreme_scenes(gen_seed, gen_output, std::cerr);
    if (rcmd->parsed()) return run_render(render);
    if (ccmd->parsed()) return run_compare(compare);
    if (run_cmd->parsed()) return run_conformance(conf);
    if (merge_cmd->parsed()) return run_merge(merge_shards, merge_output);
    if (hash_cmd->parsed()) return run_hashes(hash_scenes, hash_profile);
    if (xcmd->parsed()) return run_explain(explain);
    if (dcmd->parsed()) return run_reduce(reduce);
    if (bcmd->parsed()) return run_bench(bench);
    if (fcmd->parsed()) return cmd_fingerprint(fp);
    if (pcmd->parsed()) {
        try {
            std::cout << harness::profile_to_json(show.load()) << "\n";
            return kExitOk;
        } catch (const refraster::ProfileError& e) {
            std::cerr << "refraster: " << e.what() << "\n";
            return kExitBadInput;
        }
    }
    return kExitBadInput;
}
