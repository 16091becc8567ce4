// The precision and stability studies' kernels and exact answers: the oracle is the gl-exact
// profile's, the 8-bit snapped kernel is llvmpipe's coverage rule, and the studies' tables hold
// what their documentation says.
#include <gtest/gtest.h>

#include <map>
#include <sstream>

#include "harness/study.hpp"
#include "refraster/renderer.hpp"
#include "study/variants.hpp"
#include "study/workloads.hpp"

namespace {

using namespace harness::study;

// The pixels the reference rasterizer lights for one triangle under a profile, row-major.
std::vector<std::pair<int, int>> rendered(const ClipTriangle& t, const Viewport& vp,
                                          const refraster::Profile& profile) {
    refraster::DrawList list;
    list.target = {static_cast<std::uint32_t>(vp.width), static_cast<std::uint32_t>(vp.height),
                   refraster::ColorFormat::Rgba8, refraster::DepthFormat::None, 1};
    refraster::Draw d;
    d.state.viewport = {0, 0, vp.width, vp.height};
    for (const ClipVertex& v : t)
        for (double c : v.position) d.vertices.data.push_back(static_cast<float>(c));
    list.draws.push_back(std::move(d));
    refraster::RenderOptions o;
    o.profile = profile;
    o.record_owners = true;
    refraster::Framebuffer fb;
    EXPECT_EQ(refraster::render(list, o, fb).status, refraster::RenderStatus::Ok);
    std::vector<std::pair<int, int>> out;
    for (std::uint32_t y = 0; y < fb.height; ++y)
        for (std::uint32_t x = 0; x < fb.width; ++x)
            if (fb.owner[fb.index(x, y)] != 0)
                out.emplace_back(static_cast<int>(x), static_cast<int>(y));
    return out;
}

template <typename F>
std::vector<std::pair<int, int>> pixels(const std::vector<F>& frags) {
    std::vector<std::pair<int, int>> out;
    for (const auto& f : frags) out.emplace_back(f.x, f.y);
    return out;
}

// The study's oracle is the one behind the gl-exact profile: the same centres for every
// triangle of the small, medium, sliver and perspective families.
TEST(StudyPrecision, OracleIsTheGlExactProfile) {
    const auto families = precision_families(5, true);
    int compared = 0;
    for (const Family& f : families) {
        if (f.viewport.width > 256) continue;
        SCOPED_TRACE(f.name);
        for (std::size_t i = 0; i < f.triangles.size() && i < 25; ++i) {
            const auto exact = exact_fragments(f.triangles[i], f.viewport);
            EXPECT_EQ(pixels(exact),
                      rendered(f.triangles[i], f.viewport, refraster::gl_exact_profile()))
                << "triangle " << i;
            ++compared;
        }
    }
    EXPECT_GE(compared, 100);
}

// The 8-bit snapped kernel is llvmpipe's coverage rule: with the viewport transform unfused
// (the kernel's order of operations), the llvmpipe-22.3 model lights the same pixels.
TEST(StudyPrecision, SnappedEightBitsIsLlvmpipesRule) {
    refraster::Profile p = refraster::llvmpipe_22_3_profile();
    p.gl.viewport_fma = refraster::FmaMode::Off;
    const Variant snap8{CoverageRule::Snapped, 8, true, DepthFormat::Z24};
    const auto families = precision_families(9, true);
    std::vector<Fragment> frags;
    int compared = 0;
    for (const Family& f : families) {
        if (f.viewport.width > 256 || f.name == "perspective") continue;
        SCOPED_TRACE(f.name);
        for (std::size_t i = 0; i < f.triangles.size() && i < 40; ++i) {
            rasterize(snap8, f.triangles[i], f.viewport, frags);
            EXPECT_EQ(pixels(frags), rendered(f.triangles[i], f.viewport, p)) << "triangle " << i;
            ++compared;
        }
    }
    EXPECT_GE(compared, 100);
}

// Snapping changes coverage less the finer its grid; the exact rule is the oracle.
TEST(StudyPrecision, ErrorsFallWithSubpixelBits) {
    const auto families = precision_families(3, true);
    std::map<int, std::size_t> wrong;
    for (const Family& f : families) {
        for (const ClipTriangle& t : f.triangles) {
            const auto exact = pixels(exact_fragments(t, f.viewport));
            for (int b : {4, 8, 16}) {
                std::vector<Fragment> frags;
                rasterize({CoverageRule::Snapped, b, true, DepthFormat::Z24}, t, f.viewport, frags);
                const auto got = pixels(frags);
                std::vector<std::pair<int, int>> diff;
                std::set_symmetric_difference(got.begin(), got.end(), exact.begin(), exact.end(),
                                              std::back_inserter(diff));
                wrong[b] += diff.size();
            }
        }
    }
    EXPECT_GT(wrong[4], wrong[8]);
    EXPECT_GT(wrong[8], wrong[16]);
}

// The clipper keeps the part inside the view volume: a triangle half outside loses the
// outside half, and every vertex of the result satisfies |x| <= w.
TEST(StudyPrecision, ClipperKeepsTheInside) {
    const Viewport vp{64, 64};
    ClipTriangle t;
    t[0] = clip_vertex(vp, 8, 8, 0.0, 1.0, 0.0);
    t[1] = clip_vertex(vp, 8, 56, 0.0, 1.0, 0.5);
    t[2] = clip_vertex(vp, 120, 32, 0.0, 1.0, 1.0);
    for (CoverageRule r : {CoverageRule::Float32, CoverageRule::Float64}) {
        const auto pieces = clip_triangle({r, 0, true, DepthFormat::Z24}, t, 1.0);
        ASSERT_EQ(pieces.size(), 2u);  // a quadrilateral
        for (const ClipTriangle& p : pieces)
            for (const ClipVertex& v : p) EXPECT_LE(v.position[0], v.position[3] * (1 + 1e-6));
    }
}

std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::string cell;
        std::istringstream l(line);
        while (std::getline(l, cell, ',')) cells.push_back(cell);
        if (!line.empty() && line.back() == ',') cells.emplace_back();
        rows.push_back(cells);
    }
    return rows;
}

