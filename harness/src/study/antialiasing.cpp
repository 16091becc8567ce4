// antialiasing.cpp: `refraster study antialiasing` (study.hpp): supersampling patterns resolved
// with box, tent and Gaussian filters, against the exact coverage of every pixel
// (exact_area.hpp), error against run time.
//
// Variants: samples x pattern x filter.
// - 1 sample: the pixel centre. 4 samples: GL's standard 4x pattern, offsets from the pixel's
//   bottom-left corner (0.375, 0.125), (0.875, 0.375), (0.125, 0.625), (0.625, 0.875).
// - 16 and 64 samples (n = 4, 8) in three patterns:
//   regular, the centres of an n x n grid of cells;
//   rotated, the n-rooks lattice ((k + 1/2) / N, ((g k mod N) + 1/2) / N), k < N = n^2, with
//   the generator g that keeps samples farthest apart (g = 3 for 16, 19 for 64): a rotated
//   (slightly skewed) grid in which every sample has a column and a row of its own, so that
//   an edge a few degrees off an axis crosses the samples one at a time instead of a row at a
//   time, and which continues seamlessly into the neighbouring pixels (a square grid rotated
//   by atan(1/2) and wrapped into the pixel does not: it leaves some columns with two samples
//   and brings some samples close together where it wraps);
//   stratified, one uniformly random point in each of the n x n cells, a different pattern
//   for every pixel of a 16 x 16 tile (std::mt19937_64 from the seed).
//   Sample positions are on a 1/65536 px grid and the sample test is exact (integer edge
//   functions and GL-style tie rule, exact_area.hpp), so the errors are sampling error only.
// - Resolve: box, the pixel's own samples with equal weights; tent and Gaussian, every sample
//   of the pixel and its neighbours within the filter's support, weighted by the filter at the
//   sample and normalised by the sum of those weights.
// Families (800 triangles each, 20 with --quick, drawn one at a time on a 64 x 64 image,
// seeded from the seed):
// medium, random triangles in squares of 8 to 40 px; sliver, long (10 to 40 px) and thin
// (0.2 to 2 px high) triangles at random angles; near-axis, triangles whose two legs lie 1 to 6
// degrees off the horizontal and the vertical, where regular grids alias. --quick draws from
// the same families, so its numbers estimate the default run's.
// Exact answers (computed once per family, untimed): for the box filter the pixel's area
// coverage, rational and correctly rounded; for the tent and the Gaussian the filter integrated
// over the triangle (exact_area.hpp says to what precision). A triangle's error is counted over
// every pixel of its bounding box grown by the filter's support; edge pixels are those whose
// support the triangle's boundary crosses (exact coverage strictly between 0 and 1, decided
// exactly).
// Run time: ns per evaluated pixel for sample coverage plus resolve, over the whole family,
// measured with std::chrono::steady_clock in 5 rounds (3 with --quick) interleaved over the
// variants, after an untimed pass whose estimates are compared with the exact answers, as the
// median with the range of the rounds (study_common.hpp's Timing). summary.md's decision table
// gives, for each target of mean edge error, the cheapest variant that meets it, its time against
// one sample's with the range the rounds allow, and the variants not slower beyond the spread. The
// table: one row per family and variant, then one per variant for the family "all" (the three
// pooled: sums of pixels and errors, so means are pixel-weighted), with columns study, family,
// seed, samples, pattern, filter, pixels, edge_pixels, mean_error, max_error, mean_edge_error,
// max_edge_error (absolute coverage errors), ns_per_pixel, triangles. The figure: per filter, mean
// edge error against ns per pixel, a labelled point per variant and the Pareto front; and mean edge
// error against samples, a curve per pattern and filter.
//
// Deliberately does not: model a GPU's resolve (no gamma, no sample masks, no compression),
// time the exact answers, or share samples between triangles (each is drawn on its own).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <numbers>
#include <numeric>
#include <random>
#include <sstream>

#include "exact_area.hpp"
#include "harness/study.hpp"
#include "plot.hpp"
#include "refraster/assert.hpp"
#include "study_common.hpp"

