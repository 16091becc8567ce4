// stability.cpp: `refraster study stability`: families swept towards their limits, the error of
// each rule variant against the sweep parameter.
//
// The sweeps (each step a seeded batch of triangles in a 256 x 256 viewport unless stated):
// - area: slivers 100 px long whose third vertex lies 2^-k px off the long edge;
// - w-positive: a triangle whose third vertex's w is 10^-k (in front of the eye, its window
//   position held fixed: only perspective changes);
// - w-negative: the same vertex at w = -10^-k (behind the eye): the variants clip against the
//   view volume in their arithmetic (Mesa's clipper's intersection), the oracle needs no clipper;
// - guard-band: a triangle whose far vertex lies at NDC x = 2^k, clipped by the variants at the
//   guard band (|x| <= 2w), by the llvmpipe model as its profile clips;
// - coordinates: 10-50 px triangles in the far corner of a viewport of 2^k pixels, up to 16384
//   (GL_MAX_VIEWPORT_DIMS of Mesa's drivers);
// - parallel-edges: 200 px wedges whose two long edges meet at an angle of 2^-k radians;
// - depth-slope: a wide triangle whose window depth rises by 2^-k a pixel along x, its z24
//   values along one row: steps that go down (a planar depth must not) and the largest error in
//   z24 steps.
// Variants: snapped at 4, 8 and 16 bits, float32 and float64 setup (fused planes; float32 also
// unfused), the exact oracle, on the sweeps that clip a float32 rule whose clipper interpolates
// each crossing edge in polygon order (the textbook form) instead of Mesa's order from the
// outside vertex, and the llvmpipe model (refraster::render under llvmpipe-22.3,
// bit-exact with the driver: "where llvmpipe itself" breaks is read from it). For each curve the
// summary names where the error starts to grow (the first step whose error exceeds twice the
// first step's, or any error when the first step has none) and how fast (the slope of log error
// against log parameter from there on); summary.md opens with the same as a table, a row per
// sweep and metric and a column per curve, and a few conclusions drawn from the curves.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <numbers>
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

constexpr const char* kLlvmpipe = "llvmpipe model";
constexpr const char* kInOrderClip = "float32 in-order clip";

struct Step {
    double parameter = 0.0;
    std::vector<ClipTriangle> triangles;
    Viewport viewport;
    double clip_band = 0.0;  // 0: no clipping; 1 view volume; 2 guard band
};

struct Sweep {
    std::string name;
    std::string x_label;
    std::string description;
    std::vector<Step> steps;
    bool log_x = true;
};

struct Measure {
    std::uint64_t misclassified = 0;
    std::uint64_t exact_centres = 0;
    double max_ulps = 0.0;
};

std::vector<Variant> coverage_variants() {
    return {{CoverageRule::Snapped, 4, true, DepthFormat::Z24},
            {CoverageRule::Snapped, 8, true, DepthFormat::Z24},
            {CoverageRule::Snapped, 16, true, DepthFormat::Z24},
            {CoverageRule::Float32, 0, true, DepthFormat::Z24},
            {CoverageRule::Float32, 0, false, DepthFormat::Z24},
            {CoverageRule::Float64, 0, true, DepthFormat::Z24},
            {CoverageRule::Exact, 0, false, DepthFormat::Z24}};
}

std::string curve_name(const Variant& v) {
    if (v.coverage == CoverageRule::Float32) return v.fused ? "float32 fma" : "float32 no-fma";
    if (v.coverage == CoverageRule::Float64) return "float64 fma";
    return v.coverage_name();
}

