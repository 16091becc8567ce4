#include "fragment.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "refraster/assert.hpp"
#include "rules.hpp"

namespace refraster::detail {

std::uint8_t clear_to_unorm8(float c) {
    if (!(c > 0.0f)) return 0;  // NaN too
    if (c >= 1.0f) return 255;
    const float t = c * (255.0f / 256.0f) + 32768.0f;
    return static_cast<std::uint8_t>(std::bit_cast<std::uint32_t>(t) & 0xffu);
}

std::uint8_t color_to_unorm8(float c) {
    if (!(c > 0.0f)) return 0;
    if (c >= 1.0f) return 255;
    return static_cast<std::uint8_t>(std::nearbyint(c * 255.0f));
}

namespace {

// calc_coef4 for one channel (lp_state_setup.c), given the shared setup terms.
struct SetupTerms {
    float x0c, y0c, dx01o, dy01o, dx20o, dy20o;
};

Plane calc_coef(const Fp& fp, const SetupTerms& s, float a0, float a1, float a2) {
    const float da01 = fp.sub(a0, a1);
    const float da20 = fp.sub(a2, a0);
    Plane p;
    p.dadx = fp.sub(fp.mul(da01, s.dy20o), fp.mul(da20, s.dy01o));
    p.dady = fp.sub(fp.mul(da20, s.dx01o), fp.mul(da01, s.dx20o));
    p.a0 = fp.sub(a0, fp.add(fp.mul(p.dadx, s.x0c), fp.mul(p.dady, s.y0c)));
    return p;
}

// lp_state_fs.c, lp_build_depth_clamp: lp_build_clamp(z, 0, 1), which is lp_build_min(z, 1)
// then lp_build_max(., 0) (lp_bld_arit.c) with undefined NaN behaviour, lowered to the x86
// minps/maxps instructions: each returns its second operand unless the first compares less
// (greater). A NaN depth therefore becomes 1 (the far value, in every depth format), -0 becomes
// +0, and infinities clamp to the ends.
inline float x86_min(float a, float b) { return a < b ? a : b; }
inline float x86_max(float a, float b) { return a > b ? a : b; }

}  // namespace

float clamp_depth(float z) { return x86_max(x86_min(z, 1.0f), 0.0f); }

namespace {

bool compare(CompareFunc f, std::uint32_t frag, std::uint32_t stored, bool is_float) {
    // z32f values are compared as floats (both are in [0, 1], so their bit patterns order the
    // same way, but the intent is kept explicit).
    const auto lt = [&] { return is_float ? std::bit_cast<float>(frag) < std::bit_cast<float>(stored) : frag < stored; };
    const auto eq = [&] { return is_float ? std::bit_cast<float>(frag) == std::bit_cast<float>(stored) : frag == stored; };
    switch (f) {
        case CompareFunc::Never: return false;
        case CompareFunc::Less: return lt();
        case CompareFunc::Equal: return eq();
        case CompareFunc::Lequal: return lt() || eq();
        case CompareFunc::Greater: return !lt() && !eq();
        case CompareFunc::NotEqual: return !eq();
        case CompareFunc::Gequal: return !lt();
        case CompareFunc::Always: return true;
    }
    return true;
}

}  // namespace

FragmentShader::FragmentShader(const Planes& planes, const Draw& draw, const Target& target, FragmentOptions options,
                               std::uint32_t owner)
    : draw_(draw), target_(target), options_(options), shade_(draw.state.shade), p_(planes), owner_(owner) {
    depth_test_ = draw.state.depth_test.has_value() && target.depth != DepthFormat::None;
    if (options_.flush_denormals) {
        // The per-pixel code runs under DAZ (lp_rast.c): a plane term that setup left subnormal
        // (setup without FTZ, see the renderer) counts as zero in every operation that reads it.
        // Flat values are only moved and keep their bits.
        const auto daz = [](Plane& q) {
            q.a0 = flush_denormal(q.a0);
            q.dadx = flush_denormal(q.dadx);
            q.dady = flush_denormal(q.dady);
        };
        daz(p_.z);
        daz(p_.w);
        for (auto& c : p_.color) daz(c);
        p_.z_offset = flush_denormal(p_.z_offset);
    }
}

Planes triangle_planes(const std::array<const StageVertex*, 3>& v, const VertexStage& stage, const Draw& draw,
                       const Target& target, bool provoking_first, FragmentOptions options) {
    REFRASTER_ASSERT(stage.attribute_floats() >= 4, "a colour of four components");
    const Fp fp{options.flush_denormals};
    Planes out;
    const auto& p0 = v[0]->window;
    const auto& p1 = v[1]->window;
    const auto& p2 = v[2]->window;
    // init_args: the position deltas as vectors (x, y, z, 1/w).
    std::array<float, 4> d01{}, d20{};
    for (std::size_t k = 0; k < 4; ++k) {
        d01[k] = fp.sub(p0[k], p1[k]);
        d20[k] = fp.sub(p2[k], p0[k]);
    }
    const float e = fp.mul(d01[0], d20[1]);
    const float f = fp.mul(d01[1], d20[0]);
    const float ooa = fp.div(1.0f, fp.sub(e, f));

    if (draw.state.polygon_offset) {
        // lp_do_offset_tri: res12 = (dz20*dy01 - dy20*dz01, dx20*dz01 - dz20*dx01), times ooa.
        const float res1 = fp.sub(fp.mul(d20[2], d01[1]), fp.mul(d20[1], d01[2]));
        const float res2 = fp.sub(fp.mul(d20[0], d01[2]), fp.mul(d20[2], d01[0]));
        const float dzdx = std::fabs(fp.mul(res1, ooa));
        const float dzdy = std::fabs(fp.mul(res2, ooa));
        // LLVMRealUGT: unordered or greater picks dzdx.
        const float max_slope = (dzdx > dzdy || std::isnan(dzdx) || std::isnan(dzdy)) ? dzdx : dzdy;
        const float mult = fp.mul(max_slope, draw.state.polygon_offset->factor);
        const float units = draw.state.polygon_offset->units;
        if (target.depth == DepthFormat::Z32f) {
            // units * 2^(exponent(max |z_i|) - 23).
            const float maxz = std::max(std::fabs(p2[2]), std::max(std::fabs(p0[2]), std::fabs(p1[2])));
            out.z_offset = fp.add(fp.mul(z32f_offset_scale(maxz), units), mult);
        } else {
            out.z_offset = fp.add(fixed_depth_offset_units(units, target.depth), mult);
        }
    }

    SetupTerms s;
    s.x0c = fp.sub(p0[0], 0.5f);
    s.y0c = fp.sub(p0[1], 0.5f);
    s.dx20o = fp.mul(d20[0], ooa);
    s.dy20o = fp.mul(d20[1], ooa);
    s.dx01o = fp.mul(d01[0], ooa);
    s.dy01o = fp.mul(d01[1], ooa);
    out.z = calc_coef(fp, s, p0[2], p1[2], p2[2]);
    out.w = calc_coef(fp, s, p0[3], p1[3], p2[3]);

    const auto c0 = stage.attributes(*v[0]);
    const auto c1 = stage.attributes(*v[1]);
    const auto c2 = stage.attributes(*v[2]);
    const auto& prov = provoking_first ? c0 : c2;
    for (std::size_t k = 0; k < 4; ++k) {
        out.flat[k] = prov[k];
        if (draw.state.shade == ShadeModel::Smooth) {
            // apply_perspective_corr: each vertex value times its own 1/w.
            out.color[k] = calc_coef(fp, s, fp.mul(c0[k], p0[3]), fp.mul(c1[k], p1[3]), fp.mul(c2[k], p2[3]));
        } else if (draw.state.shade == ShadeModel::NoPerspective) {
            out.color[k] = calc_coef(fp, s, c0[k], c1[k], c2[k]);
        }
    }
    return out;
}

float FragmentShader::eval_plane(const Plane& p, float px, float py) const {
    const Fp fp{options_.flush_denormals};
    if (options_.fma) {
        return fp.fma(p.dady, py, fp.fma(p.dadx, px, p.a0));
    }
    return fp.add(fp.mul(p.dady, py), fp.add(fp.mul(p.dadx, px), p.a0));
}

FragmentShader::PixelResult FragmentShader::evaluate(int x, int y, const Framebuffer& fb) const {
    const Fp fp{options_.flush_denormals};
    const float px = static_cast<float>(x);
    const float py = static_cast<float>(y);
    PixelResult r;
    if (depth_test_) {
        float z = fp.add(eval_plane(p_.z, px, py), p_.z_offset);
        z = clamp_depth(z);
        r.z = z;
        r.depth = quantise_depth(z, target_.depth);
        const std::uint32_t stored = fb.depth[fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y))];
        r.depth_pass = compare(*draw_.state.depth_test, r.depth, stored, target_.depth == DepthFormat::Z32f);
    }
    if (shade_ == ShadeModel::Flat) {
        r.color = p_.flat;
    } else if (shade_ == ShadeModel::NoPerspective) {
        for (std::size_t k = 0; k < 4; ++k) r.color[k] = eval_plane(p_.color[k], px, py);
    } else {
        const float w = fp.div(1.0f, eval_plane(p_.w, px, py));  // lp_build_rcp: a true division
        for (std::size_t k = 0; k < 4; ++k) r.color[k] = fp.mul(eval_plane(p_.color[k], px, py), w);
    }
    return r;
}

