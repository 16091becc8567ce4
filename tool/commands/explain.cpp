// explain SCENE --pixel X,Y: every decision the reference takes about one pixel (or one sample
// of it), beside the backend's bytes, as text, JSON or an SVG of its neighbourhood.
#include "harness/explain.hpp"

#include <algorithm>
#include <array>
#include <iostream>
#include <memory>
#include <new>

#include "commands/commands.hpp"
#include "harness/backend.hpp"
#include "harness/encode.hpp"
#include "harness/files.hpp"
#include "harness/gl_verdict.hpp"
#include "refraster/renderer.hpp"

namespace tool {
namespace {

struct ExplainArgs {
    std::string scene;
    SceneArgs scene_args;  // --texture-root
    std::string pixel;
    bool json = false;
    std::string svg;
    BackendArgs against{"osmesa"};
    bool no_backend = false;
    int sample = -1;  // -1: the resolved pixel
};

int run_explain(const ExplainArgs& a) {
    const auto scene = load_or_report(a.scene, a.scene_args);
    if (!scene) return kExitBadInput;
    const auto pixel = parse_pixel(a.pixel);
    if (!pixel) {
        std::cerr << "refraster explain: --pixel " << harness::encode::terminal(a.pixel)
                  << ": expected X,Y\n";
        return kExitBadInput;
    }
    const int x = (*pixel)[0];
    const int y = (*pixel)[1];
    const auto& target = scene->draw_list.target;
    if (!inside(target, *pixel)) {
        std::cerr << harness::encode::terminal(a.scene) << ": --pixel "
                  << harness::encode::terminal(a.pixel) << ": outside the " << target.width << "x"
                  << target.height << " target\n";
        return kExitBadInput;
    }
    if (a.sample >= 0 && target.samples != 4) {
        std::cerr << harness::encode::terminal(a.scene) << ": --sample " << a.sample
                  << ": the target has " << target.samples << " sample"
                  << (target.samples == 1 ? "" : "s") << " (--sample needs a 4x target)\n";
        return kExitBadInput;
    }
    refraster::Profile profile;
    std::unique_ptr<harness::Backend> backend;
    if (const auto rc = profile_and_backend(a.against, a.scene, !a.no_backend, profile, backend))
        return *rc;
    try {
        harness::Explainer explainer(*scene, profile, backend.get(), a.sample, a.against.timeout);
        auto e = explainer.explain(x, y);
        // Whether GL allows the backend's pixel (gl_verdict.hpp), for a differing pixel, judged
        // over the same variations (rule_search.hpp). A 4x target is judged sample by sample,
        // at the sample explained or sample 0; the explanation's rule is the variation preferred.
        if (!e.agree && e.backend && e.backend->status == harness::RenderStatus::Ok) {
            std::string preferred;
            for (const auto& [rule, change] : e.candidates)
                if (rule == e.rule) preferred = change;
            const bool multisampled = e.backend->samples.width > 0;
            const auto v = harness::gl_verdict(*scene, profile, explainer.reference_render(),
                                               multisampled ? e.backend->samples : e.backend->image,
                                               std::array<int, 2>{x, y}, a.against.timeout,
                                               std::max(a.sample, 0), preferred);
            e.gl_verdict = v.at_pixel;
        }
        std::cout << (a.json ? harness::explanation_json(e) + "\n" : harness::explanation_text(e));
        if (!a.json && !e.gl_verdict.empty()) std::cout << "GL: " << e.gl_verdict << "\n";
        if (!a.svg.empty()) harness::write_file_atomically(a.svg, harness::explanation_svg(e));
        return e.agree ? kExitOk : kExitMismatch;
    } catch (const std::bad_alloc&) {
        throw;  // running out of memory: main reports it (exit 3)
    } catch (const refraster::RenderStopped& ex) {
        // The reference ran out of --timeout (its message names the scene).
        std::cerr << "refraster explain: " << harness::encode::terminal(ex.what()) << "\n";
        return kExitBackendFailure;
    } catch (const std::exception& ex) {
        std::cerr << harness::encode::terminal(a.scene) << ": "
                  << harness::encode::terminal(ex.what()) << "\n";
        return kExitBackendFailure;
    }
}

}  // namespace

Command add_explain_command(CLI::App& app) {
    auto a = std::make_shared<ExplainArgs>();
    auto* cmd = app.add_subcommand(
        "explain", "Trace every decision about one pixel, and where the backend departs from them");
    cmd->add_option("scene", a->scene, "Scene file (format refraster-scene/1)")->required();
    add_scene_options(cmd, a->scene_args);
    cmd->add_option("--pixel", a->pixel,
                    "The pixel, X,Y in window coordinates (row 0 at the bottom)")
        ->required();
    cmd->add_flag("--json", a->json, "Print the trace and verdict as JSON");
    cmd->add_option("--svg", a->svg,
                    "Draw the pixel's neighbourhood at subpixel zoom into this SVG file");
    add_backend_option(cmd, "--against", a->against.backend, "GL backend whose bytes to compare",
                       {"osmesa", "egl"});
    cmd->add_flag("--no-backend", a->no_backend, "Trace the reference alone");
    cmd->add_option("--sample", a->sample,
                    "On a 4x target, explain sample S (0..3) of the pixel instead of its resolve")
        ->check(CLI::Range(0, 3));
    add_driver_options(cmd, a->against);
    add_profile_options(cmd, a->against.profile);
    return {cmd, [a] { return run_explain(*a); }};
}

}  // namespace tool
