// exact_support.hpp: the exact arithmetic the textbook tests state their expectations in.
//
// Implements: Rational, a reduced fraction of two __int128 whose every operation checks for
// overflow and aborts instead of wrapping (a wrong expectation must never pass silently);
// exact points and predicates on them (orientation, segment intersection, point in polygon,
// the open-interior tests that show a set of convex pieces tiles a polygon); a deterministic
// generator of simple polygons with integer vertices.
//
// Bit budget: the tests keep coordinates below 2^12 in magnitude with denominators built from
// at most a few differences of them; every product the predicates form stays far below the
// 2^126 that the checked operations enforce, and a test that broke that would abort.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace textbook_test {

__extension__ using Int128 = __int128;

[[noreturn]] inline void exact_overflow(const char* what) {
    std::fprintf(stderr, "exact arithmetic overflow in %s\n", what);
    std::abort();
}

inline Int128 mul(Int128 a, Int128 b) {
    Int128 r = 0;
    if (__builtin_mul_overflow(a, b, &r)) exact_overflow("a product");
    return r;
}
inline Int128 add(Int128 a, Int128 b) {
    Int128 r = 0;
    if (__builtin_add_overflow(a, b, &r)) exact_overflow("a sum");
    return r;
}
inline Int128 sub(Int128 a, Int128 b) {
    Int128 r = 0;
    if (__builtin_sub_overflow(a, b, &r)) exact_overflow("a difference");
    return r;
}
inline Int128 abs128(Int128 a) {
    return a < 0 ? -a : a;
}
inline Int128 gcd128(Int128 a, Int128 b) {
    a = abs128(a);
    b = abs128(b);
    while (b != 0) {
        const Int128 t = a % b;
        a = b;
        b = t;
    }
    return a;
}

class Rational {
  public:
    Rational() = default;
    Rational(long long n) : num_(n) {}  // NOLINT: integers are rationals
    Rational(Int128 n, Int128 d) : num_(n), den_(d) {
        if (d == 0) exact_overflow("a division by zero");
        normalize();
    }
    Int128 num() const { return num_; }
    Int128 den() const { return den_; }
    int sign() const { return num_ > 0 ? 1 : (num_ < 0 ? -1 : 0); }
    double to_double() const { return static_cast<double>(num_) / static_cast<double>(den_); }
    // floor(this), as an integer.
    Int128 floor() const {
        Int128 q = num_ / den_;
        if (num_ % den_ != 0 && num_ < 0) --q;
        return q;
    }

    friend Rational operator+(const Rational& a, const Rational& b) {
        const Int128 g = gcd128(a.den_, b.den_);
        return {add(mul(a.num_, b.den_ / g), mul(b.num_, a.den_ / g)), mul(a.den_, b.den_ / g)};
    }
    friend Rational operator-(const Rational& a) { return {-a.num_, a.den_}; }
    friend Rational operator-(const Rational& a, const Rational& b) { return a + (-b); }
    friend Rational operator*(const Rational& a, const Rational& b) {
        const Int128 g1 = gcd128(a.num_, b.den_);
        const Int128 g2 = gcd128(b.num_, a.den_);
        const Int128 n1 = g1 == 0 ? a.num_ : a.num_ / g1;
        const Int128 d2 = g1 == 0 ? b.den_ : b.den_ / g1;
        const Int128 n2 = g2 == 0 ? b.num_ : b.num_ / g2;
        const Int128 d1 = g2 == 0 ? a.den_ : a.den_ / g2;
        return {mul(n1, n2), mul(d1, d2)};
    }
    friend Rational operator/(const Rational& a, const Rational& b) {
        if (b.num_ == 0) exact_overflow("a division by zero");
        return a * Rational(b.den_, b.num_);
    }
    friend bool operator==(const Rational& a, const Rational& b) {
        return a.num_ == b.num_ && a.den_ == b.den_;
    }
    friend bool operator<(const Rational& a, const Rational& b) { return (a - b).sign() < 0; }
    friend bool operator>(const Rational& a, const Rational& b) { return b < a; }
    friend bool operator<=(const Rational& a, const Rational& b) { return !(b < a); }
    friend bool operator>=(const Rational& a, const Rational& b) { return !(a < b); }

