// precision.cpp: `refraster study precision`: every rule variant (variants.hpp) on every family
// (workloads.hpp), its errors against the exact oracle and its run time.
//
// Errors, per variant and family:
// - misclassified centres: centres the variant covers and the oracle does not, or the reverse,
//   summed over triangles (each triangle against its own exact coverage);
// - on the mesh families, holes (centres of the mesh's square no triangle covers) and double
//   hits (centres two or more triangles cover): the oracle has neither, by GL's tie rule;
// - attribute error at the centres the oracle covers: in float32 units in the last place of the
//   exact value (max and mean) and absolute (max);
// - depth order inversions: pairs of triangles the oracle puts at one centre, drawn in order
//   with GL_LESS, where the variant's stored depths let the later one pass and the exact depths
//   do not, or the reverse; pairs whose exact depths are closer than 1e-12 (below the double
//   rounding of the oracle's weights) are not counted.
// Run time: the variant's kernel over the whole family (setup, traversal of each bounding box,
// interpolation and depth at covered centres), the best of three runs (one with --quick),
// with the errors computed afterwards and untimed. The fast core itself (refraster::render under
// llvmpipe-22.3, one thread, depth test on z24) draws the same families as a calibration point.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <map>
#include <numeric>
#include <sstream>

#include "harness/study.hpp"
#include "plot.hpp"
#include "refraster/renderer.hpp"
#include "study_common.hpp"
#include "variants.hpp"
#include "workloads.hpp"

