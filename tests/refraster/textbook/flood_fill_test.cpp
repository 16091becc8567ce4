// The boundary fill (flood_fill.hpp) against the connected component of the seed, computed by
// a different method: union-find over all non-boundary pixels with 4- or 8-adjacency, then
// the pixels in the seed's class. Exhaustive over seeds, on many random boundary images of
// several densities, and on Bresenham outlines, where the 8-connected fill must leak.
#include "refraster/textbook/flood_fill.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <optional>
#include <random>
#include <vector>

#include "refraster/textbook/lines.hpp"
#include "refraster/textbook/scanline_fill.hpp"

namespace {

using refraster::textbook::Connectivity;
using refraster::textbook::PixelIndex;
using refraster::textbook::Raster;

class UnionFind {
  public:
    explicit UnionFind(int n) : parent_(static_cast<std::size_t>(n)) {
        std::iota(parent_.begin(), parent_.end(), 0);
    }
    int find(int a) {
        while (parent_[static_cast<std::size_t>(a)] != a) {
            const auto i = static_cast<std::size_t>(a);
            parent_[i] = parent_[static_cast<std::size_t>(parent_[i])];
            a = parent_[i];
        }
        return a;
    }
    void join(int a, int b) { parent_[static_cast<std::size_t>(find(a))] = find(b); }

  private:
    std::vector<int> parent_;
};

// The seed's component among non-boundary pixels, as a raster.
Raster component(const Raster& boundary, PixelIndex seed, Connectivity c) {
    const int w = boundary.width();
    const int h = boundary.height();
    UnionFind uf(w * h);
    const auto open = [&](int x, int y) {
        return boundary.contains(x, y) && boundary.at(x, y) == 0.0;
    };
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            if (!open(x, y)) continue;
            // Links to the neighbours already visited in row-major order, plus the up-left
            // diagonal's mirror (up-right) for 8-adjacency.
            if (open(x - 1, y)) uf.join(y * w + x, y * w + x - 1);
            if (open(x, y - 1)) uf.join(y * w + x, (y - 1) * w + x);
            if (c == Connectivity::Eight) {
                if (open(x - 1, y - 1)) uf.join(y * w + x, (y - 1) * w + x - 1);
                if (open(x + 1, y - 1)) uf.join(y * w + x, (y - 1) * w + x + 1);
            }
        }
    }
    Raster out(w, h);
    if (!open(seed.x, seed.y)) return out;
    const int root = uf.find(seed.y * w + seed.x);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            if (open(x, y) && uf.find(y * w + x) == root) out.set(x, y, 1.0);
        }
    }
    return out;
}

TEST(TextbookFloodFill, EverySeedOfRandomBoundariesFillsExactlyItsComponent) {
    std::mt19937 rng(99);
    for (int image = 0; image < 600; ++image) {
        const int w = 3 + image % 6;
        const int h = 3 + (image / 6) % 5;
        std::bernoulli_distribution wall(0.15 + 0.1 * (image % 5));
        Raster boundary(w, h);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) boundary.set(x, y, wall(rng) ? 1.0 : 0.0);
        }
        for (int s = -1; s <= w * h; ++s) {
            const PixelIndex seed =
                s < 0 || s == w * h ? PixelIndex{s, 0} : PixelIndex{s % w, s / w};
            for (const Connectivity c : {Connectivity::Four, Connectivity::Eight}) {
                const auto r = refraster::textbook::flood_fill(boundary, seed, c);
                ASSERT_EQ(r.raster, component(boundary, seed, c))
                    << "image " << image << " seed " << seed.x << ", " << seed.y;
                ASSERT_EQ(static_cast<int>(r.order.size()), r.raster.count_nonzero());
            }
        }
    }
}

TEST(TextbookFloodFill, ABresenhamOutlineHoldsTheFourFillAndLeaksTheEightFill) {
    // A triangle outlined by Bresenham lines: 8-connected, with diagonal steps.
    constexpr int kSize = 16;
    const refraster::textbook::Point2 a{1.5, 1.5}, b{14.5, 3.5}, c{5.5, 13.5};
    Raster outline(kSize, kSize);
    for (const auto& [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
        const auto line = refraster::textbook::bresenham_line(p, q, kSize, kSize);
        for (int y = 0; y < kSize; ++y) {
            for (int x = 0; x < kSize; ++x) {
                if (line.raster.at(x, y) > 0.0) outline.set(x, y, 1.0);
            }
        }
    }
    const PixelIndex seed{6, 5};
    const auto four = refraster::textbook::flood_fill(outline, seed, Connectivity::Four);
    const auto eight = refraster::textbook::flood_fill(outline, seed, Connectivity::Eight);
    EXPECT_EQ(four.raster, component(outline, seed, Connectivity::Four));
    EXPECT_EQ(eight.raster, component(outline, seed, Connectivity::Eight));
    // The 4-fill stays inside the triangle through the three centres; the 8-fill reaches a
    // corner of the raster outside it.
    const auto inside = refraster::textbook::scanline_fill(
        {{a, b, c}}, refraster::textbook::FillRule::EvenOdd, kSize, kSize);
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            if (four.raster.at(x, y) > 0.0) {
                EXPECT_EQ(inside.raster.at(x, y), 1.0) << x << ", " << y;
            }
        }
    }
    EXPECT_GT(four.raster.count_nonzero(), 20);
    EXPECT_EQ(eight.raster.at(0, kSize - 1), 1.0);
}

