// scene_text.hpp: scene files written in a chosen vertex form, and a seeded scene of many
// small triangles to load.
//
// Implements: scene_json_text, which writes a SceneFile with its vertices in the plain form
// ("vertices") or in the extension "vertex_arrays" (flat "values", or "float32_base64" with
// indices as "uint32_base64"), streamed so that millions of vertices cost no document in
// memory; every number as the shortest text that reads back to the same float32. And
// many_triangles_scene, the load benchmark's and the big-scene test's workload.
//
// Deliberately does not: time anything, or decide which form a tool writes (reduce keeps the
// plain form, scene_to_json).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <span>
#include <string>

#include "harness/scene.hpp"

namespace harness {

enum class VertexForm : std::uint8_t {
    Plain,   // "vertices": [{"position": [...], "color": [...]}, ...]
    Values,  // "vertex_arrays": {"count", "position": {"components", "values": [...]}, ...}
    Base64,  // "vertex_arrays" with "float32_base64"; indices as {"uint32_base64": ...}
};

// The file text; load_scene_text reads it back to the same SceneFile (with
// "vertex_arrays" added to `requires` for the compact forms). A draw's vertices must share one
// position size in the compact forms (std::invalid_argument otherwise).
std::string scene_json_text(const SceneFile& s, VertexForm form);

// The layout every scene file this project writes shares: one top-level key a line, each draw
// an object of one key a line; `draw(out, index, draw_json)` appends the fields of draw `index`
// (its object in `scene["draws"]`), each starting with `field(out)`. Everything else is the
// value's compact JSON.
using DrawFieldWriter =
    std::function<void(std::string& out, std::size_t index, const nlohmann::ordered_json& draw)>;
void open_draw_field(std::string& out, bool& first);
std::string lay_out_scene_json(const nlohmann::ordered_json& scene, const DrawFieldWriter& draw);

// `bytes` as base64 (RFC 4648, section 4, padded with '='), the spelling the loader reads.
std::string base64_text(std::span<const std::uint8_t> bytes);

// Whether a vertex's texture coordinate is the default (0, 0, 0, 1), and whether it is
// (s, t, 0, 1), which a file can spell [s, t]; bit for bit, so -0 is no default.
bool is_default_texcoord(const std::array<float, 4>& t);
bool is_two_component_texcoord(const std::array<float, 4>& t);

// `triangles` unindexed triangles of a few pixels each, scattered over a 1024 x 1024 target
// with depth, positions [x, y, z] on a 1/256 grid and colours on a 1/16 grid: the shape of
// scenes with millions of small triangles. The same seed gives the same scene.
SceneFile many_triangles_scene(std::uint64_t triangles, std::uint64_t seed);

}  // namespace harness