namespace harness {

namespace {

using namespace study;

constexpr std::int64_t kUnits = kSampleUnitsPerPixel;
constexpr int kImage = 64;  // pixels a side
// Vertices keep this far from the image's sides, so that a triangle's evaluated pixels (its
// bounding box grown by 1) and the samples their resolve reads (2 more) stay on it.
constexpr int kMargin = 5;
constexpr int kRandomTile = 16;
constexpr int kRounds = 5;
constexpr int kQuickRounds = 3;

// ---- patterns ----

struct Pattern {
    std::string name;
    int samples = 1;
    int tile = 1;                      // the pattern repeats every `tile` pixels in x and in y
    std::vector<SamplePoint> offsets;  // [((ty * tile) + tx) * samples + k], in [0, kUnits)^2

    const SamplePoint* at(int x, int y) const {
        const int tx = x % tile;
        const int ty = y % tile;
        return &offsets[static_cast<std::size_t>((ty * tile + tx) * samples)];
    }
};

std::int64_t units(double pixels) {
    return static_cast<std::int64_t>(std::llround(pixels * kUnits));
}

Pattern centre_pattern() {
    return {"centre", 1, 1, {{kUnits / 2, kUnits / 2}}};
}

Pattern gl4_pattern() {
    Pattern p{"gl4", 4, 1, {}};
    for (const auto& [x, y] :
         {std::pair{0.375, 0.125}, {0.875, 0.375}, {0.125, 0.625}, {0.625, 0.875}}) {
        p.offsets.push_back({units(x), units(y)});
    }
    return p;
}

Pattern regular_pattern(int n) {
    Pattern p{"regular", n * n, 1, {}};
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            p.offsets.push_back({(2 * i + 1) * kUnits / (2 * n), (2 * j + 1) * kUnits / (2 * n)});
        }
    }
    return p;
}

// The smallest distance between two samples of the n-rooks lattice with generator g, on the
// torus (the pattern repeated in every pixel), in units of 1/N.
double lattice_spacing(int count, int g) {
    double best = count;
    for (int k = 1; k < count; ++k) {
        int dx = k;
        int dy = (g * k) % count;
        dx = std::min(dx, count - dx);
        dy = std::min(dy, count - dy);
        best = std::min(best, std::hypot(dx, dy));
    }
    return best;
}

Pattern rotated_pattern(int n) {
    const int count = n * n;
    int generator = 1;
    for (int g = 1; g < count; ++g) {
        if (std::gcd(g, count) != 1) continue;  // not n-rooks
        if (lattice_spacing(count, g) > lattice_spacing(count, generator)) generator = g;
    }
    Pattern p{"rotated", count, 1, {}};
    for (int k = 0; k < count; ++k) {
        const std::int64_t row = (std::int64_t{generator} * k) % count;
        p.offsets.push_back(
            {(2 * k + 1) * kUnits / (2 * count), (2 * row + 1) * kUnits / (2 * count)});
    }
    return p;
}

// A uniform integer in [0, bound) from 32 random bits by multiply-shift (bias below
// bound / 2^32, under 2^-18 here), the same with every standard library, which
// std::uniform_int_distribution is not.
std::int64_t uniform_below(std::mt19937_64& rng, std::int64_t bound) {
    return static_cast<std::int64_t>(((rng() >> 32) * static_cast<std::uint64_t>(bound)) >> 32);
}

Pattern stratified_pattern(int n, std::uint64_t seed) {
    Pattern p{"stratified", n * n, kRandomTile, {}};
    std::mt19937_64 rng(seed ^ (0x5bd1e995u * static_cast<std::uint64_t>(n)));
    const std::int64_t cell = kUnits / n;
    for (int t = 0; t < kRandomTile * kRandomTile; ++t) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                const std::int64_t x = i * cell + uniform_below(rng, cell);
                const std::int64_t y = j * cell + uniform_below(rng, cell);
                p.offsets.push_back({x, y});
            }
        }
    }
    return p;
}

// ---- resolve ----

// How many pixels beyond a triangle's pixels can have coverage: those whose support overlaps
// them (0 for the box, 1 for the tent and the Gaussian).
int filter_reach(Filter f) {
    return static_cast<int>(std::ceil(filter_radius(f) - 0.5));
}

// How many pixels away a pixel's support can reach a sample (1 for the tent; 2 for the
// Gaussian, whose support's side can pass through a sample two pixels away).
int sample_reach(Filter f) {
    return static_cast<int>(std::floor(filter_radius(f) + 0.5));
}