// A variant's fragments for a triangle: clipped first where the step clips.
std::vector<Fragment> variant_fragments(const Variant& v, const ClipTriangle& t, const Step& s,
                                        bool from_outside = true) {
    std::vector<Fragment> all, part;
    const std::vector<ClipTriangle> pieces = s.clip_band > 0.0
                                                 ? clip_triangle(v, t, s.clip_band, from_outside)
                                                 : std::vector<ClipTriangle>{t};
    for (const ClipTriangle& p : pieces) {
        rasterize(v, p, s.viewport, part);
        all.insert(all.end(), part.begin(), part.end());
    }
    std::sort(all.begin(), all.end(), [](const Fragment& a, const Fragment& b) {
        return std::pair{a.y, a.x} < std::pair{b.y, b.x};
    });
    return all;
}

// The llvmpipe model's coverage of one triangle (its owner buffer), row-major.
std::vector<std::pair<int, int>> llvmpipe_coverage(const ClipTriangle& t, const Viewport& vp) {
    refraster::DrawList list;
    list.target = {static_cast<std::uint32_t>(vp.width), static_cast<std::uint32_t>(vp.height),
                   refraster::ColorFormat::Rgba8, refraster::DepthFormat::None, 1};
    refraster::Draw d;
    d.state.viewport = {0, 0, vp.width, vp.height};
    for (const ClipVertex& v : t) {
        for (double c : v.position) d.vertices.data.push_back(static_cast<float>(c));
    }
    list.draws.push_back(std::move(d));
    refraster::RenderOptions o;
    o.profile = refraster::llvmpipe_22_3_profile();
    o.threads = 1;
    o.record_owners = true;
    refraster::Framebuffer fb;
    refraster::render(list, o, fb);
    std::vector<std::pair<int, int>> out;
    for (std::uint32_t y = 0; y < fb.height; ++y)
        for (std::uint32_t x = 0; x < fb.width; ++x)
            if (fb.owner[fb.index(x, y)] != 0)
                out.emplace_back(static_cast<int>(y), static_cast<int>(x));
    return out;
}

// Attribute error of a variant at the oracle's centres of one (unclipped) triangle: its planes
// over the clipped pieces, each centre taken from the first piece that covers it.
double attribute_ulps(const Variant& v, const ClipTriangle& t, const Step& s,
                      const std::vector<ExactFragment>& exact, bool from_outside = true) {
    if (v.coverage == CoverageRule::Exact) return 0.0;
    double worst = 0.0;
    const std::vector<ClipTriangle> pieces = s.clip_band > 0.0
                                                 ? clip_triangle(v, t, s.clip_band, from_outside)
                                                 : std::vector<ClipTriangle>{t};
    std::vector<Fragment> part;
    std::map<std::pair<int, int>, double> value;
    for (const ClipTriangle& p : pieces) {
        rasterize(v, p, s.viewport, part);
        for (const Fragment& f : part) value.try_emplace({f.x, f.y}, f.attribute);
    }
    for (const ExactFragment& e : exact) {
        const auto it = value.find({e.x, e.y});
        if (it == value.end()) continue;  // a coverage difference, counted there
        const double u = std::isfinite(it->second) ? float32_ulps(it->second, e.attribute)
                                                   : std::numeric_limits<double>::infinity();
        worst = std::max(worst, u);
    }
    return worst;
}

ClipTriangle window_triangle(const Viewport& vp, const std::array<std::array<double, 2>, 3>& p,
                             StudyRandom& r) {
    ClipTriangle t;
    for (std::size_t i = 0; i < 3; ++i)
        t[i] = clip_vertex(vp, p[i][0], p[i][1], r.uniform(-0.9, 0.9), 1.0, r.uniform(0.0, 1.0));
    return t;
}

