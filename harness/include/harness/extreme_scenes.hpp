// extreme_scenes.hpp: a seeded generator of stiff and extreme scenes.
//
// Implements: one scene per kind (about fifty kinds) from a seed: coordinates at float's limits
// and below its normal range in every component, tiny w of both signs, vertices far beyond any
// guard band, the largest viewports and targets the format allows, 16,000-pixel slivers,
// triangles collinear in float but not after snapping (attribute planes of NaN) with every
// depth format, draws of more than 4,095 vertices that clip and cull, depth at the range
// limits with huge polygon offsets, colours far out of range into rgba8 and rgba32f with
// blending, width-255 lines and size-255 points across the clip planes, and perspective with
// a w ratio of 10^8. Each scene is named "extreme.<kind>" and carries a description; the same
// seed gives the same scenes.
//
// Deliberately does not: render anything, or know which backend will draw the scenes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "harness/scene.hpp"

namespace harness {

// Every kind the generator knows, in a fixed order.
std::vector<std::string> extreme_kinds();

// The scene of one kind for `seed` (its name: "extreme." + kind). Throws std::invalid_argument
// for an unknown kind.
SceneFile extreme_scene(const std::string& kind, std::uint64_t seed);

// A scene as JSON text, one vertex a line, that load_scene_text reads back to the same values.
std::string extreme_scene_json(const SceneFile& s);

// Writes every kind's scene for `seed` as DIR/<kind>.json (each file complete or absent);
// returns 0, or 2 after one line on `err`.
int write_extreme_scenes(std::uint64_t seed, const std::filesystem::path& dir, std::ostream& err);

}  // namespace harness
