// The benchmark's workloads: what each promises (counts, sizes, state), from a seed.
#include "harness/bench.hpp"

#include <gtest/gtest.h>

#include <cmath>

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
    EXPECT_EQ(harness::bench_workload_names().size(), 8u);
}

TEST(BenchReport, JsonHoldsTheDocumentedKeys) {
    harness::BenchRow r;
    r.name = "tiny-flat";
    r.ref_ms = 10;
    r.llvmpipe_t0_ms = 25;
    r.split = {1, 2, 3, 4};
    const std::string j = harness::bench_json({r});
    for (const char* key :
         {"\"scenes\"", "\"name\": \"tiny-flat\"", "\"ref_ms\"", "\"llvmpipe_t0_ms\"",
          "\"llvmpipe_ms\": null", "\"softpipe_ms\": null", "\"speedup_vs_llvmpipe_t0\": 2.5",
          "\"ref_heap_peak_mb\"", "\"split_ms\"", "\"load\"", "\"setup\"", "\"raster\"",
          "\"fragment\""}) {
        EXPECT_NE(j.find(key), std::string::npos) << key << "\n" << j;
    }
    EXPECT_NE(harness::bench_table({r}).find("| tiny-flat |"), std::string::npos);
}

}  // namespace
