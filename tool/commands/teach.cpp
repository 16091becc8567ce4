// teach SCENE --algorithm A --output DIR: a textbook algorithm run on the scene beside GL's
// rules (from the reference or a GL backend), written as a teaching page with its images.
#include "harness/teach.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <new>
#include <optional>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "commands/commands.hpp"
#include "harness/encode.hpp"
#include "harness/files.hpp"
#include "harness/image_io.hpp"
#include "harness/teach_frames.hpp"
#include "harness/teach_page.hpp"

namespace tool {
namespace {

struct TeachArgs {
    std::string scene;
    SceneArgs scene_args;  // --texture-root
    std::string algorithm;
    std::string beside;           // a second algorithm, drawn where GL's image is
    std::string against = "ref";  // ref, or a GL backend: gl (OSMesa), osmesa, egl
    BackendArgs backend{"ref"};
    std::string output;
    int zoom = 8;
    // Lecture frames: each step of FIRST-LAST (1-based) as frames/step-NNNN.svg and .png, and
    // the same steps as frames/steps.gif at `frame_rate` frames a second.
    bool frames = false;
    std::string frame_steps;
    int frame_rate = 4;
};

// "K-L" (1-based, inclusive) or "K": the steps to draw as frames, checked against the run's
// step count and kMaxTeachFrames. Returns the 0-based [first, last], or an error message.
std::variant<std::pair<std::size_t, std::size_t>, std::string> frame_range(const std::string& text,
                                                                           std::size_t steps) {
    if (steps == 0) return std::string("the algorithm recorded no steps to draw");
    std::size_t first = 1, last = std::min(steps, harness::kMaxTeachFrames);
    if (!text.empty()) {
        const auto dash = text.find('-');
        const auto parse = [](const std::string& t) -> std::optional<std::size_t> {
            if (t.empty() || t.size() > 9 ||
                !std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; }))
                return std::nullopt;
            return static_cast<std::size_t>(std::stoul(t));
        };
        const auto a = parse(text.substr(0, dash));
        const auto b = dash == std::string::npos ? a : parse(text.substr(dash + 1));
        if (!a || !b || *a < 1 || *b < *a)
            return "'" + text + "' is not a range of steps K-L with 1 <= K <= L";
        first = *a;
        last = *b;
    }
    if (last > steps)
        return "step " + std::to_string(last) + " is past the run's " + std::to_string(steps) +
               " steps";
    if (last - first + 1 > harness::kMaxTeachFrames)
        return std::to_string(last - first + 1) + " frames, over the limit of " +
               std::to_string(harness::kMaxTeachFrames) + " (choose fewer steps)";
    return std::pair{first - 1, last - 1};
}

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
    const auto scene = load_or_report(a.scene, a.scene_args);
    if (!scene) return kExitBadInput;
    if (scene->file.target.samples != 1) {
        std::cerr << harness::encode::terminal(a.scene)
                  << ": target.samples: teach compares single-sample targets, got "
                  << scene->file.target.samples << "\n";
        return kExitBadInput;
    }
    // Every bound on the input before any work (docs/limits.md, "Teaching pages").
    try {
        harness::check_teach_input(*scene, a.algorithm);
        if (!a.beside.empty()) harness::check_teach_input(*scene, a.beside);
    } catch (const harness::TeachError& e) {
        std::cerr << a.scene << ": " << e.what() << "\n";
        return exit_code(e.exit_class());
    }
    {
        const std::uint64_t zoomed =
            std::uint64_t{scene->file.target.width} * scene->file.target.height *
            static_cast<std::uint64_t>(a.zoom) * static_cast<std::uint64_t>(a.zoom);
        if (zoomed > harness::TeachLimits::kMaxImagePixels) {
            std::cerr << "--zoom: " << a.zoom << " makes images of "
                      << scene->file.target.width * static_cast<std::uint64_t>(a.zoom) << " x "
                      << scene->file.target.height * static_cast<std::uint64_t>(a.zoom) << " = "
                      << zoomed << " pixels, over the limit of "
                      << harness::TeachLimits::kMaxImagePixels << " (docs/limits.md)\n";
            return kExitBadInput;
        }
    }
    a.backend.backend = a.against == "gl" ? "osmesa" : a.against;
    auto backend = backend_or_report(a.backend, a.scene);
    if (!backend) return kExitBackendFailure;
    // The owner pass: which primitive lit each pixel, so that coverage is known even where a
    // colour equals the clear colour.
    const harness::RenderResult gl = backend->render_owners(*scene);
    if (gl.status != harness::RenderStatus::Ok) {
        std::cerr << harness::encode::terminal(a.scene) << ": " << to_string(gl.status) << " in "
                  << backend->name() << ": " << harness::encode::terminal(gl.message) << "\n";
        return exit_code_for(gl.status);
    }
    harness::TeachResult r;
    try {
        r = harness::teach(*scene, a.algorithm, gl.image);
        if (!a.beside.empty())
            r = harness::teach_beside(r, harness::teach(*scene, a.beside, gl.image));
    } catch (const harness::TeachError& e) {
        std::cerr << harness::encode::terminal(a.scene) << ": "
                  << harness::encode::terminal(e.what()) << "\n";
        return exit_code(e.exit_class());
    }
    std::pair<std::size_t, std::size_t> frames{0, 0};
    if (a.frames) {
        const auto range = frame_range(a.frame_steps, r.steps.size());
        if (const auto* error = std::get_if<std::string>(&range)) {
            std::cerr << "--frame-steps: " << harness::encode::terminal(*error) << "\n";
            return kExitBadInput;
        }
        frames = std::get<std::pair<std::size_t, std::size_t>>(range);
    } else if (!a.frame_steps.empty()) {
        std::cerr << "--frame-steps: draws frames only with --frames\n";
        return kExitBadInput;
    }
    const auto prov = [&](const char* key) {
        const auto it = gl.provenance.find(key);
        return it == gl.provenance.end() ? std::string("?") : it->second;
    };
    std::string source = a.against == "ref" ? "the reference rasterizer, profile " + prov("profile")
                                            : backend->name() + " (" + prov("renderer") + ")";
    if (!a.beside.empty())
        source += "; the middle image is " + r.beside +
                  "'s, and each difference gives both algorithms' reasons against GL's rules";
    auto data = harness::teach_json(r, *scene, a.scene, source);
    // The options that chose this page's GL image and pictures, for its "Reproduce this page"
    // command (defaults left out), each a shell word.
    {
        const auto word = [](const std::string& w) { return harness::encode::shell_word(w); };
        std::string options;
        const auto add = [&](const char* flag, const std::string& value) {
            options += std::string(" ") + flag + " " + word(value);
        };
        if (!a.scene_args.texture_root.empty()) add("--texture-root", a.scene_args.texture_root);
        if (!a.beside.empty()) add("--beside", a.beside);
        if (a.against != "ref") add("--against", a.against);
        if (!a.backend.driver.empty()) add("--driver", a.backend.driver);
        if (!a.backend.mesa_prefix.empty()) add("--mesa-prefix", a.backend.mesa_prefix);
        if (!a.backend.egl_device.empty()) add("--egl-device", a.backend.egl_device);
        if (a.backend.profile.profile != ProfileArgs{}.profile)
            add("--profile", a.backend.profile.profile);
        for (const auto& o : a.backend.profile.overrides) add("--profile-set", o);
        if (a.zoom != TeachArgs{}.zoom) add("--zoom", std::to_string(a.zoom));
        data["command_options"] = options;
    }
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
    // The page's bytes, before anything is written.
    const std::string json_text = data.dump(1) + "\n";
    const std::string html = harness::teach_page_html(data);
    for (const auto& [name, bytes] :
         {std::pair<const char*, std::size_t>{"teach.json", json_text.size()},
          std::pair<const char*, std::size_t>{"index.html", html.size()}}) {
        if (bytes > harness::TeachLimits::kMaxPageBytes) {
            std::cerr << a.scene << ": the page's " << name << " would take " << bytes
                      << " bytes, over the limit of " << harness::TeachLimits::kMaxPageBytes
                      << " (docs/limits.md); nothing written\n";
            return kExitBadInput;
        }
    }
    try {
        std::filesystem::create_directories(dir);
        harness::write_color_images({{&algorithm_png, dir / "algorithm.png"},
                                     {&gl_png, dir / "gl.png"},
                                     {&mask_png, dir / "differences.png"}});
        harness::write_file_atomically(dir / "teach.json", json_text);
        harness::write_file_atomically(dir / "index.html", html);
        if (a.frames) {
            // The lecture frames: each step's SVG and PNG, then the animation of them all.
            const auto fdir = dir / "frames";
            std::filesystem::create_directories(fdir);
            harness::TeachFrames f(r, a.zoom);
            std::vector<refraster::Framebuffer> images;
            for (std::size_t k = frames.first; k <= frames.second; ++k) {
                f.seek(k);
                char name[32];
                std::snprintf(name, sizeof name, "step-%04zu", k + 1);
                harness::write_file_atomically(fdir / (std::string(name) + ".svg"), f.svg());
                images.push_back(f.image());
                harness::write_color_image(images.back(), fdir / (std::string(name) + ".png"));
                if (::isatty(STDERR_FILENO) != 0 && (k - frames.first) % 50 == 49)
                    std::cerr << "frames: " << (k - frames.first + 1) << " of "
                              << (frames.second - frames.first + 1) << "\n";
            }
            harness::write_color_animation(images, fdir / "steps.gif", a.frame_rate);
        }
    } catch (const std::bad_alloc&) {
        throw;  // running out of memory: main reports it (exit 3)
    } catch (const std::exception& e) {
        std::cerr << harness::encode::terminal(a.output) << ": "
                  << harness::encode::terminal(e.what()) << "\n";
        return kExitBadInput;
    }
    std::cout << r.title << " on " << scene->file.name << " against " << source << ": " << r.summary
              << "; " << r.steps.size() << " steps";
    if (r.omitted_steps > 0) std::cout << " (" << r.omitted_steps << " more not recorded)";
    std::cout << "\n";
    std::cout << "wrote " << (dir / "index.html").string() << "\n";
    if (a.frames)
        std::cout << "wrote " << (frames.second - frames.first + 1) << " frames (steps "
                  << frames.first + 1 << " to " << frames.second + 1 << ") to "
                  << (dir / "frames").string() << ": step-NNNN.svg, step-NNNN.png, steps.gif\n";
    return kExitOk;
}

}  // namespace

