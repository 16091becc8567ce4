// exact_area.cpp: big integers, rationals, exact pixel areas and filtered coverage
// (exact_area.hpp).
#include "exact_area.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "refraster/assert.hpp"

namespace harness::study {

namespace {

using Limbs = std::vector<std::uint32_t>;

void trim_limbs(Limbs& m) {
    while (!m.empty() && m.back() == 0) m.pop_back();
}

Limbs add_magnitudes(const Limbs& a, const Limbs& b) {
    const Limbs& longer = a.size() >= b.size() ? a : b;
    const Limbs& shorter = a.size() >= b.size() ? b : a;
    Limbs r(longer.size() + 1, 0);
    std::uint64_t carry = 0;
    for (std::size_t i = 0; i < longer.size(); ++i) {
        const std::uint64_t s =
            std::uint64_t{longer[i]} + (i < shorter.size() ? shorter[i] : 0u) + carry;
        r[i] = static_cast<std::uint32_t>(s);
        carry = s >> 32;
    }
    r[longer.size()] = static_cast<std::uint32_t>(carry);
    trim_limbs(r);
    return r;
}

// a - b for |a| >= |b|.
Limbs subtract_magnitudes(const Limbs& a, const Limbs& b) {
    Limbs r(a.size(), 0);
    std::int64_t borrow = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        std::int64_t d = std::int64_t{a[i]} - (i < b.size() ? std::int64_t{b[i]} : 0) - borrow;
        borrow = d < 0 ? 1 : 0;
        if (d < 0) d += std::int64_t{1} << 32;
        r[i] = static_cast<std::uint32_t>(d);
    }
    REFRASTER_ASSERT(borrow == 0, "the larger magnitude first");
    trim_limbs(r);
    return r;
}

Limbs multiply_magnitudes(const Limbs& a, const Limbs& b) {
    if (a.empty() || b.empty()) return {};
    Limbs r(a.size() + b.size(), 0);
    for (std::size_t i = 0; i < a.size(); ++i) {
        std::uint64_t carry = 0;
        for (std::size_t j = 0; j < b.size(); ++j) {
            // At most (2^32 - 1)^2 + 2 (2^32 - 1) < 2^64: no overflow.
            const std::uint64_t t = std::uint64_t{a[i]} * b[j] + r[i + j] + carry;
            r[i + j] = static_cast<std::uint32_t>(t);
            carry = t >> 32;
        }
        r[i + b.size()] = static_cast<std::uint32_t>(carry);
    }
    trim_limbs(r);
    return r;
}

}  // namespace

// ---- BigInt ----

BigInt::BigInt(std::int64_t v) {
    negative_ = v < 0;
    // Two's complement negation in unsigned arithmetic also covers INT64_MIN.
    std::uint64_t u = static_cast<std::uint64_t>(v);
    if (negative_) u = ~u + 1;
    mag_ = {static_cast<std::uint32_t>(u), static_cast<std::uint32_t>(u >> 32)};
    trim();
}

void BigInt::trim() {
    trim_limbs(mag_);
    if (mag_.empty()) negative_ = false;
}

std::size_t BigInt::bit_length() const {
    if (mag_.empty()) return 0;
    return 32 * (mag_.size() - 1) + static_cast<std::size_t>(32 - std::countl_zero(mag_.back()));
}

std::strong_ordering BigInt::compare_magnitude(const Limbs& a, const Limbs& b) {
    if (a.size() != b.size()) return a.size() <=> b.size();
    for (std::size_t i = a.size(); i-- > 0;) {
        if (a[i] != b[i]) return a[i] <=> b[i];
    }
    return std::strong_ordering::equal;
}

BigInt operator+(const BigInt& a, const BigInt& b) {
    BigInt r;
    if (a.negative_ == b.negative_) {
        r.mag_ = add_magnitudes(a.mag_, b.mag_);
        r.negative_ = a.negative_;
    } else if (BigInt::compare_magnitude(a.mag_, b.mag_) >= 0) {
        r.mag_ = subtract_magnitudes(a.mag_, b.mag_);
        r.negative_ = a.negative_;
    } else {
        r.mag_ = subtract_magnitudes(b.mag_, a.mag_);
        r.negative_ = b.negative_;
    }
    r.trim();
    return r;
}

