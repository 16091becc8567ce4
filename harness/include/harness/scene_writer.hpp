// scene_writer.hpp: writing a scene file back to JSON.
//
// Implements: scene_to_json, the inverse of the loader: every value the file held, defaults
// left out, so that loading the text gives the same SceneFile and the same draw list.
#pragma once

#include <string>

#include "harness/scene.hpp"

namespace harness {

// Textures (extension "textures") are written with their texels as base64 "data", and
// "textures" is added to "requires" when the scene uses the extension (uses_textures).
std::string scene_to_json(const SceneFile& s);

// Whether `s` uses the extension "textures": it defines a texture, a draw samples one, or a
// vertex has a texture coordinate other than the default (0, 0, 0, 1), bit for bit.
bool uses_textures(const SceneFile& s);

}  // namespace harness