std::vector<Sweep> coverage_sweeps(std::uint64_t seed, bool quick) {
    StudyRandom r(seed);
    const int n = quick ? 4 : 40;
    const Viewport vp{256, 256};
    // Triangles reaching behind the eye or far outside the viewport give the oracle no bounding
    // box to narrow its candidates to: their sweeps use a smaller viewport and fewer triangles.
    const Viewport small_vp{96, 96};
    const int n_far = quick ? 2 : 12;
    std::vector<Sweep> out;

    Sweep area{"area",
               "distance of the third vertex from the long edge (px)",
               "slivers 100 px long, the third vertex 2^-k px off the long edge",
               {},
               true};
    for (int k = 0; k <= 26; k += quick ? 2 : 1) {
        Step s{std::ldexp(1.0, -k), {}, vp, 0.0};
        for (int i = 0; i < n; ++i) {
            const double a = r.uniform(0.0, 2.0 * std::numbers::pi);
            const double dx = std::cos(a), dy = std::sin(a);
            const double ax = r.uniform(100.0, 156.0) - 50.0 * dx,
                         ay = r.uniform(100.0, 156.0) - 50.0 * dy;
            const double t = r.uniform(0.2, 0.8);
            const double h = s.parameter;
            s.triangles.push_back(
                window_triangle(vp,
                                {{{ax, ay},
                                  {ax + 100.0 * dx, ay + 100.0 * dy},
                                  {ax + 100.0 * t * dx - h * dy, ay + 100.0 * t * dy + h * dx}}},
                                r));
        }
        area.steps.push_back(std::move(s));
    }
    out.push_back(std::move(area));

    for (int sign : {1, -1}) {
        Sweep w{sign > 0 ? "w-positive" : "w-negative",
                sign > 0 ? "w of the third vertex" : "|w| of the third vertex (w < 0)",
                sign > 0
                    ? "third vertex at w = 10^-k in front of the eye, its window position fixed"
                    : "third vertex at w = -10^-k behind the eye, clipped to the view volume",
                {},
                true};
        for (int k = 0; k <= 8; ++k) {
            const double wc = sign * std::pow(10.0, -k);
            Step s{std::fabs(wc), {}, small_vp, 1.0};
            for (int i = 0; i < n_far; ++i) {
                ClipTriangle t;
                const Viewport& v = small_vp;
                t[0] =
                    clip_vertex(v, r.uniform(5, 40), r.uniform(5, 35), 0.0, 1.0, r.uniform(0, 1));
                t[1] =
                    clip_vertex(v, r.uniform(56, 91), r.uniform(5, 35), 0.0, 1.0, r.uniform(0, 1));
                // Window position (x, y) at w: clip (ndc w, ndc w); behind the eye the same clip
                // coordinates with w < 0 project to the mirrored point, as GL's homogeneous
                // primitive defines.
                t[2] =
                    clip_vertex(v, r.uniform(20, 76), r.uniform(55, 91), 0.0, wc, r.uniform(0, 1));
                s.triangles.push_back(t);
            }
            w.steps.push_back(std::move(s));
        }
        out.push_back(std::move(w));
    }

    Sweep band{"guard-band",
               "NDC x of the far vertex",
               "a triangle reaching NDC x = 2^k, clipped at the guard band |x| <= 2w",
               {},
               true};
    for (int k = 0; k <= 24; k += quick ? 3 : 1) {
        Step s{std::ldexp(1.0, k), {}, small_vp, 2.0};
        for (int i = 0; i < n_far; ++i) {
            ClipTriangle t;
            const Viewport& v = small_vp;
            t[0] = clip_vertex(v, r.uniform(5, 40), r.uniform(5, 40), 0.0, 1.0, r.uniform(0, 1));
            t[1] = clip_vertex(v, r.uniform(5, 40), r.uniform(56, 91), 0.0, 1.0, r.uniform(0, 1));
            const double far_x = 48.0 * (1.0 + s.parameter);
            t[2] = clip_vertex(v, far_x, r.uniform(20, 76), 0.0, 1.0, r.uniform(0, 1));
            s.triangles.push_back(t);
        }
        band.steps.push_back(std::move(s));
    }
    out.push_back(std::move(band));

    Sweep coords{"coordinates",
                 "viewport size and coordinate magnitude (px)",
                 "10-50 px triangles in the far corner of a 2^k px viewport",
                 {},
                 true};
    for (int k = 6; k <= kMaxViewportBits; k += quick ? 2 : 1) {
        const int side = 1 << k;
        Step s{static_cast<double>(side), {}, {side, side}, 0.0};
        for (int i = 0; i < n; ++i) {
            const double cx = side - r.uniform(26.0, 40.0), cy = side - r.uniform(26.0, 40.0);
            std::array<std::array<double, 2>, 3> p{};
            for (auto& q : p) q = {cx + r.uniform(-25.0, 25.0), cy + r.uniform(-25.0, 25.0)};
            s.triangles.push_back(window_triangle(s.viewport, p, r));
        }
        coords.steps.push_back(std::move(s));
    }
    out.push_back(std::move(coords));

    Sweep wedge{"parallel-edges",
                "angle between the long edges (rad)",
                "200 px wedges whose long edges meet at 2^-k rad",
                {},
                true};
    for (int k = 0; k <= 24; k += quick ? 2 : 1) {
        Step s{std::ldexp(1.0, -k), {}, vp, 0.0};
        for (int i = 0; i < n; ++i) {
            const double a0 = r.uniform(0.05, std::numbers::pi / 2 - 1.05);
            const double a1 = a0 + s.parameter;
            const double ax = r.uniform(10.0, 40.0), ay = r.uniform(10.0, 40.0);
            s.triangles.push_back(
                window_triangle(vp,
                                {{{ax, ay},
                                  {ax + 200.0 * std::cos(a0), ay + 200.0 * std::sin(a0)},
                                  {ax + 200.0 * std::cos(a1), ay + 200.0 * std::sin(a1)}}},
                                r));
        }
        wedge.steps.push_back(std::move(s));
    }
    out.push_back(std::move(wedge));
    return out;
}