  private:
    void normalize() {
        if (den_ < 0) {
            num_ = -num_;
            den_ = -den_;
        }
        const Int128 g = gcd128(num_, den_);
        if (g > 1) {
            num_ /= g;
            den_ /= g;
        }
    }
    Int128 num_ = 0;
    Int128 den_ = 1;
};

inline Rational abs(const Rational& a) {
    return a.sign() < 0 ? -a : a;
}
inline Rational min(const Rational& a, const Rational& b) {
    return b < a ? b : a;
}
inline Rational max(const Rational& a, const Rational& b) {
    return a < b ? b : a;
}
inline std::string to_string(const Rational& a) {
    return std::to_string(static_cast<long long>(a.num())) + "/" +
           std::to_string(static_cast<long long>(a.den()));
}

struct RPoint {
    Rational x;
    Rational y;
};

// Twice the signed area of (a, b, c): positive when counter-clockwise.
inline Rational orient(const RPoint& a, const RPoint& b, const RPoint& c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Twice the signed (shoelace) area.
inline Rational twice_area(const std::vector<RPoint>& poly) {
    Rational s;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const RPoint& a = poly[i];
        const RPoint& b = poly[(i + 1) % poly.size()];
        s = s + (a.x * b.y - b.x * a.y);
    }
    return s;
}

inline bool on_segment(const RPoint& p, const RPoint& a, const RPoint& b) {
    return orient(a, b, p).sign() == 0 && min(a.x, b.x) <= p.x && p.x <= max(a.x, b.x) &&
           min(a.y, b.y) <= p.y && p.y <= max(a.y, b.y);
}

// Whether the closed segments ab and cd share a point.
inline bool segments_intersect(const RPoint& a, const RPoint& b, const RPoint& c, const RPoint& d) {
    const int o1 = orient(a, b, c).sign();
    const int o2 = orient(a, b, d).sign();
    const int o3 = orient(c, d, a).sign();
    const int o4 = orient(c, d, b).sign();
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    return on_segment(c, a, b) || on_segment(d, a, b) || on_segment(a, c, d) || on_segment(b, c, d);
}

// Whether p is strictly inside the simple polygon (crossing number of a rightward ray, with
// boundary points reported separately by on_boundary).
inline bool on_boundary(const RPoint& p, const std::vector<RPoint>& poly) {
    for (std::size_t i = 0; i < poly.size(); ++i) {
        if (on_segment(p, poly[i], poly[(i + 1) % poly.size()])) return true;
    }
    return false;
}
inline bool strictly_inside(const RPoint& p, const std::vector<RPoint>& poly) {
    if (on_boundary(p, poly)) return false;
    bool inside = false;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const RPoint& a = poly[i];
        const RPoint& b = poly[(i + 1) % poly.size()];
        // Half-open in y: the edge counts when p.y is in [min y, max y).
        const bool a_below = a.y <= p.y;
        const bool b_below = b.y <= p.y;
        if (a_below == b_below) continue;
        // The crossing is right of p when orient has the edge's upward sign.
        const Rational o = orient(a, b, p);
        if ((b.y > a.y && o.sign() > 0) || (b.y < a.y && o.sign() < 0)) inside = !inside;
    }
    return inside;
}

