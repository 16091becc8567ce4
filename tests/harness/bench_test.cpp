// The benchmark's workloads: what each promises (counts, sizes, state), from a seed.
#include "harness/bench.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "harness/scene_text.hpp"
#include "refraster/renderer.hpp"

namespace {

double window_area(const refraster::VertexArray& v, std::size_t first) {
    std::array<std::array<double, 2>, 3> p{};
    for (std::size_t k = 0; k < 3; ++k) {
        const auto pos = v.position(first + k);
        const double x = pos[0], y = pos[1], w = pos[3];
        p[k] = {(x / w + 1.0) * 512.0, (y / w + 1.0) * 512.0};
    }
    return 0.5 * std::abs((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) -
                          (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]));
}

TEST(BenchWorkloads, CountsSizesAndState) {
    struct Want {
        std::string name;
        std::size_t triangles;
        double min_area, max_area;
    };
    for (const Want& w :
         {Want{"tiny-flat", 1'000'000, 2, 10}, Want{"medium-smooth", 100'000, 100, 500},
          Want{"medium-perspective", 100'000, 0, 0}, Want{"full-flat", 200, 1024.0 * 1024, 1e9}}) {
        const auto b = harness::make_bench_workload(w.name, 7);
        EXPECT_EQ(b.triangles, w.triangles) << w.name;
        ASSERT_EQ(b.list.draws.size(), 1u);
        const auto& d = b.list.draws[0];
        EXPECT_EQ(d.vertices.size(), 3 * w.triangles) << w.name;
        EXPECT_EQ(b.list.target.width, 1024u);
        EXPECT_EQ(b.list.target.height, 1024u);
        EXPECT_EQ(b.list.target.depth, refraster::DepthFormat::Z24);
        EXPECT_EQ(d.state.depth_test, refraster::CompareFunc::Less);
        EXPECT_EQ(d.state.shade, w.name.ends_with("flat") ? refraster::ShadeModel::Flat
                                                          : refraster::ShadeModel::Smooth);
        bool any_w = false;
        for (std::size_t t = 0; t < w.triangles;
             t += std::max<std::size_t>(1, w.triangles / 2000)) {
            if (w.max_area > 0) {
                const double a = window_area(d.vertices, 3 * t);
                EXPECT_GE(a, w.min_area * 0.999) << w.name << " triangle " << t;
                EXPECT_LE(a, w.max_area * 1.001) << w.name << " triangle " << t;
            }
            for (std::size_t k = 0; k < 3; ++k)
                any_w = any_w || d.vertices.position(3 * t + k)[3] != 1.0f;
        }
        EXPECT_EQ(any_w, w.name.ends_with("perspective")) << w.name;
    }
}

TEST(BenchWorkloads, SeededAndScaled) {
    EXPECT_EQ(harness::make_bench_workload("tiny-smooth", 3).list,
              harness::make_bench_workload("tiny-smooth", 3).list);
    EXPECT_NE(harness::make_bench_workload("tiny-smooth", 3).list,
              harness::make_bench_workload("tiny-smooth", 4).list);
    EXPECT_EQ(harness::make_bench_workload("medium-flat", 3, 0.01).triangles, 1000u);
    EXPECT_THROW((void)harness::make_bench_workload("huge-flat", 3), std::invalid_argument);
    EXPECT_THROW((void)harness::make_bench_workload("tiny-flat", 3, 0.0), std::invalid_argument);
    EXPECT_EQ(harness::bench_workload_names().size(), 28u);
    // The textured workloads carry a texture and coordinates after the colour.
    const auto tex = harness::make_bench_workload("medium-textured-trilinear", 3, 0.01);
    ASSERT_EQ(tex.list.textures.size(), 1u);
    ASSERT_TRUE(tex.list.draws.front().state.texture);
    EXPECT_EQ(tex.list.draws.front().vertices.stride(), 12u);
}

// The window position of vertex `i` of a 1024x1024 draw, in pixels.
std::array<double, 2> window_xy(const refraster::VertexArray& v, std::size_t i) {
    const auto pos = v.position(i);
    const double x = pos[0], y = pos[1], w = pos[3];
    return {(x / w + 1.0) * 512.0, (y / w + 1.0) * 512.0};
}

TEST(BenchWorkloads, TexturedFiltersAndWrap) {
    using F = refraster::TextureFilter;
    struct Want {
        std::string name;
        F min, mag;
        std::size_t triangles;
        bool perspective;
    };
    for (const Want& w :
         {Want{"medium-textured-bilinear", F::Linear, F::Linear, 100'000, false},
          Want{"medium-textured-trilinear", F::LinearMipmapLinear, F::Linear, 100'000, false},
          Want{"medium-textured-nearest", F::Nearest, F::Nearest, 100'000, false},
          Want{"full-textured-bilinear", F::Linear, F::Linear, 200, false},
          Want{"full-textured-trilinear", F::LinearMipmapLinear, F::Linear, 200, false},
          Want{"full-textured-perspective", F::Linear, F::Linear, 200, true}}) {
        const auto b = harness::make_bench_workload(w.name, 2);
        EXPECT_EQ(b.triangles, w.triangles) << w.name;
        ASSERT_EQ(b.list.textures.size(), 1u) << w.name;
        EXPECT_TRUE(b.list.textures[0].generate_mipmaps) << w.name;
        EXPECT_EQ(b.list.textures[0].levels.at(0).width, 256u) << w.name;
        ASSERT_EQ(b.list.draws.size(), 1u) << w.name;
        const auto& d = b.list.draws[0];
        ASSERT_TRUE(d.state.texture) << w.name;
        EXPECT_EQ(d.state.texture->min_filter, w.min) << w.name;
        EXPECT_EQ(d.state.texture->mag_filter, w.mag) << w.name;
        EXPECT_EQ(d.state.texture->wrap_s, refraster::TextureWrap::Repeat) << w.name;
        EXPECT_EQ(d.state.texture->wrap_t, refraster::TextureWrap::Repeat) << w.name;
        EXPECT_EQ(d.vertices.size(), 3 * w.triangles) << w.name;
        bool any_w = false;
        for (std::size_t v = 0; v < d.vertices.size(); ++v)
            any_w = any_w || d.vertices.position(v)[3] != 1.0f;
        EXPECT_EQ(any_w, w.perspective) << w.name;
        if (w.name.starts_with("full")) {
            for (std::size_t t = 0; t < w.triangles; ++t)
                EXPECT_GE(window_area(d.vertices, 3 * t), 1024.0 * 1024) << w.name << " " << t;
        }
    }
}

TEST(BenchWorkloads, MultisampledTargets) {
    for (const auto& name : harness::bench_workload_names()) {
        const auto b = harness::make_bench_workload(name, 2, 0.001);
        EXPECT_EQ(b.list.target.samples, name.ends_with("-4x") ? 4u : 1u) << name;
        EXPECT_EQ(b.list.target.width, 1024u) << name;
        EXPECT_EQ(b.list.target.color, refraster::ColorFormat::Rgba8) << name;
        EXPECT_EQ(b.list.target.depth, refraster::DepthFormat::Z24) << name;
        for (const auto& d : b.list.draws)
            EXPECT_EQ(d.state.depth_test, refraster::CompareFunc::Less) << name;
    }
    const auto m = harness::make_bench_workload("medium-smooth-4x", 2);
    EXPECT_EQ(m.triangles, 100'000u);
    EXPECT_EQ(m.list.draws.at(0).vertices.size(), 300'000u);
    EXPECT_EQ(harness::make_bench_workload("full-smooth-4x", 2).triangles, 200u);
}

TEST(BenchWorkloads, LinesAndPoints) {
    struct Want {
        std::string name;
        refraster::PrimitiveType primitive;
        int min_width, max_width;
    };
    using P = refraster::PrimitiveType;
    for (const Want& w : {Want{"lines", P::Lines, 1, 1}, Want{"wide-lines", P::Lines, 2, 10},
                          Want{"lines-4x", P::Lines, 1, 3}, Want{"points", P::Points, 1, 8},
                          Want{"points-4x", P::Points, 1, 8}}) {
        const auto b = harness::make_bench_workload(w.name, 4);
        EXPECT_EQ(b.triangles, 100'000u) << w.name;
        EXPECT_EQ(b.primitive, w.primitive == P::Lines ? "lines" : "points") << w.name;
        // One draw per integer width (size), each once, every width of the range drawn.
        EXPECT_EQ(b.list.draws.size(), static_cast<std::size_t>(w.max_width - w.min_width + 1))
            << w.name;
        std::size_t primitives = 0;
        std::vector<float> widths;
        for (const auto& d : b.list.draws) {
            EXPECT_EQ(d.primitive, w.primitive) << w.name;
            const float width = w.primitive == P::Lines ? d.state.line_width : d.state.point_size;
            EXPECT_EQ(width, std::floor(width)) << w.name;
            EXPECT_GE(width, static_cast<float>(w.min_width)) << w.name;
            EXPECT_LE(width, static_cast<float>(w.max_width)) << w.name;
            widths.push_back(width);
            const std::size_t per = w.primitive == P::Lines ? 2 : 1;
            EXPECT_EQ(d.vertices.size() % per, 0u) << w.name;
            primitives += d.vertices.size() / per;
            if (w.primitive != P::Lines) continue;
            for (std::size_t v = 0; v < d.vertices.size(); v += 2) {
                const auto a = window_xy(d.vertices, v), e = window_xy(d.vertices, v + 1);
                const double length = std::hypot(e[0] - a[0], e[1] - a[1]);
                EXPECT_GE(length, 3.0 - 1e-3) << w.name << " line " << v / 2;
                EXPECT_LE(length, 50.0 + 1e-3) << w.name << " line " << v / 2;
                // One depth a line.
                EXPECT_EQ(d.vertices.position(v)[2], d.vertices.position(v + 1)[2]) << w.name;
            }
        }
        EXPECT_EQ(primitives, 100'000u) << w.name;
        EXPECT_TRUE(std::is_sorted(widths.begin(), widths.end())) << w.name;
        EXPECT_EQ(std::adjacent_find(widths.begin(), widths.end()), widths.end()) << w.name;
    }
}

TEST(BenchWorkloads, PolygonsWithFillRules) {
    for (const auto& [name, rule] :
         {std::pair{std::string("polygons-nonzero"), refraster::FillRule::NonZero},
          std::pair{std::string("polygons-evenodd"), refraster::FillRule::EvenOdd}}) {
        const auto b = harness::make_bench_workload(name, 4);
        EXPECT_EQ(b.triangles, 10'000u) << name;
        EXPECT_EQ(b.primitive, "polygons") << name;
        ASSERT_EQ(b.list.draws.size(), 10'000u) << name;
        std::size_t fewest = 1000, most = 0;
        double smallest = 1e9, largest = 0;
        for (const auto& d : b.list.draws) {
            EXPECT_EQ(d.primitive, refraster::PrimitiveType::Polygon) << name;
            EXPECT_EQ(d.state.fill_rule, rule) << name;
            EXPECT_EQ(d.state.cull, refraster::CullMode::None) << name;
            EXPECT_EQ(d.state.polygon_mode, refraster::PolygonMode::Fill) << name;
            const std::size_t n = d.vertices.size();
            fewest = std::min(fewest, n);
            most = std::max(most, n);
            // The disc the vertices scatter over: its area from the farthest vertex.
            std::array<double, 2> c{0, 0};
            for (std::size_t v = 0; v < n; ++v) {
                const auto p = window_xy(d.vertices, v);
                c[0] += p[0] / static_cast<double>(n);
                c[1] += p[1] / static_cast<double>(n);
            }
            double reach = 0;
            for (std::size_t v = 0; v < n; ++v) {
                const auto p = window_xy(d.vertices, v);
                reach = std::max(reach, std::hypot(p[0] - c[0], p[1] - c[1]));
            }
            smallest = std::min(smallest, reach);
            largest = std::max(largest, reach);
        }
        EXPECT_EQ(fewest, 8u) << name;
        EXPECT_EQ(most, 64u) << name;
        // Radii of discs of 100 to 2000 pixels: about 5.6 to 25 pixels, the spokes 0.2 to 1 of
        // it (the centroid is not the centre, hence the margins).
        EXPECT_GT(smallest, 2.0) << name;
        EXPECT_LT(largest, 2 * 25.3) << name;
        EXPECT_GT(largest, 20.0) << name;
    }
}

TEST(BenchWorkloads, AllpassLayersAreEachNearer) {
    for (const char* name : {"full-flat-allpass", "full-smooth-allpass"}) {
        const auto b = harness::make_bench_workload(name, 6);
        EXPECT_EQ(b.triangles, 200u) << name;
        const auto& d = b.list.draws.at(0);
        EXPECT_EQ(d.state.shade, std::string(name).starts_with("full-flat")
                                     ? refraster::ShadeModel::Flat
                                     : refraster::ShadeModel::Smooth);
        float before = 1.0f;  // the clear depth
        for (std::size_t t = 0; t < b.triangles; ++t) {
            EXPECT_GE(window_area(d.vertices, 3 * t), 1024.0 * 1024) << name << " " << t;
            const float z = d.vertices.position(3 * t)[2];
            for (std::size_t k = 1; k < 3; ++k)
                EXPECT_EQ(d.vertices.position(3 * t + k)[2], z) << name << " " << t;
            // In window depth, (z + 1) / 2, nearer by far more than z24's step.
            EXPECT_LT((z + 1.0f) / 2.0f, before - 1e-3f) << name << " " << t;
            before = (z + 1.0f) / 2.0f;
        }
    }
}

// Rendered by the reference, each layer of a scaled-down allpass workload changes every pixel's
// depth: every layer passes the depth test everywhere.
TEST(BenchWorkloads, AllpassLayersAllPassWhenRendered) {
    const auto b = harness::make_bench_workload("full-smooth-allpass", 6, 0.02);  // 4 layers
    ASSERT_EQ(b.triangles, 4u);
    refraster::RenderOptions ro;
    ro.threads = 1;
    std::optional<refraster::Framebuffer> previous;
    for (std::size_t layers = 1; layers <= b.triangles; ++layers) {
        refraster::DrawList list = b.list;
        auto& data = list.draws[0].vertices.data;
        data.resize(layers * 3 * list.draws[0].vertices.stride());
        refraster::Framebuffer fb;
        ASSERT_EQ(refraster::render(list, ro, fb).status, refraster::RenderStatus::Ok);
        ASSERT_EQ(fb.depth.size(), 1024u * 1024u);
        std::size_t unchanged = 0;
        for (std::size_t p = 0; p < fb.depth.size(); ++p) {
            const std::uint32_t before = previous ? previous->depth[p] : 0xffffffu;  // the clear
            if (fb.depth[p] >= before) ++unchanged;
        }
        EXPECT_EQ(unchanged, 0u) << layers << " layers";
        previous = std::move(fb);
    }
}

// A softpipe row draws its counterpart's scene, byte for byte.
TEST(BenchWorkloads, SoftpipeRowsDrawTheirCounterparts) {
    for (const char* name :
         {"softpipe-medium-smooth", "softpipe-tiny-flat", "softpipe-medium-textured-bilinear"}) {
        const auto counterpart = harness::bench_softpipe_counterpart(name);
        ASSERT_TRUE(counterpart) << name;
        EXPECT_EQ(std::string(name), "softpipe-" + *counterpart);
        EXPECT_EQ(harness::make_bench_workload(name, 8, 0.01).list,
                  harness::make_bench_workload(*counterpart, 8, 0.01).list)
            << name;
        EXPECT_EQ(harness::make_bench_workload(name, 8, 0.01).name, name);
    }
    EXPECT_FALSE(harness::bench_softpipe_counterpart("medium-smooth"));
    EXPECT_FALSE(harness::bench_softpipe_counterpart("softpipe-huge"));
    EXPECT_THROW((void)harness::make_bench_workload("softpipe-huge", 1), std::invalid_argument);
}

// The scene file the whole-process runs load gives the in-memory draw list back, bit for bit:
// the two columns time the same scene. Scaled down: each kind of workload once.
TEST(BenchWorkloads, SceneFileLoadsToTheSameDrawList) {
    for (const char* name :
         {"medium-smooth", "full-perspective", "medium-textured-trilinear", "full-smooth-4x",
          "wide-lines", "points-4x", "polygons-evenodd", "full-flat-allpass"}) {
        const auto b = harness::make_bench_workload(name, 9, 0.01);
        const std::string text = harness::scene_json_text(harness::bench_scene_file(name, b.list),
                                                          harness::VertexForm::Base64);
        const auto loaded = harness::load_scene_text(text, std::string(name) + ".json");
        EXPECT_TRUE(loaded.unsupported_extensions.empty()) << name;
        EXPECT_EQ(loaded.draw_list, b.list) << name;
    }
}

TEST(BenchWorkloads, ScalingWorkloadsScaleTheirCounterparts) {
    const auto& standard = harness::bench_workload_names();
    for (const auto& name : harness::bench_scaling_workload_names()) {
        EXPECT_EQ(std::find(standard.begin(), standard.end(), name), standard.end()) << name;
        EXPECT_TRUE(harness::bench_scaling_counterpart(name)) << name;
    }
    for (const auto& name : standard) EXPECT_FALSE(harness::bench_scaling_counterpart(name));
    EXPECT_EQ(harness::bench_scaling_counterpart("tiny-flat-4m"), "tiny-flat");
    EXPECT_EQ(harness::bench_scaling_counterpart("full-flat-2048"), "full-flat");
    EXPECT_EQ(harness::bench_scaling_counterpart("full-smooth-2048"), "full-smooth");

    // tiny-flat-4m: four times tiny-flat's triangles at the same scale, of the same sizes.
    const auto tiny = harness::make_bench_workload("tiny-flat", 5, 0.01);
    const auto tiny4 = harness::make_bench_workload("tiny-flat-4m", 5, 0.01);
    EXPECT_EQ(tiny4.triangles, 4 * tiny.triangles);
    EXPECT_EQ(tiny4.list.draws[0].vertices.size(), 3 * tiny4.triangles);
    EXPECT_EQ(tiny4.list.target, tiny.list.target);
    EXPECT_EQ(tiny4.list.draws[0].state.shade, refraster::ShadeModel::Flat);
    for (std::size_t t = 0; t < tiny4.triangles; t += 97) {
        const double a = window_area(tiny4.list.draws[0].vertices, 3 * t);
        EXPECT_GE(a, 2 * 0.999) << t;
        EXPECT_LE(a, 10 * 1.001) << t;
    }
    EXPECT_EQ(harness::make_bench_workload("tiny-flat-4m", 5).triangles, 4'000'000u);

    // full-*-2048: full's 200 triangles on a 2048x2048 target, each over the whole of it.
    for (const char* name : {"full-flat-2048", "full-smooth-2048"}) {
        const auto b = harness::make_bench_workload(name, 5);
        EXPECT_EQ(b.triangles, 200u) << name;
        EXPECT_EQ(b.list.target.width, 2048u) << name;
        EXPECT_EQ(b.list.target.height, 2048u) << name;
        EXPECT_EQ(b.list.target.depth, refraster::DepthFormat::Z24) << name;
        const auto& d = b.list.draws[0];
        EXPECT_EQ(d.state.viewport.width, 2048) << name;
        EXPECT_EQ(d.state.viewport.height, 2048) << name;
        EXPECT_EQ(d.state.shade, std::string(name).starts_with("full-flat")
                                     ? refraster::ShadeModel::Flat
                                     : refraster::ShadeModel::Smooth);
        for (std::size_t t = 0; t < b.triangles; ++t) {
            // In the target's pixels: window_area measures in 1024ths of the target's side.
            EXPECT_GE(window_area(d.vertices, 3 * t) * 4.0, 2048.0 * 2048.0) << name << " " << t;
        }
    }
    // The standard workloads are what they were: the scaling ones take other seeds.
    EXPECT_NE(harness::make_bench_workload("full-flat-2048", 5).list.draws[0].vertices.data,
              harness::make_bench_workload("full-flat", 5).list.draws[0].vertices.data);
}

TEST(BenchHeap, BoundIsTwiceTheFramebufferPlusTheVertexData) {
    const auto w = harness::make_bench_workload("medium-flat", 1, 0.001);  // 100 triangles
    EXPECT_EQ(harness::bench_framebuffer_bytes(w.list.target), 1024u * 1024u * (4 + 4));
    EXPECT_EQ(harness::bench_vertex_data_bytes(w.list), 100u * 3 * 8 * sizeof(float));
    EXPECT_EQ(harness::bench_heap_bound_bytes(w.list),
              2u * 1024 * 1024 * 8 + 100u * 3 * 8 * sizeof(float));
    EXPECT_EQ(harness::bench_framebuffer_bytes(
                  harness::make_bench_workload("full-flat-2048", 1, 0.01).list.target),
              2048u * 2048u * 8);

    // Float colour, 4 samples, no depth; indices count as vertex data.
    refraster::DrawList list;
    list.target = {10, 20, refraster::ColorFormat::Rgba32f, refraster::DepthFormat::None, 4};
    refraster::Draw d;
    d.vertices.data.assign(24, 0.0f);
    d.indices = std::vector<std::uint32_t>{0, 1, 2, 2, 1, 0, 0};
    list.draws = {d, d};
    EXPECT_EQ(harness::bench_framebuffer_bytes(list.target), 10u * 20 * 4 * 16);
    EXPECT_EQ(harness::bench_vertex_data_bytes(list), 2u * (24 * 4 + 7 * 4));
    EXPECT_EQ(harness::bench_heap_bound_bytes(list), 2u * 12800 + 2 * 124);

    harness::BenchRow r;
    r.framebuffer_bytes = 4 * 1024 * 1024;
    r.vertex_bytes = 2 * 1024 * 1024;
    EXPECT_DOUBLE_EQ(r.heap_bound_mb(), 10.0);
    r.ref_heap_peak_mb = 3;
    r.ref2_heap_peak_mb = 4;
    EXPECT_DOUBLE_EQ(r.heap_peak_mb(), 4.0);
}

TEST(BenchTargets, SpeedTargetsOfTheIssue) {
    const std::map<std::string, double> want{
        {"tiny-flat", 3.0},
        {"tiny-smooth", 3.0},
        {"medium-flat", 2.0},
        {"medium-smooth", 2.0},
        {"medium-perspective", 2.0},
        {"full-flat", 2.0},
        {"full-smooth", 2.0},
        {"full-perspective", 2.0},
        {"medium-textured-bilinear", 1.5},
        {"medium-textured-trilinear", 1.5},
        {"medium-textured-nearest", 1.5},
        {"full-textured-bilinear", 1.5},
        {"full-textured-trilinear", 1.5},
        {"full-textured-perspective", 1.5},
        {"medium-smooth-4x", 2.0},
        {"full-smooth-4x", 2.0},
        {"lines", 2.0},
        {"wide-lines", 2.0},
        {"lines-4x", 2.0},
        {"points", 2.0},
        {"points-4x", 2.0},
        {"polygons-nonzero", 2.0},
        {"polygons-evenodd", 2.0},
        {"full-flat-allpass", 2.0},
        {"full-smooth-allpass", 2.0},
        {"softpipe-medium-smooth", 5.0},
        {"softpipe-tiny-flat", 5.0},
        {"softpipe-medium-textured-bilinear", 5.0},
    };
    // Every standard workload has its target, and the list is the standard one.
    EXPECT_EQ(want.size(), harness::bench_workload_names().size());
    for (const auto& n : harness::bench_workload_names()) {
        ASSERT_TRUE(want.count(n)) << n;
        EXPECT_EQ(harness::bench_speed_target(n), want.at(n)) << n;
    }
    for (const auto& n : harness::bench_scaling_workload_names())
        EXPECT_FALSE(harness::bench_speed_target(n)) << n;
}

// A softpipe row is judged by softpipe's time over the reference's, whatever llvmpipe's.
TEST(BenchTargets, SoftpipeRowsAgainstSoftpipe) {
    harness::BenchRow r;
    r.name = "softpipe-medium-smooth";
    r.ref_ms = 100;
    r.ref2_ms = 50;
    r.softpipe_ms = 600;
    r.llvmpipe_t0_ms = 10;  // not the judge here
    EXPECT_DOUBLE_EQ(*r.speedup_vs_softpipe(), 6.0);
    EXPECT_DOUBLE_EQ(*r.speedup2_vs_softpipe(), 12.0);
    harness::BenchRow other = r;
    other.name = "medium-smooth";
    EXPECT_FALSE(other.speedup_vs_softpipe());
    const auto targets = harness::bench_targets({r});
    ASSERT_GE(targets.size(), 2u);
    EXPECT_EQ(targets[0].what, "speed");
    EXPECT_DOUBLE_EQ(*targets[0].value, 6.0);
    EXPECT_DOUBLE_EQ(targets[0].target, 5.0);
    EXPECT_TRUE(targets[0].met());
    EXPECT_EQ(targets[1].what, "speed 2T");
    EXPECT_DOUBLE_EQ(*targets[1].value, 12.0);
    EXPECT_FALSE(targets[1].required);
    r.softpipe_ms = 400;  // 4 < 5
    EXPECT_FALSE(harness::bench_targets({r})[0].met());
    harness::BenchReport report;
    report.rows = {r};
    const std::string json = harness::bench_json(report);
    EXPECT_NE(json.find("\"speedup_vs_softpipe\": 4"), std::string::npos) << json;
}

// Made-up rows judged against their targets: nothing here is timed.
TEST(BenchTargets, JudgesEachRow) {
    const auto row = [](std::string name, double ref, std::optional<double> t0) {
        harness::BenchRow r;
        r.name = std::move(name);
        r.ref_ms = ref;
        r.llvmpipe_t0_ms = t0;
        r.triangles = 1000;
        r.pixels = 1e6;
        r.framebuffer_bytes = 1024 * 1024;  // bound 2 MB
        return r;
    };
    std::vector<harness::BenchRow> rows{
        row("tiny-flat", 100, 310),       // 3.1 >= 3: met
        row("medium-flat", 50, 100),      // 2.0 >= 2: met, at the boundary
        row("full-smooth", 100, 140),     // 1.4 < 2: missed
        row("full-perspective", 10, {}),  // no llvmpipe: not measured
        row("tiny-flat-4m", 420, {}),     // 4x the triangles in 4.2x the time: 0.95
        row("full-flat-2048", 500, {}),   // 4x the pixels in 5x the time: 0.8
        row("full-flat", 100, 150),       // 1.5 < 2: missed
    };
    rows[4].triangles = 4000;
    rows[5].pixels = 4e6;
    rows[1].llvmpipe_ms = 60;
    rows[1].ref2_ms = 20;            // 2T: 3.0
    rows[2].ref_heap_peak_mb = 2.5;  // over the bound
    const auto targets = harness::bench_targets(rows);
    const auto find = [&](const std::string& scene, const std::string& what) {
        for (const auto& t : targets)
            if (t.scene == scene && t.what == what) return t;
        ADD_FAILURE() << "no " << what << " target for " << scene;
        return harness::BenchTarget{};
    };
    EXPECT_TRUE(find("tiny-flat", "speed").met());
    EXPECT_DOUBLE_EQ(*find("tiny-flat", "speed").value, 3.1);
    EXPECT_DOUBLE_EQ(find("tiny-flat", "speed").target, 3.0);
    EXPECT_TRUE(find("medium-flat", "speed").met());
    EXPECT_FALSE(find("full-smooth", "speed").met());
    EXPECT_FALSE(find("full-perspective", "speed").value);
    EXPECT_FALSE(find("full-perspective", "speed").met());
    EXPECT_FALSE(find("full-flat", "speed").met());
    // 2 threads against llvmpipe's default threads: reported, not required.
    EXPECT_FALSE(find("medium-flat", "speed 2T").required);
    EXPECT_DOUBLE_EQ(*find("medium-flat", "speed 2T").value, 3.0);
    EXPECT_TRUE(find("medium-flat", "speed 2T").met());
    EXPECT_FALSE(find("tiny-flat", "speed 2T").value);
    // Linearity: Mtri/s for tiny, Mpix/s for full, over the counterpart's.
    EXPECT_NEAR(*find("tiny-flat-4m", "linearity").value, 1000.0 / 1050.0, 1e-12);
    EXPECT_TRUE(find("tiny-flat-4m", "linearity").met());
    EXPECT_NEAR(*find("full-flat-2048", "linearity").value, 0.8, 1e-12);
    EXPECT_FALSE(find("full-flat-2048", "linearity").met());
    EXPECT_DOUBLE_EQ(harness::bench_rate(rows[0]), 0.01);  // Mtri/s
    EXPECT_DOUBLE_EQ(harness::bench_rate(rows[6]), 10.0);  // Mpix/s
    // Heap: within the bound except where the row says otherwise.
    EXPECT_TRUE(find("tiny-flat", "heap").met());
    EXPECT_TRUE(find("tiny-flat", "heap").at_most);
    EXPECT_FALSE(find("full-smooth", "heap").met());
    // A scaling row whose counterpart did not run has no ratio.
    EXPECT_FALSE(harness::bench_rate_ratio(row("full-smooth-2048", 1, {}), {rows[0], rows[1]}));
    EXPECT_FALSE(harness::bench_rate_ratio(rows[0], rows));

    harness::BenchReport report;
    report.rows = rows;
    const std::string table = harness::bench_table(report);
    EXPECT_NE(table.find("targets: tiny-flat 3.10/3.0 met, medium-flat 2.00/2.0 met, full-smooth "
                         "1.40/2.0 missed, full-perspective -/2.0 not measured, tiny-flat-4m rate "
                         "0.95/0.9 met, full-flat-2048 rate 0.80/0.9 missed, full-flat 1.50/2.0 "
                         "missed; heap within bound on 6 of 7 (over: full-smooth); 9 of 14 met"),
              std::string::npos)
        << table;
    EXPECT_NE(table.find("reported, not required (ref 2T / llvmpipe): tiny-flat -/3.0 not "
                         "measured, medium-flat 3.00/2.0 met"),
              std::string::npos)
        << table;
    const std::string json = harness::bench_json(report);
    for (const char* key :
         {"\"targets\"", "\"all_met\": false", "\"met\": 9", "\"missed\": 4", "\"not_measured\": 1",
          "\"what\": \"linearity\"", "\"comparison\": \"<=\""}) {
        EXPECT_NE(json.find(key), std::string::npos) << key << "\n" << json;
    }
}

TEST(BenchOptions, KernelPathNames) {
    for (const auto p :
         {refraster::KernelPath::Model, refraster::KernelPath::Scalar, refraster::KernelPath::Avx2,
          refraster::KernelPath::Avx512, refraster::KernelPath::Fastest}) {
        EXPECT_EQ(harness::parse_kernel_path(refraster::to_string(p)), p);
    }
    EXPECT_FALSE(harness::parse_kernel_path("sse"));
    EXPECT_FALSE(harness::parse_kernel_path(""));
}

// The whole bench without GL at a tiny scale: every configuration, the scaling rows after
// their counterparts, and the options in the JSON. Nothing about the times is asserted.
TEST(BenchRun, ReferenceOnlyWithScaling) {
    harness::BenchOptions o;
    o.scenes = {"medium-flat"};
    o.scaling = true;
    o.rounds = 1;
    o.scale = 1e-4;
    o.gl = false;
    o.kernels = refraster::KernelPath::Scalar;
    o.threads = 1;
    o.second_threads = 2;
    std::ostringstream log;
    const auto report = harness::run_bench(o, log);
    std::vector<std::string> names;
    for (const auto& r : report.rows) names.push_back(r.name);
    EXPECT_EQ(names,
              (std::vector<std::string>{"medium-flat", "tiny-flat", "tiny-flat-4m", "full-flat",
                                        "full-flat-2048", "full-smooth", "full-smooth-2048"}));
    EXPECT_EQ(report.kernels, "scalar");
    for (const auto& r : report.rows) {
        EXPECT_TRUE(r.ref2_ms) << r.name;
        EXPECT_FALSE(r.llvmpipe_t0_ms) << r.name;
        EXPECT_GT(r.pixels, 0.0) << r.name;
        EXPECT_EQ(r.framebuffer_bytes,
                  r.name.ends_with("2048") ? 2048u * 2048 * 8 : 1024u * 1024 * 8);
        EXPECT_EQ(r.vertex_bytes, r.triangles * 3 * 8 * sizeof(float)) << r.name;
    }
    EXPECT_EQ(report.rows[2].triangles, 4 * report.rows[1].triangles);
    EXPECT_TRUE(harness::bench_rate_ratio(report.rows[2], report.rows));
    EXPECT_NE(log.str().find("ref 2T"), std::string::npos) << log.str();

    const std::string j = harness::bench_json(report);
    for (const char* key :
         {"\"kernels_asked\": \"scalar\"", "\"kernels\": \"scalar\"", "\"threads\": 1",
          "\"second_threads\": 2", "\"scaling\": true", "\"softpipe\": false", "\"cpu_flags\"",
          "\"commit\"", "\"date\"", "\"gl_renderer\": \"\"", "\"ref2_ms\"", "\"rate_ratio\"",
          "\"heap_bound_mb\"", "\"heap_within_bound\"", "\"counterpart\": \"tiny-flat\"",
          "\"all_met\": false"}) {
        EXPECT_NE(j.find(key), std::string::npos) << key << "\n" << j;
    }
    const std::string table = harness::bench_table(report);
    EXPECT_NE(table.find("kernels scalar (asked: scalar); ref: 1 thread; ref 2T: 2 threads"),
              std::string::npos)
        << table;
}

TEST(BenchReport, JsonHoldsTheDocumentedKeys) {
    harness::BenchReport report;
    harness::BenchRow r;
    r.name = "tiny-flat";
    r.ref_ms = 10;
    r.llvmpipe_t0_ms = 25;
    r.split = {1, 2, 3, 4};
    report.rows = {r};
    const std::string j = harness::bench_json(report);
    for (const char* key :
         {"\"bench\"", "\"host\"", "\"scenes\"", "\"name\": \"tiny-flat\"", "\"ref_ms\"",
          "\"ref2_ms\": null", "\"llvmpipe_t0_ms\"", "\"llvmpipe_ms\": null",
          "\"softpipe_ms\": null", "\"speedup_vs_llvmpipe_t0\": 2.5",
          "\"speedup_2t_vs_llvmpipe\": null", "\"ref_heap_peak_mb\"", "\"split_ms\"", "\"load\"",
          "\"setup\"", "\"raster\"", "\"fragment\"", "\"targets\""}) {
        EXPECT_NE(j.find(key), std::string::npos) << key << "\n" << j;
    }
    EXPECT_NE(harness::bench_table(report).find("| tiny-flat |"), std::string::npos);
}

}  // namespace
