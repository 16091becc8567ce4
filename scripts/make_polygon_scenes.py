#!/usr/bin/env python3
"""Writes the polygon scenes of conformance/scenes/polygons/ (scene format extension
"polygons": the primitive "polygon" and the draw state key "fill_rule"). Deterministic: the
same files every run.

    python3 scripts/make_polygon_scenes.py [OUTPUT_DIR]
"""
import json
import math
import os
import random
import sys

OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "conformance", "scenes", "polygons")

PALETTE = [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 0, 1], [1, 0, 1, 1], [0, 1, 1, 1],
           [1, 0.5, 0, 1], [0.5, 0, 1, 1], [0, 0.5, 0.25, 1], [0.75, 0.75, 0.75, 1]]


def vertices(points, colours=None, z=None):
    out = []
    for i, p in enumerate(points):
        pos = list(p)
        if z is not None and len(pos) == 2:
            pos.append(z)
        v = {"position": pos}
        v["color"] = (colours[i] if colours else PALETTE[i % len(PALETTE)])
        out.append(v)
    return out


def draw(points, state=None, primitive="polygon", colours=None, z=None, space=None,
         indices=None):
    d = {"primitive": primitive}
    if space:
        d["space"] = space
    d["vertices"] = vertices(points, colours, z)
    if indices is not None:
        d["indices"] = indices
    if state:
        d["state"] = state
    return d


def scene(name, description, draws, width=32, height=32, depth=None, color=None,
          clear=(0, 0, 0, 1), samples=None, clear_depth=None):
    target = {"width": width, "height": height}
    if color:
        target["color"] = color
    if depth:
        target["depth"] = depth
    if samples:
        target["samples"] = samples
    c = {"color": list(clear)}
    if clear_depth is not None:
        c["depth"] = clear_depth
    return name, {
        "format": "refraster-scene/1",
        "name": "polygons." + name,
        "description": description,
        "requires": ["polygons"],
        "target": target,
        "clear": c,
        "draws": draws,
    }


def star(cx, cy, r, n=5, step=2, rot=0.0, grid=256):
    """A star polygon {n/step}: vertex k at angle 90 + 360 k step / n degrees, snapped to a
    1/grid grid so that the window coordinates are exact."""
    pts = []
    for k in range(n):
        a = math.radians(90 + rot + 360.0 * k * step / n)
        pts.append([round((cx + r * math.cos(a)) * grid) / grid,
                    round((cy + r * math.sin(a)) * grid) / grid])
    return pts


def regular(cx, cy, r, n, rot=0.0, grid=256):
    return star(cx, cy, r, n, 1, rot, grid)


