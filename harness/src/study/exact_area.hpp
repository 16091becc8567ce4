// exact_area.hpp: the exact answers of the antialiasing study: how much of a pixel, or of a
// pixel's filter support, a triangle covers.
//
// Implements:
// - BigInt, a signed integer of any size (32-bit limbs) with +, -, *, shifts, comparison and a
//   correctly rounded conversion to double; Rational, an unnormalised fraction of two BigInts
//   (positive denominator) with +, -, *, comparison and a correctly rounded conversion;
// - exact_pixel_area: the area of a triangle (vertices on the 1/256 px grid) intersected with a
//   unit pixel square, as a Rational: the triangle is clipped to the square in rational
//   arithmetic, so the answer has no rounding at all;
// - filtered_coverage: the integral of the box, tent or Gaussian filter centred on a pixel over
//   a triangle, divided by the filter's own integral, by 1-D quadrature over x of the filter's
//   closed-form integral over the triangle's cross-section in y;
// - classify_support: whether a filter's support lies wholly outside, wholly inside or across
//   the triangle's boundary, decided exactly, so that "edge pixel" has an exact meaning;
// - SampleCoverage: the estimators' sample test, exact too (integer edge functions and a tie
//   rule), so that the study measures sampling error and nothing else.
// What "exact" means for each answer:
// - box area: exact (a rational number); its double is correctly rounded;
// - tent: the integrand is a polynomial of degree 3 on every piece between breakpoints, and
//   Gauss-Legendre of order 4 integrates degree 7 exactly: exact up to rounding (~1e-16);
// - Gaussian: the integrand is analytic on every piece and the pieces are subdivided until
//   the result has converged: within 1e-12 of the true integral (the tests show halving the
//   pieces moves it by less than 1e-13).
// Filters (centred on the pixel centre, in pixel units): box, the pixel square; tent,
// (1 - |dx|)(1 - |dy|) for |dx|, |dy| <= 1; Gaussian, exp(-(dx^2 + dy^2) / (2 sigma^2)) with
// sigma = 0.5, truncated to the square |dx|, |dy| <= 1.5 and normalised over that square.
//
// Deliberately does not: divide BigInts (only the final conversion to double needs a
// quotient, and it computes just the bits it needs), reduce fractions (no gcd: the study's
// fractions stay a few hundred bits), or handle vertices beyond 2^40 grid units (2^32 px).
#pragma once

#include <array>
#include <compare>
#include <cstdint>
#include <string>
#include <vector>

namespace harness::study {

class BigInt {
  public:
    BigInt() = default;
    explicit BigInt(std::int64_t v);

    int sign() const { return mag_.empty() ? 0 : (negative_ ? -1 : 1); }
    bool is_zero() const { return mag_.empty(); }
    // Bits of |value| (0 for zero).
    std::size_t bit_length() const;

    friend BigInt operator+(const BigInt& a, const BigInt& b);
    friend BigInt operator-(const BigInt& a, const BigInt& b);
    friend BigInt operator*(const BigInt& a, const BigInt& b);
    BigInt operator-() const;
    BigInt abs() const;
    // value * 2^bits; value / 2^bits rounded towards zero (bits >= 0).
    BigInt shifted_left(std::size_t bits) const;
    BigInt shifted_right(std::size_t bits) const;

    friend bool operator==(const BigInt& a, const BigInt& b) = default;
    friend std::strong_ordering operator<=>(const BigInt& a, const BigInt& b);

    // Correctly rounded (to nearest, ties to even) in the normal range; beyond 2^1024, inf.
    double to_double() const;
    std::string to_string() const;  // decimal, with a leading '-' when negative

  private:
    friend class Rational;
    // |a| <=> |b|.
    static std::strong_ordering compare_magnitude(const std::vector<std::uint32_t>& a,
                                                  const std::vector<std::uint32_t>& b);
    void trim();

    bool negative_ = false;           // never true for zero
    std::vector<std::uint32_t> mag_;  // |value|, least significant limb first, no zero on top
};

class Rational {
  public:
    Rational() : num_(0), den_(1) {}
    explicit Rational(std::int64_t v) : num_(v), den_(1) {}
    // den != 0 (asserted); the sign moves to the numerator.
    Rational(BigInt num, BigInt den);

    const BigInt& num() const { return num_; }
    const BigInt& den() const { return den_; }
    int sign() const { return num_.sign(); }

    friend Rational operator+(const Rational& a, const Rational& b);
    friend Rational operator-(const Rational& a, const Rational& b);
    friend Rational operator*(const Rational& a, const Rational& b);
    Rational operator-() const { return Rational(-num_, den_); }
    Rational abs() const { return Rational(num_.abs(), den_); }

    // By value (cross-multiplied), so 1/2 == 2/4.
    friend bool operator==(const Rational& a, const Rational& b);
    friend std::strong_ordering operator<=>(const Rational& a, const Rational& b);

