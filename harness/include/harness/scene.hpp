// scene.hpp: a scene file (format v1) as the harness holds it, and how to load one.
//
// Implements: the parsed, validated content of a scene file (docs/scene-format.md), in
// two layers. `SceneFile` keeps what the file says (positions as written, their space and
// matrix); `Scene` adds the API-neutral draw list the front end computes from it, identical
// for every backend.
//
// Deliberately does not: render, compare, or know any backend.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "refraster/draw.hpp"
#include "refraster/error.hpp"

namespace harness {

// The scene format's version string. The extensions this reader implements, "multisample",
// "vertex_arrays" and "textures", are checked by the loader (scene_reader.cpp); any other
// required name is unsupported.
inline constexpr const char* kSceneFormatV1 = "refraster-scene/1";

enum class VertexSpace : std::uint8_t { Window, Clip };

// One vertex as written in the file, each number already rounded once to float32.
struct SceneVertex {
    std::array<float, 4> position{0.0f, 0.0f, 0.0f, 1.0f};
    std::uint32_t position_size = 0;  // how many coordinates the file gave (2, 3 or 4)
    std::array<float, 4> color{1.0f, 1.0f, 1.0f, 1.0f};
    // (s, t, r, q); extension "textures". A file's [s, t] gives r = 0, q = 1.
    std::array<float, 4> texcoord{0.0f, 0.0f, 0.0f, 1.0f};
};

struct SceneDraw {
    refraster::PrimitiveType primitive = refraster::PrimitiveType::Triangles;
    VertexSpace space = VertexSpace::Window;
    std::optional<std::array<float, 16>> matrix;  // column-major; only with space "clip"
    std::vector<SceneVertex> vertices;
    std::optional<std::vector<std::uint32_t>> indices;
    refraster::DrawState state;  // viewport already defaulted to the whole target
    // The name of the texture `state.texture` samples (a key of SceneFile::textures), empty
    // without one. The front end turns it into state.texture->texture, the texture's index in
    // the draw list.
    std::string texture;
    // The file gave the vertices as "vertex_arrays" (extension "vertex_arrays") rather than
    // "vertices": the values are the same, only the paths of messages differ.
    bool from_vertex_arrays = false;
};

struct Expect {
    std::uint32_t color_tolerance = 0;        // in units of the target's last bit
    std::uint64_t max_mismatched_pixels = 0;  // pixels outside the tolerance
};

struct SceneFile {
    std::string name;
    std::string description;
    std::vector<std::string> requires_extensions;
    refraster::Target target;
    refraster::ClearValues clear;
    Expect expect;
    // Extension "textures": every texture the file defines, by name, decoded (RGBA8, rows
    // bottom to top, the given mipmap levels after the base). The draw list holds them all,
    // in this (name) order.
    std::map<std::string, refraster::Texture> textures;
    std::vector<SceneDraw> draws;
};

struct Scene {
    std::filesystem::path path;
    SceneFile file;
    refraster::DrawList draw_list;  // the front end's output
    // Required extensions this reader does not implement; non-empty means NotSupported.
    std::vector<std::string> unsupported_extensions;
};

// A refusal of bad input. `what()` is the whole one-line message:
//   FILE: JSON.PATH: what was expected        (a value that is wrong)
//   FILE:LINE:COLUMN: what was expected       (a file that does not parse)
//   FILE: what went wrong                     (a file that cannot be read)
class SceneError : public refraster::Error {
  public:
    SceneError(std::string file, std::string json_path, std::string message, std::size_t line = 0,
               std::size_t column = 0);
    const std::string& file() const { return file_; }
    const std::string& json_path() const { return json_path_; }
    const std::string& detail() const { return detail_; }
    std::size_t line() const { return line_; }
    std::size_t column() const { return column_; }