struct Tap {
    std::int64_t offset;  // into the coverage buffer, from the pixel's first sample
    double weight;        // normalised: a pixel's weights sum to 1
};

struct Resolve {
    int tile = 1;
    std::vector<std::vector<Tap>> taps;  // per pixel of the tile

    const std::vector<Tap>& at(int x, int y) const {
        return taps[static_cast<std::size_t>((y % tile) * tile + x % tile)];
    }
};

Resolve make_resolve(const Pattern& p, Filter f) {
    Resolve r;
    r.tile = p.tile;
    const int reach = f == Filter::box ? 0 : sample_reach(f);
    for (int ty = 0; ty < p.tile; ++ty) {
        for (int tx = 0; tx < p.tile; ++tx) {
            std::vector<Tap> taps;
            double total = 0.0;
            for (int dy = -reach; dy <= reach; ++dy) {
                for (int dx = -reach; dx <= reach; ++dx) {
                    // The neighbour's own pattern: the tile wraps (tx + dx + tile is >= 0).
                    const SamplePoint* o = p.at(tx + dx + p.tile, ty + dy + p.tile);
                    for (int k = 0; k < p.samples; ++k) {
                        const double sx =
                            dx + static_cast<double>(o[k].x) / static_cast<double>(kUnits) - 0.5;
                        const double sy =
                            dy + static_cast<double>(o[k].y) / static_cast<double>(kUnits) - 0.5;
                        // The box resolves a pixel's own samples (a neighbour's sample on the
                        // shared side is not the pixel's).
                        const double w = f == Filter::box ? 1.0 : filter_weight(f, sx, sy);
                        if (w <= 0.0) continue;
                        taps.push_back({(std::int64_t{dy} * kImage + dx) * p.samples + k, w});
                        total += w;
                    }
                }
            }
            for (Tap& t : taps) t.weight /= total;
            r.taps.push_back(std::move(taps));
        }
    }
    return r;
}

// ---- families ----

struct PixelBox {
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // inclusive
    int width() const { return x1 - x0 + 1; }
    int height() const { return y1 - y0 + 1; }
    int count() const { return width() * height(); }
    PixelBox grown(int by) const { return {x0 - by, y0 - by, x1 + by, y1 + by}; }
};

// The pixels holding samples the triangle can cover: those its bounding box overlaps, and
// the next one where the box ends on a pixel's side (for the tie rule's sake).
PixelBox bounding_pixels(const GridTriangle& t) {
    const auto [min_x, max_x] = std::minmax({t[0].x, t[1].x, t[2].x});
    const auto [min_y, max_y] = std::minmax({t[0].y, t[1].y, t[2].y});
    return {static_cast<int>(min_x / kGridPerPixel), static_cast<int>(min_y / kGridPerPixel),
            static_cast<int>(max_x / kGridPerPixel), static_cast<int>(max_y / kGridPerPixel)};
}

struct TriangleExact {
    GridTriangle triangle;
    PixelBox box;  // bounding_pixels
    // Per filter, over box.grown(filter_reach): the exact coverage and whether it is an edge
    // pixel, row by row.
    std::array<std::vector<double>, 3> value;
    std::array<std::vector<std::uint8_t>, 3> edge;
};

struct Family {
    std::string name;
    std::vector<TriangleExact> triangles;
};

double uniform(std::mt19937_64& rng, double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1p-53;
}

GridPoint snap(double x, double y) {
    return {static_cast<std::int64_t>(std::llround(x * kGridPerPixel)),
            static_cast<std::int64_t>(std::llround(y * kGridPerPixel))};
}

double area_px(const GridTriangle& t) {
    const double twice = static_cast<double>((t[1].x - t[0].x) * (t[2].y - t[0].y) -
                                             (t[2].x - t[0].x) * (t[1].y - t[0].y));
    return std::abs(twice) / (2.0 * kGridPerPixel * kGridPerPixel);
}

bool on_image(const GridTriangle& t) {
    for (const GridPoint& p : t) {
        const std::int64_t lo = kMargin * kGridPerPixel;
        const std::int64_t hi = (kImage - kMargin) * kGridPerPixel;
        if (p.x < lo || p.x > hi || p.y < lo || p.y > hi) return false;
    }
    return true;
}