// Whether the closed segment ab meets the open interior of the convex polygon piece
// (counter-clockwise, non-degenerate): the parameters t in [0, 1] at which a + t(b - a) is
// strictly inside every edge's half-plane form an interval; it is non-empty iff its lower
// bound is below its upper bound.
inline bool segment_meets_open_convex(const RPoint& a, const RPoint& b,
                                      const std::vector<RPoint>& piece) {
    Rational lo(0);
    Rational hi(1);
    for (std::size_t i = 0; i < piece.size(); ++i) {
        const RPoint& p = piece[i];
        const RPoint& q = piece[(i + 1) % piece.size()];
        const Rational fa = orient(p, q, a);
        const Rational fb = orient(p, q, b);
        const Rational slope = fb - fa;  // f(t) = fa + t * slope > 0 wanted
        if (slope.sign() == 0) {
            if (fa.sign() <= 0) return false;
            continue;
        }
        const Rational root = -fa / slope;
        if (slope.sign() > 0) {
            lo = max(lo, root);  // t > root (open; lo < hi below keeps it open)
        } else {
            hi = min(hi, root);
        }
    }
    return lo < hi;
}

// Whether two convex pieces (counter-clockwise, non-degenerate) have disjoint interiors: some
// edge line of one has the whole other piece on or outside its outer side.
inline bool convex_interiors_disjoint(const std::vector<RPoint>& a, const std::vector<RPoint>& b) {
    const auto separates = [](const std::vector<RPoint>& s, const std::vector<RPoint>& t) {
        for (std::size_t i = 0; i < s.size(); ++i) {
            const RPoint& p = s[i];
            const RPoint& q = s[(i + 1) % s.size()];
            bool all_outside = true;
            for (const RPoint& v : t) {
                if (orient(p, q, v).sign() > 0) {
                    all_outside = false;
                    break;
                }
            }
            if (all_outside) return true;
        }
        return false;
    };
    return separates(a, b) || separates(b, a);
}

// Whether a convex piece (counter-clockwise, non-degenerate) lies in the closed simple
// polygon: no boundary edge meets the piece's open interior (which is connected), and one
// interior point of the piece, its vertex centroid, is inside.
inline bool convex_piece_inside(const std::vector<RPoint>& piece, const std::vector<RPoint>& poly) {
    for (std::size_t i = 0; i < poly.size(); ++i) {
        if (segment_meets_open_convex(poly[i], poly[(i + 1) % poly.size()], piece)) return false;
    }
    Rational cx;
    Rational cy;
    for (const RPoint& v : piece) {
        cx = cx + v.x;
        cy = cy + v.y;
    }
    const Rational n(static_cast<long long>(piece.size()));
    return strictly_inside({cx / n, cy / n}, poly);
}

// Whether the polygon is simple: non-adjacent edges share no point, adjacent edges share only
// their common vertex (no fold back along each other), and no vertex repeats.
inline bool is_simple(const std::vector<RPoint>& poly) {
    const std::size_t n = poly.size();
    if (n < 3) return false;
    for (std::size_t i = 0; i < n; ++i) {
        const RPoint& a = poly[i];
        const RPoint& b = poly[(i + 1) % n];
        for (std::size_t j = i + 1; j < n; ++j) {
            const RPoint& c = poly[j];
            const RPoint& d = poly[(j + 1) % n];
            const bool adjacent = j == i + 1 || (i == 0 && j == n - 1);
            if (!adjacent) {
                if (segments_intersect(a, b, c, d)) return false;
                continue;
            }
            // Adjacent: the far endpoint of either must not lie on the other (a fold back).
            const RPoint& far_i = j == i + 1 ? a : b;
            const RPoint& far_j = j == i + 1 ? d : c;
            if (on_segment(far_j, a, b) || on_segment(far_i, c, d)) return false;
        }
    }
    return twice_area(poly).sign() != 0;
}

struct IPoint {
    long long x = 0;
    long long y = 0;
};

inline std::vector<RPoint> to_rational(const std::vector<IPoint>& poly) {
    std::vector<RPoint> out;
    out.reserve(poly.size());
    for (const IPoint& p : poly) out.push_back({Rational(p.x), Rational(p.y)});
    return out;
}

