// planes.hpp: llvmpipe's attribute planes, as its setup computes them for a triangle.
//
// Implements:
//  - attribute planes (gallium/drivers/llvmpipe/lp_state_setup.c, init_args and calc_coef4):
//    from the unsnapped window positions in setup's (swapped) vertex order,
//    x0c = x0 - 0.5, ooa = 1 / (dx01*dy20 - dy01*dx20) with both products rounded, the deltas
//    pre-multiplied by ooa, dadx = da01*dy20o - da20*dy01o, dady = da20*dx01o - da01*dx20o,
//    A0 = a0 - (dadx*x0c + dady*y0c); smooth attributes are multiplied by their vertex's 1/w
//    first (apply_perspective_corr); flat ones take the provoking vertex (emit_constant_coef4);
//    window z and 1/w get planes of their own. All unfused.
//  - polygon offset (lp_do_offset_tri): the slopes |dz/dx|, |dz/dy| from the cross product of
//    the unscaled deltas times ooa; offset = units' + max slope * factor, where units' is
//    units * 2 * mrd for fixed-point depth (lp_make_setup_variant_key), and for float depth
//    units * 2^(exponent(max |z_i|) - 23).
//
// Deliberately does not: evaluate the planes at a pixel (the fragment kernels do:
// fragment.hpp), or set up lines and points (line_point.hpp writes their planes through the
// same PlaneWriter).
#pragma once

#include <array>
#include <cstdint>

#include "common/float_ops.hpp"
#include "models/llvmpipe/fragment.hpp"
#include "models/llvmpipe/setup_list.hpp"
#include "refraster/draw.hpp"
#include "stages/vertex_stage.hpp"

namespace refraster::detail {

// Writes one primitive's planes into a SetupList: window z and 1/w first, then its
// attributes. The per-pixel code runs under DAZ (lp_rast.c): with `daz`, a plane term that
// setup left subnormal (setup without FTZ, see the llvmpipe model) is stored as the zero
// every operation reading it would see. Flat values are only moved and keep their bits.
class PlaneWriter {
  public:
    PlaneWriter(SetupList& list, SetupPrimitive& prim, bool daz)
        : list_(list), prim_(prim), daz_(daz) {
        prim_.planes = static_cast<std::uint32_t>(list_.planes.size());
        prim_.flat = static_cast<std::uint32_t>(list_.flat.size());
    }
    void depth(const Plane& z, const Plane& w, float z_offset) {
        list_.planes.push_back(daz(z));
        list_.planes.push_back(daz(w));
        prim_.z_offset = daz_ ? flush_denormal(z_offset) : z_offset;
    }
    // smooth and noperspective draws
    void attribute(const Plane& p) { list_.planes.push_back(daz(p)); }
    void constant(float v) { list_.flat.push_back(v); }  // flat draws

  private:
    Plane daz(Plane p) const {
        if (daz_) {
            p.a0 = flush_denormal(p.a0);
            p.dadx = flush_denormal(p.dadx);
            p.dady = flush_denormal(p.dady);
        }
        return p;
    }
    SetupList& list_;
    SetupPrimitive& prim_;
    bool daz_;
};

// Triangle planes (lp_state_setup.c); `v` in setup's order, after the orientation swap; one
// plane (or constant) per attribute float of the draw. `options` are setup's (its FTZ may be
// off, see the llvmpipe model), `daz` the per-pixel stage's.
//
// Planes no reader needs are left out (stored as zero): window z and the polygon offset
// unless the draw tests depth, 1/w unless it is smooth-shaded, unless an observer records
// them (PlaneNeeds).
struct PlaneNeeds {
    bool depth = true;  // the z plane and the polygon offset
    bool w = true;      // the 1/w plane
};
void triangle_planes(const std::array<const StageVertex*, 3>& v, const VertexStage& stage,
                     const Draw& draw, const Target& target, bool provoking_first,
                     FragmentOptions options, bool daz, PlaneNeeds needs, SetupList& list,
                     SetupPrimitive& prim);

}  // namespace refraster::detail
