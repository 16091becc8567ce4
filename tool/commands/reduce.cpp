// reduce SCENE -o OUT: the scene shrunk, primitive by primitive, while the backend keeps the
// same mismatch with the reference; written as a valid scene of its own.
#include "harness/reduce.hpp"

#include <filesystem>
#include <iostream>
#include <memory>
#include <new>

#include "commands/commands.hpp"
#include "harness/encode.hpp"
#include "harness/files.hpp"
#include "harness/scene_text.hpp"
#include "refraster/renderer.hpp"

namespace tool {
namespace {

struct ReduceArgs {
    std::string scene;
    SceneArgs scene_args;  // --texture-root
    std::string output;
    std::string pixel;
    std::string difference;
    BackendArgs against{"osmesa"};
};

int run_reduce(const ReduceArgs& a) {
    const auto scene = load_or_report(a.scene, a.scene_args);
    if (!scene) return kExitBadInput;
    harness::MismatchToKeep keep;
    keep.difference = a.difference;
    if (!a.pixel.empty()) {
        keep.pixel = parse_pixel(a.pixel);
        if (!keep.pixel) {
            std::cerr << "refraster reduce: --pixel " << harness::encode::terminal(a.pixel)
                      << ": expected X,Y\n";
            return kExitBadInput;
        }
        if (!inside(scene->draw_list.target, *keep.pixel)) {
            std::cerr << harness::encode::terminal(a.scene) << ": --pixel "
                      << harness::encode::terminal(a.pixel) << ": outside the "
                      << scene->draw_list.target.width << "x" << scene->draw_list.target.height
                      << " target\n";
            return kExitBadInput;
        }
    }
    refraster::Profile profile;
    std::unique_ptr<harness::Backend> backend;
    if (const auto rc = profile_and_backend(a.against, a.scene, true, profile, backend)) return *rc;
    try {
        const auto r = harness::reduce_scene(scene->file, a.scene, profile, *backend, std::cout,
                                             keep, a.against.timeout);
        auto reduced = r.scene;
        // The reduced scene is a scene of its own: named after its file, as a scene under
        // conformance/scenes is named after its path.
        reduced.name = std::filesystem::path(a.output).stem().string();
        reduced.description =
            "Reduced from " + a.scene + " (" + std::to_string(r.primitives_before) + " -> " +
            std::to_string(r.primitives_after) + " primitives), keeping a " + r.signature +
            " mismatch" +
            (keep.pixel                ? " at pixel " + a.pixel
             : keep.difference.empty() ? ""
                                       : " of class " + keep.difference) +
            " under profile " + profile.name + ", against " + backend->name() + ".";
        const std::string text = harness::scene_to_json(reduced);
        (void)harness::load_scene_text(text, a.output);  // what is written is a valid scene
        harness::write_file_atomically(a.output, text);
        std::cout << "wrote " << a.output << "\n";
        return kExitOk;
    } catch (const harness::SceneError& e) {
        // The reducer's own output failed to load: a bug, not the user's input.
        std::cerr << "refraster reduce: internal error, the reduced scene is invalid: "
                  << harness::encode::terminal(e.what()) << "\n";
        return kExitBackendFailure;
    } catch (const std::bad_alloc&) {
        throw;  // running out of memory: main reports it (exit 3)
    } catch (const refraster::RenderStopped& e) {
        // The reference ran out of --timeout: the run was cut short, as for a GL backend.
        std::cerr << "refraster reduce: " << harness::encode::terminal(e.what()) << "\n";
        return kExitBackendFailure;
    } catch (const std::exception& e) {
        std::cerr << "refraster reduce: " << harness::encode::terminal(e.what()) << "\n";
        return kExitBadInput;
    }
}

}  // namespace

Command add_reduce_command(CLI::App& app) {
    auto a = std::make_shared<ReduceArgs>();
    auto* cmd =
        app.add_subcommand("reduce", "Shrink a failing scene while it keeps the same mismatch");
    cmd->add_option("scene", a->scene, "Scene file that mismatches")->required();
    add_scene_options(cmd, a->scene_args);
    cmd->add_option("-o,--output", a->output,
                    "Where to write the reduced scene (.json); it is named after the file")
        ->required();
    cmd->add_option("--pixel", a->pixel,
                    "Keep the mismatch at this pixel, X,Y (default: the largest difference)");
    cmd->add_option("--class", a->difference, "Keep the largest mismatch of this class")
        ->check(CLI::IsMember({"coverage", "colour", "depth"}));
    add_backend_option(cmd, "--against", a->against.backend, "GL backend", {"osmesa", "egl"});
    add_driver_options(cmd, a->against);
    add_profile_options(cmd, a->against.profile);
    return {cmd, [a] { return run_reduce(*a); }};
}

}  // namespace tool
