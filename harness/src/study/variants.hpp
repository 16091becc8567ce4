// variants.hpp: the rule variants `refraster study precision` and `stability` compare, as
// small scalar kernels, and the exact answers they are measured against.
//
// Implements: a triangle in float32 clip space (position, one attribute, depth) taken to window
// space and rasterized under one of these coverage rules:
// - Snapped<b>: float32 window coordinates (x * (1/w), then the viewport's scale and offset, as
//   Mesa's draw module computes them) rounded to the nearest multiple of 2^-b pixel (ties to
//   even), integer edge functions, GL's tie rule for centres on an edge (left and bottom edges
//   own them); b from 4 to 16;
// - Float<T>: no snapping; window coordinates and edge functions in float32 or float64, the
//   same tie rule applied to an edge function of exactly zero;
// - Exact: the exact oracle (the `gl-exact` profile's predicates on the float32 clip-space
//   inputs, refraster/src/models/exact/exact_coverage.hpp).
// Attributes are interpolated perspective-correctly from planes of a/w and 1/w over the
// unsnapped window coordinates, in float32 for the snapped and float32 rules and float64 for
// the float64 rule, fused (fma) or unfused; depth (window z, linear in window space) comes from
// a plane in the same arithmetic and is stored as z16, z24 (round to nearest, as GL's
// conversion of a normalised value) or z32f (the float32 value). The exact rule's attribute
// and depth are the oracle's: the centre's homogeneous weights in wide integers, rounded once.
//
// Every kernel evaluates each edge function and plane directly at each pixel centre of the
// triangle's bounding box, with no incremental stepping, so that kernel times compare the
// arithmetic and not the traversal.
//
// Deliberately does not: clip (workloads keep every vertex inside the view volume, except the
// stability sweeps that clip against the near plane themselves), cull, or model any driver's
// order of floating-point operations beyond the window transform (the bit-exact models are the
// profiles of refraster/; these kernels are the textbook forms the study compares).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "models/exact/exact_coverage.hpp"
#include "refraster/assert.hpp"
#include "refraster/draw.hpp"

namespace harness::study {

// Workload inputs are float32 values, as GL's are; they are held in double so that a clipper
// working in double can hand its vertices on without rounding them (the float32 kernels round
// every input to float32 first, which leaves a float32 value unchanged).
struct ClipVertex {
    std::array<double, 4> position{0.0, 0.0, 0.0, 1.0};  // clip space x, y, z, w
    double attribute = 0.0;                              // one interpolated scalar
};
using ClipTriangle = std::array<ClipVertex, 3>;

struct Viewport {
    int width = 256;
    int height = 256;
};

enum class CoverageRule : std::uint8_t { Snapped, Float32, Float64, Exact };
enum class DepthFormat : std::uint8_t { Z16, Z24, Z32F };

struct Variant {
    CoverageRule coverage = CoverageRule::Snapped;
    int subpixel_bits = 8;  // Snapped only
    bool fused = true;      // fma in the plane evaluation (not the Exact rule)
    DepthFormat depth = DepthFormat::Z24;

    std::string coverage_name() const;       // "snap-8", "float32", "float64", "exact"
    std::string interpolation_name() const;  // "fused", "unfused", "exact"
    std::string depth_name() const;          // "z16", "z24", "z32f"
    std::string name() const;                // "snap-8/fused/z24"
};

// The sub-pixel precisions the study sweeps. 16 bits at the largest viewport (2^14 pixels)
// puts snapped coordinates below 2^30 and edge-function products below 2^62: the kernels use
// 128-bit products, so no variant overflows.
inline constexpr std::array<int, 6> kSubpixelBits{4, 6, 8, 10, 12, 16};
inline constexpr int kMaxViewportBits = 14;  // GL_MAX_VIEWPORT_DIMS of Mesa's drivers: 16384
static_assert(kMaxViewportBits + 16 + 1 < 63, "snapped coordinates and their differences");
static_assert(2 * (kMaxViewportBits + 16 + 2) + 1 < 127, "edge-function products in 128 bits");

// Every variant of the precision study, in a stable order: the snapped and float rules with
// fused and unfused interpolation and each depth format, then the exact rule per depth format.
std::vector<Variant> all_variants();

// A pixel a triangle covers, with its interpolated attribute and stored depth.
struct Fragment {
    std::int32_t x = 0;
    std::int32_t y = 0;
    double attribute = 0.0;
    double depth = 0.0;  // the stored value: z16/z24 as integers, z32f as the float
};

// The exact answer at a pixel centre: the oracle's coverage, attribute and window depth.
struct ExactFragment {
    std::int32_t x = 0;
    std::int32_t y = 0;
    double attribute = 0.0;
    double depth = 0.0;  // window z in [0, 1], unquantised
};

// The exact oracle for one triangle in a viewport at the origin: the covered centres in
// row-major order (y, then x). Degenerate triangles cover nothing.
std::vector<ExactFragment> exact_fragments(const ClipTriangle& t, const Viewport& vp);

// The triangle clipped against the planes -g w <= x, y <= g w (g = 1: the view volume; g = 2:
// a guard band), as a fan of triangles, with Sutherland-Hodgman and the intersection of Mesa's
// clipper (draw_pipe_clip.c: from the outside vertex, t = d_out / (d_out - d_in)), in float32
// for the snapped and float32 rules and float64 for the float64 rule. The exact rule needs no
// clipper (the oracle clips exactly); it gets the triangle back unchanged. Only the x and y
// planes: the sweeps that clip keep z = 0, between the near and far planes wherever w > 0, and
// the x and y planes alone already remove every part with w <= 0.
// `from_outside` false interpolates each crossing edge in polygon order instead
// (v = v_a + t (v_b - v_a), t = d_a / (d_a - d_b)): the textbook form, which the stability study
// shows breaking down as w -> 0 from below.
std::vector<ClipTriangle> clip_triangle(const Variant& v, const ClipTriangle& t, double g,
                                        bool from_outside = true);

// One triangle through a variant: covered pixels in row-major order with their values.
// `out` is cleared first. The Exact rule runs the oracle and stores its values quantised.
void rasterize(const Variant& v, const ClipTriangle& t, const Viewport& vp,
               std::vector<Fragment>& out);

// The variant's attribute and stored depth at the centres the oracle covers, whether or not
// the variant covers them: one value per element of `at`, all nullopt where the variant's setup
// has no plane (a triangle of zero area in its arithmetic).
struct PlaneValues {
    double attribute = 0.0;
    double depth = 0.0;
};
std::vector<std::optional<PlaneValues>> evaluate_at(const Variant& v, const ClipTriangle& t,
                                                    const Viewport& vp,
                                                    const std::vector<ExactFragment>& at);

// A window depth in [0, 1] stored in a depth format, in double (z16 and z24: the integer).
double quantise_depth(DepthFormat f, double z);
// The distance between a value and the exact one in float32 units in the last place of the
// exact value (the attribute a GL implementation stores is a float32); exact values below 2^-8
// in magnitude are measured in the ulps of 2^-8.
double float32_ulps(double value, double exact);

}  // namespace harness::study