// A simple polygon of n distinct integer vertices in [0, extent]^2, by 2-opt untangling: a
// random tour of random points, and while two edges meet, the tour between them reversed
// (which shortens it, so it ends). Collinear overlaps that 2-opt cannot undo restart the
// attempt. Deterministic in the generator.
inline std::vector<IPoint> random_simple_polygon(std::mt19937& rng, int n, int extent) {
    std::uniform_int_distribution<int> coord(0, extent);
    for (;;) {
        std::vector<IPoint> pts;
        while (static_cast<int>(pts.size()) < n) {
            const IPoint p{coord(rng), coord(rng)};
            const bool repeat = std::any_of(
                pts.begin(), pts.end(), [&](const IPoint& q) { return q.x == p.x && q.y == p.y; });
            if (!repeat) pts.push_back(p);
        }
        const auto size = static_cast<std::size_t>(n);
        bool changed = true;
        int rounds = 0;
        while (changed && rounds < 2000) {
            changed = false;
            ++rounds;
            const std::vector<RPoint> r = to_rational(pts);
            for (std::size_t i = 0; i < size && !changed; ++i) {
                for (std::size_t j = i + 2; j < size && !changed; ++j) {
                    if (i == 0 && j == size - 1) continue;
                    if (segments_intersect(r[i], r[i + 1], r[j], r[(j + 1) % size])) {
                        std::reverse(pts.begin() + static_cast<std::ptrdiff_t>(i + 1),
                                     pts.begin() + static_cast<std::ptrdiff_t>(j + 1));
                        changed = true;
                    }
                }
            }
        }
        if (is_simple(to_rational(pts))) return pts;
    }
}

}  // namespace textbook_test

namespace textbook_test {

// Hand-built simple polygons (counter-clockwise; the tests also run them reversed): collinear
// vertices on every edge, a comb of deep teeth, a staircase of horizontal edges at shared
// heights, a spiral.
inline std::vector<std::vector<IPoint>> hand_polygons() {
    std::vector<std::vector<IPoint>> out;
    out.push_back({{0, 0}, {2, 0}, {4, 0}, {4, 2}, {4, 4}, {2, 4}, {0, 4}, {0, 2}});
    out.push_back({{0, 0}, {2, 0}, {4, 0}, {6, 0}, {8, 0}, {6, 3}, {4, 6}, {2, 3}, {1, 1}});
    std::vector<IPoint> comb{{0, 0}, {14, 0}, {14, 10}};
    for (int t = 6; t >= 0; --t) {
        comb.push_back({2 * t + 1, 10});
        comb.push_back({2 * t + 1, 1});
        comb.push_back({2 * t, 10});
    }
    out.push_back(comb);
    out.push_back({{0, 0},
                   {6, 0},
                   {6, 1},
                   {5, 1},
                   {5, 2},
                   {4, 2},
                   {4, 3},
                   {3, 3},
                   {3, 4},
                   {2, 4},
                   {2, 5},
                   {1, 5},
                   {1, 6},
                   {0, 6}});
    out.push_back({{0, 0},
                   {8, 0},
                   {8, 8},
                   {2, 8},
                   {2, 4},
                   {5, 4},
                   {5, 6},
                   {4, 6},
                   {4, 5},
                   {3, 5},
                   {3, 7},
                   {7, 7},
                   {7, 1},
                   {0, 1}});
    out.push_back({{0, 0}, {3, 0}, {3, 3}, {6, 3}, {6, 0}, {9, 0}, {9, 6}, {6, 6}, {3, 6}, {0, 6}});
    out.push_back({{0, 0}, {4, 2}, {8, 0}, {8, 8}, {4, 6}, {0, 8}});
    return out;
}

inline std::vector<IPoint> reversed(std::vector<IPoint> p) {
    std::reverse(p.begin(), p.end());
    return p;
}

}  // namespace textbook_test
