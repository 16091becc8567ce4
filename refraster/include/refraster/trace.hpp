// trace.hpp: every decision the reference makes about one pixel, for `refraster explain`.
//
// Implements: PixelTrace, filled by render() when RenderOptions::trace is set: for each
// primitive that reaches the pixel's neighbourhood, its clip-space input, clip masks, the
// clipper's output polygon, each triangle handed to setup (window coordinates, snapped
// fixed-point vertices, area and orientation, the three edge functions with their value at
// the pixel and the tie decisions) and whether it covered the pixel; finally the bytes written.
//
// Deliberately does not: format anything (the harness prints it), or cost anything when no
// trace is requested (the pipeline is then compiled with NoObserver, refraster/src/observer.hpp,
// whose hooks are empty; TraceObserver fills this record).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace refraster {

struct EdgeTrace {
    std::int32_t a = 0;  // Y_i - Y_{i+1}
    std::int32_t b = 0;  // X_i - X_{i+1}
    std::int64_t c = 0;  // with the tie bias
    bool owns_ties = false;
    // E at the pixel (at the traced sample when the draw multisamples), bias included:
    // covered needs > 0 on all edges.
    std::int64_t value = 0;
    bool tie = false;  // the pixel centre (sample) lies exactly on this edge (E minus bias is 0)
};

// What the fragment stage did at the pixel.
// What the sampler decided for a textured fragment (docs/precision.md, "Textures").
struct TextureTrace {
    bool aos = true;               // the 8-bit path (else the float path)
    std::array<float, 2> coord{};  // (s, t) as sampled, after the division by q
    bool point_coord = false;      // (s, t) are point sprite coordinates (no division by q)
    // The quad's differences in base-level texels: W*ds/dx, H*dt/dx, W*ds/dy, H*dt/dy.
    std::array<float, 4> rho_terms{};
    float rho2 = 0.0f;         // the larger of the two squared lengths
    bool minified = false;     // the min filter applies (rho2 > 1), else the mag filter
    float lod = 0.0f;          // trilinear: the approximate log2 of rho; otherwise 0
    std::uint32_t level0 = 0;  // the level read (the first of two, trilinear)
    std::uint32_t level1 = 0;
    float level_weight = 0.0f;        // trilinear: the float fraction between the levels
    std::uint32_t level_weight8 = 0;  // the 8-bit path's trunc(fraction * 256)
    bool linear = false;              // the image filter used: bilinear (else nearest)
    // Per level read: texel columns and rows x0, x1, y0, y1 after wrapping (nearest: x0, y0),
    // the weights along s and t (8-bit path: in 1/256; float path: floats), and which of the
    // texels (x0,y0) (x1,y0) (x0,y1) (x1,y1) read the border colour.
    std::array<std::array<std::int32_t, 4>, 2> texels{};
    std::array<std::array<float, 2>, 2> weights{};
    std::array<std::array<bool, 4>, 2> border{};
    std::array<float, 4> color{};  // what the shader receives
};

struct FragmentTrace {
    std::array<float, 3> z_plane{};  // A0, dz/dx, dz/dy (A0 at the centre of pixel (0, 0))
    std::array<float, 3> w_plane{};  // the same for 1/w
    float z_offset = 0.0f;           // polygon offset added to z
    float z = 0.0f;                  // z after offset and clamp
    bool depth_tested = false;
    std::uint32_t depth_value = 0;   // quantised (z32f: the float's bits)
    std::uint32_t depth_stored = 0;  // what the depth buffer held
    bool depth_pass = true;
    std::array<float, 4> shader_color{};  // the interpolated colour
    std::array<float, 4> destination{};   // the framebuffer before this fragment
    std::array<float, 4> written{};       // after conversion and blending
    bool textured = false;
    TextureTrace texture;  // when textured; shader_color is then the textured colour
};

struct SetupTrace {
    std::vector<std::array<float, 4>> window;  // x, y, z, 1/w in setup's input order
    bool clipped = false;                      // made by the clipper
    std::string outcome;  // "drawn", "zero area", "culled (back)", "culled by draw module", ...
    int subpixel_bits = 8;
    std::vector<std::int32_t> x;  // snapped corners (triangles: after the orientation swap)
    std::vector<std::int32_t> y;
    std::array<int, 3> order{0, 1, 2};
    std::int64_t area = 0;
    bool front_facing = true;
    std::vector<EdgeTrace> edges;  // 3 for triangles, 4 for lines and points
    bool covered = false;
    std::string coverage_note;  // a rule besides the edges that decided coverage, if any
    bool has_fragment = false;
    FragmentTrace fragment;  // when covered
};

struct PrimitiveTrace {
    std::size_t draw = 0;
    std::size_t primitive = 0;            // index of the assembled primitive within its draw
    std::string kind = "triangle";        // "triangle", "line", "point"
    std::vector<std::uint32_t> vertices;  // vertex indices, in setup order
    std::vector<std::array<float, 4>> clip;
    std::vector<std::uint32_t> clipmask;
    bool in_draw_pipeline = false;  // its vertex segment needed clipping
    std::vector<std::vector<std::array<float, 4>>> clipped_polygon;  // clip-space, if clipped
    std::vector<SetupTrace> setups;
    std::string note;
    bool covered = false;
    bool multisample = false;  // coverage tested at the traced sample, not the pixel centre
};

struct PixelTrace {
    int x = 0;
    int y = 0;
    // The sample traced on a 4x target (0..3): edge values, coverage, depth and the bytes
    // written are that sample's; colour is shaded once for the pixel. 0 otherwise.
    int sample = 0;
    std::string profile;
    std::vector<PrimitiveTrace> primitives;
    std::array<float, 4> final_color{};  // as stored (rgba8 targets: byte values)
};

}  // namespace refraster