namespace harness {

namespace {

using namespace study;

// Three significant digits, for the summary's sentences (the CSV keeps every digit).
std::string short_number(double v) {
    std::ostringstream o;
    o << std::setprecision(3) << v;
    return o.str();
}

struct Errors {
    std::uint64_t exact_centres = 0;
    std::uint64_t misclassified = 0;
    std::uint64_t holes = 0;
    std::uint64_t double_hits = 0;
    std::uint64_t attribute_samples = 0;
    double max_ulps = 0.0;
    double sum_ulps = 0.0;
    double max_abs = 0.0;
    std::uint64_t depth_pairs = 0;
    std::uint64_t depth_inversions = 0;
    std::uint64_t degenerate = 0;  // triangles with no plane in the variant's arithmetic
    double seconds = 0.0;
};

// Centres of one triangle that are in one row-major list and not the other.
template <typename A, typename B>
std::uint64_t symmetric_difference(const std::vector<A>& a, const std::vector<B>& b) {
    const auto key = [](const auto& f) { return std::pair{f.y, f.x}; };
    return count_difference(a, b, key, key);
}

struct ExactFamily {
    std::vector<std::vector<ExactFragment>> per_triangle;
    std::uint64_t centres = 0;
    double seconds = 0.0;
};

ExactFamily exact_family(const Family& f) {
    ExactFamily e;
    const auto t0 = std::chrono::steady_clock::now();
    for (const ClipTriangle& t : f.triangles) {
        e.per_triangle.push_back(exact_fragments(t, f.viewport));
        e.centres += e.per_triangle.back().size();
    }
    e.seconds = seconds_since(t0);
    return e;
}

double time_variant(const Variant& v, const Family& f, int repeats,
                    std::vector<std::vector<Fragment>>& out) {
    double best = 1e300;
    out.resize(f.triangles.size());
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        for (std::size_t i = 0; i < f.triangles.size(); ++i)
            rasterize(v, f.triangles[i], f.viewport, out[i]);
        best = std::min(best, seconds_since(t0));
    }
    return best;
}

Errors measure(const Variant& v, const Family& f, const ExactFamily& e,
               const std::vector<std::vector<Fragment>>& frags) {
    Errors r;
    r.exact_centres = e.centres;
    for (std::size_t i = 0; i < f.triangles.size(); ++i)
        r.misclassified += symmetric_difference(frags[i], e.per_triangle[i]);
    if (f.mesh) {
        const auto n = static_cast<std::size_t>(f.mesh_size);
        std::vector<std::uint8_t> hits(n * n);
        for (const auto& list : frags)
            for (const Fragment& g : list) {
                const int x = g.x - f.mesh_x0, y = g.y - f.mesh_x0;
                if (x < 0 || y < 0 || x >= f.mesh_size || y >= f.mesh_size) continue;
                auto& h = hits[static_cast<std::size_t>(y) * n + static_cast<std::size_t>(x)];
                h = static_cast<std::uint8_t>(std::min(h + 1, 2));
            }
        for (std::uint8_t h : hits) {
            r.holes += h == 0;
            r.double_hits += h >= 2;
        }
    }
    // Values at the oracle's centres, and the depth each pixel's triangles store there.
    std::map<std::pair<int, int>, std::vector<std::pair<double, double>>> depths;  // exact, stored
    for (std::size_t i = 0; i < f.triangles.size(); ++i) {
        const auto& at = e.per_triangle[i];
        if (at.empty()) continue;
        const auto values = evaluate_at(v, f.triangles[i], f.viewport, at);
        if (!values.empty() && !values[0]) ++r.degenerate;
        for (std::size_t k = 0; k < at.size(); ++k) {
            if (!values[k]) continue;
            const double a = values[k]->attribute;
            if (!std::isfinite(a)) {
                r.max_ulps = std::numeric_limits<double>::infinity();
                r.max_abs = std::numeric_limits<double>::infinity();
            } else {
                const double u = float32_ulps(a, at[k].attribute);
                r.max_ulps = std::max(r.max_ulps, u);
                r.sum_ulps += u;
                r.max_abs = std::max(r.max_abs, std::fabs(a - at[k].attribute));
            }
            ++r.attribute_samples;
            depths[{at[k].x, at[k].y}].emplace_back(at[k].depth, values[k]->depth);
        }
    }
    for (const auto& [pixel, list] : depths) {
        for (std::size_t i = 0; i < list.size(); ++i) {
            for (std::size_t j = i + 1; j < list.size(); ++j) {
                const double ez = list[j].first - list[i].first;
                if (std::fabs(ez) <= 1e-12) continue;
                ++r.depth_pairs;
                const bool exact_passes = ez < 0.0;
                const bool variant_passes = list[j].second < list[i].second;
                r.depth_inversions += exact_passes != variant_passes;
            }
        }
    }
    return r;
}

// The fast core on the same family: refraster::render with the llvmpipe-22.3 profile.
std::optional<double> time_fast_core(const Family& f, int repeats) {
    if (f.viewport.width > 4096) return std::nullopt;  // a 16384^2 target is 2 GiB of pixels
    refraster::DrawList list;
    list.target = {static_cast<std::uint32_t>(f.viewport.width),
                   static_cast<std::uint32_t>(f.viewport.height), refraster::ColorFormat::Rgba8,
                   refraster::DepthFormat::Z24, 1};
    refraster::Draw d;
    d.state.viewport = {0, 0, f.viewport.width, f.viewport.height};
    d.state.depth_test = refraster::CompareFunc::Less;
    d.vertices.attributes = {{"color", 4}};
    for (const ClipTriangle& t : f.triangles)
        for (const ClipVertex& v : t) {
            for (double c : v.position) d.vertices.data.push_back(static_cast<float>(c));
            const auto a = static_cast<float>(v.attribute);
            d.vertices.data.insert(d.vertices.data.end(), {a, a, a, 1.0f});
        }
    list.draws.push_back(std::move(d));
    refraster::RenderOptions o;
    o.profile = refraster::llvmpipe_22_3_profile();
    o.threads = 1;
    double best = 1e300;
    for (int r = 0; r < repeats; ++r) {
        refraster::Framebuffer fb;
        const auto t0 = std::chrono::steady_clock::now();
        refraster::render(list, o, fb);
        best = std::min(best, seconds_since(t0));
    }
    return best;
}

struct Row {
    Variant variant;
    std::string family;
    Errors errors;
};

}  // namespace

