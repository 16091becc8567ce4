// exact_shader.cpp: the exact oracle's fragments (exact_shader.hpp).
#include "models/exact/exact_shader.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "stages/output_merge.hpp"
#include "stages/rules.hpp"

namespace refraster::detail {

ExactShader::ExactShader(const ExactCoverage& coverage, const std::array<StageVertex, 3>& v,
                         const VertexStage& stage, const Draw& draw, const Target& target,
                         bool provoking_first, double offset_units_scale)
    : coverage_(coverage),
      v_(v),
      stage_(stage),
      draw_(draw),
      target_(target),
      provoking_first_(provoking_first) {
    depth_test_ = draw.state.depth_test.has_value() && target.depth != DepthFormat::None;
    if (draw.state.polygon_offset && depth_test_) {
        // The slope of window z over window x and y: z is linear in window space. Only
        // meaningful for triangles entirely in front of the eye.
        std::array<std::array<double, 3>, 3> p{};
        const auto& vp = draw.state.viewport;
        const double n = draw.state.depth_near;
        const double f = draw.state.depth_far;
        for (std::size_t i = 0; i < 3; ++i) {
            const auto& c = v[i].clip;
            p[i] = {(double{c[0]} / double{c[3]} + 1.0) * 0.5 * vp.width + vp.x,
                    (double{c[1]} / double{c[3]} + 1.0) * 0.5 * vp.height + vp.y,
                    double{c[2]} / double{c[3]} * 0.5 * (f - n) + 0.5 * (n + f)};
        }
        const double ax = p[1][0] - p[0][0], ay = p[1][1] - p[0][1], az = p[1][2] - p[0][2];
        const double bx = p[2][0] - p[0][0], by = p[2][1] - p[0][1], bz = p[2][2] - p[0][2];
        const double det = ax * by - ay * bx;
        const double m = det == 0.0 ? 0.0
                                    : std::max(std::fabs((az * by - ay * bz) / det),
                                               std::fabs((ax * bz - az * bx) / det));
        double r = 0.0;
        if (target.depth == DepthFormat::Z32f) {
            const double maxz =
                std::max({std::fabs(p[0][2]), std::fabs(p[1][2]), std::fabs(p[2][2])});
            r = exact_z32f_offset_scale(maxz);
        } else {
            r = depth_mrd(target.depth);
        }
        offset_ = m * double{draw.state.polygon_offset->factor} +
                  r * offset_units_scale * double{draw.state.polygon_offset->units};
    }
}

void ExactShader::shade(int x, int y, Framebuffer& fb, std::uint32_t owner) const {
    const auto b = coverage_.weights(x, y);
    const std::size_t i = fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
    if (depth_test_) {
        double zn = 0.0;
        for (std::size_t k = 0; k < 3; ++k) zn += b[k] * double{v_[k].clip[2]};
        const double n = draw_.state.depth_near;
        const double f = draw_.state.depth_far;
        double z = zn * 0.5 * (f - n) + 0.5 * (n + f) + offset_;
        z = std::min(std::max(z, 0.0), 1.0);
        const std::uint32_t q = quantise_depth(z, target_.depth);
        if (!depth_passes(*draw_.state.depth_test, q, fb.depth[i],
                          target_.depth == DepthFormat::Z32f))
            return;
        if (draw_.state.depth_write) fb.depth[i] = q;
    }
    std::array<float, 4> c{};
    const auto a0 = stage_.attributes(v_[0]);
    const auto a1 = stage_.attributes(v_[1]);
    const auto a2 = stage_.attributes(v_[2]);
    const std::array<std::span<const float>, 3> a{a0, a1, a2};
    for (std::size_t k = 0; k < 4; ++k) {
        switch (draw_.state.shade) {
            case ShadeModel::Flat:
                c[k] = a[provoking_first_ ? 0 : 2][k];
                break;
            case ShadeModel::Smooth: {
                // Perspective-correct: the clip-space barycentric weights are b / sum b
                // (exact_coverage.hpp, weights).
                double s = 0.0;
                for (std::size_t j = 0; j < 3; ++j) s += b[j] * double{a[j][k]};
                c[k] = static_cast<float>(s / (b[0] + b[1] + b[2]));
                break;
            }
            case ShadeModel::NoPerspective: {
                double s = 0.0;
                for (std::size_t j = 0; j < 3; ++j)
                    s += b[j] * double{v_[j].clip[3]} * double{a[j][k]};
                c[k] = static_cast<float>(s);
                break;
            }
        }
    }
    write_fragment_color(draw_, fb, i, c, true);
    if (!fb.owner.empty()) fb.owner[i] = owner;
}

}  // namespace refraster::detail
