// softpipe_sampler.cpp: softpipe's 2D texture sampling (softpipe_sampler.hpp).
//
// Every float operation rounds once, in the order written (the project compiles with
// -ffp-contract=off); the comments name the Mesa 22.3 function whose order each reproduces.
#include "models/softpipe/softpipe_sampler.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <utility>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "refraster/assert.hpp"

namespace refraster::detail {

namespace {

constexpr std::int32_t kTileSize = 32;      // sp_tex_tile_cache.h TEX_TILE_SIZE
constexpr std::uint32_t kTileEntries = 16;  // NUM_TEX_TILE_ENTRIES

// util/macros.h CLAMP(x, lo, hi): x > lo ? (x > hi ? hi : x) : lo, so NaN gives lo.
float clamp_as_mesa(float x, float lo, float hi) {
    return x > lo ? (x > hi ? hi : x) : lo;
}

// util/macros.h MAX2(a, b): a > b ? a : b.
float max2(float a, float b) {
    return a > b ? a : b;
}

// util/u_math.h util_ifloor, the variant built for x86-64: the sums 12582912.5 + f and
// 12582912.5 - f in double, each rounded to float, and half the difference of the two
// floats' bit patterns (wrapping as the C int subtraction does on x86). That is floor(f) for
// |f| < 2^22 and its own value beyond.
std::int32_t util_ifloor(float f) {
    constexpr double kBias = 12582912.5;  // (3 << 22) + 0.5
    const auto up = static_cast<float>(kBias + static_cast<double>(f));
    const auto down = static_cast<float>(kBias - static_cast<double>(f));
    const std::uint32_t diff =
        std::bit_cast<std::uint32_t>(up) - std::bit_cast<std::uint32_t>(down);
    return static_cast<std::int32_t>(diff) >> 1;
}

// sp_tex_sample.c frac: f - floorf(f).
float frac(float f) {
    return f - std::floor(f);
}

// sp_tex_sample.c lerp: v0 + a * (v1 - v0).
float lerp(float a, float v0, float v1) {
    return v0 + a * (v1 - v0);
}

// sp_tex_sample.c lerp_2d: the two rows at weight a, then between them at weight b.
float lerp_2d(float a, float b, float v00, float v10, float v01, float v11) {
    const float bottom = lerp(a, v00, v10);
    const float top = lerp(a, v01, v11);
    return lerp(b, bottom, top);
}

// sp_tex_sample.c repeat: (coord + size * 1024) % size with coord converted to unsigned, so a
// coordinate below -1024 * size lands on another texel than a true modulo gives.
std::int32_t repeat(std::int32_t coord, std::uint32_t size) {
    return static_cast<std::int32_t>((static_cast<std::uint32_t>(coord) + size * 1024u) % size);
}

// util/u_math.h util_fast_log2: the float's unbiased exponent plus log2_table[k], k the top
// 8 mantissa bits rounded (a 257-entry table of (float)log2(1 + k/256) made in double,
// util/u_math.c init_log2_table); added in float.
float util_fast_log2(float x) {
    static const std::array<float, 257> table = [] {
        std::array<float, 257> t{};
        for (std::size_t k = 0; k < t.size(); ++k)
            t[k] = static_cast<float>(std::log2(1.0 + static_cast<double>(k) * (1.0 / 256.0)));
        return t;
    }();
    const auto bits = std::bit_cast<std::uint32_t>(x);
    const auto exponent =
        static_cast<float>(static_cast<std::int32_t>((bits & 0x7f800000u) >> 23) - 127);
    const float mantissa = table[((bits & 0x007fffffu) + (1u << 14)) >> 15];
    return exponent + mantissa;
}

// util/u_math.h float_to_ubyte: 0 for NaN and values <= 0, 255 from 1 on, otherwise the low
// byte of fl(fl(f * 255/256) + 32768), which is fl(f * 255) rounded to nearest, ties to even.
std::uint8_t float_to_ubyte(float f) {
    if (!(f > 0.0f)) return 0;
    if (f >= 1.0f) return 255;
    const float biased = f * (255.0f / 256.0f) + 32768.0f;
    return static_cast<std::uint8_t>(std::bit_cast<std::uint32_t>(biased) & 0xffu);
}

// The R8G8B8A8_UNORM unpack that fills the texture tile cache (u_tile.c pipe_get_tile_rgba,
// util_format_read_4; generated from util/format/u_format_pack.py): (float)b * (1.0f/0xff).
std::vector<float> texels_as_floats(const TextureImage& image) {
    std::vector<float> out(image.rgba.size());
    constexpr float kScale = 1.0f / 255.0f;
    for (std::size_t i = 0; i < image.rgba.size(); ++i)
        out[i] = static_cast<float>(image.rgba[i]) * kScale;
    return out;
}

bool is_pot(std::uint32_t v) {
    return v != 0 && (v & (v - 1)) == 0;
}

// One level as the filters read it.
struct LevelRef {
    const float* texels = nullptr;  // width * height RGBA, row 0 first
    std::int32_t width = 1;
    std::int32_t height = 1;
    std::uint32_t index = 0;  // the level number: the tile cache's entry depends on it
};

const float* texel_at(const LevelRef& l, std::int32_t x, std::int32_t y) {
    return l.texels + (static_cast<std::size_t>(y) * static_cast<std::size_t>(l.width) +
                       static_cast<std::size_t>(x)) *
                          4;
}

// ---------------------------------------------------------------------------------------
// Wraps (sp_tex_sample.c wrap_nearest_* and wrap_linear_*, texel offset 0; adding the zero
// offset only turns -0 into +0, which no result depends on).

std::int32_t wrap_nearest(TextureWrap wrap, float s, std::uint32_t size) {
    const auto fsize = static_cast<float>(size);
    const auto last = static_cast<std::int32_t>(size) - 1;
    switch (wrap) {
        case TextureWrap::Repeat:  // wrap_nearest_repeat
            return repeat(util_ifloor(s * fsize), size);
        case TextureWrap::ClampToEdge: {  // wrap_nearest_clamp_to_edge
            const float max = fsize - 0.5f;
            const float u = s * fsize;
            if (u < 0.5f) return 0;
            if (u > max) return last;
            return util_ifloor(u);
        }
        case TextureWrap::ClampToBorder: {  // wrap_nearest_clamp_to_border
            const float max = fsize + 0.5f;
            const float u = s * fsize;
            if (u <= -0.5f) return -1;
            if (u >= max) return last + 1;
            return util_ifloor(u);
        }
        case TextureWrap::MirroredRepeat: {  // wrap_nearest_mirror_repeat
            const float min = 1.0f / (2.0f * fsize);
            const float max = 1.0f - min;
            const std::int32_t flr = util_ifloor(s);
            float u = frac(s);
            if ((flr & 1) != 0) u = 1.0f - u;
            if (u < min) return 0;
            if (u > max) return last;
            return util_ifloor(u * fsize);
        }
    }
    return 0;
}

struct LinearAxis {
    std::int32_t i0 = 0;
    std::int32_t i1 = 0;
    float w = 0.0f;  // the weight of i1
};

LinearAxis wrap_linear(TextureWrap wrap, float s, std::uint32_t size) {
    const auto fsize = static_cast<float>(size);
    const auto isize = static_cast<std::int32_t>(size);
    LinearAxis a;
    switch (wrap) {
        case TextureWrap::Repeat: {  // wrap_linear_repeat
            const float u = s * fsize - 0.5f;
            a.i0 = repeat(util_ifloor(u), size);
            a.i1 = repeat(a.i0 + 1, size);
            a.w = frac(u);
            break;
        }
        case TextureWrap::ClampToEdge: {  // wrap_linear_clamp_to_edge
            const float u = clamp_as_mesa(s * fsize, 0.0f, fsize) - 0.5f;
            a.i0 = util_ifloor(u);
            a.i1 = a.i0 + 1;
            if (a.i0 < 0) a.i0 = 0;
            if (a.i1 >= isize) a.i1 = isize - 1;
            a.w = frac(u);
            break;
        }
        case TextureWrap::ClampToBorder: {  // wrap_linear_clamp_to_border
            const float u = clamp_as_mesa(s * fsize, -1.0f, fsize + 0.5f) - 0.5f;
            a.i0 = util_ifloor(u);
            a.i1 = a.i0 + 1;
            a.w = frac(u);
            break;
        }
        case TextureWrap::MirroredRepeat: {  // wrap_linear_mirror_repeat
            const std::int32_t flr = util_ifloor(s);
            const bool forward = (flr & 1) == 0;
            float u = frac(s);
            if (forward) {
                u = u * fsize - 0.5f;
            } else {
                u = 1.0f - u;
                u = u * fsize + 0.5f;
            }
            a.i0 = util_ifloor(u);
            a.i1 = forward ? a.i0 + 1 : a.i0 - 1;
            // The fix-ups in softpipe's order.
            if (a.i0 < 0) a.i0 = 1 + a.i0;
            if (a.i0 >= isize) a.i0 = isize - 1;
            if (a.i1 >= isize) a.i1 = isize - 1;
            if (a.i1 < 0) a.i1 = 1 + a.i1;
            a.w = forward ? frac(u) : frac(1.0f - u);
            break;
        }
    }
    return a;
}

// ---------------------------------------------------------------------------------------
// Texel fetches.

// get_texel_2d: the border colour for a texel outside the level, whatever the wrap.
const float* texel_or_border(const LevelRef& l, const float* border, std::int32_t x,
                             std::int32_t y) {
    if (x < 0 || x >= l.width || y < 0 || y >= l.height) return border;
    return texel_at(l, x, y);
}

// The four fetches of a bilinear sample, (x[0], y[0]) ... (x[3], y[3]), as pointers into
// softpipe's texture tile cache, read after the last fetch (img_filter_2d_linear,
// get_texel_quad_2d_no_border; sp_tex_tile_cache.c sp_find_cached_tile_tex, tex_cache_pos;
// u_tile.c pipe_get_tile_rgba, u_clip_tile). Fetch k's entry is
// (x/32 + 9*(y/32) + 7*level) % 16; a miss loads the tile's part inside the level into the
// entry, at the tile's offsets, and leaves the rest of the entry as it was. So pointer k shows,
// at its offset, the tile of the last fetch n >= k into the same entry whose loaded part
// covers the offset; fetch k's own tile covers it, and any tile loaded before fetch k into that
// entry has been overwritten there, so nothing older than the sample shows. Texels outside
// the level are the border colour and use no entry.
std::array<const float*, 4> fetch_quad(const LevelRef& l, const float* border,
                                       const std::array<std::int32_t, 4>& x,
                                       const std::array<std::int32_t, 4>& y) {
    std::array<bool, 4> inside{};
    std::array<std::uint32_t, 4> entry{};
    for (std::size_t k = 0; k < 4; ++k) {
        inside[k] = x[k] >= 0 && x[k] < l.width && y[k] >= 0 && y[k] < l.height;
        if (!inside[k]) continue;
        const auto tx = static_cast<std::uint32_t>(x[k] / kTileSize);
        const auto ty = static_cast<std::uint32_t>(y[k] / kTileSize);
        entry[k] = (tx + ty * 9u + l.index * 7u) % kTileEntries;
    }
    std::array<const float*, 4> out{};
    for (std::size_t k = 0; k < 4; ++k) {
        if (!inside[k]) {
            out[k] = border;
            continue;
        }
        const std::int32_t ox = x[k] % kTileSize;
        const std::int32_t oy = y[k] % kTileSize;
        std::size_t from = k;
        for (std::size_t n = 3; n > k; --n) {
            if (!inside[n] || entry[n] != entry[k]) continue;
            const std::int32_t tile_x = x[n] / kTileSize * kTileSize;
            const std::int32_t tile_y = y[n] / kTileSize * kTileSize;
            // The loaded part of fetch n's tile (u_clip_tile).
            if (ox < std::min(kTileSize, l.width - tile_x) &&
                oy < std::min(kTileSize, l.height - tile_y)) {
                from = n;
                break;
            }
        }
        out[k] =
            texel_at(l, x[from] / kTileSize * kTileSize + ox, y[from] / kTileSize * kTileSize + oy);
    }
    return out;
}

void bilinear(const std::array<const float*, 4>& tx, float xw, float yw, float* rgba) {
    for (std::size_t c = 0; c < 4; ++c)
        rgba[c] = lerp_2d(xw, yw, tx[0][c], tx[1][c], tx[2][c], tx[3][c]);
}

// bilinear for sample_quad_direct: the four channels as one vector, lane c lerp_2d's
// operations on channel c in its order (v0 + a * (v1 - v0) for each row, then between them).
void bilinear_direct(const std::array<const float*, 4>& tx, float xw, float yw, float* rgba) {
#if defined(__SSE2__)
    const __m128 a = _mm_set1_ps(xw);
    const __m128 t00 = _mm_loadu_ps(tx[0]);
    const __m128 t10 = _mm_loadu_ps(tx[1]);
    const __m128 t01 = _mm_loadu_ps(tx[2]);
    const __m128 t11 = _mm_loadu_ps(tx[3]);
    const __m128 bottom = _mm_add_ps(t00, _mm_mul_ps(a, _mm_sub_ps(t10, t00)));
    const __m128 top = _mm_add_ps(t01, _mm_mul_ps(a, _mm_sub_ps(t11, t01)));
    _mm_storeu_ps(rgba, _mm_add_ps(bottom, _mm_mul_ps(_mm_set1_ps(yw), _mm_sub_ps(top, bottom))));
#else
    bilinear(tx, xw, yw, rgba);
#endif
}

// img_filter_2d_linear with the wraps of the sampler.
void linear_generic(const LevelRef& l, TextureWrap wrap_s, TextureWrap wrap_t, const float* border,
                    float s, float t, float* rgba) {
    const LinearAxis u = wrap_linear(wrap_s, s, static_cast<std::uint32_t>(l.width));
    const LinearAxis v = wrap_linear(wrap_t, t, static_cast<std::uint32_t>(l.height));
    bilinear(fetch_quad(l, border, {u.i0, u.i1, u.i0, u.i1}, {v.i0, v.i0, v.i1, v.i1}), u.w, v.w,
             rgba);
}

// ---------------------------------------------------------------------------------------
// glGenerateMipmap (st_gen_mipmap.c, util_gen_mipmap: one pipe->blit per level with a linear
// filter; softpipe sends it to util_blitter_blit, u_blitter.c).

struct Plane {
    float a0 = 0.0f;
    float dadx = 0.0f;
    float dady = 0.0f;
};

// tgsi_exec.c eval_linear_coef: the quad at (qx, qy) takes (a0 + dadx*qx) + dady*qy, its
// pixels 1 and 2 that plus dadx or dady, pixel 3 (that + dadx) + dady.
float quad_value(const Plane& p, std::int32_t qx, std::int32_t qy, std::uint32_t k) {
    const float base = p.a0 + p.dadx * static_cast<float>(qx) + p.dady * static_cast<float>(qy);
    switch (k) {
        case 0:
            return base;
        case 1:
            return base + p.dadx;
        case 2:
            return base + p.dady;
        default:
            return base + p.dadx + p.dady;
    }
}

// A vertex of the blitter's rectangle: window x, y and texture s, t.
struct BlitVertex {
    float x = 0.0f;
    float y = 0.0f;
    float s = 0.0f;
    float t = 0.0f;
};

struct Edge {
    float dx = 0.0f;
    float dy = 0.0f;
    float dxdy = 0.0f;
    float sx = 0.0f;
    float sy = 0.0f;
    std::int32_t lines = 0;
};

// One triangle of the blitter's rectangle as softpipe sets it up and walks it in a width x
// height target (sp_setup.c setup_sort_vertices, setup_tri_edges, subtriangle,
// tri_linear_coeff; pixel centres at +0.5, no culling): `pixel(x, y, s, t)` for each pixel
// it covers, s and t its quad's linear interpolation.
template <class Pixel>
void blit_triangle(const std::array<BlitVertex, 3>& v, std::int32_t width, std::int32_t height,
                   Pixel&& pixel) {
    // setup_sort_vertices: bottom to top with <= comparisons.
    const float y0 = v[0].y;
    const float y1 = v[1].y;
    const float y2 = v[2].y;
    std::array<std::size_t, 3> o{};
    if (y0 <= y1) {
        if (y1 <= y2) {
            o = {0, 1, 2};
        } else if (y2 <= y0) {
            o = {2, 0, 1};
        } else {
            o = {0, 2, 1};
        }
    } else {
        if (y0 <= y2) {
            o = {1, 0, 2};
        } else if (y2 <= y1) {
            o = {2, 1, 0};
        } else {
            o = {1, 2, 0};
        }
    }
    const BlitVertex& vmin = v[o[0]];
    const BlitVertex& vmid = v[o[1]];
    const BlitVertex& vmax = v[o[2]];
    Edge ebot;
    Edge emaj;
    Edge etop;
    ebot.dx = vmid.x - vmin.x;
    ebot.dy = vmid.y - vmin.y;
    emaj.dx = vmax.x - vmin.x;
    emaj.dy = vmax.y - vmin.y;
    etop.dx = vmax.x - vmid.x;
    etop.dy = vmax.y - vmid.y;
    const float area = emaj.dx * ebot.dy - ebot.dx * emaj.dy;
    const float oneoverarea = 1.0f / area;
    if (!std::isfinite(oneoverarea)) return;

    // tri_linear_coeff on the sorted values.
    const auto plane = [&](float a_min, float a_mid, float a_max) {
        const float botda = a_mid - a_min;
        const float majda = a_max - a_min;
        const float a = ebot.dy * majda - botda * emaj.dy;
        const float b = emaj.dx * botda - majda * ebot.dx;
        Plane p;
        p.dadx = a * oneoverarea;
        p.dady = b * oneoverarea;
        p.a0 = a_min - (p.dadx * (vmin.x - 0.5f) + p.dady * (vmin.y - 0.5f));
        return p;
    };
    const Plane ps = plane(vmin.s, vmid.s, vmax.s);
    const Plane pt = plane(vmin.t, vmid.t, vmax.t);

    // setup_tri_edges.
    const float vmin_x = vmin.x + 0.5f;
    const float vmid_x = vmid.x + 0.5f;
    const float vmin_y = vmin.y - 0.5f;
    const float vmid_y = vmid.y - 0.5f;
    const float vmax_y = vmax.y - 0.5f;
    const auto start = [](Edge& e, float x, float y, float y_end) {
        e.sy = std::ceil(y);
        e.lines = static_cast<std::int32_t>(std::ceil(y_end - e.sy));
        e.dxdy = e.dy != 0.0f ? e.dx / e.dy : 0.0f;
        e.sx = x + (e.sy - y) * e.dxdy;
    };
    start(emaj, vmin_x, vmin_y, vmax_y);
    start(etop, vmid_x, vmid_y, vmax_y);
    start(ebot, vmin_x, vmin_y, vmid_y);

    // subtriangle: rows clipped to the target, spans [left, right) truncated.
    const auto walk = [&](Edge& left, Edge& right, std::int32_t lines) {
        const auto sy = static_cast<std::int32_t>(left.sy);
        const std::int32_t first = std::max(sy, 0) - sy;
        const std::int32_t end = std::min(sy + lines, height) - sy;
        for (std::int32_t r = first; r < end; ++r) {
            const auto fr = static_cast<float>(r);
            const std::int32_t x0 =
                std::max(static_cast<std::int32_t>(left.sx + fr * left.dxdy), 0);
            const std::int32_t x1 =
                std::min(static_cast<std::int32_t>(right.sx + fr * right.dxdy), width);
            const std::int32_t y = sy + r;
            for (std::int32_t x = x0; x < x1; ++x) {
                const std::int32_t qx = x & ~1;
                const std::int32_t qy = y & ~1;
                const auto k = static_cast<std::uint32_t>((x & 1) + 2 * (y & 1));
                pixel(x, y, quad_value(ps, qx, qy, k), quad_value(pt, qx, qy, k));
            }
        }
        const auto flines = static_cast<float>(lines);
        left.sx += flines * left.dxdy;
        right.sx += flines * right.dxdy;
        left.sy += flines;
        right.sy += flines;
    };
    if (oneoverarea < 0.0f) {
        walk(emaj, ebot, ebot.lines);
        walk(emaj, etop, etop.lines);
    } else {
        walk(ebot, emaj, ebot.lines);
        walk(etop, emaj, etop.lines);
    }
}

// Level `src`'s next level, width x height: the blitter's rectangle (0,0) (W,0) (W,H) (0,H)
// with texture coordinates (0,0) (1,0) (1,1) (0,1) (u_blitter.c get_texcoords: x / src_width)
// drawn as the fan's triangles (v0, v1, v2) then (v0, v2, v3) (sp_prim_vbuf.c), each pixel
// a linear, clamp-to-edge, non-mipmapped sample of `src` (mip_filter_none_no_filter_select,
// img_filter_2d_linear) stored with float_to_ubyte.
TextureImage blit_level(const LevelRef& src, std::uint32_t width, std::uint32_t height) {
    TextureImage dst;
    dst.width = width;
    dst.height = height;
    dst.rgba.assign(std::size_t{width} * height * 4, 0);
    const auto fw = static_cast<float>(width);
    const auto fh = static_cast<float>(height);
    const std::array<BlitVertex, 4> corner{{{0.0f, 0.0f, 0.0f, 0.0f},
                                            {fw, 0.0f, 1.0f, 0.0f},
                                            {fw, fh, 1.0f, 1.0f},
                                            {0.0f, fh, 0.0f, 1.0f}}};
    constexpr std::array<float, 4> kNoBorder{};
    const auto store = [&](std::int32_t x, std::int32_t y, float s, float t) {
        std::array<float, 4> c{};
        linear_generic(src, TextureWrap::ClampToEdge, TextureWrap::ClampToEdge, kNoBorder.data(), s,
                       t, c.data());
        const std::size_t i =
            (static_cast<std::size_t>(y) * width + static_cast<std::size_t>(x)) * 4;
        for (std::size_t ch = 0; ch < 4; ++ch) dst.rgba[i + ch] = float_to_ubyte(c[ch]);
    };
    const auto w = static_cast<std::int32_t>(width);
    const auto h = static_cast<std::int32_t>(height);
    blit_triangle({corner[0], corner[1], corner[2]}, w, h, store);
    blit_triangle({corner[0], corner[2], corner[3]}, w, h, store);
    return dst;
}

// sp_tex_sample.c compute_gradient_2d, compute_lambda_2d_explicit_gradients and
// compute_lambda_lod (no bias, min_lod 0, max_lod 1000): pixel 2 is softpipe's
// QUAD_BOTTOM_LEFT, 3 QUAD_BOTTOM_RIGHT and 0 QUAD_TOP_LEFT.
float quad_lod(const std::array<float, 4>& s, const std::array<float, 4>& t, float base_width,
               float base_height) {
    const float dsdx = std::fabs(s[3] - s[2]);
    const float dsdy = std::fabs(s[0] - s[2]);
    const float dtdx = std::fabs(t[3] - t[2]);
    const float dtdy = std::fabs(t[0] - t[2]);
    const float maxx = max2(dsdx, dsdy) * base_width;
    const float maxy = max2(dtdx, dtdy) * base_height;
    const float rho = max2(maxx, maxy);
    const float lambda = util_fast_log2(rho) + 0.0f;  // + lod_bias
    return clamp_as_mesa(lambda, 0.0f, 1000.0f);
}

}  // namespace

SoftpipeSampler::SoftpipeSampler(const TextureState& state, const std::vector<TextureImage>& levels,
                                 bool generate_mipmaps) {
    REFRASTER_ASSERT(!levels.empty(), "a texture has a base level");
    if (generate_mipmaps) {
        images_.push_back(levels.front());
        texels_.push_back(texels_as_floats(images_.back()));
        // The whole chain down to 1x1 (GL_TEXTURE_MAX_LEVEL stays 1000).
        while (images_.back().width > 1 || images_.back().height > 1) {
            const TextureImage& above = images_.back();
            const LevelRef src{texels_.back().data(), static_cast<std::int32_t>(above.width),
                               static_cast<std::int32_t>(above.height),
                               static_cast<std::uint32_t>(images_.size() - 1)};
            TextureImage next =
                blit_level(src, std::max(1u, above.width / 2), std::max(1u, above.height / 2));
            texels_.push_back(texels_as_floats(next));
            images_.push_back(std::move(next));
        }
    } else {
        images_ = levels;
        for (const TextureImage& image : images_) texels_.push_back(texels_as_floats(image));
    }
    for (const TextureImage& image : images_)
        REFRASTER_ASSERT(image.width >= 1 && image.height >= 1 &&
                             image.rgba.size() == std::size_t{image.width} * image.height * 4,
                         "a level's texels fill its size");
    last_ = static_cast<std::uint32_t>(images_.size() - 1);

    wrap_s_ = state.wrap_s;
    wrap_t_ = state.wrap_t;
    switch (state.min_filter) {
        case TextureFilter::Nearest:
            min_ = ImageFilter::Nearest;
            mip_ = MipFilter::None;
            break;
        case TextureFilter::Linear:
            min_ = ImageFilter::Linear;
            mip_ = MipFilter::None;
            break;
        case TextureFilter::NearestMipmapNearest:
            min_ = ImageFilter::Nearest;
            mip_ = MipFilter::Nearest;
            break;
        case TextureFilter::LinearMipmapNearest:
            min_ = ImageFilter::Linear;
            mip_ = MipFilter::Nearest;
            break;
        case TextureFilter::NearestMipmapLinear:
            min_ = ImageFilter::Nearest;
            mip_ = MipFilter::Linear;
            break;
        case TextureFilter::LinearMipmapLinear:
            min_ = ImageFilter::Linear;
            mip_ = MipFilter::Linear;
            break;
    }
    REFRASTER_ASSERT(!uses_mipmaps(state.mag_filter), "the mag filter is nearest or linear");
    mag_ = state.mag_filter == TextureFilter::Nearest ? ImageFilter::Nearest : ImageFilter::Linear;
    // Clamped at each sample (sample_quad), under the batch's floating-point mode.
    border_ = state.border_color;

    const TextureImage& base = images_.front();
    base_width_ = static_cast<float>(base.width);
    base_height_ = static_cast<float>(base.height);
    // sp_texture.c spr->pot (the base level's size) and sp_tex_sample.c get_img_filter,
    // softpipe_create_sampler_state, get_filters.
    const bool pot = is_pot(base.width) && is_pot(base.height);
    pot_repeat_ = pot && wrap_s_ == TextureWrap::Repeat && wrap_t_ == TextureWrap::Repeat;
    pot_trilinear_ = pot_repeat_ && mip_ == MipFilter::Linear && min_ == ImageFilter::Linear &&
                     mag_ == ImageFilter::Linear;
}

void SoftpipeSampler::nearest(std::uint32_t level, float s, float t, const float* border,
                              float* rgba) const {
    const TextureImage& image = images_[level];
    const LevelRef l{texels_[level].data(), static_cast<std::int32_t>(image.width),
                     static_cast<std::int32_t>(image.height), level};
    const float* p = nullptr;
    if (pot_repeat_) {
        // img_filter_2d_nearest_repeat_POT: the floored coordinate masked to the size.
        const float u = s * static_cast<float>(image.width);
        const float v = t * static_cast<float>(image.height);
        const auto x = static_cast<std::int32_t>(static_cast<std::uint32_t>(util_ifloor(u)) &
                                                 (image.width - 1));
        const auto y = static_cast<std::int32_t>(static_cast<std::uint32_t>(util_ifloor(v)) &
                                                 (image.height - 1));
        p = texel_at(l, x, y);
    } else {
        // img_filter_2d_nearest.
        p = texel_or_border(l, border, wrap_nearest(wrap_s_, s, image.width),
                            wrap_nearest(wrap_t_, t, image.height));
    }
    std::copy(p, p + 4, rgba);
}

template <bool kDirect>
void SoftpipeSampler::linear(std::uint32_t level, float s, float t, const float* border,
                             float* rgba) const {
    const TextureImage& image = images_[level];
    const LevelRef l{texels_[level].data(), static_cast<std::int32_t>(image.width),
                     static_cast<std::int32_t>(image.height), level};
    if (!pot_repeat_) {
        linear_generic(l, wrap_s_, wrap_t_, border, s, t, rgba);
        return;
    }
    // img_filter_2d_linear_repeat_POT: the weights from the unmasked floor.
    const float u = s * static_cast<float>(image.width) - 0.5f;
    const float v = t * static_cast<float>(image.height) - 0.5f;
    const std::int32_t uflr = util_ifloor(u);
    const std::int32_t vflr = util_ifloor(v);
    const float xw = u - static_cast<float>(uflr);
    const float yw = v - static_cast<float>(vflr);
    const std::uint32_t xmask = image.width - 1;
    const std::uint32_t ymask = image.height - 1;
    const auto x0 = static_cast<std::int32_t>(static_cast<std::uint32_t>(uflr) & xmask);
    const auto y0 = static_cast<std::int32_t>(static_cast<std::uint32_t>(vflr) & ymask);
    // "All four in one tile" compares the whole coordinate with the last in-tile offset
    // (xpot - 1) & 31, so only the level's first tile column and row qualify; the four
    // fetches otherwise (which alias only across the seam).
    const auto xmax = static_cast<std::int32_t>(xmask & 31u);
    const auto ymax = static_cast<std::int32_t>(ymask & 31u);
    //
    // sample_quad_direct reads the four texels directly wherever no seam lies between them
    // (x0 != xmask and y0 != ymask), the same values fetch_quad gives. Proof: then x1 = x0 + 1
    // and y1 = y0 + 1, all four inside the level, so fetch k's tile is (a + (k & 1) d,
    // b + (k >> 1) e) with (a, b) = (x0/32, y0/32) and d, e in {0, 1}. Two fetches in different
    // tiles differ in tile coordinates by (1, 0), (0, 1), (1, 1) or (-1, 1) (fetches 1 and 2),
    // so in entry, (x/32 + 9 (y/32) + 7 level) % 16, by 1, 9, 10 or 8 modulo 16, never 0
    // (the level is the same for all four): no fetch loads another tile into an earlier
    // fetch's entry. Two fetches that share an entry share the tile, so pointer k reads, at its
    // offset, its own tile: texel (x_k, y_k). The seam samples (x0 = xmask or y0 = ymask,
    // about one in `width` or `height`) keep the emulation: across a seam the tiles' distance
    // is no longer 0 or 1, and entries can coincide. On a 256x256 level, a seam in t puts
    // fetch 1 in tile (a + 1, 7) and fetch 2 in (a, 0) when x0 ends a tile column (entries
    // a + 1 + 63 and a), a seam in s fetch 1 in (0, b) and fetch 2 in (7, b + 1) when y0
    // ends a tile row (9b and 7 + 9b + 9): pointer 1 then reads fetch 2's tile.
    const bool direct =
        kDirect ? x0 != static_cast<std::int32_t>(xmask) && y0 != static_cast<std::int32_t>(ymask)
                : x0 < xmax && y0 < ymax;
    std::array<const float*, 4> tx{};
    if (direct) {  // get_texel_quad_2d_no_border_single_tile, or the proof above
        tx = {texel_at(l, x0, y0), texel_at(l, x0 + 1, y0), texel_at(l, x0, y0 + 1),
              texel_at(l, x0 + 1, y0 + 1)};
    } else {  // get_texel_quad_2d_no_border
        const auto x1 = static_cast<std::int32_t>(static_cast<std::uint32_t>(x0 + 1) & xmask);
        const auto y1 = static_cast<std::int32_t>(static_cast<std::uint32_t>(y0 + 1) & ymask);
        tx = fetch_quad(l, border, {x0, x1, x0, x1}, {y0, y0, y1, y1});
    }
    if constexpr (kDirect) {
        bilinear_direct(tx, xw, yw, rgba);
    } else {
        bilinear(tx, xw, yw, rgba);
    }
}

template <bool kDirect>
void SoftpipeSampler::filter(ImageFilter f, std::uint32_t level, float s, float t,
                             const float* border, float* rgba) const {
    if (f == ImageFilter::Nearest) {
        nearest(level, s, t, border, rgba);
    } else {
        linear<kDirect>(level, s, t, border, rgba);
    }
}

template <bool kDirect>
void SoftpipeSampler::sample(const std::array<float, 4>& s, const std::array<float, 4>& t,
                             std::array<std::array<float, 4>, 4>& out) const {
    // sp_tgsi_get_samples: a unorm view clamps the border colour to [0, 1] at every call, so
    // under the batch's DAZ (draw_vbo's, "Whether the driver sets up each output triangle")
    // CLAMP's compares read a denormal as zero and give 0: textures.border_color_denormal.
    std::array<float, 4> clamped{};
    for (std::size_t c = 0; c < 4; ++c) clamped[c] = clamp_as_mesa(border_[c], 0.0f, 1.0f);
    const float* border = clamped.data();
    if (mip_ == MipFilter::None && min_ == mag_) {
        // mip_filter_none_no_filter_select: the mag filter on the base, no LOD.
        for (std::size_t k = 0; k < 4; ++k)
            filter<kDirect>(mag_, 0, s[k], t[k], border, out[k].data());
        return;
    }
    // The LOD is never NaN (util_fast_log2 of a NaN is finite) and lies in [0, 1000].
    const float lod = quad_lod(s, t, base_width_, base_height_);
    for (std::size_t k = 0; k < 4; ++k) {
        float* rgba = out[k].data();
        switch (mip_) {
            case MipFilter::None:  // mip_filter_none
                filter<kDirect>(lod <= 0.0f ? mag_ : min_, 0, s[k], t[k], border, rgba);
                break;
            case MipFilter::Nearest: {  // mip_filter_nearest
                if (lod <= 0.0f) {
                    filter<kDirect>(mag_, 0, s[k], t[k], border, rgba);
                    break;
                }
                const auto level = static_cast<std::uint32_t>(lod + 0.5f);
                filter<kDirect>(min_, std::min(level, last_), s[k], t[k], border, rgba);
                break;
            }
            case MipFilter::Linear: {
                const auto level0 = static_cast<std::uint32_t>(lod);
                if (!pot_trilinear_ && lod <= 0.0f) {  // mip_filter_linear's mag test
                    filter<kDirect>(mag_, 0, s[k], t[k], border, rgba);
                } else if (level0 >= last_) {
                    // mip_filter_linear and mip_filter_linear_2d_linear_repeat_POT: the last
                    // level alone.
                    filter<kDirect>(min_, last_, s[k], t[k], border, rgba);
                } else {
                    // Both levels, blended by frac(lod); the POT path does this at lod 0 too,
                    // where the weight 0 leaves the base's value.
                    const float blend = frac(lod);
                    std::array<float, 4> c0{};
                    std::array<float, 4> c1{};
                    filter<kDirect>(min_, level0, s[k], t[k], border, c0.data());
                    filter<kDirect>(min_, level0 + 1, s[k], t[k], border, c1.data());
                    for (std::size_t c = 0; c < 4; ++c) rgba[c] = lerp(blend, c0[c], c1[c]);
                }
                break;
            }
        }
    }
}

void SoftpipeSampler::sample_quad(const std::array<float, 4>& s, const std::array<float, 4>& t,
                                  std::array<std::array<float, 4>, 4>& out) const {
    sample<false>(s, t, out);
}

void SoftpipeSampler::sample_quad_direct(const std::array<float, 4>& s,
                                         const std::array<float, 4>& t,
                                         std::array<std::array<float, 4>, 4>& out) const {
    sample<true>(s, t, out);
}

}  // namespace refraster::detail