// Least-squares slope of log10(error) against log10(parameter) over the points given.
double log_slope(const std::vector<PlotPoint>& p) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    double n = 0;
    for (const PlotPoint& q : p) {
        if (!(q.x > 0.0) || !(q.y > 0.0) || !std::isfinite(q.y)) continue;
        const double x = std::log10(q.x), y = std::log10(q.y);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
        n += 1;
    }
    const double d = n * sxx - sx * sx;
    return n >= 2 && d != 0.0 ? (n * sxy - sx * sy) / d : 0.0;
}

// Where a curve starts to grow (in sweep order) and how fast from there.
std::string onset(const std::string& sweep, const PlotSeries& s) {
    if (s.points.empty()) return {};
    const double base = s.points.front().y;
    for (std::size_t i = 0; i < s.points.size(); ++i) {
        const double y = s.points[i].y;
        const bool grown = base > 0.0 ? y > 2.0 * base : y > 0.0;
        if (!grown) continue;
        std::vector<PlotPoint> rest(s.points.begin() + static_cast<std::ptrdiff_t>(i),
                                    s.points.end());
        std::ostringstream o;
        o << sweep << ": " << s.name << " error starts to grow at " << short_number(s.points[i].x)
          << " (error " << short_number(y) << ", first step " << short_number(base) << ")";
        if (rest.size() >= 2)
            o << ", from there error ~ parameter^"
              << short_number(std::round(log_slope(rest) * 100) / 100);
        return o.str();
    }
    double lo = base, hi = base;
    for (const PlotPoint& p : s.points) {
        lo = std::min(lo, p.y);
        hi = std::max(hi, p.y);
    }
    if (lo == hi) return sweep + ": " + s.name + " stays at " + short_number(base) + " throughout";
    return sweep + ": " + s.name + " does not grow (between " + short_number(lo) + " and " +
           short_number(hi) + ", never above twice its first step's " + short_number(base) + ")";
}

