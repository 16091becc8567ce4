// profile.hpp: every rasterization rule the reference follows, as data.
//
// Implements: Profile, in three parts kept apart: the model that draws (llvmpipe 22.3's
// snapped setup and traversal, softpipe 22.3's scanline setup, or the exact oracle), the general GL
// rules, the parameters in which the GL specification leaves implementations free and one
// implementation differs from another (subpixel precision, snapping rounding, pixel-centre offset,
// the tie rule, the clipper, FMA and denormal behaviour), and the quirks of the model's driver
// beyond those rules (Mesa draw-module and llvmpipe behaviour); the built-in profiles
// `llvmpipe-22.3`, `softpipe-22.3` and `gl-exact`; reading and writing single parameters as text
// (`tie_rule=right-top`), one flat list of keys over all three parts, so that profiles can be
// stored and overridden from the outside.
//
// Deliberately does not: parse files (the harness reads profile JSON through these setters),
// or describe rules not implemented yet (attribute, depth, line and point rules arrive with
// their implementations).
//
// The meaning and evidence of every parameter: docs/precision.md.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "refraster/error.hpp"
#include "refraster/fixed.hpp"

namespace refraster {

// The model: how coverage is decided, and so which setup, traversal and fragment code runs.
enum class CoverageModel : std::uint8_t {
    Snapped,   // llvmpipe 22.3: window coordinates snapped to a subpixel grid, integer edge
               // functions
    Exact,     // the oracle: exact predicates on the float32 clip-space inputs, no snapping, no
               // clipper
    Scanline,  // softpipe 22.3: float window coordinates, a scanline walk of truncated spans,
               // Bresenham lines, attribute planes evaluated a 2x2 quad at a time
};

// Which edges own a pixel centre lying exactly on them, in GL window terms (y up).
// The first word names the owned non-horizontal edges (left: the interior is to the edge's
// right), the second the owned horizontal edges (bottom: the interior is above).
// Two more rules break GL's requirement that a centre on an edge shared by two polygons belongs
// to exactly one of them (14.6.1), and exist to show and test what that looks like: None (no edge
// owns its centres: holes along shared edges) and All (every edge does: double hits).
enum class TieRule : std::uint8_t { LeftBottom, LeftTop, RightBottom, RightTop, None, All };

// Which x/y clip test decides that a triangle goes to the clipper.
enum class Clipping : std::uint8_t {
    ViewVolume,  // |x|, |y| <= w (llvmpipe with a depth buffer, OSMesa, FBOs)
    GuardBand,   // |x|, |y| <= 2w, the viewport then applied as a scissor (draw's guard band)
};

// How points and lines (and polygons drawn in polygon mode point or line) are clipped in x and
// y. OpenGL 4.6, 13.7 clips them by their vertices against the view volume: a point whose
// centre is outside is dropped whole, and the pixels of a wide point or line kept may lie
// beyond the viewport. Vulkan (and GL on Vulkan) clips them by the pixels they light instead:
// the vertices pass a guard band and the viewport limits the pixels (Mesa's draw module:
// guard_band_points_lines_xy, set by the rasterizer state's point_line_tri_clip).
enum class PointLineClipping : std::uint8_t {
    Vertices,  // as the `clipping` rule for triangles (GL's rule)
    Pixels,    // the guard band test, the viewport then applied as a scissor
};

// How a value becomes an integer where the specification leaves it free (OpenGL 4.6, 2.3.5:
// "rounded to the nearest", which implementations read as round-to-nearest or truncation).
enum class Rounding : std::uint8_t { Nearest, Truncate };

// How glClearDepth's value is quantised for z16 and z24: RNE(z * (2^n - 1)) computed in double
// (util_pack_z, both Mesa drivers) or in float.
enum class ClearPrecision : std::uint8_t { Double, Float };

// Which pixels a line lights (OpenGL 4.6, 14.5.1 leaves the exact set free within the
// diamond-exit tolerance): llvmpipe's snapped parallelogram with its diamond-exit end tests
// (lp_setup_line.c, integer-rounded widths), or softpipe's Bresenham walk of the truncated
// end points with wide lines as the draw module's two triangles (sp_setup.c,
// draw_pipe_wide_line.c).
enum class LineRule : std::uint8_t { Parallelogram, Bresenham };

// Which pixels a point lights (14.4 leaves non-antialiased point coverage to the square's
// centre test): llvmpipe's snapped square tested like a triangle (lp_setup_point.c), or the
// draw module's two sprite triangles with their 1/8-pixel bias, drawn by softpipe's scanline
// rules (draw_pipe_wide_point.c).
enum class PointRule : std::uint8_t { Square, TwoTriangles };

// The scale factor rho of a quad's texture LOD (OpenGL 4.6, 8.14.1: rho may be approximated by
// any function between the largest partial derivative and the sum of their magnitudes):
// llvmpipe's default, sqrt of the larger of the two squared gradient lengths (computed as half
// the log2 of its square), or the approximation GALLIVM_PERF=rho_approx selects, the largest
// absolute partial derivative (lp_bld_sample.c, lp_build_rho and lp_build_lod_selector).
enum class TextureRho : std::uint8_t { Exact, Approx };

// How LINEAR_MIPMAP_LINEAR blends its two levels: by frac(lambda) (OpenGL 4.6, 8.14.3), or
// llvmpipe's brilinear approximation under GALLIVM_PERF=brilinear, whose lambda is a
// piecewise-linear log2 within a quarter level of the true one: only the base level where
// lambda is within a quarter of an integer (lp_bld_sample.c, lp_build_brilinear_lod and
// lp_build_brilinear_rho, BRILINEAR_FACTOR 2). 8.14.1 bounds rho's approximations, and
// brilinear's effective rho falls below the lower bound: the rule search calls it a violation.
enum class MipBlend : std::uint8_t { Linear, Brilinear };

// The arithmetic of texture filtering (OpenGL 4.6, 8.14.2 and 8.14.3 give the weights; 2.3.4.1
// leaves their precision to the implementation). llvmpipe by default filters rgba8 textures
// whose wraps are both REPEAT or CLAMP_TO_EDGE in 8-bit fixed point, weights and the mip
// fraction quantised to 1/256 (lp_bld_sample_aos.c), and every other texture in float
// (lp_bld_sample_soa.c); GALLIVM_PERF=no_aos_sampling takes the float path for all
// (lp_bld_sample_soa.c, lp_build_sample_soa_code's use_aos), glGenerateMipmap's blit included.
enum class TextureFiltering : std::uint8_t { FixedPoint, Float };

enum class FmaMode : std::uint8_t {
    Auto,  // fuse where the reproduced driver fuses iff this CPU has FMA (as gallivm decides)
    On,
    Off,
};

// The general GL rules: where the specification leaves an implementation free.
struct GlRules {
    // Snapped coverage: window coordinates become Fixed<subpixel_bits>, rounded by
    // `snap_rounding` after subtracting `pixel_center_offset`.
    int subpixel_bits = 8;
    SnapRounding snap_rounding = SnapRounding::NearestEven;
    float pixel_center_offset = 0.5f;

