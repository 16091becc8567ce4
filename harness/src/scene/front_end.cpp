#include "harness/front_end.hpp"

#include <cmath>
#include <iterator>

namespace harness {

std::array<float, 4> to_clip_space(const SceneDraw& draw, const SceneVertex& v) {
    const auto& p = v.position;
    std::array<float, 4> c{};
    if (draw.space == VertexSpace::Window) {
        // Scene format v1, "A draw", space "window": float32, round to nearest, unfused.
        const auto& vp = draw.state.viewport;
        const float x = p[0];
        const float y = p[1];
        const float z = v.position_size >= 3 ? p[2] : 0.0f;
        const float w = v.position_size >= 4 ? p[3] : 1.0f;
        const float ndc_x =
            ((x - static_cast<float>(vp.x)) / static_cast<float>(vp.width)) * 2.0f - 1.0f;
        const float ndc_y =
            ((y - static_cast<float>(vp.y)) / static_cast<float>(vp.height)) * 2.0f - 1.0f;
        const float n = draw.state.depth_near;
        const float f = draw.state.depth_far;
        const float ndc_z = (f == n) ? 0.0f : ((z - n) / (f - n)) * 2.0f - 1.0f;
        c = {ndc_x * w, ndc_y * w, ndc_z * w, w};
    } else if (draw.matrix) {
        // space "clip" with a matrix: p'[r] = ((m[r]*x + m[4+r]*y) + m[8+r]*z) + m[12+r]*w,
        // left to right (glm's operator* would sum pairwise).
        const auto& m = *draw.matrix;
        for (std::size_t r = 0; r < 4; ++r) {
            const float t0 = m[r] * p[0];
            const float t1 = m[4 + r] * p[1];
            const float t2 = m[8 + r] * p[2];
            const float t3 = m[12 + r] * p[3];
            c[r] = ((t0 + t1) + t2) + t3;
        }
    } else {
        c = p;
    }
    return c;
}

refraster::DrawList run_front_end(const SceneFile& scene, const std::string& file_label) {
    refraster::DrawList out;
    out.target = scene.target;
    out.clear = scene.clear;
    // Every texture the file defines, in name order: a draw's texture is its name's index.
    out.textures.reserve(scene.textures.size());
    for (const auto& [name, texture] : scene.textures) out.textures.push_back(texture);
    out.draws.reserve(scene.draws.size());
    for (std::size_t d = 0; d < scene.draws.size(); ++d) {
        const SceneDraw& sd = scene.draws[d];
        refraster::Draw draw;
        draw.primitive = sd.primitive;
        draw.state = sd.state;
        draw.indices = sd.indices;
        const bool textured = sd.state.texture.has_value();
        if (textured) {
            const auto it = scene.textures.find(sd.texture);
            if (it == scene.textures.end()) {
                throw SceneError(file_label, "draws[" + std::to_string(d) + "].state.texture.name",
                                 "no texture named \"" + escape_for_message(sd.texture) + "\"");
            }
            draw.state.texture->texture =
                static_cast<std::uint32_t>(std::distance(scene.textures.begin(), it));
            // Record [x y z w | r g b a | s t r q].
            draw.vertices.attributes = {{"color", 4}, {"texcoord", 4}};
        } else {
            draw.vertices.attributes = {{"color", 4}};
        }
        draw.vertices.data.reserve(sd.vertices.size() * draw.vertices.stride());
        for (std::size_t i = 0; i < sd.vertices.size(); ++i) {
            const auto c = to_clip_space(sd, sd.vertices[i]);
            for (std::size_t k = 0; k < 4; ++k) {
                if (!std::isfinite(c[k])) {
                    const std::string what = "clip coordinate " + std::to_string(k) +
                                             " comes out non-finite; expected finite clip space";
                    const std::string at = "draws[" + std::to_string(d) + "]";
                    if (sd.from_vertex_arrays) {
                        throw SceneError(file_label, at + ".vertex_arrays.position",
                                         "vertex " + std::to_string(i) + ": " + what);
                    }
                    throw SceneError(file_label,
                                     at + ".vertices[" + std::to_string(i) + "].position", what);
                }
            }
            draw.vertices.data.insert(draw.vertices.data.end(), c.begin(), c.end());
            const auto& col = sd.vertices[i].color;
            draw.vertices.data.insert(draw.vertices.data.end(), col.begin(), col.end());
            if (textured) {
                const auto& tc = sd.vertices[i].texcoord;
                draw.vertices.data.insert(draw.vertices.data.end(), tc.begin(), tc.end());
            }
        }
        out.draws.push_back(std::move(draw));
    }
    return out;
}

}  // namespace harness