// The same as onset(), as a table cell: "0 throughout", "flat (3-7)", "grows from 1e-05,
// ~p^-1.2".
std::string onset_cell(const PlotSeries& s) {
    if (s.points.empty()) return "";
    const double base = s.points.front().y;
    for (std::size_t i = 0; i < s.points.size(); ++i) {
        const double y = s.points[i].y;
        if (!(base > 0.0 ? y > 2.0 * base : y > 0.0)) continue;
        std::vector<PlotPoint> rest(s.points.begin() + static_cast<std::ptrdiff_t>(i),
                                    s.points.end());
        std::string cell =
            "grows from " + short_number(s.points[i].x) + " (" + short_number(y) + ")";
        if (rest.size() >= 2)
            cell += ", ~p^" + short_number(std::round(log_slope(rest) * 100) / 100);
        return cell;
    }
    double lo = base, hi = base;
    for (const PlotPoint& p : s.points) {
        lo = std::min(lo, p.y);
        hi = std::max(hi, p.y);
    }
    if (lo == hi) return short_number(base) + " throughout";
    return "flat (" + short_number(lo) + "-" + short_number(hi) + ")";
}

// Rows of the stability table: a sweep and metric, and per curve its cell.
struct TableRow {
    std::string what;
    std::map<std::string, std::string> cells;
};

// Depth along a row under a slope of `slope` per pixel: the stored z24 values of each variant.
struct DepthRow {
    std::vector<double> stored;
};

}  // namespace