GridTriangle medium_triangle(std::mt19937_64& rng) {
    for (;;) {
        const double s = uniform(rng, 8.0, 40.0);
        const double ox = uniform(rng, kMargin, kImage - kMargin - s);
        const double oy = uniform(rng, kMargin, kImage - kMargin - s);
        GridTriangle t;
        for (GridPoint& p : t) {
            p = snap(ox + s * uniform(rng, 0.0, 1.0), oy + s * uniform(rng, 0.0, 1.0));
        }
        // Not thin: at least a quarter of the largest triangle in its square.
        if (area_px(t) >= s * s / 8.0 && on_image(t)) return t;
    }
}

GridTriangle sliver_triangle(std::mt19937_64& rng) {
    for (;;) {
        const double length = uniform(rng, 10.0, 40.0);
        const double height = uniform(rng, 0.2, 2.0);
        const double angle = uniform(rng, 0.0, 2.0 * std::numbers::pi);
        const double along = uniform(rng, 0.2, 0.8);
        const double cx = uniform(rng, kMargin, kImage - kMargin);
        const double cy = uniform(rng, kMargin, kImage - kMargin);
        const double ux = std::cos(angle), uy = std::sin(angle);
        const GridTriangle t = {snap(cx - ux * length / 2, cy - uy * length / 2),
                                snap(cx + ux * length / 2, cy + uy * length / 2),
                                snap(cx + ux * length * (along - 0.5) - uy * height,
                                     cy + uy * length * (along - 0.5) + ux * height)};
        if (area_px(t) > 0.0 && on_image(t)) return t;
    }
}

GridTriangle near_axis_triangle(std::mt19937_64& rng) {
    const double degree = std::numbers::pi / 180.0;
    for (;;) {
        const double base = std::floor(uniform(rng, 0.0, 4.0)) * 90.0 * degree;
        const auto tilt = [&] {
            const double d = uniform(rng, 1.0, 6.0) * degree;
            return uniform(rng, 0.0, 1.0) < 0.5 ? -d : d;
        };
        const double a1 = base + tilt();
        const double a2 = base + 90.0 * degree + tilt();
        const double l1 = uniform(rng, 8.0, 40.0);
        const double l2 = uniform(rng, 8.0, 40.0);
        const double ax = uniform(rng, kMargin, kImage - kMargin);
        const double ay = uniform(rng, kMargin, kImage - kMargin);
        const GridTriangle t = {snap(ax, ay), snap(ax + l1 * std::cos(a1), ay + l1 * std::sin(a1)),
                                snap(ax + l2 * std::cos(a2), ay + l2 * std::sin(a2))};
        if (area_px(t) > 0.0 && on_image(t)) return t;
    }
}

TriangleExact exact_answers(const GridTriangle& t) {
    TriangleExact e;
    e.triangle = t;
    e.box = bounding_pixels(t);
    for (const Filter f : kFilters) {
        const auto fi = static_cast<std::size_t>(f);
        const PixelBox region = e.box.grown(filter_reach(f));
        for (int y = region.y0; y <= region.y1; ++y) {
            for (int x = region.x0; x <= region.x1; ++x) {
                double value = 0.0;
                const SupportOverlap where = classify_support(t, x, y, f);
                if (where == SupportOverlap::inside) {
                    value = 1.0;
                } else if (where == SupportOverlap::partial) {
                    value = f == Filter::box ? exact_pixel_area(t, x, y).to_double()
                                             : filtered_coverage(t, x, y, f);
                }
                e.value[fi].push_back(value);
                e.edge[fi].push_back(where == SupportOverlap::partial ? 1 : 0);
            }
        }
    }
    return e;
}

// ---- the measured kernel ----

struct Variant {
    const Pattern* pattern;
    Filter filter;
    Resolve resolve;

    std::string label() const { return std::to_string(pattern->samples) + " " + pattern->name; }
    std::string name() const { return label() + " " + filter_name(filter); }
};

