// The antialiasing study: the estimators' exact sample test and its tie rule, and a quick
// run's table and figure (shape, determinism, and that more samples mean less error).
#include <gtest/gtest.h>

#include <map>
#include <sstream>

#include "harness/study.hpp"
#include "study/exact_area.hpp"

namespace {

using harness::study::GridPoint;
using harness::study::GridTriangle;
using harness::study::kSampleUnitsPerPixel;
using harness::study::SampleCoverage;
using harness::study::SamplePoint;

// Vertices in 1/16 px, samples in 1/16 px: on both grids exactly.
GridPoint g16(std::int64_t x, std::int64_t y) {
    return {x * 16, y * 16};
}
SamplePoint s16(std::int64_t x, std::int64_t y) {
    return {x * kSampleUnitsPerPixel / 16, y * kSampleUnitsPerPixel / 16};
}

TEST(StudyAntialiasing, TieRuleOwnsLeftAndBottomEdges) {
    // (0,0), (4,0), (0,4) in pixels, either orientation.
    const GridTriangle ccw = {g16(0, 0), g16(64, 0), g16(0, 64)};
    const GridTriangle cw = {g16(0, 0), g16(0, 64), g16(64, 0)};
    for (const GridTriangle& t : {ccw, cw}) {
        const SampleCoverage c(t);
        EXPECT_TRUE(c.covers(s16(0, 16)));    // on the left edge
        EXPECT_TRUE(c.covers(s16(16, 0)));    // on the bottom edge
        EXPECT_TRUE(c.covers(s16(0, 0)));     // the vertex of both
        EXPECT_FALSE(c.covers(s16(32, 32)));  // on the hypotenuse, a right (top) edge
        EXPECT_FALSE(c.covers(s16(64, 0)));   // its end on the bottom edge
        EXPECT_FALSE(c.covers(s16(0, 64)));   // its end on the left edge
        EXPECT_TRUE(c.covers(s16(31, 32)));   // just inside the hypotenuse
        EXPECT_FALSE(c.covers(s16(-1, 16)));
        EXPECT_FALSE(c.covers(s16(16, -1)));
    }
    // Degenerate triangles cover nothing, not even their own points.
    const SampleCoverage line({g16(0, 0), g16(32, 32), g16(64, 64)});
    EXPECT_TRUE(line.degenerate());
    EXPECT_FALSE(line.covers(s16(16, 16)));
}

TEST(StudyAntialiasing, SharedEdgesCoverEverySampleOnce) {
    // A 4 px square split along its diagonal: every sample of the half-open square
    // [0,4) x [0,4) is covered exactly once, also on the diagonal, and nothing else is.
    const GridTriangle lower = {g16(0, 0), g16(64, 0), g16(64, 64)};
    const GridTriangle upper = {g16(0, 0), g16(64, 64), g16(0, 64)};
    const SampleCoverage a(lower);
    const SampleCoverage b(upper);
    int on_diagonal = 0;
    for (std::int64_t y = -8; y <= 72; ++y) {
        for (std::int64_t x = -8; x <= 72; ++x) {
            const int hits = (a.covers(s16(x, y)) ? 1 : 0) + (b.covers(s16(x, y)) ? 1 : 0);
            const bool in_square = x >= 0 && x < 64 && y >= 0 && y < 64;
            ASSERT_EQ(hits, in_square ? 1 : 0) << x << ", " << y;
            if (in_square && x == y) ++on_diagonal;
        }
    }
    EXPECT_EQ(on_diagonal, 64);
    // Pairs sharing a slanted edge through many samples, from both sides.
    const GridPoint p = g16(10, 7);
    const GridPoint q = g16(10 + 3 * 9, 7 + 2 * 9);  // 10 samples on the edge, 1/16 apart in t
    for (const auto& [c, d] : {std::pair{g16(0, 50), g16(60, 0)}, {g16(50, -5), g16(-9, 40)}}) {
        const SampleCoverage one({p, q, c});
        const SampleCoverage two({q, p, d});
        for (std::int64_t t = 1; t < 9; ++t) {
            const SamplePoint s = s16(10 + 3 * t, 7 + 2 * t);
            EXPECT_EQ((one.covers(s) ? 1 : 0) + (two.covers(s) ? 1 : 0), 1) << t;
        }
    }
}

TEST(StudyAntialiasing, AFanOwnsItsCentreOnce) {
    // Eight triangles around the centre (32, 32) (in 1/16 px), in both orientations: the
    // centre, a vertex of all of them, is covered by exactly one.
    const std::int64_t rim[8][2] = {{64, 32}, {60, 60}, {32, 64}, {3, 58},
                                    {0, 32},  {5, 2},   {32, 0},  {62, 1}};
    for (const bool reversed : {false, true}) {
        int hits = 0;
        for (int i = 0; i < 8; ++i) {
            const GridPoint u = g16(rim[i][0], rim[i][1]);
            const GridPoint w = g16(rim[(i + 1) % 8][0], rim[(i + 1) % 8][1]);
            const GridTriangle t =
                reversed ? GridTriangle{g16(32, 32), w, u} : GridTriangle{g16(32, 32), u, w};
            if (SampleCoverage(t).covers(s16(32, 32))) ++hits;
        }
        EXPECT_EQ(hits, 1);
    }
}

// The quick run, once for all the tests below.
const harness::StudyOutput& quick_run() {
    static const harness::StudyOutput out = [] {
        harness::StudyOptions o;
        o.quick = true;
        o.seed = 5;
        return harness::run_antialiasing_study(o);
    }();
    return out;
}

std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::istringstream cells_in(line);
        std::string cell;
        while (std::getline(cells_in, cell, ',')) cells.push_back(cell);
        rows.push_back(cells);
    }
    return rows;
}

