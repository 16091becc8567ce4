// render SCENE -o IMAGE: one scene through one backend, written as an image (and, for a 4x
// target with --samples-output, each sample's image), all or none.
#include <filesystem>
#include <iostream>
#include <memory>
#include <new>
#include <vector>

#include "commands/commands.hpp"
#include "harness/encode.hpp"
#include "harness/image_io.hpp"

namespace tool {
namespace {

struct RenderArgs {
    std::string scene;
    SceneArgs scene_args;  // --texture-root
    BackendArgs backend{"ref"};
    std::string output;
    std::string samples_output;  // PREFIX: PREFIX.s0.png .. PREFIX.s3.png for a 4x target
};

int run_render(const RenderArgs& a) {
    const auto scene = load_or_report(a.scene, a.scene_args);
    if (!scene) return kExitBadInput;
    const std::filesystem::path out(a.output);
    const auto want_ext = harness::image_extension(scene->file.target.color);
    if (out.extension() != want_ext) {
        std::cerr << harness::encode::terminal(a.output) << ": the target is "
                  << to_string(scene->file.target.color) << ", so the output must end in "
                  << want_ext << "\n";
        return kExitBadInput;
    }
    const std::uint32_t samples = scene->file.target.samples;
    if (!a.samples_output.empty() && samples == 1) {
        std::cerr << harness::encode::terminal(a.scene)
                  << ": --samples-output needs a multisampled target; target.samples is 1\n";
        return kExitBadInput;
    }
    if (!a.samples_output.empty() &&
        (a.samples_output.back() == '/' || std::filesystem::is_directory(a.samples_output))) {
        std::cerr << harness::encode::terminal(a.samples_output)
                  << ": --samples-output takes a file name prefix (PREFIX.s0" << want_ext
                  << " ...), not a directory\n";
        return kExitBadInput;
    }
    auto backend = backend_or_report(a.backend, a.scene);
    if (!backend) return kExitBackendFailure;
    const harness::RenderResult r = backend->render(*scene);
    if (r.status != harness::RenderStatus::Ok) {
        std::cerr << harness::encode::terminal(a.scene) << ": " << to_string(r.status) << " in "
                  << backend->name() << ": " << harness::encode::terminal(r.message) << "\n";
        return exit_code_for(r.status);
    }
    // The image and every sample's, all or none.
    std::vector<harness::ImageToWrite> images{{&r.image, out}};
    std::vector<refraster::Framebuffer> planes;
    std::vector<std::filesystem::path> sample_paths;
    if (!a.samples_output.empty()) {
        if (r.samples.samples != samples || r.samples.width != r.image.width ||
            r.samples.height != r.image.height) {
            std::cerr << harness::encode::terminal(a.scene) << ": " << backend->name()
                      << " returned no samples of the " << samples
                      << "x target, so --samples-output has nothing to write\n";
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
    } catch (const std::bad_alloc&) {
        throw;  // running out of memory: main reports it (exit 3)
    } catch (const std::exception& e) {
        std::cerr << harness::encode::terminal(e.what()) << "\n";
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

}  // namespace

Command add_render_command(CLI::App& app) {
    auto a = std::make_shared<RenderArgs>();
    auto* cmd = app.add_subcommand("render", "Render one scene file through one backend");
    cmd->add_option("scene", a->scene, "Scene file (format refraster-scene/1)")->required();
    add_scene_options(cmd, a->scene_args);
    add_backend_option(cmd, "--backend", a->backend.backend, "Renderer: ref, osmesa or egl",
                       {"ref", "osmesa", "egl"});
    add_driver_options(cmd, a->backend);
    add_profile_options(cmd, a->backend.profile);
    add_threads_option(cmd, a->backend.threads);
    cmd->add_option("-o,--output", a->output,
                    "Output image: .png for rgba8 targets, .exr for rgba32f")
        ->required();
    cmd->add_option("--samples-output", a->samples_output,
                    "For a 4x target, also each sample's image: PREFIX.s0.png .. PREFIX.s3.png "
                    "(.exr for rgba32f)");
    return {cmd, [a] { return run_render(*a); }};
}

}  // namespace tool