Command add_teach_command(CLI::App& app) {
    auto a = std::make_shared<TeachArgs>();
    auto* cmd = app.add_subcommand(
        "teach", "Run a textbook algorithm on a scene beside GL's rules and write a teaching page");
    cmd->add_option("scene", a->scene, "Scene file (format refraster-scene/1)")->required();
    add_scene_options(cmd, a->scene_args);
    std::vector<std::string> algorithm_names;
    std::string algorithm_help = "The algorithm:";
    for (const auto& info : harness::teach_algorithms()) {
        algorithm_names.emplace_back(info.name);
        algorithm_help += "\n  " + std::string(info.name) + ": " + std::string(info.title) + " (" +
                          std::string(info.takes) + ")";
    }
    cmd->add_option("--algorithm", a->algorithm, algorithm_help)
        ->required()
        ->check(CLI::IsMember(algorithm_names));
    cmd->add_option("--beside", a->beside,
                    "A second algorithm, drawn where GL's image is: two algorithms side by side, "
                    "each difference with both one's reasons against GL's rules")
        ->check(CLI::IsMember(algorithm_names));
    cmd->add_option("--against", a->against,
                    "GL's rules from the reference (ref) or a GL backend (gl: OSMesa, osmesa, "
                    "egl)")
        ->check(CLI::IsMember({"ref", "gl", "osmesa", "egl"}))
        ->capture_default_str();
    cmd->add_option("-o,--output", a->output,
                    "Directory for index.html, teach.json and the images algorithm.png, gl.png, "
                    "differences.png")
        ->required();
    cmd->add_option("--zoom", a->zoom, "Screen pixels a pixel in the PNG images")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    cmd->add_flag("--frames", a->frames,
                  "Also write each step as frames/step-NNNN.svg and .png, and the steps as an "
                  "animation, frames/steps.gif (for slides and handouts)");
    cmd->add_option("--frame-steps", a->frame_steps,
                    "The steps drawn by --frames, K-L counted from 1 (default: the first " +
                        std::to_string(harness::kMaxTeachFrames) + ", the most one run draws)");
    cmd->add_option("--frame-rate", a->frame_rate, "Frames a second in frames/steps.gif")
        ->check(CLI::Range(1, 50))
        ->capture_default_str();
    add_driver_options(cmd, a->backend);
    add_profile_options(cmd, a->backend.profile);
    return {cmd, [a] { return run_teach(*a); }};
}

}  // namespace tool
