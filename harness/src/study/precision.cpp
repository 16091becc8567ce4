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
// - depth order: of the pairs of triangles the oracle puts at one centre (pairs whose exact
//   depths are closer than 1e-12, below the double rounding of the oracle's weights, are not
//   counted), the inversions, whose stored depths are strictly in the other order than the
//   exact ones, and apart from them the ties, whose stored depths are equal: a depth test
//   cannot order a tie, and which of its two surfaces wins is then the compare function's
//   (GL_LESS keeps the first), not the arithmetic's. Quantising the exact depth never inverts
//   a pair (rounding is monotonic); it only ties them.
// Run time: the variant's kernel over the whole family (setup, traversal of each bounding box,
// interpolation and depth at covered centres), after an untimed pass that gives the errors and
// warms the caches, in rounds interleaved over the variants (5, or 3 with --quick; the exact
// oracle, hundreds of times slower, once: its errors' pass), as the median with the
// range of the rounds (study_common.hpp's Timing), with the errors computed afterwards
// and untimed. The fast core itself (refraster::render under llvmpipe-22.3, one thread, depth
// test on z24) draws the same families as a calibration point.
//
// The decision table of summary.md: for each error target, the variant with the lowest median
// time that meets it, its time as a ratio to the llvmpipe rule's (snap-8, fused, z24) with the
// range the rounds allow, and the variants that meet the target too and are not slower beyond
// the spread.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iomanip>
#include <map>
#include <numeric>
#include <optional>
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
    std::uint64_t depth_inversions = 0;  // stored strictly in the other order
    std::uint64_t depth_ties = 0;        // stored equal, exact depths apart
    std::uint64_t degenerate = 0;        // triangles with no plane in the variant's arithmetic
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

// One timed round of the variant's kernel over the family.
double time_variant(const Variant& v, const Family& f, std::vector<std::vector<Fragment>>& out) {
    out.resize(f.triangles.size());
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < f.triangles.size(); ++i)
        rasterize(v, f.triangles[i], f.viewport, out[i]);
    return seconds_since(t0);
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
                const double stored = list[j].second - list[i].second;
                if (stored == 0.0) {
                    ++r.depth_ties;
                } else {
                    r.depth_inversions += (ez < 0.0) != (stored < 0.0);
                }
            }
        }
    }
    return r;
}

// The fast core on the same family: refraster::render with the llvmpipe-22.3 profile.
std::optional<Timing> time_fast_core(const Family& f, int rounds) {
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
    std::vector<double> seconds;
    for (int r = 0; r < rounds; ++r) {
        refraster::Framebuffer fb;
        const auto t0 = std::chrono::steady_clock::now();
        refraster::render(list, o, fb);
        seconds.push_back(seconds_since(t0));
    }
    return timing_of(seconds);
}

struct Row {
    Variant variant;
    std::string family;
    Errors errors;
    std::vector<double> seconds;  // per round
};

std::string percent(double v) {
    std::ostringstream o;
    o << std::setprecision(2) << v * 100.0 << "%";
    return o.str();
}

}  // namespace