    TieRule tie_rule = TieRule::LeftBottom;

    Clipping clipping = Clipping::ViewVolume;
    // Points and lines: by their vertices (as `clipping` says) or by their pixels.
    PointLineClipping point_line_clipping = PointLineClipping::Vertices;

    // The viewport transform of unclipped vertices: fma(x * (1/w), scale, translate).
    FmaMode viewport_fma = FmaMode::Auto;
    // Flush denormal results and inputs to zero in the vertex pipeline (Mesa sets FTZ/DAZ
    // around draw and rasterization).
    bool flush_denormals = true;

    // Fragment depth into z16 and z24 (after the model's clamp, if any) and fragment colour into
    // rgba8 (after the clamp): RNE(fl(v * (2^n - 1))) or its truncation.
    Rounding depth_rounding = Rounding::Nearest;
    Rounding color_rounding = Rounding::Nearest;
    ClearPrecision depth_clear = ClearPrecision::Double;
    // The line and point rules; a rule of the other model's family is drawn by that model
    // (its setup, planes and fragment stage) for those draws.
    LineRule line_rule = LineRule::Parallelogram;
    PointRule point_rule = PointRule::Square;
    // Polygon offset's minimum resolvable difference r as a multiple of Mesa's (OpenGL 4.6,
    // 14.6.5 leaves r to the implementation, as long as it is applied consistently): the units
    // term, units * 2 * mrd for z16 and z24 and units * 2^(e - 23) for z32f, is computed from
    // units * offset_units_scale. A power of two from 1/16 to 16, so the product is exact: zink
    // on lavapipe applies twice llvmpipe's term (docs/precision.md, "Polygon offset").
    float offset_units_scale = 1.0f;
    // The texture LOD's scale factor rho (read by llvmpipe's sampler).
    TextureRho texture_rho = TextureRho::Exact;
    // How the two levels of LINEAR_MIPMAP_LINEAR blend (read by llvmpipe's sampler).
    MipBlend texture_mip_blend = MipBlend::Linear;
    // The filtering arithmetic (read by llvmpipe's sampler and its glGenerateMipmap).
    TextureFiltering texture_filtering = TextureFiltering::FixedPoint;