    // Correctly rounded (to nearest, ties to even) in the normal range.
    double to_double() const;

  private:
    BigInt num_;
    BigInt den_;  // > 0
};

// num / den, correctly rounded; den != 0.
double quotient_to_double(const BigInt& num, const BigInt& den);

// Window coordinates (y up) on the study's dyadic grid: units of 1/256 pixel.
inline constexpr std::int64_t kGridPerPixel = 256;
struct GridPoint {
    std::int64_t x = 0;
    std::int64_t y = 0;
};
using GridTriangle = std::array<GridPoint, 3>;
// Every coordinate of an exact answer's triangle must lie within +-kGridLimit.
inline constexpr std::int64_t kGridLimit = std::int64_t{1} << 40;

// The triangle's area in square pixels, |shoelace| / 2, exactly.
Rational triangle_area(const GridTriangle& t);
// The area of the triangle intersected with [px, px + 1] x [py, py + 1] (pixel units), in
// square pixels, exactly; >= 0 whatever the orientation, 0 for a degenerate triangle.
Rational exact_pixel_area(const GridTriangle& t, std::int64_t px, std::int64_t py);

enum class Filter { box, tent, gaussian };
inline constexpr std::array<Filter, 3> kFilters = {Filter::box, Filter::tent, Filter::gaussian};
inline constexpr double kGaussianSigma = 0.5;
const char* filter_name(Filter f);  // "box", "tent", "gaussian"
// Half the side of the filter's square support: 0.5, 1, 1.5 pixels.
double filter_radius(Filter f);
// The filter's weight at an offset from the pixel centre (pixel units), unnormalised: 1 at
// the centre, 0 outside the support.
double filter_weight(Filter f, double dx, double dy);

// The Gauss-Legendre order and the widest piece it is applied to (in pixels: a piece wider
// than that, or whose cross-section's ends move farther than that in y, is split evenly). The
// defaults are what filtered_coverage uses.
struct Quadrature {
    int order = 0;         // 0: the filter's default (4 for box and tent, 12 for Gaussian)
    double max_piece = 0;  // 0: the filter's default (no split for box and tent, 1/4 px)
};

// The integral of the filter centred on pixel (px, py)'s centre over the triangle, divided by
// the filter's integral over its support: in [0, 1].
double filtered_coverage(const GridTriangle& t, std::int64_t px, std::int64_t py, Filter f,
                         const Quadrature& q = {});

enum class SupportOverlap { outside, inside, partial };
// Where the filter support of pixel (px, py) (a closed square) lies against the triangle,
// exactly: outside (the interiors are disjoint: coverage exactly 0), inside (the support lies
// in the closed triangle: coverage exactly 1) or partial (strictly between 0 and 1).
SupportOverlap classify_support(const GridTriangle& t, std::int64_t px, std::int64_t py, Filter f);

// Sample positions for the estimators: window coordinates (y up) in units of 1/65536 pixel, a
// refinement of the vertex grid (256 sample units a grid unit), fine enough for rotated and
// random patterns; coordinates within +-kSampleLimit (8192 px), so that an edge function is
// a difference of two products below 2^60 each and int64 holds it.
inline constexpr std::int64_t kSampleUnitsPerPixel = 65536;
inline constexpr std::int64_t kSampleLimit = std::int64_t{1} << 29;
struct SamplePoint {
    std::int64_t x = 0;
    std::int64_t y = 0;
};

// A triangle set up for exact sample tests: integer edge functions, so that an estimator's
// error is sampling error only, with nothing from rounding.
// Tie rule: a sample exactly on an edge is covered when the edge is a left edge (the triangle
// lies to its right) or a horizontal bottom edge (the triangle lies above it); a sample on
// a vertex, when both its edges are. Two triangles sharing an edge see it from opposite
// sides, so exactly one of them owns a sample on it, and of a fan of triangles around a
// vertex exactly one owns the vertex. Degenerate triangles cover nothing.
class SampleCoverage {
  public:
    explicit SampleCoverage(const GridTriangle& t);
    bool degenerate() const { return degenerate_; }
    bool covers(SamplePoint p) const {
        if (degenerate_) return false;
        for (std::size_t i = 0; i < 3; ++i) {
            // > 0 strictly inside; the bias of 1 lets an owned edge's 0 through.
            const std::int64_t e = dx_[i] * (p.y - y_[i]) - dy_[i] * (p.x - x_[i]);
            if (e + bias_[i] <= 0) return false;
        }
        return true;
    }

  private:
    // Edge i: from (x_, y_) by (dx_, dy_), counter-clockwise, in sample units.
    std::array<std::int64_t, 3> x_{}, y_{}, dx_{}, dy_{}, bias_{};
    bool degenerate_ = true;
};

}  // namespace harness::study