TEST(StudyAntialiasing, QuickRunTableAndFigure) {
    const harness::StudyOutput& out = quick_run();
    EXPECT_EQ(out.name, "antialiasing");
    const auto rows = parse_csv(out.csv);
    ASSERT_FALSE(rows.empty());
    const std::vector<std::string> header = {
        "study",        "family",           "seed",
        "samples",      "pattern",          "filter",
        "pixels",       "edge_pixels",      "mean_error",
        "max_error",    "mean_edge_error",  "max_edge_error",
        "ns_per_pixel", "ns_per_pixel_low", "ns_per_pixel_high",
        "rounds",       "triangles"};
    EXPECT_EQ(rows[0], header);
    // 8 sample patterns x 3 filters, for 3 families and their total.
    ASSERT_EQ(rows.size(), 1u + 24u * 4u);
    std::map<std::string, int> per_family;
    for (std::size_t i = 1; i < rows.size(); ++i) {
        const auto& r = rows[i];
        ASSERT_EQ(r.size(), header.size());
        EXPECT_EQ(r[0], "antialiasing");
        EXPECT_EQ(r[2], "5");
        ++per_family[r[1]];
        const double pixels = std::stod(r[6]);
        const double edge = std::stod(r[7]);
        EXPECT_GT(edge, 0.0);
        EXPECT_LE(edge, pixels);
        for (const int c : {8, 9, 10, 11}) {
            EXPECT_GE(std::stod(r[static_cast<std::size_t>(c)]), 0.0);
            EXPECT_LE(std::stod(r[static_cast<std::size_t>(c)]), 1.0);
        }
        EXPECT_LE(std::stod(r[8]), std::stod(r[10]));  // edge pixels hold all the error
        EXPECT_LE(std::stod(r[10]), std::stod(r[11]));
        EXPECT_GT(std::stod(r[12]), 0.0);
        // A time is the median of its rounds, within their range; a quick run times 3 rounds.
        EXPECT_LE(std::stod(r[13]), std::stod(r[12]));
        EXPECT_LE(std::stod(r[12]), std::stod(r[14]));
        EXPECT_EQ(r[15], "3");
    }
    EXPECT_EQ(per_family, (std::map<std::string, int>{
                              {"all", 24}, {"medium", 24}, {"near-axis", 24}, {"sliver", 24}}));
    EXPECT_NE(out.svg.find("<svg"), std::string::npos);
    EXPECT_NE(out.svg.find("Pareto front"), std::string::npos);
    EXPECT_NE(out.svg.find("error against samples"), std::string::npos);
    EXPECT_FALSE(out.summary.empty());
}

double column(const harness::StudyOutput& out, const std::string& family,
              const std::string& samples, const std::string& pattern, const std::string& filter,
              std::size_t col) {
    for (const auto& r : parse_csv(out.csv)) {
        if (r[1] == family && r[3] == samples && r[4] == pattern && r[5] == filter) {
            return std::stod(r[col]);
        }
    }
    ADD_FAILURE() << "no row " << family << " " << samples << " " << pattern << " " << filter;
    return 0.0;
}

TEST(StudyAntialiasing, MoreSamplesLessError) {
    const harness::StudyOutput& out = quick_run();
    constexpr std::size_t mean = 8, mean_edge = 10;
    for (const std::string filter : {"box", "tent", "gaussian"}) {
        const double one = column(out, "medium", "1", "centre", filter, mean);
        const double four = column(out, "medium", "4", "gl4", filter, mean);
        const double sixteen = column(out, "medium", "16", "regular", filter, mean);
        const double many = column(out, "medium", "64", "regular", filter, mean);
        EXPECT_LT(four, one) << filter;
        EXPECT_LT(sixteen, four) << filter;
        EXPECT_LT(many, sixteen) << filter;
        // Regular grids converge like about 1/n on edges: 4x the samples, at least 1.5x less.
        EXPECT_LT(column(out, "all", "64", "regular", filter, mean_edge) * 1.5,
                  column(out, "all", "16", "regular", filter, mean_edge))
            << filter;
    }
    // The same variant on the same triangles counts the same pixels whatever the pattern.
    EXPECT_EQ(column(out, "sliver", "64", "rotated", "tent", 6),
              column(out, "sliver", "1", "centre", "tent", 6));
}

TEST(StudyAntialiasing, SameSeedSameErrors) {
    harness::StudyOptions o;
    o.quick = true;
    o.seed = 5;
    std::vector<std::string> lines;
    o.progress = [&](const std::string& l) { lines.push_back(l); };
    const harness::StudyOutput again = harness::run_antialiasing_study(o);
    const auto a = parse_csv(quick_run().csv);
    const auto b = parse_csv(again.csv);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 1; i < a.size(); ++i) {
        for (std::size_t c = 0; c < a[i].size(); ++c) {
            if (c >= 12 && c <= 14) continue;  // the run time and its range
            EXPECT_EQ(a[i][c], b[i][c]) << "row " << i << " column " << c;
        }
    }
    // A line per family's exact answers, its timing rounds and per family and variant.
    EXPECT_EQ(lines.size(), 3u * (1u + 1u + 24u));
}

}  // namespace