    friend bool operator==(const GlRules&, const GlRules&) = default;
};

// The snapped model's driver beyond GL's rules: Mesa 22.3's draw module and llvmpipe.
struct DriverQuirks {
    // Mesa's draw module: triangles of a vertex segment in which any vertex needs clipping
    // go through the draw pipeline, whose cull stage culls in float before setup culls in
    // fixed point. Segments hold `draw_segment_vertices` vertices.
    bool draw_pipeline_cull = true;
    int draw_segment_vertices = 4096;
    // llvmpipe's lp_setup_analyse_triangles: a non-indexed draw of exactly 9 smooth-shaded
    // triangle vertices whose last triangle has three equal window y values draws nothing.
    bool nine_vertex_quirk = true;
    // llvmpipe's integer widths where they change the pixels: a window position that is not
    // finite or leaves the 24.8 range converts to 0x80000000 (cvtps2dq) and setup and the
    // tile walk wrap in 32 bits (lp_setup_tri.c, lp_rast_tri_tmp.h); false refuses such a
    // triangle and walks in-range triangles exactly.
    bool wrapping_arithmetic = true;
    // Mesa's draw module, shared by both Mesa drivers: the polygon offset of polygon modes line
    // and point saturates each vertex's z with util/macros.h's CLAMP, which turns a NaN (the
    // offset of a zero-area triangle) into 0, the near end; false keeps the NaN, which the
    // fragment's clamp then makes 1 (lp_build_depth_clamp).
    bool draw_offset_nan_to_zero = true;
    // softpipe, under the scanline model: a draw with a fill rule starts with a clear of the
    // stencil alone, which writes softpipe's colour tile cache back (sp_clear.c); false keeps
    // the tiles' float colours across it.
    bool fill_clear_writes_tiles = true;

    friend bool operator==(const DriverQuirks&, const DriverQuirks&) = default;
};

struct Profile {
    std::string name = "llvmpipe-22.3";
    CoverageModel model = CoverageModel::Snapped;  // parameter key "coverage"
    GlRules gl;
    DriverQuirks quirks;

    friend bool operator==(const Profile&, const Profile&) = default;
};

// An unknown profile or parameter, or a value out of range: bad input.
class ProfileError : public Error {
  public:
    explicit ProfileError(const std::string& message) : Error(ExitClass::BadInput, message) {}
};

// The built-in profiles.
Profile llvmpipe_22_3_profile();
Profile gl_exact_profile();
Profile softpipe_22_3_profile();
// By name; throws ProfileError for an unknown name.
Profile builtin_profile(const std::string& name);
std::vector<std::string> builtin_profile_names();

// Every parameter as (key, value) text pairs, in a stable order: what a profile file holds.
std::vector<std::pair<std::string, std::string>> profile_parameters(const Profile& p);
// Sets one parameter from text; throws ProfileError naming the key and the accepted values.
void set_profile_parameter(Profile& p, const std::string& key, const std::string& value);

// Why no scene renders differently when `key` changes under this profile, or nullopt when some
// can: the model does not read it (the scanline model does not snap; the exact model has no
// clipper, snapping or conversion rules), or reads it only through a route this profile does
// not take (the scanline model reads tie_rule only for lines and points drawn by llvmpipe's
// rules, line_rule=parallelogram or point_rule=square), or does not model that value (the exact
// model has no tie_rule none or all). The table and its evidence: docs/precision.md, "What each
// model reads". "name" and "coverage" are always read.
std::optional<std::string> unread_parameter(const Profile& p, const std::string& key);

std::string to_string(TieRule r);
std::string to_string(SnapRounding r);
std::string to_string(Rounding r);
std::string to_string(TextureRho r);
std::string to_string(MipBlend b);
std::string to_string(TextureFiltering f);
std::string to_string(LineRule r);
std::string to_string(PointRule r);

}  // namespace refraster