BigInt BigInt::operator-() const {
    BigInt r = *this;
    if (!r.mag_.empty()) r.negative_ = !r.negative_;
    return r;
}

BigInt operator-(const BigInt& a, const BigInt& b) {
    return a + (-b);
}

BigInt operator*(const BigInt& a, const BigInt& b) {
    BigInt r;
    r.mag_ = multiply_magnitudes(a.mag_, b.mag_);
    r.negative_ = a.negative_ != b.negative_;
    r.trim();
    return r;
}

BigInt BigInt::abs() const {
    BigInt r = *this;
    r.negative_ = false;
    return r;
}

BigInt BigInt::shifted_left(std::size_t bits) const {
    if (mag_.empty()) return {};
    const std::size_t limbs = bits / 32;
    const unsigned rest = static_cast<unsigned>(bits % 32);
    BigInt r;
    r.negative_ = negative_;
    r.mag_.assign(mag_.size() + limbs + 1, 0);
    for (std::size_t i = 0; i < mag_.size(); ++i) {
        const std::uint64_t v = std::uint64_t{mag_[i]} << rest;
        r.mag_[i + limbs] |= static_cast<std::uint32_t>(v);
        r.mag_[i + limbs + 1] |= static_cast<std::uint32_t>(v >> 32);
    }
    r.trim();
    return r;
}

BigInt BigInt::shifted_right(std::size_t bits) const {
    const std::size_t limbs = bits / 32;
    if (limbs >= mag_.size()) return {};
    const unsigned rest = static_cast<unsigned>(bits % 32);
    BigInt r;
    r.negative_ = negative_;
    r.mag_.assign(mag_.size() - limbs, 0);
    for (std::size_t i = 0; i < r.mag_.size(); ++i) {
        std::uint64_t v = mag_[i + limbs];
        if (i + limbs + 1 < mag_.size()) v |= std::uint64_t{mag_[i + limbs + 1]} << 32;
        r.mag_[i] = static_cast<std::uint32_t>(v >> rest);
    }
    r.trim();
    return r;
}

std::strong_ordering operator<=>(const BigInt& a, const BigInt& b) {
    if (a.sign() != b.sign()) return a.sign() <=> b.sign();
    const auto m = BigInt::compare_magnitude(a.mag_, b.mag_);
    return a.negative_ ? 0 <=> m : m;
}

double BigInt::to_double() const {
    return quotient_to_double(*this, BigInt(1));
}

std::string BigInt::to_string() const {
    if (mag_.empty()) return "0";
    // Peel off base-10^9 digits, least significant first, by short division.
    Limbs m = mag_;
    std::vector<std::uint32_t> chunks;
    while (!m.empty()) {
        std::uint64_t rem = 0;
        for (std::size_t i = m.size(); i-- > 0;) {
            const std::uint64_t cur = (rem << 32) | m[i];
            m[i] = static_cast<std::uint32_t>(cur / 1000000000u);
            rem = cur % 1000000000u;
        }
        trim_limbs(m);
        chunks.push_back(static_cast<std::uint32_t>(rem));
    }
    std::string s = negative_ ? "-" : "";
    s += std::to_string(chunks.back());
    for (std::size_t i = chunks.size() - 1; i-- > 0;) {
        const std::string part = std::to_string(chunks[i]);
        s += std::string(9 - part.size(), '0') + part;
    }
    return s;
}

