// setup_list.hpp: the hand-off between setup and traversal: set-up primitives in API order.
//
// Implements: SetupPrimitive, what the snapped model's setup makes of one triangle, line or
// point (its edge functions, bounding box, llvmpipe's own planes and walk where its integer
// widths decide the pixels, its attribute planes and its owner), and SetupList, a run of them in
// the order the API drew them with the pools their planes live in. A list holds any number of
// attributes: a primitive's planes are window z, 1/w, then one plane per attribute float
// (smooth and noperspective draws) or one constant per attribute float (flat draws).
// Setup fills a list and hands it on when full (as llvmpipe's setup bins into a scene and
// flushes it, lp_setup.c), so that tiles can be binned from it without holding a whole
// draw.
//
// Deliberately does not: bin into tiles yet, or hold the exact oracle's primitives
// (exact_model.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "models/llvmpipe/setup.hpp"

namespace refraster::detail {

struct Plane {
    float a0 = 0.0f;
    float dadx = 0.0f;
    float dady = 0.0f;
};

struct SetupPrimitive {
    int bits = 8;
    std::uint8_t edge_count = 3;  // 3: triangle, 4: line or point
    std::array<EdgeFunction, 4> edges;
    PixelRect bbox;
    // When llvmpipe's integer widths decide the pixels (TriangleSetup::llvmpipe_walk): the
    // index of its planes in SetupList::walks; -1 otherwise.
    std::int32_t walk = -1;
    std::uint32_t planes = 0;       // index in SetupList::planes of its z plane
    std::uint32_t flat = 0;         // index in SetupList::flat of its first constant (flat draws)
    float z_offset = 0.0f;          // polygon offset added to z
    std::uint8_t scissor_leak = 0;  // multisample_scissor_leak (setup.hpp)
    std::uint32_t owner = 0;        // owner_id of the API primitive
};

// Planes of a primitive in SetupList::planes, from SetupPrimitive::planes on.
inline constexpr std::size_t kZPlane = 0;
inline constexpr std::size_t kWPlane = 1;
inline constexpr std::size_t kFirstAttributePlane = 2;

struct SetupList {
    // Primitives a list holds before setup hands it on: bounded memory for draws of any
    // length, and few enough (about 60 KB with their planes) that traversal finds them still
    // in the cache; binning may want more.
    static constexpr std::size_t kCapacity = 256;
    // With shading threads (band_workers.hpp) each list handed on costs a wake-up and a wait,
    // which a list of small primitives does not repay: setup fills this many first (about
    // 1 MB with their planes).
    static constexpr std::size_t kThreadedCapacity = 4096;
    std::size_t capacity = kCapacity;

    std::size_t attribute_floats = 0;
    // Coverage is per sample (SetupParams::multisample): traversal tests each of a pixel's
    // four samples.
    bool multisample = false;
    std::vector<SetupPrimitive> primitives;
    std::vector<Plane> planes;
    std::vector<float> flat;
    std::vector<lp::Triangle> walks;  // the rare primitives llvmpipe_walk.hpp walks

    bool full() const { return primitives.size() >= capacity; }
    void clear() {
        primitives.clear();
        planes.clear();
        flat.clear();
        walks.clear();
    }
};

}  // namespace refraster::detail