// Sample coverage of every sample in the triangle's pixels, the resolve of every evaluated
// pixel into `out`, and the coverage buffer cleared again for the next triangle.
void estimate(const TriangleExact& e, const Variant& v, std::vector<std::uint8_t>& coverage,
              std::vector<double>& out) {
    const Pattern& p = *v.pattern;
    const auto samples = static_cast<std::size_t>(p.samples);
    const SampleCoverage test(e.triangle);
    for (int y = e.box.y0; y <= e.box.y1; ++y) {
        for (int x = e.box.x0; x <= e.box.x1; ++x) {
            const SamplePoint* o = p.at(x, y);
            std::uint8_t* c = &coverage[static_cast<std::size_t>(y * kImage + x) * samples];
            for (std::size_t k = 0; k < samples; ++k) {
                c[k] = test.covers({x * kUnits + o[k].x, y * kUnits + o[k].y}) ? 1 : 0;
            }
        }
    }
    const PixelBox region = e.box.grown(filter_reach(v.filter));
    for (int y = region.y0; y <= region.y1; ++y) {
        for (int x = region.x0; x <= region.x1; ++x) {
            const std::uint8_t* c = &coverage[static_cast<std::size_t>(y * kImage + x) * samples];
            double sum = 0.0;
            for (const Tap& t : v.resolve.at(x, y)) sum += t.weight * c[t.offset];
            out.push_back(sum);
        }
    }
    for (int y = e.box.y0; y <= e.box.y1; ++y) {
        std::memset(&coverage[static_cast<std::size_t>(y * kImage + e.box.x0) * samples], 0,
                    static_cast<std::size_t>(e.box.width()) * samples);
    }
}

struct Measure {
    std::uint64_t pixels = 0;
    std::uint64_t edge_pixels = 0;
    double error_sum = 0.0;
    double error_max = 0.0;
    double edge_error_sum = 0.0;
    double edge_error_max = 0.0;
    std::vector<double> rounds;  // seconds per timed round
    std::size_t triangles = 0;

    void add(const Measure& m) {
        pixels += m.pixels;
        edge_pixels += m.edge_pixels;
        error_sum += m.error_sum;
        error_max = std::max(error_max, m.error_max);
        edge_error_sum += m.edge_error_sum;
        edge_error_max = std::max(edge_error_max, m.edge_error_max);
        rounds.resize(std::max(rounds.size(), m.rounds.size()), 0.0);
        for (std::size_t k = 0; k < m.rounds.size(); ++k) rounds[k] += m.rounds[k];
        triangles += m.triangles;
    }
    double mean_error() const {
        return pixels == 0 ? 0.0 : error_sum / static_cast<double>(pixels);
    }
    double mean_edge_error() const {
        return edge_pixels == 0 ? 0.0 : edge_error_sum / static_cast<double>(edge_pixels);
    }
    Timing ns_per_pixel() const {
        return pixels == 0 ? Timing{}
                           : scaled(timing_of(rounds), 1e9 / static_cast<double>(pixels));
    }
};

// One timed round of the variant over the family; the estimates land in `estimates`.
double time_round(const Family& family, const Variant& v, std::vector<std::uint8_t>& coverage,
                  std::vector<double>& estimates) {
    estimates.clear();
    const auto t0 = std::chrono::steady_clock::now();
    for (const TriangleExact& e : family.triangles) estimate(e, v, coverage, estimates);
    return seconds_since(t0);
}

Measure measure(const Family& family, const Variant& v) {
    std::vector<std::uint8_t> coverage(
        static_cast<std::size_t>(kImage * kImage * v.pattern->samples), 0);
    std::vector<double> first;
    Measure m;
    m.triangles = family.triangles.size();
    time_round(family, v, coverage, first);  // untimed: the errors' pass, which warms the caches
    const auto fi = static_cast<std::size_t>(v.filter);
    std::size_t i = 0;
    for (const TriangleExact& e : family.triangles) {
        for (std::size_t p = 0; p < e.value[fi].size(); ++p, ++i) {
            const double err = std::abs(first[i] - e.value[fi][p]);
            ++m.pixels;
            m.error_sum += err;
            m.error_max = std::max(m.error_max, err);
            if (e.edge[fi][p] != 0) {
                ++m.edge_pixels;
                m.edge_error_sum += err;
                m.edge_error_max = std::max(m.edge_error_max, err);
            }
        }
    }
    REFRASTER_ASSERT(i == first.size(), "one estimate per evaluated pixel");
    return m;
}

std::string short_number(double v) {
    std::ostringstream o;
    o << std::setprecision(3) << v;
    return o.str();
}

}  // namespace