double quotient_to_double(const BigInt& num, const BigInt& den) {
    REFRASTER_ASSERT(!den.is_zero(), "a non-zero denominator");
    if (num.is_zero()) return 0.0;
    BigInt n = num.abs();
    BigInt d = den.abs();
    // Scale so that q = floor(n 2^s / d) lies in [2^54, 2^56): at least two bits below the
    // 53 a double keeps, so the remainder can be folded into the lowest as a sticky bit and
    // the hardware's rounding of q to double is then the correct rounding of n / d.
    const auto bn = static_cast<std::int64_t>(n.bit_length());
    const auto bd = static_cast<std::int64_t>(d.bit_length());
    const std::int64_t s = 55 - (bn - bd);
    if (s >= 0) {
        n = n.shifted_left(static_cast<std::size_t>(s));
    } else {
        d = d.shifted_left(static_cast<std::size_t>(-s));
    }
    std::uint64_t q = 0;
    BigInt step = d.shifted_left(55);  // d 2^i, for i from 55 down
    for (int i = 55; i >= 0; --i) {
        if (n >= step) {
            n = n - step;
            q |= std::uint64_t{1} << i;
        }
        step = step.shifted_right(1);
    }
    REFRASTER_ASSERT(q >= (std::uint64_t{1} << 54), "the quotient's scaling");
    if (!n.is_zero()) q |= 1u;
    const double magnitude = std::ldexp(static_cast<double>(q), static_cast<int>(-s));
    return num.sign() * den.sign() < 0 ? -magnitude : magnitude;
}

// ---- Rational ----

Rational::Rational(BigInt num, BigInt den) : num_(std::move(num)), den_(std::move(den)) {
    REFRASTER_ASSERT(!den_.is_zero(), "a non-zero denominator");
    if (den_.sign() < 0) {
        num_ = -num_;
        den_ = -den_;
    }
}

Rational operator+(const Rational& a, const Rational& b) {
    if (a.den_ == b.den_) return Rational(a.num_ + b.num_, a.den_);
    return Rational(a.num_ * b.den_ + b.num_ * a.den_, a.den_ * b.den_);
}

Rational operator-(const Rational& a, const Rational& b) {
    return a + (-b);
}

Rational operator*(const Rational& a, const Rational& b) {
    return Rational(a.num_ * b.num_, a.den_ * b.den_);
}

bool operator==(const Rational& a, const Rational& b) {
    return a.num_ * b.den_ == b.num_ * a.den_;
}

std::strong_ordering operator<=>(const Rational& a, const Rational& b) {
    return a.num_ * b.den_ <=> b.num_ * a.den_;  // both denominators are positive
}

double Rational::to_double() const {
    return quotient_to_double(num_, den_);
}

// ---- exact pixel area ----