StudyOutput run_precision_study(const StudyOptions& options) {
    const auto families = precision_families(options.seed, options.quick);
    const auto variants = all_variants();
    const int rounds = options.quick ? 3 : 5;
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
                  "depth_ties",
                  "rounds",
                  "ms",
                  "ms_low",
                  "ms_high",
                  "ns_per_triangle"});
    std::vector<Row> rows;
    std::map<std::string, Timing> fast_core;
    std::vector<double> fast_core_rounds(static_cast<std::size_t>(rounds), 0.0);
    std::size_t fast_core_triangles = 0;
    const auto rounds_of = [&](const Variant& v) {
        // The exact rule runs the oracle: once, it being by far the slowest.
        return v.coverage == CoverageRule::Exact ? 1 : rounds;
    };
    for (const Family& f : families) {
        report(options, "precision: family " + f.name + " (" + std::to_string(f.triangles.size()) +
                            " triangles): exact oracle");
        const ExactFamily e = exact_family(f);
        std::vector<std::vector<Fragment>> frags;
        const std::size_t first = rows.size();
        // Pass 0 draws every variant for its errors, untimed, and warms the caches and the
        // fragment lists; then the timed rounds. The exact rule's one round is its pass 0.
        for (int r = 0; r <= rounds; ++r) {
            for (std::size_t vi = 0; vi < variants.size(); ++vi) {
                const Variant& v = variants[vi];
                const bool exact = v.coverage == CoverageRule::Exact;
                if (r == 0) {
                    report(options, "precision: family " + f.name + ", variant " + v.name() + " (" +
                                        std::to_string(vi + 1) + "/" +
                                        std::to_string(variants.size()) + ")");
                    const double t = time_variant(v, f, frags);
                    rows.push_back({v, f.name, measure(v, f, e, frags), {}});
                    if (exact) rows.back().seconds.push_back(t);
                } else if (!exact) {
                    rows[first + vi].seconds.push_back(time_variant(v, f, frags));
                }
            }
            if (r == 0)
                report(options, "precision: family " + f.name + ", " + std::to_string(rounds) +
                                    " timed rounds of every variant");
        }
        if (const auto fc = time_fast_core(f, rounds)) {
            fast_core[f.name] = *fc;
            fast_core_triangles += f.triangles.size();
        }
    }
    std::map<std::string, std::size_t> triangles;
    for (const Family& f : families) triangles[f.name] = f.triangles.size();
    for (const Row& r : rows) {
        const Errors& e = r.errors;
        const double n = static_cast<double>(triangles[r.family]);
        const Timing t = timing_of(r.seconds);
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
                     std::to_string(e.depth_ties),
                     std::to_string(t.rounds),
                     csv_number(t.median * 1e3),
                     csv_number(t.low * 1e3),
                     csv_number(t.high * 1e3),
                     csv_number(t.median * 1e9 / n)});
    }
    for (const auto& [family, t] : fast_core) {
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
                     "",
                     std::to_string(t.rounds),
                     csv_number(t.median * 1e3),
                     csv_number(t.low * 1e3),
                     csv_number(t.high * 1e3),
                     csv_number(t.median * 1e9 / static_cast<double>(triangles[family]))});
    }

    // Totals per variant over all families; a round's total is the sum of that round over the
    // families (the exact rule's one round stands for all of its rounds).
    struct Total {
        Errors e;
        std::uint64_t triangles = 0;
        std::vector<double> rounds;
        Timing ns_per_triangle;
    };
    std::map<std::string, Total> total;
    std::vector<Variant> order;
    for (const Row& r : rows) {
        auto [it, fresh] = total.try_emplace(r.variant.name());
        if (fresh) order.push_back(r.variant);
        Total& tot = it->second;
        Errors& t = tot.e;
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
        t.depth_ties += e.depth_ties;
        tot.rounds.resize(static_cast<std::size_t>(rounds_of(r.variant)), 0.0);
        for (std::size_t k = 0; k < tot.rounds.size(); ++k)
            tot.rounds[k] += r.seconds[std::min(k, r.seconds.size() - 1)];
        tot.triangles += triangles[r.family];
    }
    for (auto& [name, t] : total)
        t.ns_per_triangle = scaled(timing_of(t.rounds), 1e9 / static_cast<double>(t.triangles));
    const auto ns = [&](const std::string& name) { return total.at(name).ns_per_triangle; };
    const auto mean_ulps = [&](const std::string& name) {
        const Total& t = total.at(name);
        return t.e.attribute_samples == 0
                   ? 0.0
                   : t.e.sum_ulps / static_cast<double>(t.e.attribute_samples);
    };
    const auto coverage_ppm = [&](const std::string& name) {
        const Errors& e = total.at(name).e;
        return 1e6 * static_cast<double>(e.misclassified + e.holes + e.double_hits) /
               static_cast<double>(std::max<std::uint64_t>(1, e.exact_centres));
    };
    const auto inversions_ppm = [&](const std::string& name) {
        const Errors& e = total.at(name).e;
        return 1e6 * static_cast<double>(e.depth_inversions) /
               static_cast<double>(std::max<std::uint64_t>(1, e.depth_pairs));
    };

    PlotPanel coverage{"Coverage (fused, z24)",
                       "ns per triangle (study kernel; median, range of rounds)",
                       "misclassified + holes + double hits per 10^6 centres",
                       true,
                       true,
                       {},
                       true,
                       {}};
    PlotPanel attributes{"Attributes (z24)",
                         "ns per triangle (study kernel; median, range of rounds)",
                         "mean attribute error (float32 ulps)",
                         true,
                         true,
                         {},
                         true,
                         {}};
    PlotPanel depth{"Depth order (fused): inversions, ties apart",
                    "ns per triangle (study kernel; median, range of rounds)",
                    "depth order inversions per 10^6 overlapping pairs",
                    true,
                    true,
                    {},
                    true,
                    {}};
    // One series per coverage rule, so that a rule has one colour in all three panels.
    const auto series_of = [](PlotPanel& panel, const std::string& name) -> PlotSeries& {
        for (PlotSeries& s : panel.series)
            if (s.name == name) return s;
        panel.series.push_back({name, {}, false});
        return panel.series.back();
    };
    const auto point = [&](const std::string& name, double y, std::string label) {
        const Timing t = ns(name);
        return PlotPoint{t.median, y, std::move(label), t.low, t.high};
    };
    // The same points labelled with the variants' full names, for the summary's fronts.
    std::vector<PlotPoint> coverage_named, attributes_named;
    for (const Variant& v : order) {
        const std::string name = v.name();
        const bool default_interp = v.coverage == CoverageRule::Exact || v.fused;
        if (default_interp && v.depth == DepthFormat::Z24) {
            series_of(coverage, v.coverage_name())
                .points.push_back(point(name, coverage_ppm(name), v.coverage_name()));
            coverage_named.push_back(point(name, coverage_ppm(name), name));
        }
        if (v.depth == DepthFormat::Z24)
            attributes_named.push_back(point(name, mean_ulps(name), name));
        if (v.depth == DepthFormat::Z24)
            series_of(attributes, v.coverage_name())
                .points.push_back(point(
                    name, mean_ulps(name),
                    v.coverage == CoverageRule::Exact ? "exact" : (v.fused ? "fma" : "no-fma")));
        if (default_interp)
            series_of(depth, v.coverage_name())
                .points.push_back(point(name, inversions_ppm(name), v.depth_name()));
    }
    Timing fast_core_total;
    if (fast_core_triangles > 0) {
        // Medians per family summed: the fast core's rounds ran per family, not interleaved.
        double median = 0.0, low = 0.0, high = 0.0;
        for (const auto& [family, t] : fast_core) {
            median += t.median;
            low += t.low;
            high += t.high;
        }
        fast_core_total = {median, low, high, rounds};
        const double fc = median * 1e9 / static_cast<double>(fast_core_triangles);
        // The fast core skips the large-coordinates family: its mark is over the others only.
        for (PlotPanel* p : {&coverage, &attributes, &depth})
            p->x_marks.push_back({fc, "fast core (llvmpipe-22.3), families <= 4096 px"});
    }

    StudyOutput out;
    out.name = "precision";
    out.csv = csv.text();
    out.svg = svg_figure("refraster study precision: error against run time (seed " +
                             std::to_string(options.seed) + (options.quick ? ", quick" : "") + ")",
                         {coverage, attributes, depth}, 2, Legend::Shared);

    // Every number, one line per variant and finding.
    const auto line = [&](const std::string& name) {
        const Total& t = total.at(name);
        const Timing time = ns(name);
        std::ostringstream o;
        o << name << ": " << t.e.misclassified << " misclassified of " << t.e.exact_centres
          << " centres, " << t.e.holes << " holes, " << t.e.double_hits
          << " double hits, attribute max " << short_number(t.e.max_ulps) << " ulps, "
          << t.e.depth_inversions << " depth inversions and " << t.e.depth_ties << " ties of "
          << t.e.depth_pairs << " pairs, " << csv_number(std::round(time.median))
          << " ns/triangle (" << csv_number(std::round(time.low)) << "-"
          << csv_number(std::round(time.high)) << ")";
        return o.str();
    };
    for (const Variant& v : order)
        if ((v.coverage == CoverageRule::Exact || v.fused) && v.depth == DepthFormat::Z24)
            out.summary.push_back(line(v.name()));
    const auto front_line = [&](const std::string& what, const std::vector<PlotPoint>& all) {
        std::string names;
        for (const std::size_t i : pareto_front(all))
            names += (names.empty() ? "" : ", ") + all[i].label;
        out.summary.push_back(what + " Pareto front (better beyond the timing spread): " + names);
    };
    front_line("coverage", coverage_named);
    front_line("attribute", attributes_named);
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
    // Depth formats: with the exact depth quantised a pair can only tie, never invert.
    for (const char* d : {"z16", "z24", "z32f"}) {
        const std::string name = std::string("exact/exact/") + d;
        const std::string f32 = std::string("float32/fused/") + d;
        if (!total.contains(name) || !total.contains(f32)) continue;
        std::ostringstream o;
        o << d << ": of " << total[name].e.depth_pairs << " overlapping pairs, the exact depth "
          << "quantised ties " << total[name].e.depth_ties << " and inverts "
          << total[name].e.depth_inversions << "; float32 planes tie " << total[f32].e.depth_ties
          << " and invert " << total[f32].e.depth_inversions;
        out.summary.push_back(o.str());
    }
    std::optional<Ratio> fast_core_ratio;
    if (fast_core_triangles > 0) {
        // The study's snap-8 kernel over the same families, for the ratio.
        std::vector<double> kernel(static_cast<std::size_t>(rounds), 0.0);
        for (const Row& r : rows)
            if (r.variant.name() == "snap-8/fused/z24" && fast_core.contains(r.family))
                for (std::size_t k = 0; k < r.seconds.size(); ++k) kernel[k] += r.seconds[k];
        fast_core_ratio = ratio_of(timing_of(kernel), fast_core_total);
        out.summary.push_back("the fast core draws the families it can hold (<= 4096 px) " +
                              ratio_text(*fast_core_ratio) +
                              " times as fast as the study's snap-8 kernel" +
                              (options.quick ? " (--quick: families too small to time the fast "
                                               "core's setup away)"
                                             : ""));
        out.summary.push_back("fast core (llvmpipe-22.3, one thread): " +
                              csv_number(std::round(fast_core_total.median * 1e9 /
                                                    static_cast<double>(fast_core_triangles))) +
                              " ns/triangle over the families it draws");
    }

    // The decision table: for each target, the cheapest variant that meets it.
    const std::string baseline = "snap-8/fused/z24";
    struct Target {
        std::string group;  // targets of one group get tighter down the list
        std::string need;
        std::function<bool(const Variant&)> eligible;
        std::function<bool(const std::string&)> meets;
    };
    const auto fused_z24 = [](const Variant& v) {
        return (v.coverage == CoverageRule::Exact || v.fused) && v.depth == DepthFormat::Z24;
    };
    const auto z24 = [](const Variant& v) { return v.depth == DepthFormat::Z24; };
    const auto fused = [](const Variant& v) {
        return v.coverage == CoverageRule::Exact || v.fused;
    };
    std::vector<Target> targets;
    for (double ppm : {10000.0, 1000.0, 100.0, 10.0})
        targets.push_back(
            {"coverage", "coverage: at most " + csv_number(ppm) + " misclassified per 10^6 centres",
             fused_z24, [&, ppm](const std::string& n) { return coverage_ppm(n) <= ppm; }});
    targets.push_back({"coverage", "coverage: exact (no misclassified centre, hole or double hit)",
                       fused_z24, [&](const std::string& n) { return coverage_ppm(n) == 0.0; }});
    for (double ulps : {100.0, 1.0, 0.01})
        targets.push_back({"attributes",
                           "attributes: mean error at most " + csv_number(ulps) + " float32 ulps",
                           z24, [&, ulps](const std::string& n) { return mean_ulps(n) <= ulps; }});
    targets.push_back({"inversions", "depth: no pair inverted (ties apart)", fused,
                       [&](const std::string& n) { return total.at(n).e.depth_inversions == 0; }});
    targets.push_back(
        {"ties", "depth: at most 1000 ties per 10^6 pairs", fused, [&](const std::string& n) {
             const Errors& e = total.at(n).e;
             return 1e6 * static_cast<double>(e.depth_ties) /
                        static_cast<double>(std::max<std::uint64_t>(1, e.depth_pairs)) <=
                    1000.0;
         }});
    // The cheapest variant meeting each target ("" when none does).
    std::vector<std::string> answer;
    for (const Target& t : targets) {
        std::string best;
        for (const Variant& v : order)
            if (t.eligible(v) && t.meets(v.name()) &&
                (best.empty() || ns(v.name()).median < ns(best).median))
                best = v.name();
        answer.push_back(best);
    }
    std::ostringstream table;
    table << "| if you need | the cheapest variant | ns per triangle, median (range) | time "
             "against llvmpipe's rule (snap-8/fused/z24) | as fast within the spread |\n"
             "|---|---|---|---|---|\n";
    for (std::size_t ti = 0; ti < targets.size(); ++ti) {
        const Target& t = targets[ti];
        // A looser target that the tighter one's answer already meets says nothing more.
        if (ti + 1 < targets.size() && targets[ti + 1].group == t.group &&
            answer[ti + 1] == answer[ti])
            continue;
        std::vector<std::string> meeting;
        for (const Variant& v : order)
            if (t.eligible(v) && t.meets(v.name())) meeting.push_back(v.name());
        if (meeting.empty()) {
            table << "| " << t.need << " | none of the variants | | | |\n";
            continue;
        }
        const auto best = *std::min_element(meeting.begin(), meeting.end(), [&](auto& a, auto& b) {
            return ns(a).median < ns(b).median;
        });
        std::string alike;
        for (const std::string& m : meeting)
            if (m != best && ns(m).low <= ns(best).high) alike += (alike.empty() ? "" : ", ") + m;
        const Timing bt = ns(best);
        table << "| " << t.need << " | " << best << " | " << csv_number(std::round(bt.median))
              << " (" << csv_number(std::round(bt.low)) << "-" << csv_number(std::round(bt.high))
              << ") | " << (total.contains(baseline) ? ratio_text(ratio_of(bt, ns(baseline))) : "")
              << " | " << (alike.empty() ? "none" : alike) << " |\n";
    }
    out.decisions = table.str();

    // A few conclusions, in words, from the same numbers.
    double widest = 0.0;
    for (const auto& [name, t] : total)
        if (t.ns_per_triangle.rounds > 1)
            widest = std::max(widest, (t.ns_per_triangle.high - t.ns_per_triangle.low) /
                                          t.ns_per_triangle.median);
    if (total.contains("snap-4/fused/z24") && total.contains("snap-10/fused/z24")) {
        std::ostringstream o;
        o << "Each two sub-pixel bits more cut the misclassified centres: snap-4, -6, -8, -10 "
             "misclassify ";
        bool first = true;
        for (const char* n :
             {"snap-4/fused/z24", "snap-6/fused/z24", "snap-8/fused/z24", "snap-10/fused/z24"}) {
            if (!total.contains(n)) continue;
            o << (first ? "" : ", ") << total.at(n).e.misclassified;
            first = false;
        }
        // One integer kernel for every snapped rule: how far apart its times came out.
        double lo = 1e300, hi = 0.0;
        for (const auto& [name, t] : total)
            if (name.rfind("snap-", 0) == 0 && name.ends_with("/fused/z24")) {
                lo = std::min(lo, t.ns_per_triangle.median);
                hi = std::max(hi, t.ns_per_triangle.median);
            }
        o << " centres; the snapped rules (one integer kernel) took " << csv_number(std::round(lo))
          << " to " << csv_number(std::round(hi)) << " ns per triangle (medians, fused, z24), "
          << percent(hi / lo - 1.0) << " apart.";
        out.conclusions.push_back(o.str());
    }
    if (total.contains("float64/fused/z24") && total.contains(baseline)) {
        std::ostringstream o;
        const Errors& e = total.at("float64/fused/z24").e;
        o << "float64 unsnapped setup misclassifies " << e.misclassified << " centres (holes "
          << e.holes << ", double hits " << e.double_hits << ") at "
          << ratio_text(ratio_of(ns("float64/fused/z24"), ns(baseline)))
          << " times the time of llvmpipe's snap-8 rule.";
        out.conclusions.push_back(o.str());
    }
    {
        std::ostringstream o;
        o << "Depth order is the format's: quantising the exact depth never inverts a pair, it "
             "ties them (ties: ";
        bool first = true;
        for (const char* d : {"z16", "z24", "z32f"}) {
            const std::string n = std::string("exact/exact/") + d;
            if (!total.contains(n)) continue;
            o << (first ? "" : ", ") << d << " " << total.at(n).e.depth_ties;
            first = false;
        }
        o << " of "
          << (total.contains("exact/exact/z24") ? total.at("exact/exact/z24").e.depth_pairs : 0)
          << " pairs); with float32 planes the inversions are ";
        first = true;
        for (const char* d : {"z16", "z24", "z32f"}) {
            const std::string n = std::string("float32/fused/") + d;
            if (!total.contains(n)) continue;
            o << (first ? "" : ", ") << d << " " << total.at(n).e.depth_inversions;
            first = false;
        }
        o << ".";
        out.conclusions.push_back(o.str());
    }
    if (fast_core_ratio)
        out.conclusions.push_back("The fast core is " + ratio_text(*fast_core_ratio) +
                                  " times as fast as the study's scalar snap-8 kernel on the "
                                  "families it can hold" +
                                  (options.quick ? " (quick sizes: not a stable time)" : "") + ".");
    out.conclusions.push_back(
        "Times are medians of " + std::to_string(rounds) +
        " interleaved rounds; the widest range of one variant's rounds was " + percent(widest) +
        " of its median" +
        (widest > 0.2 ? ": the machine was loaded, and only differences beyond the ranges count"
                      : "") +
        ".");
    return out;
}

}  // namespace harness