StudyOutput run_antialiasing_study(const StudyOptions& options) {
    // About a minute on one core by default; a second or two with --quick.
    const std::size_t per_family = options.quick ? 20 : 800;
    const int rounds = options.quick ? kQuickRounds : kRounds;

    std::vector<Pattern> patterns;
    patterns.push_back(centre_pattern());
    patterns.push_back(gl4_pattern());
    for (const int n : {4, 8}) {
        patterns.push_back(regular_pattern(n));
        patterns.push_back(rotated_pattern(n));
        patterns.push_back(stratified_pattern(n, options.seed));
    }
    std::vector<Variant> variants;
    for (const Pattern& p : patterns) {
        for (const Filter f : kFilters) variants.push_back({&p, f, make_resolve(p, f)});
    }

    using Maker = GridTriangle (*)(std::mt19937_64&);
    const std::vector<std::pair<std::string, Maker>> makers = {{"medium", medium_triangle},
                                                               {"sliver", sliver_triangle},
                                                               {"near-axis", near_axis_triangle}};

    // results[variant][family], and the pixel-weighted total over families.
    std::vector<std::vector<Measure>> results(variants.size());
    std::vector<Measure> totals(variants.size());
    for (std::size_t fam = 0; fam < makers.size(); ++fam) {
        Family family{makers[fam].first, {}};
        std::mt19937_64 rng(options.seed * 0x9e3779b97f4a7c15u + fam + 1);
        report(options, "antialiasing: family " + family.name + ", exact coverage of " +
                            std::to_string(per_family) + " triangles");
        for (std::size_t n = 0; n < per_family; ++n) {
            family.triangles.push_back(exact_answers(makers[fam].second(rng)));
        }
        for (std::size_t vi = 0; vi < variants.size(); ++vi) {
            report(options, "antialiasing: family " + family.name + ", variant " +
                                variants[vi].name() + " (" + std::to_string(vi + 1) + "/" +
                                std::to_string(variants.size()) + ")");
            results[vi].push_back(measure(family, variants[vi]));
        }
        report(options, "antialiasing: family " + family.name + ", " + std::to_string(rounds) +
                            " timed rounds of every variant");
        std::vector<double> estimates;
        for (int r = 0; r < rounds; ++r) {
            for (std::size_t vi = 0; vi < variants.size(); ++vi) {
                std::vector<std::uint8_t> coverage(
                    static_cast<std::size_t>(kImage * kImage * variants[vi].pattern->samples), 0);
                results[vi].back().rounds.push_back(
                    time_round(family, variants[vi], coverage, estimates));
            }
        }
        for (std::size_t vi = 0; vi < variants.size(); ++vi) totals[vi].add(results[vi].back());
    }

    StudyOutput out;
    out.name = "antialiasing";
    CsvTable csv({"study", "family", "seed", "samples", "pattern", "filter", "pixels",
                  "edge_pixels", "mean_error", "max_error", "mean_edge_error", "max_edge_error",
                  "ns_per_pixel", "ns_per_pixel_low", "ns_per_pixel_high", "rounds", "triangles"});
    const auto row = [&](const std::string& family, const Variant& v, const Measure& m) {
        csv.add_row({"antialiasing", family, std::to_string(options.seed),
                     std::to_string(v.pattern->samples), v.pattern->name, filter_name(v.filter),
                     std::to_string(m.pixels), std::to_string(m.edge_pixels),
                     csv_number(m.mean_error()), csv_number(m.error_max),
                     csv_number(m.mean_edge_error()), csv_number(m.edge_error_max),
                     csv_number(m.ns_per_pixel().median), csv_number(m.ns_per_pixel().low),
                     csv_number(m.ns_per_pixel().high), std::to_string(m.rounds.size()),
                     std::to_string(m.triangles)});
    };
    for (std::size_t fam = 0; fam < makers.size(); ++fam) {
        for (std::size_t vi = 0; vi < variants.size(); ++vi) {
            row(makers[fam].first, variants[vi], results[vi][fam]);
        }
    }
    for (std::size_t vi = 0; vi < variants.size(); ++vi) row("all", variants[vi], totals[vi]);
    out.csv = csv.text();

    // The figure: per filter, error against run time, a series per pattern; then error
    // against samples, a curve per pattern and filter (1 and 4 samples are the centre and
    // GL's pattern for every curve).
    const auto find = [&](const std::string& pattern, int samples, Filter f) -> const Measure& {
        for (std::size_t vi = 0; vi < variants.size(); ++vi) {
            if (variants[vi].pattern->name == pattern && variants[vi].pattern->samples == samples &&
                variants[vi].filter == f) {
                return totals[vi];
            }
        }
        REFRASTER_ASSERT(false, "a measured variant");
        return totals.front();
    };
    std::vector<PlotPanel> panels;
    for (const Filter f : kFilters) {
        PlotPanel panel{std::string(filter_name(f)) + " filter: error against run time",
                        "ns per pixel (sample coverage + resolve)",
                        "mean |error| on edge pixels",
                        true,
                        true,
                        {},
                        true,
                        {}};
        for (const Pattern& p : patterns) {
            const auto it = std::find_if(panel.series.begin(), panel.series.end(),
                                         [&](const PlotSeries& s) { return s.name == p.name; });
            PlotSeries& s = it != panel.series.end()
                                ? *it
                                : panel.series.emplace_back(PlotSeries{p.name, {}, false});
            const Measure& m = find(p.name, p.samples, f);
            const Timing t = m.ns_per_pixel();
            s.points.push_back({t.median, m.mean_edge_error(),
                                std::to_string(p.samples) + " " + p.name, t.low, t.high});
        }
        panels.push_back(std::move(panel));
    }
    for (PlotPanel& panel : panels) panel.x_label = "ns per pixel (median, range of rounds)";
    PlotPanel by_samples{"error against samples (all families)",
                         "samples per pixel",
                         "mean |error| on edge pixels",
                         true,
                         true,
                         {},
                         false,
                         {}};
    const std::vector<std::string> grid_patterns = {"regular", "rotated", "stratified"};
    for (const std::string& pattern : grid_patterns) {
        for (const Filter f : kFilters) {
            PlotSeries s{pattern + ", " + filter_name(f), {}, true};
            s.points.push_back({1.0, find("centre", 1, f).mean_edge_error(), ""});
            s.points.push_back({4.0, find("gl4", 4, f).mean_edge_error(), ""});
            for (const int n : {16, 64}) {
                s.points.push_back(
                    {static_cast<double>(n), find(pattern, n, f).mean_edge_error(), ""});
            }
            by_samples.series.push_back(std::move(s));
        }
    }
    panels.push_back(std::move(by_samples));
    out.svg = svg_figure("refraster study antialiasing: error against run time (seed " +
                             std::to_string(options.seed) + (options.quick ? ", quick" : "") + ")",
                         panels, 2, Legend::Shared);

    // Conclusions.
    for (const Filter f : kFilters) {
        const std::string fname = filter_name(f);
        const double e1 = find("centre", 1, f).mean_edge_error();
        const double e4 = find("gl4", 4, f).mean_edge_error();
        out.summary.push_back(fname + ": mean edge error " + short_number(e1) + " with 1 sample, " +
                              short_number(e4) + " with GL's 4 (x" + short_number(e4 / e1) + ")");
        for (const std::string& pattern : grid_patterns) {
            const double e16 = find(pattern, 16, f).mean_edge_error();
            const double e64 = find(pattern, 64, f).mean_edge_error();
            const double slope = std::log(e64 / e16) / std::log(4.0);
            out.summary.push_back(fname + ", " + pattern + ": mean edge error " +
                                  short_number(e16) + " at 16 samples, " + short_number(e64) +
                                  " at 64: x" + short_number(e64 / e16) +
                                  " per 4x samples (error ~ samples^" + short_number(slope) + ")");
        }
        std::vector<PlotPoint> points;
        for (const Pattern& p : patterns) {
            const Measure& m = find(p.name, p.samples, f);
            const Timing t = m.ns_per_pixel();
            points.push_back({t.median, m.mean_edge_error(),
                              std::to_string(p.samples) + " " + p.name, t.low, t.high});
        }
        std::string front;
        for (const std::size_t i : pareto_front(points)) {
            front += (front.empty() ? "" : ", ") + points[i].label + " (" +
                     short_number(points[i].x) + " ns/px, " + short_number(points[i].y) + ")";
        }
        out.summary.push_back(fname +
                              " Pareto front (better beyond the timing spread; ns per pixel, "
                              "mean edge error): " +
                              front);
    }
    // Where regular grids alias: the near-axis family, per pattern.
    for (const int n : {16, 64}) {
        std::string line = "near-axis, box, " + std::to_string(n) + " samples: mean edge error";
        for (const std::string& pattern : grid_patterns) {
            for (std::size_t vi = 0; vi < variants.size(); ++vi) {
                const Variant& v = variants[vi];
                if (v.pattern->name == pattern && v.pattern->samples == n &&
                    v.filter == Filter::box) {
                    line += " " + pattern + " " + short_number(results[vi][2].mean_edge_error());
                }
            }
        }
        out.summary.push_back(line);
    }

    // The decision table: for each target of mean edge error, the cheapest variant meeting it.
    const Timing one = find("centre", 1, Filter::box).ns_per_pixel();
    std::ostringstream table;
    table << "| mean edge error at most | the cheapest variant | ns per pixel, median (range) | "
             "time against 1 sample (box) | as fast within the spread |\n"
             "|---|---|---|---|---|\n";
    for (const double target : {0.1, 0.03, 0.01, 0.003, 0.001}) {
        std::vector<std::size_t> meeting;
        for (std::size_t vi = 0; vi < variants.size(); ++vi)
            if (totals[vi].mean_edge_error() <= target) meeting.push_back(vi);
        if (meeting.empty()) {
            table << "| " << short_number(target) << " | none of the variants | | | |\n";
            continue;
        }
        const std::size_t best =
            *std::min_element(meeting.begin(), meeting.end(), [&](std::size_t a, std::size_t b) {
                return totals[a].ns_per_pixel().median < totals[b].ns_per_pixel().median;
            });
        const Timing bt = totals[best].ns_per_pixel();
        std::string alike;
        for (const std::size_t vi : meeting)
            if (vi != best && totals[vi].ns_per_pixel().low <= bt.high)
                alike += (alike.empty() ? "" : ", ") + variants[vi].name();
        table << "| " << short_number(target) << " | " << variants[best].name() << " (error "
              << short_number(totals[best].mean_edge_error()) << ") | " << short_number(bt.median)
              << " (" << short_number(bt.low) << "-" << short_number(bt.high) << ") | "
              << ratio_text(ratio_of(bt, one)) << " | " << (alike.empty() ? "none" : alike)
              << " |\n";
    }
    out.decisions = table.str();

    // In words.
    {
        const double e1 = find("centre", 1, Filter::box).mean_edge_error();
        const double e4 = find("gl4", 4, Filter::box).mean_edge_error();
        out.conclusions.push_back("GL's 4x pattern removes " +
                                  short_number(100.0 * (1.0 - e4 / e1)) +
                                  "% of one sample's mean edge error with the box filter (" +
                                  short_number(e1) + " to " + short_number(e4) + ").");
        const double r16 = find("rotated", 16, Filter::box).mean_edge_error();
        const double r64 = find("rotated", 64, Filter::box).mean_edge_error();
        const double g64 = find("regular", 64, Filter::box).mean_edge_error();
        const double s64 = find("stratified", 64, Filter::box).mean_edge_error();
        out.conclusions.push_back(
            "Four times the samples cut the rotated grid's box error by " +
            short_number(r16 / r64) + " (16 to 64 samples: " + short_number(r16) + " to " +
            short_number(r64) + "); at 64 samples the rotated grid's " + short_number(r64) +
            " beats the regular grid's " + short_number(g64) + " and stratified random's " +
            short_number(s64) + ".");
        const double t1 = find("centre", 1, Filter::tent).mean_edge_error();
        const double t4 = find("gl4", 4, Filter::tent).mean_edge_error();
        const double q4 = find("gl4", 4, Filter::gaussian).mean_edge_error();
        out.conclusions.push_back(
            "Against the coverage each filter defines, the tent and the "
            "Gaussian reach a given error with fewer samples than the box "
            "(GL 4x: " +
            short_number(t4) + " and " + short_number(q4) + " against " + short_number(e4) +
            "; one sample's tent error: " + short_number(t1) + ").");
        double widest = 0.0;
        for (const Measure& m : totals) {
            const Timing t = m.ns_per_pixel();
            if (t.median > 0.0) widest = std::max(widest, (t.high - t.low) / t.median);
        }
        out.conclusions.push_back(
            "Times are medians of " + std::to_string(rounds) +
            " interleaved rounds; the widest range of one variant's rounds was " +
            short_number(100.0 * widest) + "% of its median" +
            (widest > 0.2 ? ": the machine was loaded, and only differences beyond the ranges count"
                          : "") +
            ".");
    }
    return out;
}

}  // namespace harness