namespace {

void check_grid(const GridTriangle& t) {
    for (const auto& p : t) {
        REFRASTER_ASSERT(
            p.x >= -kGridLimit && p.x <= kGridLimit && p.y >= -kGridLimit && p.y <= kGridLimit,
            "vertices within the exact answers' range");
    }
}

// A clipped polygon's vertex, (x / d, y / d) in grid units relative to the pixel's corner.
struct RationalPoint {
    BigInt x, y, d;  // d > 0
};

// The line a clipped polygon's edge lies on: one of the triangle's edges, or a side of the
// pixel square. Intersecting with the line it came from (instead of with the previous
// clipped segment) keeps every vertex's denominator a single edge's dx or dy.
struct EdgeLine {
    enum Kind { triangle_edge, vertical, horizontal } kind = triangle_edge;
    int edge = 0;         // triangle_edge: from vertex edge to edge + 1
    std::int64_t at = 0;  // vertical: x = at; horizontal: y = at
};

struct ClipVertex {
    RationalPoint p;
    EdgeLine out;  // the line of the edge from this vertex to the next
};

// One side of the pixel square: keep x >= at (or <=, or the same for y).
struct Boundary {
    bool vertical;  // x = at
    std::int64_t at;
    bool keep_greater;
};

bool inside(const RationalPoint& p, const Boundary& b) {
    const BigInt& c = b.vertical ? p.x : p.y;
    const BigInt diff = c - BigInt(b.at) * p.d;  // sign of c / d - at, d > 0
    return b.keep_greater ? diff.sign() >= 0 : diff.sign() <= 0;
}

RationalPoint intersect(const EdgeLine& line, const Boundary& b,
                        const std::array<GridPoint, 3>& v) {
    if (line.kind != EdgeLine::triangle_edge) {
        // A side of the square crossed by the perpendicular side: the corner.
        REFRASTER_ASSERT((line.kind == EdgeLine::vertical) != b.vertical,
                         "parallel sides never cross");
        const std::int64_t x = b.vertical ? b.at : line.at;
        const std::int64_t y = b.vertical ? line.at : b.at;
        return {BigInt(x), BigInt(y), BigInt(1)};
    }
    const GridPoint& a = v[static_cast<std::size_t>(line.edge)];
    const GridPoint& e = v[static_cast<std::size_t>((line.edge + 1) % 3)];
    // Along the edge from a to e, the point where the coordinate across the boundary equals
    // `at`: parameter (at - a) / (e - a) in that coordinate.
    const std::int64_t a_across = b.vertical ? a.x : a.y;
    const std::int64_t e_across = b.vertical ? e.x : e.y;
    const std::int64_t a_along = b.vertical ? a.y : a.x;
    const std::int64_t e_along = b.vertical ? e.y : e.x;
    std::int64_t den = e_across - a_across;
    REFRASTER_ASSERT(den != 0, "a crossing edge is not parallel to the side");
    BigInt along =
        BigInt(a_along) * BigInt(den) + BigInt(e_along - a_along) * BigInt(b.at - a_across);
    BigInt across = BigInt(b.at) * BigInt(den);
    if (den < 0) {
        along = -along;
        across = -across;
        den = -den;
    }
    if (b.vertical) return {std::move(across), std::move(along), BigInt(den)};
    return {std::move(along), std::move(across), BigInt(den)};
}

// Sutherland-Hodgman against one side, keeping each edge's line.
std::vector<ClipVertex> clip(const std::vector<ClipVertex>& poly, const Boundary& b,
                             const std::array<GridPoint, 3>& v) {
    std::vector<ClipVertex> out;
    const EdgeLine side{b.vertical ? EdgeLine::vertical : EdgeLine::horizontal, 0, b.at};
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const ClipVertex& p = poly[i];
        const ClipVertex& q = poly[(i + 1) % poly.size()];
        const bool p_in = inside(p.p, b);
        const bool q_in = inside(q.p, b);
        if (p_in) out.push_back(p);
        if (p_in && !q_in) {
            out.push_back({intersect(p.out, b, v), side});
        } else if (!p_in && q_in) {
            out.push_back({intersect(p.out, b, v), p.out});
        }
    }
    return out;
}

}  // namespace

Rational triangle_area(const GridTriangle& t) {
    check_grid(t);
    const BigInt twice = BigInt(t[1].x - t[0].x) * BigInt(t[2].y - t[0].y) -
                         BigInt(t[2].x - t[0].x) * BigInt(t[1].y - t[0].y);
    return Rational(twice.abs(), BigInt(2 * kGridPerPixel * kGridPerPixel));
}

Rational exact_pixel_area(const GridTriangle& t, std::int64_t px, std::int64_t py) {
    check_grid(t);
    // Relative to the pixel's corner, so the square is [0, 256]^2 and the numbers stay small.
    std::array<GridPoint, 3> v;
    for (std::size_t i = 0; i < 3; ++i) {
        v[i] = {t[i].x - px * kGridPerPixel, t[i].y - py * kGridPerPixel};
    }
    const auto [min_x, max_x] = std::minmax({v[0].x, v[1].x, v[2].x});
    const auto [min_y, max_y] = std::minmax({v[0].y, v[1].y, v[2].y});
    if (max_x <= 0 || min_x >= kGridPerPixel || max_y <= 0 || min_y >= kGridPerPixel) {
        return Rational(0);
    }
    std::vector<ClipVertex> poly;
    for (int i = 0; i < 3; ++i) {
        const GridPoint& p = v[static_cast<std::size_t>(i)];
        poly.push_back({{BigInt(p.x), BigInt(p.y), BigInt(1)}, {EdgeLine::triangle_edge, i, 0}});
    }
    const Boundary sides[4] = {{true, 0, true},
                               {true, kGridPerPixel, false},
                               {false, 0, true},
                               {false, kGridPerPixel, false}};
    for (const Boundary& b : sides) {
        poly = clip(poly, b, v);
        if (poly.empty()) return Rational(0);
    }
    // Shoelace over rational vertices: sum of (x_i y_j - x_j y_i) / (d_i d_j).
    Rational twice;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const RationalPoint& a = poly[i].p;
        const RationalPoint& b = poly[(i + 1) % poly.size()].p;
        twice = twice + Rational(a.x * b.y - b.x * a.y, a.d * b.d);
    }
    return twice.abs() * Rational(BigInt(1), BigInt(2 * kGridPerPixel * kGridPerPixel));
}

