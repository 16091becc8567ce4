// compare SCENE: the scene through the reference and a GL backend (or two GL drivers), pixel by
// pixel; the verdict on stdout, and optionally the record (--json) and the error mask (--diff).
#include <filesystem>
#include <iostream>
#include <memory>
#include <new>
#include <string_view>
#include <utility>
#include <vector>

#include "commands/commands.hpp"
#include "harness/case_result.hpp"
#include "harness/encode.hpp"
#include "harness/files.hpp"
#include "harness/image_io.hpp"

namespace tool {
namespace {

struct CompareArgs {
    std::string scene;
    SceneArgs scene_args;  // --texture-root
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
    const auto scene = load_or_report(a.scene, a.scene_args);
    if (!scene) return kExitBadInput;
    if (!a.diff.empty() && std::filesystem::path(a.diff).extension() != ".png") {
        std::cerr << harness::encode::terminal(a.diff) << ": the error mask is written as .png\n";
        return kExitBadInput;
    }
    if (a.reference_driver.empty()) a.reference_driver = a.against.driver;
    a.reference.driver = a.reference_driver;
    a.reference.timeout = a.against.timeout;
    a.against.profile = a.reference.profile;
    a.against.threads = a.reference.threads;
    auto ref = backend_or_report(a.reference, a.scene);
    if (!ref) return kExitBackendFailure;
    auto act = backend_or_report(a.against, a.scene);
    if (!act) return kExitBackendFailure;
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
    } catch (const std::bad_alloc&) {
        throw;  // running out of memory: main reports it (exit 3)
    } catch (const std::exception& e) {
        std::cerr << harness::encode::terminal(e.what()) << "\n";
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
            std::cerr << harness::encode::terminal(a.scene)
                      << ": NotSupported: " << harness::encode::terminal(r.message) << "\n";
            return kExitNotSupported;
        default:
            std::cerr << harness::encode::terminal(a.scene) << ": " << to_string(r.status) << ": "
                      << harness::encode::terminal(r.message) << "\n";
            return kExitBackendFailure;
    }
}

}  // namespace

Command add_compare_command(CLI::App& app) {
    auto a = std::make_shared<CompareArgs>();
    auto* cmd = app.add_subcommand(
        "compare", "Render one scene through the reference and a GL backend and compare pixels");
    cmd->add_option("scene", a->scene, "Scene file (format refraster-scene/1)")->required();
    add_scene_options(cmd, a->scene_args);
    add_backend_option(cmd, "--against", a->against.backend, "Backend compared with the reference",
                       {"ref", "osmesa", "egl"});
    add_backend_option(cmd, "--reference", a->reference.backend,
                       "Backend taken as the truth (ref, or a GL backend to compare two drivers)",
                       {"ref", "osmesa", "egl"});
    add_driver_options(cmd, a->against);
    add_profile_options(cmd, a->reference.profile);
    add_threads_option(cmd, a->reference.threads);
    cmd->add_option("--reference-driver", a->reference_driver,
                    "Mesa driver of a GL --reference (default: --driver)");
    cmd->add_option("--json", a->json, "Write the result record (JSON) here");
    cmd->add_option(
        "--diff", a->diff,
        "Write the error mask here (.png), both images beside it as NAME.<backend>.png and, "
        "for a 4x target, the sample mask as NAME.samples.png");
    return {cmd, [a] { return run_compare(*a); }};
}

}  // namespace tool
