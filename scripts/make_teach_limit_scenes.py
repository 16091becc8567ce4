#!/usr/bin/env python3
"""Writes the scenes at teach's bounds that docs/limits.md ("Teaching pages") measures: each as
large as the bounds let the algorithm's input be, on a 256 x 256 target (65,536 pixels).
Deterministic: the same files every run.

    python3 scripts/make_teach_limit_scenes.py OUTPUT_DIR

comb4096.json   a polygon comb of 2,047 teeth (4,096 vertices): scanline, flood fills
comb1024.json   a polygon comb of 511 teeth (1,024 vertices): ear clipping, trapezoids
tris1365.json   1,365 random triangles (4,095 vertices), depth tested: painter, homogeneous,
                half-space
lines2048.json  2,048 random segments (4,096 vertices): the line algorithms
points4096.json 4,096 random points of size 64: the midpoint circle
sliver.json     one sliver along the diagonal of a 16384 x 4 target, no pixel centre inside it:
                the flood fills' seed search
"""
import json
import os
import random
import sys

W = H = 256


def scene(name, draws, width=W, height=H, depth=False, polygons=False):
    s = {"format": "refraster-scene/1", "name": name,
         "target": {"width": width, "height": height}, "clear": {"color": [0, 0, 0, 1]},
         "draws": draws}
    if depth:
        s["target"]["depth"] = "z24"
    if polygons:
        s["requires"] = ["polygons"]
    return s


def comb(teeth):
    step = (W - 2.0) / (2 * teeth)
    pts = [[1, 1], [1 + 2 * teeth * step, 1]]
    for i in range(teeth, 0, -1):
        pts.append([1 + 2 * i * step, H - 1])
        pts.append([1 + (2 * i - 1) * step, 2])
    return pts


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    rng = random.Random(1)
    files = {
        "comb4096.json": scene("teach_limits.comb4096", [
            {"primitive": "polygon", "vertices": [{"position": p} for p in comb(2047)]}],
            polygons=True),
        "comb1024.json": scene("teach_limits.comb1024", [
            {"primitive": "polygon", "vertices": [{"position": p} for p in comb(511)]}],
            polygons=True),
        "tris1365.json": scene("teach_limits.tris1365", [
            {"primitive": "triangles", "state": {"depth_test": "less"},
             "vertices": [{"position": [rng.uniform(0, W), rng.uniform(0, H), rng.uniform(0, 1)]}
                          for _ in range(3 * 1365)]}], depth=True),
        "lines2048.json": scene("teach_limits.lines2048", [
            {"primitive": "lines",
             "vertices": [{"position": [rng.uniform(0, W), rng.uniform(0, H)]}
                          for _ in range(2 * 2048)]}]),
        "points4096.json": scene("teach_limits.points4096", [
            {"primitive": "points", "state": {"point_size": 64},
             "vertices": [{"position": [rng.uniform(0, W), rng.uniform(0, H)]}
                          for _ in range(4096)]}]),
        "sliver.json": scene("teach_limits.sliver", [
            {"primitive": "triangles",
             "vertices": [{"position": [0, 0]}, {"position": [16384, 4]},
                          {"position": [16384, 4.00001]}]}], width=16384, height=4),
    }
    for name, s in files.items():
        with open(os.path.join(out, name), "w") as f:
            json.dump(s, f)
            f.write("\n")


if __name__ == "__main__":
    main()