TEST(TextbookFloodFill, TraceHasOneStepPerPopWithTheStack) {
    Raster boundary(3, 3);
    boundary.set(1, 1, 1.0);
    refraster::textbook::Trace trace;
    const auto r = refraster::textbook::flood_fill(boundary, {0, 0}, Connectivity::Four, &trace);
    EXPECT_EQ(r.order.size(), 8u);
    // 8 fills push 4 each: 1 + 32 pops.
    EXPECT_EQ(trace.steps.size(), 33u);
    EXPECT_EQ(trace.steps.front().title, "pop (0, 0): fill, push its neighbours");
    EXPECT_EQ(trace.steps.front().state[0].second, "[(1, 0), (-1, 0), (0, 1), (0, -1)]");
}

// The seed by its definition: among the pixels that are not boundary pixels and whose centre
// the outline winds around, the first by (Chebyshev distance from the pixel holding the
// vertices' mean, row, column), found by testing every pixel of the raster.
std::optional<PixelIndex> seed_by_definition(const Raster& boundary,
                                             const std::vector<refraster::textbook::Point2>& o) {
    double mx = 0, my = 0;
    for (const auto& p : o) {
        mx += p.x;
        my += p.y;
    }
    const int cx = static_cast<int>(std::floor(mx / static_cast<double>(o.size())));
    const int cy = static_cast<int>(std::floor(my / static_cast<double>(o.size())));
    std::optional<PixelIndex> best;
    int best_r = 0;
    for (int y = 0; y < boundary.height(); ++y) {
        for (int x = 0; x < boundary.width(); ++x) {
            if (boundary.at(x, y) > 0.0) continue;
            if (refraster::textbook::winding_at_centre(o, x, y) == 0) continue;
            const int r = std::max(std::abs(x - cx), std::abs(y - cy));
            if (!best || r < best_r) {  // row-major order breaks ties within a ring
                best = PixelIndex{x, y};
                best_r = r;
            }
        }
    }
    return best;
}

TEST(TextbookSeed, IsTheNearestInsidePixelAndTestsEachPixelOfTheBoxOnce) {
    std::mt19937 rng(4242);
    std::uniform_real_distribution<double> coord(-6.0, 26.0);
    for (int n = 0; n < 400; ++n) {
        const int w = 4 + n % 17;
        const int h = 3 + n % 11;
        std::vector<refraster::textbook::Point2> outline;
        const int vertices = 3 + n % 6;
        for (int k = 0; k < vertices; ++k) outline.push_back({coord(rng), coord(rng)});
        Raster boundary(w, h);
        for (int k = 0; k < vertices; ++k) {
            const auto line = refraster::textbook::bresenham_line(
                outline[static_cast<std::size_t>(k)],
                outline[static_cast<std::size_t>((k + 1) % vertices)], w, h);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    if (line.raster.at(x, y) > 0.0) boundary.set(x, y, 1.0);
        }
        std::size_t examined = 0;
        const auto seed = refraster::textbook::seed_inside(boundary, outline, &examined);
        const auto expected = seed_by_definition(boundary, outline);
        SCOPED_TRACE("outline " + std::to_string(n));
        ASSERT_EQ(seed.has_value(), expected.has_value());
        if (seed) {
            EXPECT_EQ(seed->x, expected->x);
            EXPECT_EQ(seed->y, expected->y);
        }
        EXPECT_LE(examined, static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    }
}

TEST(TextbookSeed, ASliverAcrossAWideRasterTestsOnlyItsBox) {
    // A sliver along the diagonal of a 16384 x 4 raster, thinner than the distance from its
    // spine to any pixel centre: no centre is inside, so the search tests every pixel of its box
    // (the whole raster) once; a search over growing squares around the mean would test about
    // 16384^3 pixels.
    const Raster boundary(16384, 4);
    const std::vector<refraster::textbook::Point2> sliver = {
        {0.0, 0.0}, {16384.0, 4.0}, {16384.0, 4.00001}};
    std::size_t examined = 0;
    const auto seed = refraster::textbook::seed_inside(boundary, sliver, &examined);
    EXPECT_FALSE(seed.has_value());
    EXPECT_EQ(examined, 16384u * 4u);
}

}  // namespace