// ---- filters and filtered coverage ----

const char* filter_name(Filter f) {
    switch (f) {
        case Filter::box:
            return "box";
        case Filter::tent:
            return "tent";
        case Filter::gaussian:
            return "gaussian";
    }
    return "?";
}

double filter_radius(Filter f) {
    switch (f) {
        case Filter::box:
            return 0.5;
        case Filter::tent:
            return 1.0;
        case Filter::gaussian:
            return 3.0 * kGaussianSigma;
    }
    return 0.0;
}

namespace {

double weight_1d(Filter f, double t) {
    if (std::abs(t) > filter_radius(f)) return 0.0;
    switch (f) {
        case Filter::box:
            return 1.0;
        case Filter::tent:
            return 1.0 - std::abs(t);
        case Filter::gaussian:
            return std::exp(-t * t / (2.0 * kGaussianSigma * kGaussianSigma));
    }
    return 0.0;
}

// The integral of the 1-D filter over [a, b], within the support.
double integral_1d(Filter f, double a, double b) {
    switch (f) {
        case Filter::box:
            return b - a;
        case Filter::tent: {
            const auto antiderivative = [](double t) { return t - t * std::abs(t) / 2.0; };
            return antiderivative(b) - antiderivative(a);
        }
        case Filter::gaussian: {
            const double k = 1.0 / (kGaussianSigma * std::numbers::sqrt2);
            const double c = kGaussianSigma * std::sqrt(std::numbers::pi / 2.0);
            return c * (std::erf(k * b) - std::erf(k * a));
        }
    }
    return 0.0;
}

struct GaussLegendre {
    std::vector<double> nodes;  // on [-1, 1]
    std::vector<double> weights;
};

// Nodes are the roots of the Legendre polynomial P_n, found by Newton's method from the
// usual cosine estimates; accurate to a few ulps.
GaussLegendre make_gauss_legendre(int n) {
    GaussLegendre g;
    for (int i = 1; i <= n; ++i) {
        double x = std::cos(std::numbers::pi * (i - 0.25) / (n + 0.5));
        double derivative = 0.0;
        for (int iter = 0; iter < 100; ++iter) {
            double p0 = 1.0;
            double p1 = x;
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            derivative = n * (x * p1 - p0) / (x * x - 1.0);
            const double dx = p1 / derivative;
            x -= dx;
            if (std::abs(dx) < 1e-17) break;
        }
        // One more derivative at the converged root, for the weight.
        double p0 = 1.0;
        double p1 = x;
        for (int k = 2; k <= n; ++k) {
            const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
            p0 = p1;
            p1 = p2;
        }
        derivative = n * (x * p1 - p0) / (x * x - 1.0);
        g.nodes.push_back(x);
        g.weights.push_back(2.0 / ((1.0 - x * x) * derivative * derivative));
    }
    return g;
}

constexpr int kMaxOrder = 32;

const GaussLegendre& gauss_legendre(int n) {
    REFRASTER_ASSERT(n >= 1 && n <= kMaxOrder, "a Gauss-Legendre order in 1..32");
    static const std::vector<GaussLegendre> rules = [] {
        std::vector<GaussLegendre> r(kMaxOrder + 1);
        for (int k = 1; k <= kMaxOrder; ++k)
            r[static_cast<std::size_t>(k)] = make_gauss_legendre(k);
        return r;
    }();
    return rules[static_cast<std::size_t>(n)];
}

struct Vec {
    double x, y;
};

}  // namespace

double filter_weight(Filter f, double dx, double dy) {
    return weight_1d(f, dx) * weight_1d(f, dy);
}