StudyOutput run_precision_study(const StudyOptions& options) {
    const auto families = precision_families(options.seed, options.quick);
    const auto variants = all_variants();
    const int repeats = options.quick ? 1 : 3;
    CsvTable csv({"study",
                  "family",
                  "seed",
                  "variant",
                  "coverage",
                  "interpolation",
                  "depth",
                  "triangles",
                  "exact_centres",
                  "misclassified",
                  "misclassified_ppm",
                  "holes",
                  "double_hits",
                  "degenerate",
                  "attribute_max_ulps",
                  "attribute_mean_ulps",
                  "attribute_max_abs",
                  "depth_pairs",
                  "depth_inversions",
                  "ms",
                  "ns_per_triangle"});
    std::vector<Row> rows;
    std::map<std::string, double> fast_core_ms;
    double fast_core_total = 0.0;
    std::size_t fast_core_triangles = 0;
    for (const Family& f : families) {
        report(options, "precision: family " + f.name + " (" + std::to_string(f.triangles.size()) +
                            " triangles): exact oracle");
        const ExactFamily e = exact_family(f);
        std::vector<std::vector<Fragment>> frags;
        for (std::size_t vi = 0; vi < variants.size(); ++vi) {
            const Variant& v = variants[vi];
            report(options, "precision: family " + f.name + ", variant " + v.name() + " (" +
                                std::to_string(vi + 1) + "/" + std::to_string(variants.size()) +
                                ")");
            // The exact rule runs the oracle: once, it being by far the slowest.
            const double s =
                time_variant(v, f, v.coverage == CoverageRule::Exact ? 1 : repeats, frags);
            Errors err = measure(v, f, e, frags);
            err.seconds = s;
            rows.push_back({v, f.name, err});
        }
        if (const auto fc = time_fast_core(f, repeats)) {
            fast_core_ms[f.name] = *fc * 1e3;
            fast_core_total += *fc;
            fast_core_triangles += f.triangles.size();
        }
    }
    std::map<std::string, std::size_t> triangles;
    for (const Family& f : families) triangles[f.name] = f.triangles.size();
    for (const Row& r : rows) {
        const Errors& e = r.errors;
        const double n = static_cast<double>(triangles[r.family]);
        csv.add_row({"precision",
                     r.family,
                     std::to_string(options.seed),
                     r.variant.name(),
                     r.variant.coverage_name(),
                     r.variant.interpolation_name(),
                     r.variant.depth_name(),
                     std::to_string(triangles[r.family]),
                     std::to_string(e.exact_centres),
                     std::to_string(e.misclassified),
                     csv_number(e.exact_centres == 0 ? 0.0
                                                     : 1e6 * static_cast<double>(e.misclassified) /
                                                           static_cast<double>(e.exact_centres)),
                     std::to_string(e.holes),
                     std::to_string(e.double_hits),
                     std::to_string(e.degenerate),
                     csv_number(e.max_ulps),
                     csv_number(e.attribute_samples == 0
                                    ? 0.0
                                    : e.sum_ulps / static_cast<double>(e.attribute_samples)),
                     csv_number(e.max_abs),
                     std::to_string(e.depth_pairs),
                     std::to_string(e.depth_inversions),
                     csv_number(e.seconds * 1e3),
                     csv_number(e.seconds * 1e9 / n)});
    }
    for (const auto& [family, ms] : fast_core_ms) {
        csv.add_row({"precision",
                     family,
                     std::to_string(options.seed),
                     "llvmpipe-22.3 (fast core)",
                     "snap-8",
                     "llvmpipe",
                     "z24",
                     std::to_string(triangles[family]),
                     "",
                     "",
                     "",
                     "",
                     "",
                     "",
                     "",
                     "",
                     "",
                     "",
                     "",
                     csv_number(ms),
                     csv_number(ms * 1e6 / static_cast<double>(triangles[family]))});
    }

    // Totals per variant over all families.
    struct Total {
        Errors e;
        std::uint64_t triangles = 0;
    };
    std::map<std::string, Total> total;
    std::vector<Variant> order;
    for (const Row& r : rows) {
        auto [it, fresh] = total.try_emplace(r.variant.name());
        if (fresh) order.push_back(r.variant);
        Errors& t = it->second.e;
        const Errors& e = r.errors;
        t.exact_centres += e.exact_centres;
        t.misclassified += e.misclassified;
        t.holes += e.holes;
        t.double_hits += e.double_hits;
        t.degenerate += e.degenerate;
        t.max_ulps = std::max(t.max_ulps, e.max_ulps);
        t.sum_ulps += e.sum_ulps;
        t.attribute_samples += e.attribute_samples;
        t.max_abs = std::max(t.max_abs, e.max_abs);
        t.depth_pairs += e.depth_pairs;
        t.depth_inversions += e.depth_inversions;
        t.seconds += e.seconds;
        it->second.triangles += triangles[r.family];
    }
    const auto ns_per_triangle = [&](const std::string& name) {
        const Total& t = total[name];
        return t.e.seconds * 1e9 / static_cast<double>(t.triangles);
    };

    PlotPanel coverage{"Coverage (fused, z24)",
                       "ns per triangle (study kernel)",
                       "misclassified + holes + double hits per 10^6 centres",
                       true,
                       true,
                       {},
                       true,
                       {}};
    PlotPanel attributes{"Attributes (z24)",
                         "ns per triangle (study kernel)",
                         "mean attribute error (float32 ulps)",
                         true,
                         true,
                         {},
                         true,
                         {}};
    PlotPanel depth{"Depth order (fused)",
                    "ns per triangle (study kernel)",
                    "depth order inversions per 10^6 overlapping pairs",
                    true,
                    true,
                    {},
                    true,
                    {}};
    PlotSeries cov_s{"variants", {}, false}, attr_s{"variants", {}, false},
        depth_s{"variants", {}, false};
    for (const Variant& v : order) {
        const Total& t = total[v.name()];
        const double x = ns_per_triangle(v.name());
        const bool default_interp = v.coverage == CoverageRule::Exact || v.fused;
        if (default_interp && v.depth == DepthFormat::Z24) {
            const double bad = static_cast<double>(t.e.misclassified + t.e.holes + t.e.double_hits);
            cov_s.points.push_back(
                {x, 1e6 * bad / static_cast<double>(std::max<std::uint64_t>(1, t.e.exact_centres)),
                 v.coverage_name()});
        }
        if (v.depth == DepthFormat::Z24)
            attr_s.points.push_back(
                {x,
                 t.e.attribute_samples == 0
                     ? 0.0
                     : t.e.sum_ulps / static_cast<double>(t.e.attribute_samples),
                 v.coverage_name() +
                     (v.coverage == CoverageRule::Exact ? "" : (v.fused ? " fma" : " no-fma"))});
        if (default_interp)
            depth_s.points.push_back(
                {x,
                 1e6 * static_cast<double>(t.e.depth_inversions) /
                     static_cast<double>(std::max<std::uint64_t>(1, t.e.depth_pairs)),
                 v.coverage_name() + " " + v.depth_name()});
    }
    coverage.series.push_back(cov_s);
    attributes.series.push_back(attr_s);
    depth.series.push_back(depth_s);
    if (fast_core_triangles > 0) {
        const double fc = fast_core_total * 1e9 / static_cast<double>(fast_core_triangles);
        // The fast core skips the large-coordinates family: its mark is over the others only.
        for (PlotPanel* p : {&coverage, &attributes, &depth})
            p->x_marks.push_back({fc, "fast core (llvmpipe-22.3), families <= 4096 px"});
    }

    StudyOutput out;
    out.name = "precision";
    out.csv = csv.text();
    out.svg = svg_figure("refraster study precision: error against run time (seed " +
                             std::to_string(options.seed) + (options.quick ? ", quick" : "") + ")",
                         {coverage, attributes, depth}, 3);

    // Conclusions the numbers support.
    const auto line = [&](const std::string& name) {
        const Total& t = total[name];
        std::ostringstream o;
        o << name << ": " << t.e.misclassified << " misclassified of " << t.e.exact_centres
          << " centres, " << t.e.holes << " holes, " << t.e.double_hits
          << " double hits, attribute max " << short_number(t.e.max_ulps) << " ulps, "
          << t.e.depth_inversions << "/" << t.e.depth_pairs << " depth inversions, "
          << csv_number(std::round(ns_per_triangle(name))) << " ns/triangle";
        return o.str();
    };
    for (const Variant& v : order)
        if ((v.coverage == CoverageRule::Exact || v.fused) && v.depth == DepthFormat::Z24)
            out.summary.push_back(line(v.name()));
    for (const auto& i : pareto_front(cov_s.points))
        out.summary.push_back("coverage Pareto front: " + cov_s.points[i].label);
    for (const auto& i : pareto_front(attr_s.points))
        out.summary.push_back("attribute Pareto front: " + attr_s.points[i].label);
    // Fusing: the float32 rule's mean error with and without fma.
    const auto mean_ulps = [&](const std::string& name) {
        const Total& t = total[name];
        return t.e.attribute_samples == 0
                   ? 0.0
                   : t.e.sum_ulps / static_cast<double>(t.e.attribute_samples);
    };
    for (const char* rule : {"float32", "float64"}) {
        const std::string f = std::string(rule) + "/fused/z24",
                          u = std::string(rule) + "/unfused/z24";
        if (!total.contains(f) || !total.contains(u)) continue;
        std::ostringstream o;
        o << rule << " planes: mean attribute error " << short_number(mean_ulps(f))
          << " ulps fused, " << short_number(mean_ulps(u)) << " unfused (max "
          << short_number(total[f].e.max_ulps) << " and " << short_number(total[u].e.max_ulps)
          << ")";
        out.summary.push_back(o.str());
    }
    // Depth formats: the exact rule's inversions are the format's own (exact depth, quantised).
    for (const char* d : {"z16", "z24", "z32f"}) {
        const std::string name = std::string("exact/exact/") + d;
        const std::string f32 = std::string("float32/fused/") + d;
        if (!total.contains(name) || !total.contains(f32)) continue;
        std::ostringstream o;
        o << d << ": " << total[name].e.depth_inversions << " of " << total[name].e.depth_pairs
          << " overlapping pairs inverted with exact depth quantised, "
          << total[f32].e.depth_inversions << " with float32 planes";
        out.summary.push_back(o.str());
    }
    if (fast_core_triangles > 0) {
        // The study's snap-8 kernel over the same families, for the ratio.
        double kernel = 0.0;
        for (const Row& r : rows)
            if (r.variant.name() == "snap-8/fused/z24" && fast_core_ms.contains(r.family))
                kernel += r.errors.seconds;
        std::ostringstream o;
        o << "the fast core draws the families it can hold (<= 4096 px) "
          << csv_number(std::round(kernel / fast_core_total * 10) / 10)
          << " times as fast as the study's snap-8 kernel";
        out.summary.push_back(o.str());
    }
    if (fast_core_triangles > 0)
        out.summary.push_back("fast core (llvmpipe-22.3, one thread): " +
                              csv_number(std::round(fast_core_total * 1e9 /
                                                    static_cast<double>(fast_core_triangles))) +
                              " ns/triangle over the families it draws");
    return out;
}

}  // namespace harness
