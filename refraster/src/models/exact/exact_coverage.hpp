// exact_coverage.hpp: the coverage oracle: which pixel centres a triangle covers, decided
// exactly from its float32 clip-space vertices, with no snapping and no clipper.
//
// Implements homogeneous rasterization with exact predicates. With v_i = (x_i, y_i, w_i) and
// a pixel centre's NDC point p = (X, Y, 1), the weights b = M^-1 p of M = [v0 v1 v2] place
// the point on the triangle; the centre is covered iff every b_i > 0 (the point lies inside
// and in front, w > 0), it is inside the viewport and draw region, and the interpolated depth
// satisfies -w <= z <= w (the near and far clip planes). A b_i of exactly zero is decided by
// the tie rule in GL window terms. All arithmetic is on integers: every float32 is an
// integer multiple of 2^-149, and pixel centres are scaled by the viewport size, so every
// predicate is the sign of an integer polynomial, evaluated in wide integers.
//
// Deliberately does not: model any driver's rounding (that is what it is the oracle for), or
// handle degenerate triangles (det M = 0) otherwise than by drawing nothing.
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "refraster/draw.hpp"
#include "refraster/profile.hpp"
#include "stages/edge_rules.hpp"

namespace refraster::detail {

struct ExactTriangle;

class ExactCoverage {
  public:
    // `clip` are the three clip-space positions in assembly order.
    ExactCoverage(const std::array<std::array<float, 4>, 3>& clip, const DrawState& state,
                  PixelRect draw_region, TieRule tie_rule);
    ~ExactCoverage();
    ExactCoverage(const ExactCoverage&) = delete;
    ExactCoverage& operator=(const ExactCoverage&) = delete;

    bool degenerate() const;
    bool front_facing() const;  // GL: counter-clockwise in window space is front for ccw
    // Pixels worth testing: the region, narrowed to the projected box when all w > 0.
    PixelRect candidates() const;
    bool covers(int px, int py) const;
    // For traces: the sign of each b_i at the pixel (-1, 0, +1, relative to det) and whether
    // the tie rule owns edge i.
    std::array<int, 3> weight_signs(int px, int py) const;
    std::array<bool, 3> owns_ties() const;
    // The homogeneous weights b of the pixel centre (sum b_i w_i = 1): sum b_i v_i is the
    // centre's clip-space point with w = 1, on the ray through the triangle's point whose
    // clip-space barycentric weights are b / sum b. So the NDC depth is sum b_i z_i, a
    // perspective-correct attribute sum b_i a_i / sum b_i, a noperspective one sum b_i w_i a_i.
    std::array<double, 3> weights(int px, int py) const;

  private:
    std::unique_ptr<ExactTriangle> t_;
};

}  // namespace refraster::detail