double filtered_coverage(const GridTriangle& t, std::int64_t px, std::int64_t py, Filter f,
                         const Quadrature& q) {
    check_grid(t);
    const double r = filter_radius(f);
    // Pixel units relative to the pixel centre; exact (integers below 2^53, over 256).
    std::array<Vec, 3> v;
    for (std::size_t i = 0; i < 3; ++i) {
        v[i] = {static_cast<double>(t[i].x - px * kGridPerPixel - kGridPerPixel / 2) / 256.0,
                static_cast<double>(t[i].y - py * kGridPerPixel - kGridPerPixel / 2) / 256.0};
    }
    const double twice_area =
        (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
    if (twice_area == 0.0) return 0.0;
    const double lo_x = std::max(-r, std::min({v[0].x, v[1].x, v[2].x}));
    const double hi_x = std::min(r, std::max({v[0].x, v[1].x, v[2].x}));
    if (lo_x >= hi_x) return 0.0;

    // Breakpoints in x, between which the integrand is one smooth formula: the vertices, the
    // support's sides (and the tent's kink column), and where an edge crosses the support's
    // top or bottom row (or the tent's kink row).
    std::vector<double> rows = {-r, r};
    if (f == Filter::tent) rows.push_back(0.0);
    std::vector<double> breaks = rows;
    for (std::size_t i = 0; i < 3; ++i) {
        const Vec& a = v[i];
        const Vec& b = v[(i + 1) % 3];
        breaks.push_back(a.x);
        for (const double y : rows) {
            if ((a.y < y && y < b.y) || (b.y < y && y < a.y)) {
                breaks.push_back(a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y));
            }
        }
    }
    for (double& x : breaks) x = std::clamp(x, lo_x, hi_x);
    breaks.push_back(lo_x);
    breaks.push_back(hi_x);
    std::sort(breaks.begin(), breaks.end());
    breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());

    // The triangle's cross-section at x is one interval, bounded by the edges spanning x
    // (continuous in x, also at a vertex's column), clipped to the support's rows.
    const auto cross_section = [&](double x) {
        double lo = std::numeric_limits<double>::infinity();
        double hi = -lo;
        for (std::size_t i = 0; i < 3; ++i) {
            const Vec& a = v[i];
            const Vec& b = v[(i + 1) % 3];
            if (a.x == b.x || x < std::min(a.x, b.x) || x > std::max(a.x, b.x)) continue;
            const double y = a.y + (x - a.x) * (b.y - a.y) / (b.x - a.x);
            lo = std::min(lo, y);
            hi = std::max(hi, y);
        }
        return std::pair{std::clamp(lo, -r, r), std::clamp(hi, -r, r)};
    };
    // The inner integral over the cross-section is closed form.
    const auto integrand = [&](double x) {
        const auto span = cross_section(x);
        if (span.first >= span.second) return 0.0;
        return weight_1d(f, x) * integral_1d(f, span.first, span.second);
    };

    const bool polynomial = f != Filter::gaussian;
    const int order = q.order > 0 ? q.order : (polynomial ? 4 : 12);
    const double max_piece = q.max_piece > 0 ? q.max_piece : (polynomial ? 0.0 : 0.25);
    const GaussLegendre& rule = gauss_legendre(order);
    double sum = 0.0;
    for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
        const double a = breaks[i];
        const double b = breaks[i + 1];
        int splits = 1;
        if (max_piece > 0) {
            // The Gaussian varies on the scale of sigma along y as much as along x: a steep
            // edge sweeps the cross-section's end across the support within a narrow
            // column, so a piece is split by how far its ends move in y as well as in x.
            const auto [lo_a, hi_a] = cross_section(a);
            const auto [lo_b, hi_b] = cross_section(b);
            const double travel = std::max({b - a, std::abs(lo_b - lo_a), std::abs(hi_b - hi_a)});
            splits = std::max(1, static_cast<int>(std::ceil(travel / max_piece)));
        }
        for (int s = 0; s < splits; ++s) {
            const double sa = a + (b - a) * s / splits;
            const double sb = s + 1 == splits ? b : a + (b - a) * (s + 1) / splits;
            const double half = (sb - sa) / 2.0;
            const double mid = (sa + sb) / 2.0;
            double piece = 0.0;
            for (std::size_t k = 0; k < rule.nodes.size(); ++k) {
                piece += rule.weights[k] * integrand(mid + half * rule.nodes[k]);
            }
            sum += half * piece;
        }
    }
    const double norm_1d = integral_1d(f, -r, r);
    return std::clamp(sum / (norm_1d * norm_1d), 0.0, 1.0);
}