  private:
    std::string file_;
    std::string json_path_;
    std::string detail_;
    std::size_t line_;
    std::size_t column_;
};

// Largest scene file read, in bytes; a larger file is refused before it is parsed.
inline constexpr std::uintmax_t kMaxSceneFileBytes = std::uintmax_t{1} << 30;

// The work a scene may ask for (docs/limits.md). A valid scene beyond any of them is refused
// like bad input (SceneError, exit code 2) before anything is drawn, so that no file can make
// a run exhaust memory or take hours. The defaults are far above every shipped scene; callers
// may lower them (the renderer fuzzer does) but the CLI uses the defaults.
struct SceneLimits {
    std::uint64_t max_file_bytes = kMaxSceneFileBytes;
    std::uint32_t max_nesting_depth = 64;          // arrays and objects inside each other
    std::uint64_t max_json_values = 67'108'864;    // every value of the document counts one
    std::uint64_t max_target_pixels = 67'108'864;  // width x height x samples (format v1)
    std::uint64_t max_draws = 4'096;
    std::uint64_t max_vertices = 4'194'304;       // over all draws
    std::uint64_t max_indices = 4'194'304;        // over all draws
    std::uint64_t max_primitives = 4'194'304;     // assembled, over all draws
    std::uint64_t max_fragments = 2'147'483'648;  // estimated (estimate_work), over all draws
    std::uint64_t max_textures = 256;             // extension "textures"
    // RGBA8 texels over every level of every texture, those glGenerateMipmap makes included.
    std::uint64_t max_texel_bytes = std::uint64_t{1} << 30;
    // The largest texture file read (extension "textures", key "file"), in bytes: read whole
    // before it is decoded.
    std::uint64_t max_texture_file_bytes = std::uint64_t{1} << 27;
    // What files a scene may read as textures (docs/scene-format.md, "Texture files"): those
    // whose real path lies under the real path of the scene's folder (the folder of the scene
    // file; for load_scene_text and parse_scene the folder of the label, the working directory
    // when the label names none) or, when not empty, under this folder (the CLI's
    // --texture-root).
    std::filesystem::path texture_root;
};

// How the loader decodes the image file of a texture (extension "textures", key "file"): the
// loader opens and reads the file under its policy (docs/scene-format.md, "Texture files"),
// checks PNG's signature, the header and the size against the limits, then hands the whole
// file to this decoder, which returns RGBA8 texels, rows bottom to top, or throws any
// std::exception when it cannot decode them. harness_core decodes no image itself: linking
// harness_image_io installs its PNG decoder (image_io.hpp, read_texture_png); a program without
// it refuses "file" with a message that says so.
using TextureFileReader = refraster::TextureImage (*)(std::span<const std::uint8_t> png);
void set_texture_file_reader(TextureFileReader reader);
TextureFileReader texture_file_reader();

// An upper estimate of what rendering a draw list costs. `fragments` sums, over every
// assembled primitive, the pixels of its window-space bounding box (lines and points widened by
// their width or size, a pixel of margin) clipped to the target and scissor; a primitive with a
// vertex at w <= 0 counts the whole clipped region. Polygon modes line and point count each
// edge or corner. Culling and the depth test are ignored: the estimate never falls short.
struct SceneWork {
    std::uint64_t primitives = 0;
    std::uint64_t fragments = 0;
};
SceneWork estimate_work(const refraster::Draw& draw, const refraster::Target& target);
SceneWork estimate_work(const refraster::DrawList& list);

// `text` with every control character (and DEL) escaped as JSON does (\n, \t, \u0001), so that
// a message quoting a key, a path or a string from a file stays on one line.
std::string escape_for_message(std::string_view text);

// Parses and validates text that claims to be a scene file. `file_label` names it in errors;
// a texture's "file" is read relative to the directory of `file_label`'s path (load_scene: the
// scene file's own directory), and that directory (the working directory when the label has
// none) is the scene's folder its texture files must lie under (SceneLimits::texture_root).
SceneFile parse_scene(std::string_view text, const std::string& file_label,
                      const SceneLimits& limits = {});

// Reads, parses, validates and runs the front end. Throws SceneError on any bad input.
Scene load_scene(const std::filesystem::path& path, const SceneLimits& limits = {});

// The same from text already in memory (tests, generators, fuzzers): the one code path that
// load_scene also takes once it has read the file.
Scene load_scene_text(std::string_view text, const std::string& file_label,
                      const SceneLimits& limits = {});

}  // namespace harness
