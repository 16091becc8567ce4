// planes.cpp: llvmpipe's triangle planes (planes.hpp).
#include "models/llvmpipe/planes.hpp"

#include <algorithm>
#include <cmath>

#include "refraster/assert.hpp"
#include "stages/rules.hpp"

namespace refraster::detail {

namespace {

// calc_coef4 for one channel (lp_state_setup.c), given the shared setup terms.
struct SetupTerms {
    float x0c, y0c, dx01o, dy01o, dx20o, dy20o;
};

[[gnu::always_inline]] inline Plane calc_coef(const Fp& fp, const SetupTerms& s, float a0, float a1,
                                              float a2) {
    const float da01 = fp.sub(a0, a1);
    const float da20 = fp.sub(a2, a0);
    Plane p;
    p.dadx = fp.sub(fp.mul(da01, s.dy20o), fp.mul(da20, s.dy01o));
    p.dady = fp.sub(fp.mul(da20, s.dx01o), fp.mul(da01, s.dx20o));
    p.a0 = fp.sub(a0, fp.add(fp.mul(p.dadx, s.x0c), fp.mul(p.dady, s.y0c)));
    return p;
}

}  // namespace

void triangle_planes(const std::array<const StageVertex*, 3>& v, const VertexStage& stage,
                     const Draw& draw, const Target& target, bool provoking_first,
                     FragmentOptions options, bool daz, PlaneNeeds needs, SetupList& list,
                     SetupPrimitive& prim) {
    const Fp fp{options.flush_denormals};
    PlaneWriter out(list, prim, daz);
    float z_offset = 0.0f;
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

    if (draw.state.polygon_offset && needs.depth) {
        // lp_do_offset_tri: res12 = (dz20*dy01 - dy20*dz01, dx20*dz01 - dz20*dx01), times ooa.
        const float res1 = fp.sub(fp.mul(d20[2], d01[1]), fp.mul(d20[1], d01[2]));
        const float res2 = fp.sub(fp.mul(d20[0], d01[2]), fp.mul(d20[2], d01[0]));
        const float dzdx = std::fabs(fp.mul(res1, ooa));
        const float dzdy = std::fabs(fp.mul(res2, ooa));
        // LLVMRealUGT: unordered or greater picks dzdx.
        const float max_slope = (dzdx > dzdy || std::isnan(dzdx) || std::isnan(dzdy)) ? dzdx : dzdy;
        const float mult = fp.mul(max_slope, draw.state.polygon_offset->factor);
        // The implementation's r as a power-of-two multiple of llvmpipe's (offset_units_scale,
        // exact: 1 reproduces llvmpipe).
        const float units = draw.state.polygon_offset->units * options.offset_units_scale;
        if (target.depth == DepthFormat::Z32f) {
            // units * 2^(exponent(max |z_i|) - 23).
            const float maxz =
                std::max(std::fabs(p2[2]), std::max(std::fabs(p0[2]), std::fabs(p1[2])));
            z_offset = fp.add(fp.mul(z32f_offset_scale(maxz), units), mult);
        } else {
            z_offset = fp.add(fixed_depth_offset_units(units, target.depth), mult);
        }
    }

    SetupTerms s;
    // lp_state_setup.c: the pixel centre offset, which multisampling sets to 0 (the shader
    // then adds 0.5; docs/precision.md, "Multisampling (4x)").
    const float pixel_offset = options.multisample ? 0.0f : 0.5f;
    s.x0c = fp.sub(p0[0], pixel_offset);
    s.y0c = fp.sub(p0[1], pixel_offset);
    s.dx20o = fp.mul(d20[0], ooa);
    s.dy20o = fp.mul(d20[1], ooa);
    s.dx01o = fp.mul(d01[0], ooa);
    s.dy01o = fp.mul(d01[1], ooa);
    out.depth(needs.depth ? calc_coef(fp, s, p0[2], p1[2], p2[2]) : Plane{},
              needs.w ? calc_coef(fp, s, p0[3], p1[3], p2[3]) : Plane{}, z_offset);

    const auto c0 = stage.attributes(*v[0]);
    const auto c1 = stage.attributes(*v[1]);
    const auto c2 = stage.attributes(*v[2]);
    const auto& prov = provoking_first ? c0 : c2;
    for (std::size_t k = 0; k < c0.size(); ++k) {
        switch (draw.state.shade) {
            case ShadeModel::Flat:
                out.constant(prov[k]);
                break;  // emit_constant_coef4
            case ShadeModel::Smooth:
                // apply_perspective_corr: each vertex value times its own 1/w.
                out.attribute(calc_coef(fp, s, fp.mul(c0[k], p0[3]), fp.mul(c1[k], p1[3]),
                                        fp.mul(c2[k], p2[3])));
                break;
            case ShadeModel::NoPerspective:
                out.attribute(calc_coef(fp, s, c0[k], c1[k], c2[k]));
                break;
        }
    }
}

}  // namespace refraster::detail