// ---- the exact support classification ----

namespace {
__extension__ using Int128 = __int128;
}

SupportOverlap classify_support(const GridTriangle& t, std::int64_t px, std::int64_t py, Filter f) {
    check_grid(t);
    std::array<GridPoint, 3> v = t;
    const Int128 twice =
        Int128{v[1].x - v[0].x} * (v[2].y - v[0].y) - Int128{v[2].x - v[0].x} * (v[1].y - v[0].y);
    if (twice == 0) return SupportOverlap::outside;
    if (twice < 0) std::swap(v[1], v[2]);  // counter-clockwise: the inside is to each edge's left
    // The support's corners are on the grid: the radius is a multiple of half a pixel.
    const auto half = static_cast<std::int64_t>(filter_radius(f) * kGridPerPixel);
    const std::int64_t cx = px * kGridPerPixel + kGridPerPixel / 2;
    const std::int64_t cy = py * kGridPerPixel + kGridPerPixel / 2;
    const std::int64_t x0 = cx - half, x1 = cx + half, y0 = cy - half, y1 = cy + half;
    const auto [min_x, max_x] = std::minmax({v[0].x, v[1].x, v[2].x});
    const auto [min_y, max_y] = std::minmax({v[0].y, v[1].y, v[2].y});
    if (max_x <= x0 || min_x >= x1 || max_y <= y0 || min_y >= y1) return SupportOverlap::outside;
    const GridPoint corners[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    bool all_inside = true;
    for (std::size_t i = 0; i < 3; ++i) {
        const GridPoint& a = v[i];
        const GridPoint& b = v[(i + 1) % 3];
        int non_positive = 0;
        for (const GridPoint& c : corners) {
            const Int128 e = Int128{b.x - a.x} * (c.y - a.y) - Int128{b.y - a.y} * (c.x - a.x);
            if (e <= 0) ++non_positive;
            if (e < 0) all_inside = false;
        }
        // The edge's line separates the square from the triangle (touching at most).
        if (non_positive == 4) return SupportOverlap::outside;
    }
    return all_inside ? SupportOverlap::inside : SupportOverlap::partial;
}

// ---- the exact sample test ----

SampleCoverage::SampleCoverage(const GridTriangle& t) {
    constexpr std::int64_t scale = kSampleUnitsPerPixel / kGridPerPixel;
    std::array<GridPoint, 3> v;
    for (std::size_t i = 0; i < 3; ++i) {
        v[i] = {t[i].x * scale, t[i].y * scale};
        REFRASTER_ASSERT(v[i].x >= -kSampleLimit && v[i].x <= kSampleLimit &&
                             v[i].y >= -kSampleLimit && v[i].y <= kSampleLimit,
                         "vertices within the sample test's range");
    }
    const Int128 twice =
        Int128{v[1].x - v[0].x} * (v[2].y - v[0].y) - Int128{v[2].x - v[0].x} * (v[1].y - v[0].y);
    degenerate_ = twice == 0;
    if (twice < 0) std::swap(v[1], v[2]);
    for (std::size_t i = 0; i < 3; ++i) {
        const GridPoint& a = v[i];
        const GridPoint& b = v[(i + 1) % 3];
        x_[i] = a.x;
        y_[i] = a.y;
        dx_[i] = b.x - a.x;
        dy_[i] = b.y - a.y;
        // Counter-clockwise, a left edge runs down and a bottom edge runs right.
        const bool owns_ties = dy_[i] < 0 || (dy_[i] == 0 && dx_[i] > 0);
        bias_[i] = owns_ties ? 1 : 0;
    }
}

}  // namespace harness::study
