// snap.hpp: the one rounding the exact textbook algorithms apply to their double inputs.
//
// Implements: snap(), a coordinate in pixels to an integer count of 1/256 pixel (GL's 8
// sub-pixel bits), rounded to nearest with halves away from zero, and the bit budget that
// every exact predicate built on snapped values relies on.
//
// Deliberately does not: accept coordinates beyond kMaxCoordinate (a precondition, asserted),
// so that products of two differences of snapped values stay far inside int64.
#pragma once

#include <cmath>
#include <cstdint>

#include "refraster/assert.hpp"

namespace refraster::textbook::detail {

__extension__ using Int128 = __int128;

inline constexpr int kSnapBits = 8;
inline constexpr std::int64_t kSnapOne = std::int64_t{1} << kSnapBits;
// |coordinate| <= 2^14 pixels, so a snapped value is below 2^22 in magnitude, a difference of
// two below 2^23, an edge function (two products of differences) below 2^47.
inline constexpr int kMaxCoordinateBits = 14;
inline constexpr double kMaxCoordinate = static_cast<double>(1 << kMaxCoordinateBits);
inline constexpr int kSnappedBits = kMaxCoordinateBits + kSnapBits;
static_assert(2 * (kSnappedBits + 1) + 1 < 63, "an edge function of snapped values fits int64");

inline std::int64_t snap(double v) {
    REFRASTER_ASSERT(std::isfinite(v) && std::fabs(v) <= kMaxCoordinate,
                     "a textbook coordinate within 2^14 pixels");
    return static_cast<std::int64_t>(std::llround(v * static_cast<double>(kSnapOne)));
}

inline double unsnap(std::int64_t v) {
    return static_cast<double>(v) / static_cast<double>(kSnapOne);
}

struct SnappedPoint {
    std::int64_t x = 0;
    std::int64_t y = 0;
    friend bool operator==(const SnappedPoint&, const SnappedPoint&) = default;
};

// Twice the signed area of (a, b, c): positive when counter-clockwise (y up). Below 2^47.
inline std::int64_t orient(SnappedPoint a, SnappedPoint b, SnappedPoint c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Floor division for a positive divisor.
inline std::int64_t floor_div(std::int64_t a, std::int64_t b) {
    REFRASTER_ASSERT(b > 0, "a positive divisor");
    std::int64_t q = a / b;
    if ((a % b) != 0 && a < 0) --q;
    return q;
}

}  // namespace refraster::textbook::detail