StudyOutput run_stability_study(const StudyOptions& options) {
    const std::vector<Variant> variants = coverage_variants();
    CsvTable csv(
        {"study", "sweep", "seed", "parameter", "variant", "metric", "value", "triangles"});
    std::vector<PlotPanel> panels;
    StudyOutput out;
    out.name = "stability";
    std::vector<TableRow> table;
    std::vector<std::string> columns;
    const auto add_cell = [&](TableRow& row, const PlotSeries& series, std::string cell) {
        if (std::find(columns.begin(), columns.end(), series.name) == columns.end())
            columns.push_back(series.name);
        row.cells[series.name] = std::move(cell);
    };
    // For the conclusions: the largest value of each curve over every sweep, per metric.
    std::map<std::string, double> worst_attr, worst_cov;
    std::map<std::string, int> flat_cov;
    int sweeps_done = 0;

    for (const Sweep& sw : coverage_sweeps(options.seed, options.quick)) {
        report(options,
               "stability: sweep " + sw.name + " (" + std::to_string(sw.steps.size()) + " steps)");
        std::map<std::string, PlotSeries> cov, attr;
        std::vector<std::string> cov_order, attr_order;
        const auto add = [&](std::map<std::string, PlotSeries>& m, std::vector<std::string>& order,
                             const std::string& name, double x, double y) {
            auto [it, fresh] = m.try_emplace(name, PlotSeries{name, {}, true});
            if (fresh) order.push_back(name);
            it->second.points.push_back({x, y, ""});
        };
        for (const Step& s : sw.steps) {
            std::vector<std::vector<ExactFragment>> exact;
            std::uint64_t centres = 0;
            for (const ClipTriangle& t : s.triangles) {
                exact.push_back(exact_fragments(t, s.viewport));
                centres += exact.back().size();
            }
            const auto ex = [](const ExactFragment& f) { return std::pair{f.y, f.x}; };
            for (const Variant& v : variants) {
                std::uint64_t bad = 0;
                double ulps = 0.0;
                for (std::size_t i = 0; i < s.triangles.size(); ++i) {
                    const auto frags = variant_fragments(v, s.triangles[i], s);
                    bad += count_difference(
                        frags, exact[i],
                        [](const Fragment& f) {
                            return std::pair{f.y, f.x};
                        },
                        ex);
                    ulps = std::max(ulps, attribute_ulps(v, s.triangles[i], s, exact[i]));
                }
                const std::string name = curve_name(v);
                const auto row = [&](const char* metric, double value) {
                    csv.add_row({"stability", sw.name, std::to_string(options.seed),
                                 csv_number(s.parameter), name, metric, csv_number(value),
                                 std::to_string(s.triangles.size())});
                };
                row("misclassified_centres", static_cast<double>(bad));
                row("exact_centres", static_cast<double>(centres));
                row("attribute_max_ulps", ulps);
                if (v.coverage != CoverageRule::Float32 || v.fused)
                    add(cov, cov_order, v.coverage == CoverageRule::Float32 ? "float32" : name,
                        s.parameter, static_cast<double>(bad));
                if (v.coverage == CoverageRule::Float32 || v.coverage == CoverageRule::Float64 ||
                    (v.coverage == CoverageRule::Snapped && v.subpixel_bits == 8))
                    add(attr, attr_order,
                        v.coverage == CoverageRule::Snapped ? "snap-8 (float32 fma)" : name,
                        s.parameter, ulps);
            }
            if (s.clip_band > 0.0) {
                // The textbook clipper (each crossing edge interpolated in polygon order) beside
                // Mesa's order, in float32.
                const Variant v{CoverageRule::Float32, 0, true, DepthFormat::Z24};
                std::uint64_t bad = 0;
                double ulps = 0.0;
                for (std::size_t i = 0; i < s.triangles.size(); ++i) {
                    bad += count_difference(
                        variant_fragments(v, s.triangles[i], s, false), exact[i],
                        [](const Fragment& f) {
                            return std::pair{f.y, f.x};
                        },
                        ex);
                    ulps = std::max(ulps, attribute_ulps(v, s.triangles[i], s, exact[i], false));
                }
                for (const auto& [metric, value] :
                     {std::pair{"misclassified_centres", static_cast<double>(bad)},
                      std::pair{"attribute_max_ulps", ulps}})
                    csv.add_row({"stability", sw.name, std::to_string(options.seed),
                                 csv_number(s.parameter), kInOrderClip, metric, csv_number(value),
                                 std::to_string(s.triangles.size())});
                add(cov, cov_order, kInOrderClip, s.parameter, static_cast<double>(bad));
                add(attr, attr_order, kInOrderClip, s.parameter, ulps);
            }
            if (s.viewport.width <= 4096) {
                std::uint64_t bad = 0;
                for (std::size_t i = 0; i < s.triangles.size(); ++i)
                    bad += count_difference(
                        llvmpipe_coverage(s.triangles[i], s.viewport), exact[i],
                        [](const std::pair<int, int>& p) { return p; }, ex);
                csv.add_row({"stability", sw.name, std::to_string(options.seed),
                             csv_number(s.parameter), kLlvmpipe, "misclassified_centres",
                             csv_number(static_cast<double>(bad)),
                             std::to_string(s.triangles.size())});
                add(cov, cov_order, kLlvmpipe, s.parameter, static_cast<double>(bad));
            }
        }
        PlotPanel pc{sw.name + ": coverage",
                     sw.x_label,
                     "misclassified centres",
                     sw.log_x,
                     true,
                     {},
                     false,
                     {}};
        TableRow cov_row{sw.name + ": misclassified centres", {}};
        ++sweeps_done;
        for (const auto& n : cov_order) {
            pc.series.push_back(cov[n]);
            out.summary.push_back(onset(sw.name + " coverage", cov[n]));
            const std::string cell = onset_cell(cov[n]);
            if (cell.rfind("grows", 0) != 0) ++flat_cov[n];
            for (const PlotPoint& p : cov[n].points) worst_cov[n] = std::max(worst_cov[n], p.y);
            add_cell(cov_row, cov[n], cell);
        }
        table.push_back(std::move(cov_row));
        panels.push_back(std::move(pc));
        PlotPanel pa{sw.name + ": attributes",
                     sw.x_label,
                     "max attribute error (float32 ulps)",
                     sw.log_x,
                     true,
                     {},
                     false,
                     {}};
        TableRow attr_row{sw.name + ": max attribute error (ulps)", {}};
        for (const auto& n : attr_order) {
            pa.series.push_back(attr[n]);
            out.summary.push_back(onset(sw.name + " attributes", attr[n]));
            for (const PlotPoint& p : attr[n].points)
                if (std::isfinite(p.y)) worst_attr[n] = std::max(worst_attr[n], p.y);
            add_cell(attr_row, attr[n], onset_cell(attr[n]));
        }
        table.push_back(std::move(attr_row));
        panels.push_back(std::move(pa));
    }

    // Depth slopes: one wide triangle, depth rising along x only; the z24 values along row 2.
    {
        report(options, "stability: sweep depth-slope");
        const Viewport vp{256, 8};
        std::map<std::string, PlotSeries> down, err;
        std::vector<std::string> order;
        const double z0 = 0.5;
        for (int k = 8; k <= 36; k += options.quick ? 4 : 1) {
            const double slope = std::ldexp(1.0, -k);
            // Window depth z(x) = z0 + slope (x - 0.5) over the row; NDC z = 2 z - 1.
            const auto zndc = [&](double x) { return 2.0 * (z0 + slope * (x - 0.5)) - 1.0; };
            ClipTriangle t;
            t[0] = clip_vertex(vp, -1.0, -1.0, zndc(-1.0), 1.0, 0.0);
            t[1] = clip_vertex(vp, 300.0, -1.0, zndc(300.0), 1.0, 0.0);
            t[2] = clip_vertex(vp, -1.0, 12.0, zndc(-1.0), 1.0, 0.0);
            const auto exact = exact_fragments(t, vp);
            std::vector<ExactFragment> row;
            for (const ExactFragment& f : exact)
                if (f.y == 2) row.push_back(f);
            std::vector<std::pair<std::string, std::vector<double>>> stored;
            for (const Variant& v : variants) {
                if (v.coverage == CoverageRule::Snapped) continue;  // same planes as float32
                const auto values = evaluate_at(v, t, vp, row);
                std::vector<double> z;
                for (const auto& pv : values) z.push_back(pv ? pv->depth : 0.0);
                stored.emplace_back(curve_name(v), z);
            }
            {
                refraster::DrawList list;
                list.target = {256, 8, refraster::ColorFormat::Rgba8, refraster::DepthFormat::Z24,
                               1};
                list.clear.depth = 1.0f;
                refraster::Draw d;
                d.state.viewport = {0, 0, 256, 8};
                d.state.depth_test = refraster::CompareFunc::Always;
                for (const ClipVertex& v : t)
                    for (double c : v.position) d.vertices.data.push_back(static_cast<float>(c));
                list.draws.push_back(std::move(d));
                refraster::RenderOptions o;
                o.profile = refraster::llvmpipe_22_3_profile();
                o.threads = 1;
                refraster::Framebuffer fb;
                refraster::render(list, o, fb);
                std::vector<double> z;
                for (const ExactFragment& f : row)
                    z.push_back(static_cast<double>(
                        fb.depth[fb.index(static_cast<std::uint32_t>(f.x), 2)]));
                stored.emplace_back(kLlvmpipe, z);
            }
            for (const auto& [name, z] : stored) {
                double downs = 0.0, worst = 0.0;
                for (std::size_t i = 0; i < z.size(); ++i) {
                    if (i > 0 && z[i] < z[i - 1]) downs += 1.0;
                    worst = std::max(worst, std::fabs(z[i] - row[i].depth * 16777215.0));
                }
                for (const auto& [metric, value] :
                     {std::pair{"z24_steps_down", downs}, std::pair{"z24_max_error_steps", worst}})
                    csv.add_row({"stability", "depth-slope", std::to_string(options.seed),
                                 csv_number(slope), name, metric, csv_number(value), "1"});
                if (!down.contains(name)) order.push_back(name);
                down.try_emplace(name, PlotSeries{name, {}, true})
                    .first->second.points.push_back({slope, downs, ""});
                err.try_emplace(name, PlotSeries{name, {}, true})
                    .first->second.points.push_back({slope, worst, ""});
            }
        }
        PlotPanel pd{"depth-slope: z24 steps that go down along a rising row",
                     "window depth slope per pixel",
                     "steps down (of 255)",
                     true,
                     true,
                     {},
                     false,
                     {{std::ldexp(1.0, -24), "z24 step"}}};
        PlotPanel pe{"depth-slope: z24 error",
                     "window depth slope per pixel",
                     "max error (z24 steps)",
                     true,
                     true,
                     {},
                     false,
                     {{std::ldexp(1.0, -24), "z24 step"}}};
        TableRow down_row{"depth-slope: z24 steps down along a rising row", {}};
        TableRow err_row{"depth-slope: max z24 error (steps)", {}};
        for (const auto& n : order) {
            pd.series.push_back(down[n]);
            pe.series.push_back(err[n]);
            add_cell(err_row, err[n], onset_cell(err[n]));
            // Monotonic means no step down; report the largest slope at which one appears.
            double last_bad = 0.0;
            for (const PlotPoint& p : down[n].points)
                if (p.y > 0.0) last_bad = std::max(last_bad, p.x);
            out.summary.push_back(
                "depth-slope: " + n +
                (last_bad > 0.0 ? " stops being monotonic: its z24 values step down "
                                  "along a rising row at slopes up to " +
                                      short_number(last_bad) + " per pixel (" +
                                      short_number(last_bad * 16777215.0) + " z24 steps per pixel)"
                                : " stays monotonic at every slope swept"));
            add_cell(down_row, down[n],
                     last_bad > 0.0 ? "at slopes up to " + short_number(last_bad) : "never");
            if (last_bad > 0.0)
                out.conclusions.push_back(
                    "Depth: the " + n +
                    "'s z24 values step down along a rising row at slopes up "
                    "to " +
                    short_number(last_bad) + " per pixel (" + short_number(last_bad * 16777215.0) +
                    " z24 steps per pixel): there its plane evaluation, not the format, orders "
                    "neighbouring pixels.");
        }
        table.push_back(std::move(down_row));
        table.push_back(std::move(err_row));
        panels.push_back(std::move(pd));
        panels.push_back(std::move(pe));
    }

    // The table: "where each curve starts to grow" per sweep, p being the sweep's parameter.
    std::ostringstream md;
    md << "Where each curve's error starts to grow along each sweep (the first step above "
          "twice the first step's error, with the error there, and error ~ p^slope from there "
          "on), or its range when it does not grow.\n\n| sweep: metric |";
    for (const std::string& c : columns) md << " " << c << " |";
    md << "\n|---|";
    for (std::size_t i = 0; i < columns.size(); ++i) md << "---|";
    md << "\n";
    for (const TableRow& row : table) {
        md << "| " << row.what << " |";
        for (const std::string& c : columns) {
            const auto it = row.cells.find(c);
            md << " " << (it == row.cells.end() ? "" : it->second) << " |";
        }
        md << "\n";
    }
    out.decisions = md.str();
    for (const auto& [name, worst] : worst_attr)
        if (name.rfind("float64", 0) == 0)
            out.conclusions.insert(out.conclusions.begin(),
                                   "float64 setup's attribute error stays at or below " +
                                       short_number(worst) + " float32 ulps on every sweep.");
    for (const char* n : {"snap-8", "float32"}) {
        if (!flat_cov.contains(n) && !worst_cov.contains(n)) continue;
        out.conclusions.insert(out.conclusions.begin(),
                               std::string(n) + "'s coverage error does not grow on " +
                                   std::to_string(flat_cov[n]) + " of " +
                                   std::to_string(sweeps_done) + " sweeps (at most " +
                                   short_number(worst_cov[n]) +
                                   " misclassified centres in a "
                                   "batch anywhere).");
    }

    out.csv = csv.text();
    out.svg = svg_figure("refraster study stability: error against the sweep parameter (seed " +
                             std::to_string(options.seed) + (options.quick ? ", quick" : "") + ")",
                         panels, 2, Legend::Shared);
    return out;
}

}  // namespace harness