def main():
    rng = random.Random(17)
    scenes = []
    hexagon = regular(16, 16, 13, 6, 10)
    octagon = regular(16, 16, 14, 8, 5)
    pentagram = star(16, 16, 14.5)
    # An arrow pointing left, listed from the top of its shaft's end: the fan from v0 is not
    # the arrow (its triangles reach over the shaft into the notches above and below it).
    arrow = [[29, 21], [29, 11], [14, 11], [14, 3], [3, 16], [14, 29], [14, 21]]
    # Vertices on pixel centres: edges (horizontal, vertical and diagonal) through centres.
    centres = [[4.5, 4.5], [27.5, 4.5], [27.5, 27.5], [16.5, 16.5], [4.5, 27.5]]
    centre_star = [[4.5, 8.5], [27.5, 8.5], [8.5, 28.5], [16.5, 2.5], [24.5, 28.5]]

    scenes.append(scene(
        "convex_hexagon_flat_last",
        "A flat-shaded convex hexagon, last-vertex convention: GL_POLYGON's flat colour is its "
        "first vertex's (red), and llvmpipe splits it into the triangles (v[i-1], v[i], v0).",
        [draw(hexagon, {"shade": "flat"})]))
    scenes.append(scene(
        "convex_hexagon_flat_first",
        "The same hexagon under the first-vertex convention: the triangles (v0, v[i-1], v[i]), "
        "still red from v0.",
        [draw(hexagon, {"shade": "flat", "provoking_vertex": "first"})]))
    scenes.append(scene(
        "convex_octagon_smooth",
        "A smooth-shaded octagon: each triangle of the split interpolates its own three "
        "vertices' colours, set up in the split's vertex order.",
        [draw(octagon, {"shade": "smooth"})]))
    scenes.append(scene(
        "concave_arrow_fan",
        "A concave arrow drawn as GL_POLYGON: the union of its fan triangles from v0 (the end of "
        "its shaft), later triangles over earlier ones, which reach over the notch between the "
        "shaft and the head where a fill rule leaves it empty.",
        [draw(arrow, {"shade": "smooth"})]))
    scenes.append(scene(
        "pentagram_fan",
        "A self-intersecting pentagram drawn as GL_POLYGON's own triangles: the centre is covered "
        "twice and drawn by the later triangle; no fill rule.",
        [draw(pentagram, {"shade": "smooth"})]))
    scenes.append(scene(
        "outline_polygon_mode_line",
        "A concave polygon in polygon mode line: only its outline is drawn (the edge flags of "
        "the split leave out the fan's diagonals).",
        [draw(arrow, {"polygon_mode": "line", "shade": "flat"})]))
    scenes.append(scene(
        "outline_polygon_mode_line_first",
        "The outline under the first-vertex convention, whose split flags other edges of each "
        "triangle.",
        [draw(pentagram, {"polygon_mode": "line", "provoking_vertex": "first"})]))
    scenes.append(scene(
        "vertices_polygon_mode_point",
        "A hexagon in polygon mode point with 3-pixel points: each vertex drawn once.",
        [draw(hexagon, {"polygon_mode": "point", "point_size": 3})]))
    scenes.append(scene(
        "outline_clipped",
        "An octagon crossing the viewport's left and top edges in polygon mode line: the edges "
        "the clipper makes along the viewport are not drawn.",
        [draw(regular(6, 26, 13, 8, 5), {"polygon_mode": "line", "line_width": 2})]))
    scenes.append(scene(
        "cull_back_per_triangle",
        "A pentagram drawn as GL_POLYGON with back faces culled: each triangle of the split is "
        "culled by its own orientation, so some of the star's triangles remain.",
        [draw(pentagram, {"cull": "back"})]))
    scenes.append(scene(
        "indexed_polygon",
        "A polygon drawn through indices (the vertices listed out of order); the split follows "
        "the index order.",
        [draw([hexagon[3], hexagon[0], hexagon[4], hexagon[1], hexagon[5], hexagon[2]],
              {"shade": "smooth"}, indices=[1, 3, 5, 0, 2, 4])]))
    scenes.append(scene(
        "multisample_4x_polygon",
        "A smooth octagon on a 4x target: its triangles are covered per sample and resolved.",
        [draw(octagon, {"shade": "smooth"})], samples=4))

    scenes.append(scene(
        "pentagram_evenodd",
        "A pentagram with the even-odd rule: the pentagon in the middle is crossed twice and "
        "stays empty; each lit pixel is drawn by the first of the polygon's triangles covering "
        "it (the stencil method's cover pass).",
        [draw(pentagram, {"fill_rule": "evenodd", "shade": "flat"})]))
    scenes.append(scene(
        "pentagram_nonzero",
        "The same pentagram with the non-zero rule: the middle has winding number 2 and is lit.",
        [draw(pentagram, {"fill_rule": "nonzero", "shade": "flat"})]))
    scenes.append(scene(
        "pentagram_evenodd_smooth",
        "The even-odd pentagram smooth-shaded: each lit pixel takes the colour of the first "
        "triangle of the split that covers it.",
        [draw(pentagram, {"fill_rule": "evenodd", "shade": "smooth"})]))
    scenes.append(scene(
        "centre_edges_evenodd",
        "A concave polygon with its vertices on pixel centres, so that horizontal, vertical and "
        "diagonal edges pass through centres: a centre on the polygon's edge is lit iff the "
        "region just right of it (just above, for a horizontal edge) is inside.",
        [draw(centres, {"fill_rule": "evenodd"})]))
    scenes.append(scene(
        "centre_edges_nonzero",
        "A self-intersecting star with vertices on pixel centres under the non-zero rule: the "
        "tie rule on the polygon's own edges, and no crack or double hit on the split's "
        "diagonals.",
        [draw(centre_star, {"fill_rule": "nonzero"})]))
    scenes.append(scene(
        "centre_edges_evenodd_star",
        "The same star under the even-odd rule.",
        [draw(centre_star, {"fill_rule": "evenodd"})]))
    twice = regular(16, 16, 13, 7, 0) + regular(16, 16, 13, 7, 0)
    scenes.append(scene(
        "wound_twice_nonzero",
        "A heptagon traced twice around: winding number 2 everywhere inside, lit by the "
        "non-zero rule.",
        [draw(twice, {"fill_rule": "nonzero"})]))
    scenes.append(scene(
        "wound_twice_evenodd",
        "The heptagon traced twice around under the even-odd rule: every inside pixel is "
        "crossed twice and nothing is lit.",
        [draw(twice, {"fill_rule": "evenodd"})]))
    tri = [[16, 2.25], [30.5, 29], [1.5, 29]]
    scenes.append(scene(
        "wound_256_times_nonzero",
        "A triangle traced 256 times: its winding number 256 wraps to 0 in the stencil's 8 bits "
        "(INCR_WRAP), so the non-zero rule lights nothing; the same triangle traced 257 times "
        "beside it is lit.",
        [draw(tri * 256, {"fill_rule": "nonzero", "viewport": [0, 0, 32, 32]}),
         draw(tri * 257, {"fill_rule": "nonzero", "viewport": [32, 0, 32, 32]})],
        width=64))
    eight = [[4, 4], [28, 28], [28, 4], [4, 28]]
    scenes.append(scene(
        "bowtie_nonzero",
        "A bow tie whose two lobes wind in opposite directions: both have winding number +1 or "
        "-1 and are lit by the non-zero rule.",
        [draw(eight, {"fill_rule": "nonzero", "shade": "smooth"})]))
    scenes.append(scene(
        "clipped_evenodd",
        "A pentagram crossing every side of a 24x24 viewport: the stencil pass counts the "
        "triangles as the clipper cuts them, and the viewport bounds the fill.",
        [draw(star(16, 16, 22), {"fill_rule": "evenodd", "viewport": [4, 4, 24, 24]})]))
    behind = [[-0.6, -0.7, 0, 1], [0.8, -0.5, 0, 1], [0.3, 0.9, 0, -0.5], [-0.9, 0.6, 0, 1],
              [0.5, 0.1, 0, 1]]
    scenes.append(scene(
        "behind_eye_nonzero",
        "A self-intersecting polygon in clip space with a vertex behind the eye (w < 0): the "
        "clipper cuts the split's triangles against the near and side planes before the "
        "stencil pass counts them.",
        [draw(behind, {"fill_rule": "nonzero"}, space="clip")]))
    scenes.append(scene(
        "scissored_evenodd",
        "The even-odd pentagram under a scissor: only the scissor's pixels count and draw.",
        [draw(pentagram, {"fill_rule": "evenodd", "scissor": [9, 5, 13, 20]})]))
    comb = []
    for k in range(6):
        x = 3 + 4.5 * k
        comb += [[x, 4.25], [x + 2.25, 28.5]]
    comb += [[29.5, 4.25], [29.5, 2], [2.5, 2]]
    scenes.append(scene(
        "comb_evenodd",
        "A comb of 15 vertices under the even-odd rule: long thin teeth whose fan triangles from "
        "v0 overlap many times.",
        [draw(comb, {"fill_rule": "evenodd", "shade": "smooth"})]))
    scenes.append(scene(
        "depth_cover_z24",
        "A depth-tested even-odd pentagram over a tilted triangle on z24: the first triangle of "
        "the split to reach a pixel takes it, whether or not its depth test passes, as the "
        "stencil cover pass (GL_ZERO on depth fail) does.",
        [draw([[0, 0, 0.2], [32, 0, 0.8], [0, 32, 0.8]], {"depth_test": "less"},
              primitive="triangles", colours=[[0.3, 0.3, 0.3, 1]] * 3),
         draw([p + [0.3 + 0.02 * i] for i, p in enumerate(pentagram)],
              {"fill_rule": "evenodd", "depth_test": "less", "shade": "smooth"})],
        depth="z24"))
    scenes.append(scene(
        "depth_cover_z32f",
        "The depth-tested cover pass on a z32f target (a combined depth and stencil buffer).",
        [draw([[0, 0, 0.2], [32, 0, 0.8], [0, 32, 0.8]], {"depth_test": "less"},
              primitive="triangles", colours=[[0.3, 0.3, 0.3, 1]] * 3),
         draw([p + [0.3 + 0.02 * i] for i, p in enumerate(pentagram)],
              {"fill_rule": "nonzero", "depth_test": "lequal", "shade": "smooth"})],
        depth="z32f"))
    scenes.append(scene(
        "blend_add_once",
        "A non-zero pentagram drawn with additive blending: the middle, covered by two of the "
        "split's triangles, is drawn once.",
        [draw(pentagram, {"fill_rule": "nonzero", "blend": "add"},
              colours=[[0.25, 0.125, 0.5, 1]] * 5)]))
    scenes.append(scene(
        "rgba32f_smooth_evenodd",
        "The smooth even-odd pentagram on an rgba32f target: float colours of the first "
        "covering triangle.",
        [draw(pentagram, {"fill_rule": "evenodd", "shade": "smooth"})], color="rgba32f"))
    rpts = [[round(rng.uniform(2, 30) * 4) / 4, round(rng.uniform(2, 30) * 4) / 4]
            for _ in range(12)]
    scenes.append(scene(
        "random_twelve_evenodd",
        "Twelve random vertices on the quarter-pixel grid, under the even-odd rule.",
        [draw(rpts, {"fill_rule": "evenodd", "shade": "smooth"})]))
    scenes.append(scene(
        "random_twelve_nonzero",
        "The same twelve vertices under the non-zero rule.",
        [draw(rpts, {"fill_rule": "nonzero", "shade": "smooth"})]))

    # A {13/5} star whose vertices sit 1/512 pixel right of and above half-pixel positions, in
    # a viewport starting left of the target: an even-odd fill, then a blended non-zero fill
    # over it. Under softpipe each fill's stencil clear writes the colour tiles back, so the
    # blend reads the bytes of the clear and of the first fill, not their floats.
    star13 = [[math.floor(x) + 0.5 + 1 / 512, math.floor(y) + 0.5 + 1 / 512]
              for x, y in star(32, 32, 29.5, 13, 5, 7.0, 4096)]
    scenes.append(scene(
        "blend_over_fill_star",
        "A blended non-zero {13/5} star over an even-odd one, vertices 1/512 pixel beside "
        "half-pixel positions, in a viewport starting at x = -16: softpipe's stencil clear of "
        "each fill writes its colour tiles back (the clear colour's included), so blending "
        "reads bytes.",
        [draw(star13, {"fill_rule": "evenodd", "viewport": [-16, 0, 128, 64]},
              colours=[PALETTE[i % len(PALETTE)] for i in range(13)]),
         draw(star13, {"fill_rule": "nonzero", "blend": "alpha", "viewport": [-16, 0, 128, 64]},
              colours=[[0.2 + 0.05 * i, 0.9 - 0.06 * i, 0.35 + 0.04 * i, 0.3 + 0.05 * i]
                       for i in range(13)])],
        width=64, height=64, clear=(0.3, 0.6, 0.1, 1)))

    os.makedirs(OUT, exist_ok=True)
    for name, s in scenes:
        with open(os.path.join(OUT, name + ".json"), "w") as f:
            json.dump(s, f, indent=1)
            f.write("\n")
    print(f"wrote {len(scenes)} scenes to {OUT}")


if __name__ == "__main__":
    main()
