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
    // With --against ref: the compared reference's own profile (two profiles side by side);
    // empty: the same as --profile.
    std::string against_profile;
    std::vector<std::string> against_overrides;
    std::string json;
    std::string diff;
};

// Writes the mask to `diff` and both images beside it: OUT.<backend>.png (OUT.reference.png and
// OUT.against.png when both sides are one backend), and for a 4x target the sample mask as
// OUT.samples.png; all or none.
void write_diff_images(const harness::CaseResult& r, const std::filesystem::path& diff) {
    const auto beside = [&](const std::string& what, std::string_view ext) {
        auto p = diff;
        p.replace_filename(diff.stem().string() + "." + what + std::string(ext));
        return p;
    };
    std::vector<harness::ImageToWrite> images{{&r.comparison->mask, diff}};
    // Two sides of one backend (two reference profiles, two drivers of one API) are named by
    // their side instead.
    const bool same = r.reference_name == r.actual_name;
    for (const auto& [rr, who] :
         {std::pair{&*r.reference, same ? std::string("reference") : r.reference_name},
          std::pair{&*r.actual, same ? std::string("against") : r.actual_name}}) {
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
    if ((!a.against_profile.empty() || !a.against_overrides.empty()) &&
        a.against.backend != "ref") {
        std::cerr << "--against-profile, --against-profile-set: the profile of a compared "
                     "reference (--against ref); a GL backend has no profile\n";
        return kExitBadInput;
    }
    a.against.profile = a.reference.profile;
    if (!a.against_profile.empty() || !a.against_overrides.empty()) {
        // Two profiles side by side: the compared side starts from its own profile (or the
        // reference's), with its own overrides.
        if (!a.against_profile.empty()) {
            a.against.profile.profile = a.against_profile;
            a.against.profile.overrides.clear();
        }
        for (const auto& o : a.against_overrides) a.against.profile.overrides.push_back(o);
    }
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
    // Two references: each side named by its profile and overrides.
    const auto side = [&](const std::string& backend_name, const BackendArgs& b) {
        if (b.backend != "ref") return backend_name;
        std::string s = backend_name + " " + b.profile.profile;
        for (const auto& o : b.profile.overrides) s += " " + o;
        return s;
    };
    const bool two_profiles = a.reference.backend == "ref" && a.against.backend == "ref";
    std::cout << to_string(r.status) << " " << r.name << " ("
              << (two_profiles ? side(r.reference_name, a.reference) : r.reference_name) << " vs "
              << (two_profiles ? side(r.actual_name, a.against) : r.actual_name) << ")";
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
    cmd->add_option("--against-profile", a->against_profile,
                    "With --against ref: the compared reference's profile, to compare two "
                    "profiles (default: --profile)");
    cmd->add_option("--against-profile-set", a->against_overrides,
                    "With --against ref: override one parameter of the compared reference's "
                    "profile, key=value (repeatable)");
    cmd->add_option("--reference-driver", a->reference_driver,
                    "Mesa driver of a GL --reference (default: --driver)");
    cmd->add_option("--json", a->json, "Write the result record (JSON) here");
    cmd->add_option(
        "--diff", a->diff,
        "Write the error mask here (.png), both images beside it as NAME.<backend>.png "
        "(NAME.reference.png and NAME.against.png when both sides are one backend) and, for a "
        "4x target, the sample mask as NAME.samples.png");
    return {cmd, [a] { return run_compare(*a); }};
}

}  // namespace tool
