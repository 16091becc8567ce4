// ear_clipping.hpp: triangulation of a simple polygon by cutting off ears.
//
// Implements: ear clipping after Meisters 1975 ("Polygons have ears", American Mathematical
// Monthly 82(6)): every simple polygon with more than three vertices has an ear, a vertex v
// whose neighbours u and w see each other through the polygon's interior, so that the
// triangle (u, v, w) can be cut off, leaving a simple polygon with one vertex fewer. Here v is
// an ear when it is strictly convex (the turn u, v, w has the polygon's orientation, not 0)
// and no other remaining vertex lies in the closed triangle (u, v, w). The search starts at
// the vertex after the last ear cut, and walks the remaining vertices in order; each ear found
// is cut at once (O(n^3) in the worst case, plain and predictable for teaching).
//
// Either orientation: the orientation is the sign of the shoelace area, and the triangles
// keep it. Collinear vertices: a vertex whose neighbours are collinear with it is never an
// ear (its triangle would have no area); it is cut later as a corner of another ear. A vertex
// on the segment u w blocks that ear, since u w would then touch the boundary. So no output
// triangle has zero area.
//
// Exactness: vertices snapped to 1/256 pixel (snap.hpp); the predicates are integer
// orientations of snapped values, exact.
//
// Deliberately does not: accept self-intersecting polygons or polygons with holes (the result
// is then unspecified, and complete may be false), pick ears for triangle quality, or run in
// O(n^2) with an ear list.
#pragma once

#include <array>
#include <vector>

#include "refraster/textbook/trace.hpp"

namespace refraster::textbook {

struct EarClipResult {
    std::vector<std::array<int, 3>> triangles;  // indices into the polygon: (u, v, w), v the ear
    bool complete = false;  // n - 2 triangles were cut (false for degenerate input)
};

EarClipResult ear_clip(const std::vector<Point2>& polygon, Trace* trace = nullptr);

}  // namespace refraster::textbook