void write_fragment_color(const Draw& draw, Framebuffer& fb, std::size_t i, const std::array<float, 4>& c,
                          bool flush_denormals) {
    const BlendPreset blend = draw.state.blend;
    if (fb.color_format == ColorFormat::Rgba8) {
        std::uint8_t* d = fb.color8.data() + 4 * i;
        std::array<std::uint8_t, 4> s{};
        for (std::size_t k = 0; k < 4; ++k) s[k] = color_to_unorm8(c[k]);
        switch (blend) {
            case BlendPreset::None: std::memcpy(d, s.data(), 4); break;
            case BlendPreset::Alpha: {
                const std::uint32_t a = s[3];
                for (std::size_t k = 0; k < 4; ++k) {
                    const std::uint32_t v = std::uint32_t{unorm8_mul(s[k], a)} + unorm8_mul(d[k], 255 - a);
                    d[k] = static_cast<std::uint8_t>(std::min<std::uint32_t>(v, 255));
                }
                break;
            }
            case BlendPreset::Add:
                for (std::size_t k = 0; k < 4; ++k) {
                    d[k] = static_cast<std::uint8_t>(std::min<std::uint32_t>(std::uint32_t{s[k]} + d[k], 255));
                }
                break;
        }
    } else {
        // The blend runs in the rasterizer's threads under FTZ/DAZ (lp_rast.c), so a subnormal
        // source, alpha or destination counts as zero there; without blending the colour is
        // only moved and keeps its bits.
        const Fp fp{flush_denormals};
        float* d = fb.color32f.data() + 4 * i;
        switch (blend) {
            case BlendPreset::None: std::copy(c.begin(), c.end(), d); break;
            case BlendPreset::Alpha: {
                const float a = c[3];
                const float inv = fp.sub(1.0f, a);
                for (std::size_t k = 0; k < 4; ++k) d[k] = fp.add(fp.mul(c[k], a), fp.mul(d[k], inv));
                break;
            }
            case BlendPreset::Add:
                for (std::size_t k = 0; k < 4; ++k) d[k] = fp.add(c[k], d[k]);
                break;
        }
    }
}

