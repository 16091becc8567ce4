#include "suite.hpp"

#include <fnmatch.h>

#include <algorithm>
#include <fstream>
#include <ostream>
#include <stdexcept>

#include "harness/case_result.hpp"
#include "harness/image_io.hpp"

namespace conformance {

std::string case_name_for(const std::filesystem::path& root, const std::filesystem::path& file) {
    std::string rel = std::filesystem::relative(file, root).replace_extension("").generic_string();
    std::replace(rel.begin(), rel.end(), '/', '.');
    return rel;
}

std::vector<CaseFile> discover_cases(const std::filesystem::path& root,
                                     const std::vector<std::string>& globs) {
    if (!std::filesystem::is_directory(root)) {
        throw std::runtime_error(root.string() + ": not a directory of scenes");
    }
    std::vector<CaseFile> cases;
    for (const auto& e : std::filesystem::recursive_directory_iterator(root)) {
        if (!e.is_regular_file() || e.path().extension() != ".json") continue;
        CaseFile c{case_name_for(root, e.path()), e.path()};
        const bool keep = globs.empty() || std::any_of(globs.begin(), globs.end(), [&](const auto& g) {
                              return ::fnmatch(g.c_str(), c.name.c_str(), 0) == 0;
                          });
        if (keep) cases.push_back(std::move(c));
    }
    std::sort(cases.begin(), cases.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
    return cases;
}

namespace {

void write_images(const harness::CaseResult& r, const std::filesystem::path& dir) {
    const auto save = [&](const std::optional<harness::RenderResult>& rr, const std::string& who) {
        if (!rr || rr->status != harness::RenderStatus::Ok) return;
        harness::write_color_image(
            rr->image, dir / (r.name + "." + who + std::string(harness::image_extension(rr->image.color_format))));
    };
    save(r.reference, r.reference_name);
    save(r.actual, r.actual_name);
    if (r.comparison && r.comparison->mismatched_pixels > 0 && !r.comparison->size_mismatch) {
        harness::write_color_image(r.comparison->mask, dir / (r.name + ".mask.png"));
    }
}

}  // namespace

RunSummary run_suite(const RunOptions& options, std::ostream& console) {
    const auto cases = discover_cases(options.scenes_root, options.case_globs);
    if (cases.empty()) throw std::runtime_error("no scene matched the selection");

    std::filesystem::create_directories(options.output / "images");
    const auto results_path = options.output / "results.jsonl";
    std::ofstream results(results_path, std::ios::trunc);
    if (!results) throw std::runtime_error(results_path.string() + ": cannot write");

    auto reference = harness::make_backend(options.reference);
    auto actual = harness::make_backend(options.against);

    RunSummary s;
    for (const auto& c : cases) {
        harness::CaseResult r;
        try {
            const harness::Scene scene = harness::load_scene(c.file);
            r = harness::run_case(scene, c.name, *reference, *actual);
            if (!scene.file.name.empty() && scene.file.name != c.name) {
                r.status = harness::CaseStatus::InternalError;
                r.message = c.file.string() + ": name \"" + scene.file.name +
                            "\" does not match its path (expected \"" + c.name + "\")";
            }
        } catch (const harness::SceneError& e) {
            r = harness::case_error(c.name, c.file.string(), e.what());
        }
        try {
            write_images(r, options.output / "images");
        } catch (const harness::ImageIoError& e) {
            if (!harness::counts_as_failure(r.status)) {
                r.status = harness::CaseStatus::InternalError;
                r.message = e.what();
            }
        }
        results << harness::to_json_line(r) << '\n' << std::flush;
        console << to_string(r.status) << " " << r.name;
        if (!r.message.empty()) console << ": " << r.message;
        console << '\n' << std::flush;
        if (r.status == harness::CaseStatus::Pass) {
            ++s.passed;
        } else if (r.status == harness::CaseStatus::NotSupported) {
            ++s.skipped;
        } else {
            ++s.failed;
        }
    }
    console << "results: " << results_path.string() << ", images: "
            << (options.output / "images").string() << "/\n";
    console << s.passed << " passed, " << s.failed << " failed, " << s.skipped << " skipped\n";
    return s;
}

}  // namespace conformance
