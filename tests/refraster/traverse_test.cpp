// The tiled, hierarchical traversal covers exactly the pixels the plain per-pixel test covers,
// as row spans and as quad packets.
#include "models/llvmpipe/traverse.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <span>
#include <vector>

#include "models/llvmpipe/setup.hpp"
#include "models/llvmpipe/vector_kernels.hpp"

namespace {

using refraster::detail::PixelRect;
using refraster::detail::SetupOutcome;
using refraster::detail::SetupParams;
using refraster::detail::TriangleSetup;

std::vector<std::uint8_t> tiled(const TriangleSetup& t, int w, int h) {
    std::vector<std::uint8_t> m(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
    refraster::detail::traverse_triangle(t, [&](int y, int x0, int x1) {
        for (int x = x0; x < x1; ++x) {
            auto& px = m[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                         static_cast<std::size_t>(x)];
            ++px;  // counts, so a pixel reported twice shows up
        }
    });
    return m;
}

// The same coverage as the fragment stage receives it: single-sample quad packets at even
// coordinates, only sample 0's bits set.
std::vector<std::uint8_t> quads(const TriangleSetup& t, int w, int h) {
    std::vector<std::uint8_t> m(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
    refraster::detail::triangle_tiles(t, [&](const std::uint64_t* rows, int tx, int ty) {
        refraster::detail::emit_tile_quads(
            rows, tx, ty, [&](std::span<const refraster::detail::QuadPacket> qs) {
                for (const auto& q : qs) {
                    EXPECT_EQ(q.x % 2, 0);
                    EXPECT_EQ(q.y % 2, 0);
                    EXPECT_NE(q.mask, 0);
                    EXPECT_EQ(q.mask & ~refraster::detail::kSample0Pixels, 0);
                    for (unsigned i = 0; i < 4; ++i) {
                        if ((q.mask & (1u << refraster::detail::quad_bit(i, 0))) == 0) continue;
                        const int x = q.x + static_cast<int>(i & 1u);
                        const int y = q.y + static_cast<int>(i >> 1);
                        ++m[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                            static_cast<std::size_t>(x)];
                    }
                }
            });
    });
    return m;
}

std::vector<std::uint8_t> plain(const TriangleSetup& t, int w, int h) {
    std::vector<std::uint8_t> m(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
    for (int y = t.bbox.y0; y <= t.bbox.y1; ++y) {
        for (int x = t.bbox.x0; x <= t.bbox.x1; ++x) {
            if (refraster::detail::covers_pixel(t, x, y)) {
                m[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                  static_cast<std::size_t>(x)] = 1;
            }
        }
    }
    return m;
}

// Three vertices around a random centre of a w x h target, at most `size` apart on each axis;
// snapped to pixel centres when `on_grid`, so that edges pass exactly through centres.
std::array<std::array<float, 2>, 3> random_vertices(std::mt19937& rng, int w, int h, float size,
                                                    bool on_grid) {
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const float cx = unit(rng) * static_cast<float>(w);
    const float cy = unit(rng) * static_cast<float>(h);
    std::array<std::array<float, 2>, 3> v;
    for (auto& p : v) {
        p = {cx + (unit(rng) - 0.5f) * size, cy + (unit(rng) - 0.5f) * size};
        if (on_grid) p = {std::floor(p[0]) + 0.5f, std::floor(p[1]) + 0.5f};
    }
    return v;
}

TEST(Traversal, EqualsPerPixelTestOn100000RandomTriangles) {
    constexpr int kW = 300;  // not a multiple of the 64-pixel tile
    constexpr int kH = 200;
    std::mt19937 rng(20261122);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::uniform_int_distribution<int> coin(0, 3);
    int drawn = 0;
    int large = 0;
    for (int n = 0; drawn < 100000; ++n) {
        SetupParams p;
        p.tie_rule = static_cast<refraster::TieRule>(coin(rng));
        p.draw_region = {0, 0, kW - 1, kH - 1};
        if (n % 5 == 0) {  // a scissor-like region
            const int x0 = static_cast<int>(unit(rng) * kW), y0 = static_cast<int>(unit(rng) * kH);
            p.draw_region = refraster::detail::intersect(
                p.draw_region, {x0, y0, x0 + static_cast<int>(unit(rng) * kW),
                                y0 + static_cast<int>(unit(rng) * kH)});
        }
        // Sizes from a pixel to well beyond the target; a third on the pixel-centre grid so
        // that edges pass exactly through centres and exercise the tie rule.
        const float size = std::exp2(unit(rng) * 9.0f);
        const auto v = random_vertices(rng, kW, kH, size, n % 3 == 0);
        TriangleSetup t;
        if (refraster::detail::setup_triangle(v, p, t) != SetupOutcome::Ok) continue;
        ++drawn;
        large += (t.bbox.x1 - t.bbox.x0) > 64;
        const auto a = tiled(t, kW, kH);
        const auto b = plain(t, kW, kH);
        if (n % 4 == 0) {
            ASSERT_EQ(quads(t, kW, kH), b) << "quad packets of triangle " << n;
        }
        ASSERT_EQ(a, b) << "triangle " << n << ": (" << v[0][0] << "," << v[0][1] << ") ("
                        << v[1][0] << "," << v[1][1] << ") (" << v[2][0] << "," << v[2][1] << ")";
    }
    EXPECT_GT(large, 10000);  // the tile and block levels were exercised, not only 4x4 blocks
}

// The small-box path's row masks, scalar and by every vector builder this CPU runs, are the
// per-pixel test's pixels over random triangles whose boxes fit it (every width 1..64, 3 and
// 4 edges through triangles and their vertices' order).
TEST(Traversal, SmallBoxRowMasksEqualPerPixelTest) {
    constexpr int kW = 200;
    constexpr int kH = 150;
    std::vector<refraster::detail::RowMaskFn> builders = {nullptr};
    for (auto path : {refraster::KernelPath::Avx2, refraster::KernelPath::Avx512}) {
        if (!refraster::kernel_path_available(path)) continue;
        builders.push_back(refraster::detail::vector_row_masks(path));
        ASSERT_NE(builders.back(), nullptr);
    }
    std::mt19937 rng(20261202);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::uniform_int_distribution<int> coin(0, 3);
    int drawn = 0;
    int wide = 0;
    for (int n = 0; drawn < 30000; ++n) {
        SetupParams p;
        p.tie_rule = static_cast<refraster::TieRule>(coin(rng));
        p.draw_region = {0, 0, kW - 1, kH - 1};
        const float size = 1.0f + unit(rng) * 90.0f;
        const auto v = random_vertices(rng, kW, kH, size, n % 3 == 0);
        TriangleSetup t;
        if (refraster::detail::setup_triangle(v, p, t) != SetupOutcome::Ok) continue;
        if (t.llvmpipe_walk) continue;
        const auto expected = plain(t, kW, kH);
        for (auto* builder : builders) {
            std::vector<std::uint8_t> m(expected.size(), 0);
            const auto mark = [&](const refraster::detail::RowBlock& b) {
                for (int r = 0; r < b.rows; ++r) {
                    for (int i = 0; i < 64; ++i) {
                        if ((b.mask[r] >> i) & 1u) {
                            ++m[static_cast<std::size_t>(b.y0 + r) * kW +
                                static_cast<std::size_t>(b.x0 + i)];
                        }
                    }
                }
            };
            bool small = false;
            if (n % 2 == 0) {
                small = refraster::detail::small_convex_rows<3>(t, mark, builder);
            } else {
                // The same triangle as four edges, the first repeated: the 4-edge instances.
                struct Quad {
                    int bits;
                    PixelRect bbox;
                    std::array<refraster::detail::EdgeFunction, 4> edges;
                } quad{t.bits, t.bbox, {t.edges[0], t.edges[1], t.edges[2], t.edges[0]}};
                small = refraster::detail::small_convex_rows<4>(quad, mark, builder);
            }
            if (!small) break;
            if (builder == nullptr) {
                ++drawn;
                wide += (t.bbox.x1 - t.bbox.x0) >= 16;
            }
            ASSERT_EQ(m, expected) << "triangle " << n << (builder ? " (vector)" : " (scalar)");
        }
    }
    EXPECT_GT(wide, 10000);  // rows of several vectors, and the scalar path's divisions
}

// The 4x row blocks (convex_row_blocks_4x) hold exactly the samples the per-pixel multisample
// traversal (convex_quads_4x) covers: small boxes and tiles, every row builder, scissors whose
// leak widens the box, and boxes cut into 64-row bands as the band workers cut them.
TEST(Traversal, MultisampleRowBlocksEqualQuadPackets) {
    constexpr int kW = 260;
    constexpr int kH = 200;
    std::vector<refraster::detail::RowMaskFn> builders = {nullptr};
    for (auto path : {refraster::KernelPath::Avx2, refraster::KernelPath::Avx512}) {
        if (!refraster::kernel_path_available(path)) continue;
        builders.push_back(refraster::detail::vector_row_masks(path));
    }
    std::mt19937 rng(20261207);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::uniform_int_distribution<int> coin(0, 3);
    std::uniform_int_distribution<int> at_x(0, kW - 1);
    std::uniform_int_distribution<int> at_y(0, kH - 1);
    const auto index = [](int x, int y, unsigned s) {
        return (static_cast<std::size_t>(y) * kW + static_cast<std::size_t>(x)) * 4 + s;
    };
    int drawn = 0;
    int leaking = 0;
    int tiled_boxes = 0;
    for (int n = 0; drawn < 4000; ++n) {
        SetupParams p;
        p.multisample = true;
        p.pixel_center_offset = 0.0f;
        p.tie_rule = static_cast<refraster::TieRule>(coin(rng));
        p.framebuffer = {0, 0, kW - 1, kH - 1};
        p.draw_region = p.framebuffer;
        if (coin(rng) == 0) {
            const int x0 = at_x(rng);
            const int y0 = at_y(rng);
            p.draw_region = {x0, y0, std::min(kW - 1, x0 + at_x(rng)),
                             std::min(kH - 1, y0 + at_y(rng))};
        }
        const float size = 1.0f + unit(rng) * (n % 4 == 0 ? 300.0f : 60.0f);
        const auto v = random_vertices(rng, kW, kH, size, n % 3 == 0);
        TriangleSetup t;
        if (refraster::detail::setup_triangle(v, p, t) != SetupOutcome::Ok) continue;
        if (t.llvmpipe_walk) continue;
        ++drawn;
        leaking += t.scissor_leak != 0;
        tiled_boxes += (t.bbox.x1 - t.bbox.x0) >= 64 || (t.bbox.y1 - t.bbox.y0) >= 64;
        std::vector<std::uint8_t> expected(static_cast<std::size_t>(kW) * kH * 4, 0);
        refraster::detail::convex_quads_4x<3>(
            t, [&](std::span<const refraster::detail::QuadPacket> qs) {
                for (const auto& q : qs) {
                    for (unsigned i = 0; i < 4; ++i) {
                        for (unsigned s = 0; s < 4; ++s) {
                            if (q.mask & (1u << refraster::detail::quad_bit(i, s)))
                                ++expected[index(q.x + static_cast<int>(i & 1u),
                                                 q.y + static_cast<int>(i >> 1), s)];
                        }
                    }
                }
            });
        for (auto* builder : builders) {
            for (const bool bands : {false, true}) {
                std::vector<std::uint8_t> got(expected.size(), 0);
                const auto mark = [&](const refraster::detail::RowBlock& b) {
                    ASSERT_EQ(b.samples, 4);
                    for (unsigned s = 0; s < 4; ++s) {
                        for (int r = 0; r < b.rows; ++r) {
                            for (int i = 0; i < 64; ++i) {
                                if ((b.sample_rows(static_cast<int>(s))[r] >> i) & 1u)
                                    ++got[index(b.x0 + i, b.y0 + r, s)];
                            }
                        }
                    }
                };
                if (!bands) {
                    refraster::detail::convex_row_blocks_4x<3>(t, mark, builder, t.bbox.x0,
                                                               t.bbox.y0);
                } else {
                    for (int y0 = 0; y0 < kH; y0 += 64) {
                        TriangleSetup c = t;
                        c.bbox.y0 = std::max(c.bbox.y0, y0);
                        c.bbox.y1 = std::min(c.bbox.y1, y0 + 63);
                        if (c.bbox.empty()) continue;
                        refraster::detail::convex_row_blocks_4x<3>(c, mark, builder, t.bbox.x0,
                                                                   t.bbox.y0);
                    }
                }
                ASSERT_EQ(got, expected) << "triangle " << n << (bands ? " in bands" : "")
                                         << (builder ? " (vector)" : " (scalar)");
            }
        }
    }
    EXPECT_GT(leaking, 100);      // the scissor leak's samples were exercised
    EXPECT_GT(tiled_boxes, 500);  // and the tile path, not only small boxes
}

}  // namespace
