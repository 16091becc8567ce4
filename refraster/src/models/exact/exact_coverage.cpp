#include "models/exact/exact_coverage.hpp"

#include <algorithm>
#include <cmath>

#include "common/big_int.hpp"
#include "stages/rules.hpp"

namespace refraster::detail {

struct ExactTriangle {
    // Rows of adj(M): e_k(p) = A[k]*p.x + B[k]*p.y + C[k]*p.w, scaled by 2^298.
    std::array<BigInt, 3> A, B, C;
    std::array<BigInt, 3> Z;  // z_k scaled by 2^149
    BigInt det;               // v0 . (v1 x v2), scaled by 2^447
    int det_sign = 0;
    std::array<bool, 3> owns{};
    bool all_w_positive = false;
    std::array<std::array<double, 2>, 3> window_approx{};
    Rect viewport;
    PixelRect region;
};

ExactCoverage::ExactCoverage(const std::array<std::array<float, 4>, 3>& clip,
                             const DrawState& state, PixelRect draw_region, TieRule tie_rule)
    : t_(std::make_unique<ExactTriangle>()) {
    ExactTriangle& t = *t_;
    t.viewport = state.viewport;
    const PixelRect vp{state.viewport.x, state.viewport.y,
                       state.viewport.x + state.viewport.width - 1,
                       state.viewport.y + state.viewport.height - 1};
    t.region = intersect(vp, draw_region);
    std::array<BigInt, 3> x, y, w;
    t.all_w_positive = true;
    for (std::size_t i = 0; i < 3; ++i) {
        x[i] = BigInt::from_scaled_float(clip[i][0]);
        y[i] = BigInt::from_scaled_float(clip[i][1]);
        t.Z[i] = BigInt::from_scaled_float(clip[i][2]);
        w[i] = BigInt::from_scaled_float(clip[i][3]);
        t.all_w_positive = t.all_w_positive && clip[i][3] > 0.0f;
        if (clip[i][3] > 0.0f) {
            const double vw = state.viewport.width;
            const double vh = state.viewport.height;
            t.window_approx[i] = {
                (double{clip[i][0]} / double{clip[i][3]} + 1.0) * 0.5 * vw + state.viewport.x,
                (double{clip[i][1]} / double{clip[i][3]} + 1.0) * 0.5 * vh + state.viewport.y};
        }
    }
    for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t i = (k + 1) % 3;
        const std::size_t j = (k + 2) % 3;
        t.A[k] = y[i] * w[j] - w[i] * y[j];
        t.B[k] = w[i] * x[j] - x[i] * w[j];
        t.C[k] = x[i] * y[j] - y[i] * x[j];
    }
    t.det = x[0] * t.A[0] + y[0] * t.B[0] + w[0] * t.C[0];
    t.det_sign = t.det.sign();
    const bool left = owns_left_edges(tie_rule);
    const bool bottom = owns_bottom_edges(tie_rule);
    for (std::size_t k = 0; k < 3; ++k) {
        // The interior side of edge k is where b_k > 0; its gradient over window (x, y) has the
        // signs of (A_k, B_k) * sign(det), the viewport scale being positive.
        const int gx = t.A[k].sign() * t.det_sign;
        const int gy = t.B[k].sign() * t.det_sign;
        t.owns[k] = gx != 0 ? (gx > 0) == left : gy != 0 && (gy > 0) == bottom;
    }
}

ExactCoverage::~ExactCoverage() = default;

bool ExactCoverage::degenerate() const {
    return t_->det_sign == 0;
}

bool ExactCoverage::front_facing() const {
    return t_->det_sign > 0;
}

PixelRect ExactCoverage::candidates() const {
    const ExactTriangle& t = *t_;
    if (!t.all_w_positive) return t.region;
    double x0 = t.window_approx[0][0], x1 = x0, y0 = t.window_approx[0][1], y1 = y0;
    for (const auto& v : t.window_approx) {
        x0 = std::min(x0, v[0]);
        x1 = std::max(x1, v[0]);
        y0 = std::min(y0, v[1]);
        y1 = std::max(y1, v[1]);
    }
    // A margin of two pixels absorbs the approximation; the exact test decides.
    const auto clampi = [](double v) { return static_cast<int>(std::clamp(v, -1e9, 1e9)); };
    return intersect(t.region, {clampi(std::floor(x0)) - 2, clampi(std::floor(y0)) - 2,
                                clampi(std::ceil(x1)) + 2, clampi(std::ceil(y1)) + 2});
}

namespace {

// The pixel centre's NDC point, scaled by vw*vh to integers: X = (2px + 1 - 2vx - vw) / vw.
std::array<BigInt, 3> scaled_centre(const Rect& vp, int px, int py) {
    const std::int64_t nx = 2 * std::int64_t{px} + 1 - 2 * std::int64_t{vp.x} - vp.width;
    const std::int64_t ny = 2 * std::int64_t{py} + 1 - 2 * std::int64_t{vp.y} - vp.height;
    return {BigInt::from_int(nx * vp.height), BigInt::from_int(ny * vp.width),
            BigInt::from_int(std::int64_t{vp.width} * vp.height)};
}

}  // namespace

std::array<int, 3> ExactCoverage::weight_signs(int px, int py) const {
    const ExactTriangle& t = *t_;
    const auto p = scaled_centre(t.viewport, px, py);
    std::array<int, 3> s{};
    for (std::size_t k = 0; k < 3; ++k) {
        s[k] = (t.A[k] * p[0] + t.B[k] * p[1] + t.C[k] * p[2]).sign() * t.det_sign;
    }
    return s;
}

std::array<bool, 3> ExactCoverage::owns_ties() const {
    return t_->owns;
}

std::array<double, 3> ExactCoverage::weights(int px, int py) const {
    const ExactTriangle& t = *t_;
    const auto p = scaled_centre(t.viewport, px, py);
    // e_k carries the scale 2^298 (two scaled floats), det 2^447 (three): their quotient is
    // b_k * 2^-149, which the last step undoes exactly (a power of two).
    const double d = (t.det * p[2]).to_double();
    std::array<double, 3> b{};
    for (std::size_t k = 0; k < 3; ++k)
        b[k] = std::ldexp((t.A[k] * p[0] + t.B[k] * p[1] + t.C[k] * p[2]).to_double() / d,
                          BigInt::kFloatScaleBits);
    return b;
}

bool ExactCoverage::covers(int px, int py) const {
    const ExactTriangle& t = *t_;
    if (t.det_sign == 0) return false;
    if (px < t.region.x0 || px > t.region.x1 || py < t.region.y0 || py > t.region.y1) return false;
    const auto p = scaled_centre(t.viewport, px, py);
    std::array<BigInt, 3> e;
    for (std::size_t k = 0; k < 3; ++k) {
        e[k] = t.A[k] * p[0] + t.B[k] * p[1] + t.C[k] * p[2];
        const int s = e[k].sign() * t.det_sign;
        if (s < 0 || (s == 0 && !t.owns[k])) return false;
    }
    // Near and far planes: -1 <= sum(b_k z_k) <= 1 with b_k = e_k / (det * vw * vh).
    const BigInt d = t.det * p[2];
    const BigInt s = e[0] * t.Z[0] + e[1] * t.Z[1] + e[2] * t.Z[2];
    const BigInt sd = t.det_sign > 0 ? s : -s;
    const BigInt ad = t.det_sign > 0 ? d : -d;
    return (ad - sd).sign() >= 0 && (ad + sd).sign() >= 0;
}

}  // namespace refraster::detail
