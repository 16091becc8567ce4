// workloads.hpp: the seeded triangle families `refraster study precision` measures.
//
// Implements: seven families of float32 clip-space triangles with one attribute and depth, every
// vertex in front of the eye and between the near and far planes (|z| < w), drawn from a seed with
// a generator whose output is the same on every platform (std::mt19937_64 with its own uniform
// mapping): "small" (1-4 pixels across), "medium" (10-50 pixels), "sliver" (20-150 pixels long,
// 0.02-1 pixel wide), "mesh" (a jittered grid of shared-edge quads split along random diagonals,
// covering the whole viewport, a quarter of its vertices on the 1/16-pixel grid so that edges
// pass exactly through pixel centres), "perspective" (medium triangles whose vertices' w spans
// up to four decades, w ratios up to 10^4), and "large-coordinates" (medium triangles anywhere
// in a 16384 x 16384 viewport, the largest Mesa's drivers accept, half of them in its far
// quarter), and "mesh-far" (the mesh in the far corner of that viewport, where float32 window
// coordinates keep only 10 fraction bits).
//
// Deliberately does not: produce triangles that need clipping (only the mesh's outer ring lies
// outside the viewport, which the kernels bound by pixels, not by a clipper), or degenerate ones on
// purpose (a sliver's area may still round to zero in some arithmetic: that is measured, not
// avoided).
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "variants.hpp"

namespace harness::study {

struct Family {
    std::string name;
    std::string description;
    Viewport viewport;
    std::vector<ClipTriangle> triangles;
    // A mesh: every centre of the square [mesh_x0, mesh_x0 + mesh_size)^2 lies in exactly one
    // triangle (watertightness is counted there).
    bool mesh = false;
    int mesh_x0 = 0;
    int mesh_size = 0;
};

// A platform-independent uniform double in [lo, hi).
class StudyRandom {
  public:
    explicit StudyRandom(std::uint64_t seed) : rng_(seed) {}
    double uniform(double lo, double hi) {
        const double u = static_cast<double>(rng_() >> 11) * 0x1p-53;
        return lo + (hi - lo) * u;
    }
    std::uint64_t bits() { return rng_(); }

  private:
    std::mt19937_64 rng_;
};

// Window position (pixels) and depth (NDC z) to a float32 clip-space vertex with the given w.
ClipVertex clip_vertex(const Viewport& vp, double wx, double wy, double zndc, double w,
                       double attribute);

std::vector<Family> precision_families(std::uint64_t seed, bool quick);

}  // namespace harness::study