void FragmentShader::shade_span(int y, int x0, int x1, Framebuffer& fb) const {
    for (int x = x0; x < x1; ++x) {
        const PixelResult r = evaluate(x, y, fb);
        if (!r.depth_pass) continue;
        const std::size_t i = fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
        if (depth_test_ && draw_.state.depth_write) fb.depth[i] = r.depth;
        write_fragment_color(draw_, fb, i, r.color, options_.flush_denormals);
        if (!fb.owner.empty()) fb.owner[i] = owner_;
    }
}

FragmentTrace FragmentShader::trace_pixel(int x, int y, const Framebuffer& fb_before) const {
    REFRASTER_ASSERT(x >= 0 && y >= 0 && static_cast<std::uint32_t>(x) < fb_before.width &&
                         static_cast<std::uint32_t>(y) < fb_before.height,
                     "a covered pixel, inside the framebuffer");
    FragmentTrace t;
    t.z_plane = {p_.z.a0, p_.z.dadx, p_.z.dady};
    t.w_plane = {p_.w.a0, p_.w.dadx, p_.w.dady};
    t.z_offset = p_.z_offset;
    const PixelResult r = evaluate(x, y, fb_before);
    const std::size_t i = fb_before.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
    t.z = r.z;
    t.depth_tested = depth_test_;
    t.depth_value = r.depth;
    t.depth_stored = depth_test_ ? fb_before.depth[i] : 0;
    t.depth_pass = r.depth_pass;
    t.shader_color = r.color;
    Framebuffer one(1, 1, fb_before.color_format, DepthFormat::None);
    for (std::size_t k = 0; k < 4; ++k) {
        if (fb_before.color_format == ColorFormat::Rgba8) {
            one.color8[k] = fb_before.color8[4 * i + k];
            t.destination[k] = one.color8[k];
        } else {
            one.color32f[k] = fb_before.color32f[4 * i + k];
            t.destination[k] = one.color32f[k];
        }
    }
    if (r.depth_pass) write_fragment_color(draw_, one, 0, r.color, options_.flush_denormals);
    for (std::size_t k = 0; k < 4; ++k) {
        t.written[k] = fb_before.color_format == ColorFormat::Rgba8 ? one.color8[k] : one.color32f[k];
    }
    return t;
}

}  // namespace refraster::detail