// The quick precision study: one row per variant and family (and the fast core's rows), the
// exact rule without error, snapping watertight on the mesh.
TEST(StudyPrecision, QuickStudyTable) {
    harness::StudyOptions o;
    o.quick = true;
    o.seed = 11;
    const auto out = harness::run_precision_study(o);
    const auto rows = csv_rows(out.csv);
    ASSERT_GT(rows.size(), 1u);
    const auto& h = rows[0];
    const auto col = [&](const std::string& name) {
        const auto it = std::find(h.begin(), h.end(), name);
        EXPECT_NE(it, h.end()) << name;
        return static_cast<std::size_t>(it - h.begin());
    };
    const std::size_t variant = col("variant"), family = col("family"), mis = col("misclassified"),
                      holes = col("holes"), dbl = col("double_hits"),
                      ulps = col("attribute_max_ulps"), seed = col("seed"),
                      inversions = col("depth_inversions"), ties = col("depth_ties"),
                      ms = col("ms"), ms_low = col("ms_low"), ms_high = col("ms_high");
    const std::size_t variants = all_variants().size();
    std::size_t study_rows = 0, mesh_rows = 0;
    for (std::size_t i = 1; i < rows.size(); ++i) {
        const auto& r = rows[i];
        ASSERT_EQ(r.size(), h.size()) << i;
        EXPECT_EQ(r[seed], "11");
        if (r[variant].starts_with("llvmpipe")) continue;
        ++study_rows;
        if (r[variant].starts_with("exact")) {
            EXPECT_EQ(r[mis], "0") << r[family];
            EXPECT_EQ(r[ulps], "0") << r[family];
            EXPECT_EQ(r[holes], "0");
            EXPECT_EQ(r[dbl], "0");
            // Quantising the exact depth is monotonic: it ties pairs, never inverts one, and
            // ties are counted apart from inversions.
            EXPECT_EQ(r[inversions], "0") << r[variant] << " on " << r[family];
        }
        EXPECT_FALSE(r[ties].empty());
        // A time is the median of its rounds, within their range.
        EXPECT_LE(std::stod(r[ms_low]), std::stod(r[ms])) << r[variant];
        EXPECT_LE(std::stod(r[ms]), std::stod(r[ms_high])) << r[variant];
        if (r[family].starts_with("mesh")) {
            ++mesh_rows;
            if (r[variant].starts_with("snap")) {
                EXPECT_EQ(r[holes], "0") << r[variant];
                EXPECT_EQ(r[dbl], "0") << r[variant];
            }
        }
    }
    EXPECT_EQ(study_rows, variants * 7);
    EXPECT_EQ(mesh_rows, 2 * variants);
    EXPECT_NE(out.svg.find("Pareto front"), std::string::npos);
    EXPECT_FALSE(out.summary.empty());
    EXPECT_NE(out.decisions.find("| coverage: "), std::string::npos) << out.decisions;
    EXPECT_FALSE(out.conclusions.empty());
}

// The quick stability study: every sweep has rows, the oracle has no error anywhere, and an
// exactly quantised planar depth never steps down.
TEST(StudyStability, QuickStudyTable) {
    harness::StudyOptions o;
    o.quick = true;
    const auto out = harness::run_stability_study(o);
    const auto rows = csv_rows(out.csv);
    ASSERT_GT(rows.size(), 1u);
    std::map<std::string, int> per_sweep;
    for (std::size_t i = 1; i < rows.size(); ++i) {
        const auto& r = rows[i];
        ASSERT_EQ(r.size(), 8u);
        ++per_sweep[r[1]];
        if (r[4] == "exact" && (r[5] == "misclassified_centres" || r[5] == "z24_steps_down")) {
            EXPECT_EQ(r[6], "0") << r[1] << " at " << r[3];
        }
    }
    for (const char* s : {"area", "w-positive", "w-negative", "guard-band", "coordinates",
                          "parallel-edges", "depth-slope"})
        EXPECT_GT(per_sweep[s], 0) << s;
    EXPECT_NE(out.svg.find("depth-slope"), std::string::npos);
}

}  // namespace
