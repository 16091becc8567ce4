// reduce.hpp: delta debugging of a failing scene.
//
// Implements: reduce_scene, which shrinks a scene while it keeps the same mismatch signature
// (a mismatch against the backend, explained by the same rule at the pixel of largest
// difference, see explain.hpp): draws become explicit lists of primitives in the order the
// driver assembles them, then whole draws, then primitives (ddmin: halves, quarters, ... down
// to single primitives), then state keys and vertex coordinates (rounded to coarser binary
// grids) are tried one by one, each step printed.
//
// Deliberately does not: shrink the target or the viewport (the signature's pixel would
// move), or reduce below one primitive.
#pragma once

#include <array>
#include <iosfwd>
#include <optional>
#include <string>

#include "harness/backend.hpp"
#include "harness/scene.hpp"
#include "harness/scene_writer.hpp"  // scene_to_json, which writes the reduced scene

namespace harness {

// Which mismatch a reduction keeps: by default the one at the pixel of largest difference.
struct MismatchToKeep {
    std::optional<std::array<int, 2>> pixel;  // the mismatch at this pixel
    std::string difference;                   // the largest of this class: coverage, colour, depth
};

struct ReduceResult {
    SceneFile scene;
    std::string signature;  // "class: rule" of the kept mismatch
    std::size_t primitives_before = 0;
    std::size_t primitives_after = 0;
    int renders = 0;
};

// Throws std::runtime_error when the scene does not mismatch to begin with. Every render of the
// reference gets `timeout_seconds` of its own (0 or less: no limit); one that runs out of it
// ends the reduction with refraster::RenderStopped.
ReduceResult reduce_scene(const SceneFile& scene, const std::string& label,
                          const refraster::Profile& profile, Backend& backend, std::ostream& log,
                          const MismatchToKeep& keep = {}, double timeout_seconds = 0.0);

}  // namespace harness