namespace refraster::detail {

ExactShader::ExactShader(const ExactCoverage& coverage, const std::array<const StageVertex*, 3>& v,
                         const VertexStage& stage, const Draw& draw, const Target& target, bool provoking_first)
    : coverage_(coverage), v_(v), stage_(stage), draw_(draw), target_(target), provoking_first_(provoking_first) {
    REFRASTER_ASSERT(stage.attribute_floats() >= 4, "a colour of four components");
    depth_test_ = draw.state.depth_test.has_value() && target.depth != DepthFormat::None;
    if (draw.state.polygon_offset && depth_test_) {
        // The slope of window z over window x and y: z is linear in window space. Only
        // meaningful for triangles entirely in front of the eye.
        std::array<std::array<double, 3>, 3> p{};
        const auto& vp = draw.state.viewport;
        const double n = draw.state.depth_near;
        const double f = draw.state.depth_far;
        for (std::size_t i = 0; i < 3; ++i) {
            const auto& c = v[i]->clip;
            p[i] = {(double{c[0]} / double{c[3]} + 1.0) * 0.5 * vp.width + vp.x,
                    (double{c[1]} / double{c[3]} + 1.0) * 0.5 * vp.height + vp.y,
                    double{c[2]} / double{c[3]} * 0.5 * (f - n) + 0.5 * (n + f)};
        }
        const double ax = p[1][0] - p[0][0], ay = p[1][1] - p[0][1], az = p[1][2] - p[0][2];
        const double bx = p[2][0] - p[0][0], by = p[2][1] - p[0][1], bz = p[2][2] - p[0][2];
        const double det = ax * by - ay * bx;
        const double m = det == 0.0 ? 0.0 : std::max(std::fabs((az * by - ay * bz) / det), std::fabs((ax * bz - az * bx) / det));
        double r = 0.0;
        if (target.depth == DepthFormat::Z32f) {
            const double maxz = std::max({std::fabs(p[0][2]), std::fabs(p[1][2]), std::fabs(p[2][2])});
            r = exact_z32f_offset_scale(maxz);
        } else {
            r = depth_mrd(target.depth);
        }
        offset_ = m * double{draw.state.polygon_offset->factor} + r * double{draw.state.polygon_offset->units};
    }
}

void ExactShader::shade(int x, int y, Framebuffer& fb, std::uint32_t owner) const {
    const auto b = coverage_.weights(x, y);
    const std::size_t i = fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
    if (depth_test_) {
        double zn = 0.0;
        for (std::size_t k = 0; k < 3; ++k) zn += b[k] * double{v_[k]->clip[2]};
        const double n = draw_.state.depth_near;
        const double f = draw_.state.depth_far;
        double z = zn * 0.5 * (f - n) + 0.5 * (n + f) + offset_;
        z = std::min(std::max(z, 0.0), 1.0);
        const std::uint32_t q = quantise_depth(z, target_.depth);
        if (!compare(*draw_.state.depth_test, q, fb.depth[i], target_.depth == DepthFormat::Z32f)) return;
        if (draw_.state.depth_write) fb.depth[i] = q;
    }
    std::array<float, 4> c{};
    const auto a0 = stage_.attributes(*v_[0]);
    const auto a1 = stage_.attributes(*v_[1]);
    const auto a2 = stage_.attributes(*v_[2]);
    const std::array<std::span<const float>, 3> a{a0, a1, a2};
    for (std::size_t k = 0; k < 4; ++k) {
        switch (draw_.state.shade) {
            case ShadeModel::Flat: c[k] = a[provoking_first_ ? 0 : 2][k]; break;
            case ShadeModel::Smooth: {
                double s = 0.0;
                for (std::size_t j = 0; j < 3; ++j) s += b[j] * double{a[j][k]};
                c[k] = static_cast<float>(s);
                break;
            }
            case ShadeModel::NoPerspective: {
                double s = 0.0;
                for (std::size_t j = 0; j < 3; ++j) s += b[j] * double{v_[j]->clip[3]} * double{a[j][k]};
                c[k] = static_cast<float>(s);
                break;
            }
        }
    }
    write_fragment_color(draw_, fb, i, c, true);
    if (!fb.owner.empty()) fb.owner[i] = owner;
}

}  // namespace refraster::detail
