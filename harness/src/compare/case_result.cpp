#include "harness/case_result.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

namespace harness {

using ojson = nlohmann::ordered_json;

std::string_view to_string(CaseStatus s) {
    switch (s) {
        case CaseStatus::Pass:
            return "Pass";
        case CaseStatus::Fail:
            return "Fail";
        case CaseStatus::NotSupported:
            return "NotSupported";
        case CaseStatus::Crash:
            return "Crash";
        case CaseStatus::Timeout:
            return "Timeout";
        case CaseStatus::InternalError:
            return "InternalError";
        case CaseStatus::ExpectedFail:
            return "ExpectedFail";
        case CaseStatus::UnexpectedPass:
            return "UnexpectedPass";
        case CaseStatus::UnexpectedImprovement:
            return "UnexpectedImprovement";
        case CaseStatus::Flake:
            return "Flake";
        case CaseStatus::KnownFlake:
            return "KnownFlake";
    }
    return "?";
}

std::optional<CaseStatus> case_status_from_string(std::string_view s) {
    for (auto c : {CaseStatus::Pass, CaseStatus::Fail, CaseStatus::NotSupported, CaseStatus::Crash,
                   CaseStatus::Timeout, CaseStatus::InternalError, CaseStatus::ExpectedFail,
                   CaseStatus::UnexpectedPass, CaseStatus::UnexpectedImprovement, CaseStatus::Flake,
                   CaseStatus::KnownFlake}) {
        if (to_string(c) == s) return c;
    }
    return std::nullopt;
}

bool counts_as_failure(CaseStatus s) {
    switch (s) {
        case CaseStatus::Pass:
        case CaseStatus::NotSupported:
        case CaseStatus::ExpectedFail:
        case CaseStatus::Flake:
        case CaseStatus::KnownFlake:
            return false;
        default:
            return true;
    }
}

namespace {

// A pixel's four channel values for a record: numbers, and "NaN", "Infinity" or "-Infinity"
// for the values JSON has no number for (an rgba32f target stores them; nlohmann would write
// null, which says nothing).
ojson channels_json(const std::array<double, 4>& v) {
    ojson out = ojson::array();
    for (const double c : v) {
        if (std::isnan(c)) {
            out.push_back("NaN");
        } else if (std::isinf(c)) {
            out.push_back(c > 0 ? "Infinity" : "-Infinity");
        } else {
            out.push_back(c);
        }
    }
    return out;
}

// How a backend's non-Ok status becomes the case's status.
CaseStatus case_status(RenderStatus s) {
    switch (s) {
        case RenderStatus::Ok:
            return CaseStatus::Pass;
        case RenderStatus::NotSupported:
            return CaseStatus::NotSupported;
        case RenderStatus::Crash:
            return CaseStatus::Crash;
        case RenderStatus::Timeout:
            return CaseStatus::Timeout;
        case RenderStatus::InternalError:
            return CaseStatus::InternalError;
    }
    return CaseStatus::InternalError;
}

// A failure outranks NotSupported: a crash must not hide behind the other side's refusal.
int severity(RenderStatus s) {
    switch (s) {
        case RenderStatus::Ok:
            return 0;
        case RenderStatus::NotSupported:
            return 1;
        case RenderStatus::InternalError:
            return 2;
        case RenderStatus::Timeout:
            return 3;
        case RenderStatus::Crash:
            return 4;
    }
    return 5;
}

ojson render_json(const std::string& name, const RenderResult& r) {
    ojson j;
    j["backend"] = name;
    j["status"] = to_string(r.status);
    if (!r.message.empty()) j["message"] = r.message;
    j["seconds"] = r.seconds;
    if (r.round_trip_seconds > 0.0) j["round_trip_seconds"] = r.round_trip_seconds;
    j["provenance"] = ojson(r.provenance);
    return j;
}

}  // namespace

CaseResult run_case(const Scene& scene, const std::string& case_name, Backend& reference,
                    Backend& actual) {
    CaseResult c;
    c.name = case_name;
    c.scene_path = scene.path.string();
    c.expect = scene.file.expect;
    c.reference_name = reference.name();
    c.actual_name = actual.name();
    c.reference = reference.render(scene);
    c.actual = actual.render(scene);
    const RenderResult& worse =
        severity(c.actual->status) >= severity(c.reference->status) ? *c.actual : *c.reference;
    const std::string& worse_name = &worse == &*c.actual ? c.actual_name : c.reference_name;
    if (worse.status != RenderStatus::Ok) {
        c.status = case_status(worse.status);
        c.message = worse_name + ": " + worse.message;
        return c;
    }
    const auto& clear = scene.draw_list.clear;
    const auto& expect = scene.file.expect;
    const bool multisampled = scene.draw_list.target.samples > 1;
    if (multisampled) {
        // Every sample is compared, so both sides must have returned them.
        for (const auto* side : {&*c.reference, &*c.actual}) {
            const auto& ms = side->samples;
            if (ms.samples != scene.draw_list.target.samples ||
                ms.width != scene.draw_list.target.width ||
                ms.height != scene.draw_list.target.height) {
                c.status = CaseStatus::InternalError;
                c.message = (side == &*c.reference ? c.reference_name : c.actual_name) +
                            ": returned no samples of the " +
                            std::to_string(scene.draw_list.target.samples) +
                            "x target, so they cannot be compared";
                return c;
            }
        }
    }
    const auto compare_all = [&] {
        if (multisampled) {
            c.comparison = compare_resolved(c.reference->image, c.actual->image, clear, expect);
            c.sample_comparison =
                compare_samples(c.reference->samples, c.actual->samples, clear, expect);
        } else {
            c.comparison = compare_images(c.reference->image, c.actual->image, clear, expect);
        }
    };
    compare_all();
    const bool mismatch = c.comparison->mismatched_pixels > 0 ||
                          (c.sample_comparison && c.sample_comparison->mismatched_samples > 0);
    const bool comparable = !c.comparison->size_mismatch &&
                            !(c.sample_comparison && c.sample_comparison->size_mismatch);
    if (mismatch && comparable) {
        // Class the mismatch by primitive: a second pass of each side reports which primitive
        // owns every pixel (of a 4x target: every sample). Where a side cannot tell, the
        // clear-colour classes stand.
        // Only the owners of each pass are kept, and each pass's images are freed before the
        // other side's pass runs: at the target limit an image is over a gigabyte. The first
        // comparison's masks go first; it is made again below, with or without owners.
        c.comparison.reset();
        c.sample_comparison.reset();
        const auto owners_of = [&](Backend& side, const RenderResult& plain) {
            RenderResult pass = side.render_owners(scene);
            std::optional<std::vector<std::uint32_t>> owners;
            if (pass.status != RenderStatus::Ok) return owners;
            auto& o = multisampled ? pass.samples.owner : pass.image.owner;
            if (owners_plausible(o, multisampled ? plain.samples : plain.image, clear))
                owners = std::move(o);
            return owners;
        };
        auto ro = owners_of(reference, *c.reference);
        auto ao = ro ? owners_of(actual, *c.actual) : std::nullopt;
        if (ro && ao) {
            for (auto [owners, plain] :
                 {std::pair{&*ro, &*c.reference}, std::pair{&*ao, &*c.actual}}) {
                if (multisampled) {
                    // The resolved image's owners are sample 0's.
                    const std::size_t n = plain->samples.pixel_count();
                    const std::size_t k = plain->samples.samples;
                    plain->image.owner.resize(n);
                    for (std::size_t i = 0; i < n; ++i) {
                        plain->image.owner[i] = (*owners)[i * k];
                    }
                    plain->samples.owner = std::move(*owners);
                } else {
                    plain->image.owner = std::move(*owners);
                }
            }
        }
        compare_all();
    }
    const bool within =
        c.comparison->within_expect && (!c.sample_comparison || c.sample_comparison->within_expect);
    c.status = within ? CaseStatus::Pass : CaseStatus::Fail;
    if (c.status == CaseStatus::Fail) {
        c.message = c.comparison->summary();
        if (c.sample_comparison) c.message += "; " + c.sample_comparison->summary();
    }
    return c;
}

std::optional<std::array<int, 2>> pixel_of_largest_difference(const CaseResult& r) {
    const auto at = [](const auto& d) {
        return std::array<int, 2>{static_cast<int>(d.x), static_cast<int>(d.y)};
    };
    if (r.comparison && r.comparison->max_color) return at(*r.comparison->max_color);
    if (r.sample_comparison && r.sample_comparison->max_color) {
        return at(*r.sample_comparison->max_color);
    }
    if (r.comparison && r.comparison->max_depth) return at(*r.comparison->max_depth);
    if (r.sample_comparison && r.sample_comparison->max_depth) {
        return at(*r.sample_comparison->max_depth);
    }
    return std::nullopt;
}

CaseResult case_error(const std::string& case_name, const std::string& scene_path,
                      const std::string& message) {
    CaseResult c;
    c.name = case_name;
    c.scene_path = scene_path;
    c.status = CaseStatus::InternalError;
    c.message = message;
    return c;
}

std::string to_json_line(const CaseResult& r) {
    ojson j;
    j["case"] = r.name;
    j["status"] = to_string(r.status);
    if (r.raw_status) j["raw_status"] = to_string(*r.raw_status);
    j["scene"] = r.scene_path;
    if (!r.message.empty()) j["message"] = r.message;
    if (r.shard)
        j["shard"] = {
            {"index", (*r.shard)[0]}, {"count", (*r.shard)[1]}, {"source", r.shard_source}};
    j["expect"] = {{"color_tolerance", r.expect.color_tolerance},
                   {"max_mismatched_pixels", r.expect.max_mismatched_pixels}};
    if (r.alone_status)
        j["alone"] = {{"status", to_string(*r.alone_status)},
                      {"mismatched_pixels", r.alone_mismatched_pixels}};
    if (r.reference) j["reference"] = render_json(r.reference_name, *r.reference);
    if (r.actual) j["actual"] = render_json(r.actual_name, *r.actual);
    if (r.comparison) {
        const Comparison& c = *r.comparison;
        ojson k;
        k["size_mismatch"] = c.size_mismatch;
        k["mismatched_pixels"] = c.mismatched_pixels;
        k["missing"] = c.missing;
        k["extra"] = c.extra;
        k["color_only"] = c.color_only;
        k["depth_only"] = c.depth_only;
        k["other_primitive"] = c.coverage;
        k["classified_by"] = c.classified_by_owners ? "primitive owners" : "clear colour";
        if (c.max_color) {
            k["max_color"] = {{"amount", c.max_color->amount},
                              {"x", c.max_color->x},
                              {"y", c.max_color->y},
                              {"channel", c.max_color->channel},
                              {"reference", channels_json(c.max_color->reference)},
                              {"actual", channels_json(c.max_color->actual)}};
            // rgba32f: the amount counts ULPs between the float values.
            if (c.max_color->float_values) k["max_color"]["units"] = "ULPs";
        }
        if (c.max_depth) {
            k["max_depth"] = {{"amount", c.max_depth->amount},
                              {"x", c.max_depth->x},
                              {"y", c.max_depth->y},
                              {"reference", c.max_depth->reference},
                              {"actual", c.max_depth->actual}};
            // z32f: reference and actual are the floats' bits, the amount ULPs between them.
            if (c.max_depth->float_bits) k["max_depth"]["units"] = "ULPs";
        }
        if (r.sample_comparison) {
            const SampleComparison& m = *r.sample_comparison;
            k["samples"] = m.samples;
            k["sample_size_mismatch"] = m.size_mismatch;
            k["mismatched_samples"] = m.mismatched_samples;
            k["pixels_with_mismatched_samples"] = m.pixels_with_mismatched_samples;
            ojson per = ojson::array();
            for (std::size_t s = 0; s < m.per_sample.size(); ++s) {
                const Comparison& p = m.per_sample[s];
                per.push_back({{"sample", s},
                               {"mismatched", p.mismatched_pixels},
                               {"missing", p.missing},
                               {"extra", p.extra},
                               {"other_primitive", p.coverage},
                               {"color_only", p.color_only},
                               {"depth_only", p.depth_only}});
            }
            k["per_sample"] = per;
            k["samples_classified_by"] =
                m.classified_by_owners ? "primitive owners" : "clear colour";
            if (m.max_color) {
                k["max_sample_color"] = {{"amount", m.max_color->amount},
                                         {"x", m.max_color->x},
                                         {"y", m.max_color->y},
                                         {"sample", m.max_color->sample},
                                         {"channel", m.max_color->channel},
                                         {"reference", channels_json(m.max_color->reference)},
                                         {"actual", channels_json(m.max_color->actual)}};
                if (m.max_color->float_values) k["max_sample_color"]["units"] = "ULPs";
            }
            if (m.max_depth) {
                k["max_sample_depth"] = {{"amount", m.max_depth->amount},
                                         {"x", m.max_depth->x},
                                         {"y", m.max_depth->y},
                                         {"sample", m.max_depth->sample},
                                         {"reference", m.max_depth->reference},
                                         {"actual", m.max_depth->actual}};
                if (m.max_depth->float_bits) k["max_sample_depth"]["units"] = "ULPs";
            }
        }
        j["comparison"] = k;
    }
    if (!r.gl_verdict.empty()) j["gl_verdict"] = r.gl_verdict;
    if (r.explained_pixel) {
        j["explanation"] = {{"pixel", *r.explained_pixel},
                            {"difference", r.explanation_difference},
                            {"rule", r.explanation_rule},
                            {"verdict", r.explanation}};
    }
    return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace harness
