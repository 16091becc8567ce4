// The boundary fill (flood_fill.hpp) against the connected component of the seed, computed by
// a different method: union-find over all non-boundary pixels with 4- or 8-adjacency, then
// the pixels in the seed's class. Exhaustive over seeds, on many random boundary images of
// several densities, and on Bresenham outlines, where the 8-connected fill must leak.
#include "refraster/textbook/flood_fill.hpp"

#include <gtest/gtest.h>

#include <numeric>
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

}  // namespace
