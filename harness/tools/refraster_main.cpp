// refraster: the command-line front door. Subcommands share one set of exit codes:
//   0 success, 1 images differ beyond `expect`, 2 bad input or usage,
//   3 backend failure (crash, timeout, internal error), 4 NotSupported.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>

#include "harness/backend.hpp"
#include "harness/image_io.hpp"
#include "harness/scene.hpp"

namespace {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;
constexpr int kExitBackendFailure = 3;
constexpr int kExitNotSupported = 4;

struct RenderArgs {
    std::string scene;
    std::string backend = "ref";
    std::string driver = "llvmpipe";
    std::string output;
    double timeout = 60.0;
};

harness::BackendKind parse_backend(const std::string& s) {
    if (s == "osmesa") return harness::BackendKind::OSMesa;
    if (s == "egl") return harness::BackendKind::Egl;
    return harness::BackendKind::Ref;
}

int run_render(const RenderArgs& a) {
    harness::Scene scene;
    try {
        scene = harness::load_scene(a.scene);
    } catch (const harness::SceneError& e) {
        std::cerr << e.what() << "\n";
        return kExitBadInput;
    }
    const std::filesystem::path out(a.output);
    const auto want_ext = harness::image_extension(scene.file.target.color);
    if (out.extension() != want_ext) {
        std::cerr << a.output << ": the target is " << to_string(scene.file.target.color)
                  << ", so the output must end in " << want_ext << "\n";
        return kExitBadInput;
    }
    std::unique_ptr<harness::Backend> backend;
    try {
        harness::BackendOptions opt;
        opt.kind = parse_backend(a.backend);
        opt.driver = a.driver == "softpipe" ? harness::Driver::Softpipe : harness::Driver::Llvmpipe;
        opt.timeout_seconds = a.timeout;
        backend = harness::make_backend(opt);
    } catch (const std::exception& e) {
        std::cerr << a.scene << ": backend " << a.backend << ": " << e.what() << "\n";
        return kExitBackendFailure;
    }
    const harness::RenderResult r = backend->render(scene);
    switch (r.status) {
        case harness::RenderStatus::Ok: break;
        case harness::RenderStatus::NotSupported:
            std::cerr << a.scene << ": NotSupported by " << backend->name() << ": " << r.message
                      << "\n";
            return kExitNotSupported;
        default:
            std::cerr << a.scene << ": " << to_string(r.status) << " in " << backend->name()
                      << ": " << r.message << "\n";
            return kExitBackendFailure;
    }
    try {
        harness::write_color_image(r.image, out);
    } catch (const harness::ImageIoError& e) {
        std::cerr << e.what() << "\n";
        return kExitBadInput;
    }
    std::cout << "wrote " << out.string() << " (" << backend->name() << ", "
              << r.image.width << "x" << r.image.height << ")\n";
    return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"refraster: a bit-exact reference rasterizer and its comparison harness"};
    app.require_subcommand(1);

    RenderArgs render;
    auto* cmd = app.add_subcommand("render", "Render one scene file through one backend");
    cmd->add_option("scene", render.scene, "Scene file (format refraster-scene/1)")->required();
    cmd->add_option("--backend", render.backend, "Renderer: ref, osmesa or egl")
        ->check(CLI::IsMember({"ref", "osmesa", "egl"}))
        ->capture_default_str();
    cmd->add_option("--driver", render.driver, "Mesa driver for osmesa and egl")
        ->check(CLI::IsMember({"llvmpipe", "softpipe"}))
        ->capture_default_str();
    cmd->add_option("-o,--output", render.output,
                    "Output image: .png for rgba8 targets, .exr for rgba32f")
        ->required();
    cmd->add_option("--timeout", render.timeout, "Seconds a GL backend may take for the scene")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();

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
    if (cmd->parsed()) return run_render(render);
    return kExitBadInput;
}
