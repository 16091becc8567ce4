// front_end.hpp: the one place where scene vertices become clip-space float32 vertices.
//
// Implements the formulas of scene format v1, section "A draw", in float32 with round to
// nearest and no fused operations (the project compiles with -ffp-contract=off):
//   window: ndc = ((p - v) / size) * 2 - 1 per axis, ndc_z = ((z - n) / (f - n)) * 2 - 1
//           (0 when f == n), clip = (ndc_x*w, ndc_y*w, ndc_z*w, w)
//   clip:   p'[r] = ((m[r]*x + m[4+r]*y) + m[8+r]*z) + m[12+r]*w with the optional matrix.
// The matrix product is written out by hand: glm's mat4*vec4 sums pairwise (its
// detail/func_matrix code adds the column products two by two), which is not the order the format
// prescribes.
//
// Deliberately does not: clip, cull or apply the viewport; backends and the reference do.
#pragma once

#include <array>

#include "harness/scene.hpp"
#include "refraster/draw.hpp"

namespace harness {

// Clip-space position of one vertex of `draw`. Throws SceneError (path
// draws[d].vertices[v].position) when a coordinate comes out non-finite.
std::array<float, 4> to_clip_space(const SceneDraw& draw, const SceneVertex& v);

// The whole scene: every draw once, with "color" as attribute 0 and, in a draw with a texture
// (extension "textures"), "texcoord" as attribute 1; the file's textures in name order, each
// draw's texture its name's index. Throws SceneError (path draws[d].state.texture.name) for a
// texture name the scene does not define.
refraster::DrawList run_front_end(const SceneFile& scene, const std::string& file_label);

}  // namespace harness
