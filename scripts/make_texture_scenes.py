#!/usr/bin/env python3
"""Writes the texture scenes of conformance/scenes/textures/ (scene format extension
"textures"). Deterministic: the same files every run.

    python3 scripts/make_texture_scenes.py [OUTPUT_DIR]
"""
import base64
import json
import os
import random
import struct
import sys
import zlib

OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "conformance", "scenes", "textures")


def image(w, h, kind="random", seed=1):
    """RGBA8 bytes, rows bottom to top."""
    rng = random.Random(seed * 7919 + w * 131 + h)
    out = bytearray()
    for y in range(h):
        for x in range(w):
            if kind == "random":
                out += bytes(rng.randrange(256) for _ in range(4))
            elif kind == "checker":
                on = (x + y) % 2 == 0
                out += bytes([230, 40, 40, 255] if on else [30, 60, 220, 255])
            elif kind == "gradient":
                out += bytes([(x * 255) // max(1, w - 1), (y * 255) // max(1, h - 1),
                              (x * 37 + y * 91) % 256, 255 - (x * 11) % 256])
            elif kind == "alpha":
                out += bytes([rng.randrange(256), rng.randrange(256), rng.randrange(256),
                              (x * 255) // max(1, w - 1)])
            else:
                raise ValueError(kind)
    return bytes(out)


def level_colour(level):
    colours = [(255, 0, 0), (0, 255, 0), (0, 0, 255), (255, 255, 0), (255, 0, 255),
               (0, 255, 255), (255, 255, 255), (128, 128, 128)]
    return colours[level % len(colours)]


def solid(w, h, rgb, jitter_seed=None):
    rng = random.Random(jitter_seed) if jitter_seed is not None else None
    out = bytearray()
    for _ in range(w * h):
        if rng:
            out += bytes([max(0, min(255, c + rng.randrange(-40, 41))) for c in rgb] + [255])
        else:
            out += bytes(list(rgb) + [255])
    return bytes(out)


def b64(data):
    return base64.b64encode(data).decode("ascii")


def texture(w, h, kind="random", seed=1, mipmaps=None, levels=None):
    t = {"width": w, "height": h, "data": b64(image(w, h, kind, seed))}
    if mipmaps:
        t["mipmaps"] = "generate"
    if levels is not None:
        t["levels"] = levels
    return t


def quad(x0, y0, x1, y1, st0, st1, w=(1, 1, 1, 1), color=(1, 1, 1, 1), z=0.0):
    """Two triangles covering [x0,x1]x[y0,y1]; texcoords (s,t) bilinear over the corners.
    `w` gives each corner's w (bottom-left, bottom-right, top-right, top-left)."""
    corners = [(x0, y0, st0[0], st0[1]), (x1, y0, st1[0], st0[1]), (x1, y1, st1[0], st1[1]),
               (x0, y1, st0[0], st1[1])]
    verts = []
    for i in (0, 1, 2, 0, 2, 3):
        x, y, s, t = corners[i]
        wi = w[i]
        verts.append({"position": [x, y, z, wi], "color": list(color), "texcoord": [s, t]})
    return verts


def scene(name, description, draws, textures, width=32, height=32, depth="none", samples=1,
          clear=(0.0, 0.0, 0.0, 1.0)):
    requires = ["textures"]
    s = {
        "format": "refraster-scene/1",
        "name": "textures." + name,
        "description": description,
        "requires": requires,
        "target": {"width": width, "height": height, "color": "rgba8", "depth": depth},
        "clear": {"color": list(clear), "depth": 1.0},
        "textures": textures,
        "draws": draws,
    }
    if samples != 1:
        s["target"]["samples"] = samples
    return s


def tex_state(name="tex", min_filter="linear", mag_filter="linear", wrap_s="repeat",
              wrap_t="repeat", env="modulate", border=None):
    st = {"name": name, "min_filter": min_filter, "mag_filter": mag_filter, "wrap_s": wrap_s,
          "wrap_t": wrap_t, "env": env}
    if border is not None:
        st["border_color"] = border
    return st


def draw(vertices, tstate, primitive="triangles", **state):
    st = {"texture": tstate}
    st.update(state)
    return {"primitive": primitive, "vertices": vertices, "state": st}


def png_bytes(w, h, rgba_bottom_up):
    """A PNG (8-bit RGBA, top row first) of bottom-to-top RGBA bytes."""
    rows = [rgba_bottom_up[(h - 1 - y) * w * 4:(h - y) * w * 4] for y in range(h)]
    raw = b"".join(b"\x00" + r for r in rows)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(
            ">I", zlib.crc32(tag + data) & 0xffffffff)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main():
    os.makedirs(OUT, exist_ok=True)
    scenes = []

    def add(s):
        scenes.append(s)

    full = (0, 0, 32, 32)
    # Magnification: a 4x4 texture over 32x32 pixels, every filter and wrap pair.
    for wrap in ["repeat", "clamp_to_edge", "mirrored_repeat", "clamp_to_border"]:
        for f in ["nearest", "linear"]:
            lo, hi = (-0.75, 1.75) if wrap != "repeat" else (0.0, 1.0)
            add(scene(f"magnify_{f}_{wrap}",
                      f"A 4x4 texture magnified over 32x32 pixels with {f} filtering and "
                      f"{wrap} on both axes; coordinates from {lo} to {hi} reach beyond the "
                      f"image where the wrap matters.",
                      [draw(quad(*full, (lo, lo), (hi, hi)),
                            tex_state(min_filter=f, mag_filter=f, wrap_s=wrap, wrap_t=wrap,
                                      border=[0.2, 0.9, 0.4, 1.0]))],
                      {"tex": texture(4, 4, "random", 11)}))
    # Mixed wraps: one float-path wrap sends both axes to the float path.
    for ws, wt in [("repeat", "mirrored_repeat"), ("clamp_to_edge", "clamp_to_border"),
                   ("mirrored_repeat", "clamp_to_edge"), ("clamp_to_border", "repeat")]:
        add(scene(f"mixed_{ws}_{wt}",
                  f"Bilinear with wrap_s {ws} and wrap_t {wt}: the float path on both axes "
                  "(only repeat and clamp-to-edge on both keep the 8-bit path).",
                  [draw(quad(*full, (-1.3, -0.7), (2.1, 1.9)),
                        tex_state(wrap_s=ws, wrap_t=wt, border=[1.0, 0.5, 0.0, 0.5]))],
                  {"tex": texture(5, 3, "random", 12)}))
    # Minification without mipmaps.
    for f in ["nearest", "linear"]:
        add(scene(f"minify_{f}_no_mipmaps",
                  f"A 64x64 texture minified onto 16x16 pixels with {f} filtering and no "
                  "mipmaps: the same code as magnification (no LOD is computed).",
                  [draw(quad(8, 8, 24, 24, (0.0, 0.0), (1.0, 1.0)),
                        tex_state(min_filter=f, mag_filter=f))],
                  {"tex": texture(64, 64, "random", 13)}))
    # Min and mag filters that differ: decided per 2x2 quad by rho^2 > 1.
    for path, wrap in [("8bit", "repeat"), ("float", "mirrored_repeat")]:
        add(scene(f"min_nearest_mag_linear_{path}",
                  "A perspective quad whose texel density crosses one texel per pixel: quads "
                  "with rho^2 > 1 take the min filter (nearest), the others the mag filter "
                  f"(linear); wrap {wrap}, the {path} path.",
                  [draw(quad(0, 0, 32, 32, (0.0, 0.0), (1.0, 4.0), w=(1, 1, 6, 6)),
                        tex_state(min_filter="nearest", mag_filter="linear", wrap_s=wrap,
                                  wrap_t=wrap))],
                  {"tex": texture(16, 16, "random", 14)}))
    # Sizes that are not powers of two.
    for (w, h), wrap, f in [((13, 7), "repeat", "nearest"), ((13, 7), "repeat", "linear"),
                            ((5, 24), "mirrored_repeat", "linear"),
                            ((100, 37), "clamp_to_edge", "linear"),
                            ((7, 13), "clamp_to_border", "nearest")]:
        add(scene(f"npot_{w}x{h}_{wrap}_{f}",
                  f"A {w}x{h} texture (not a power of two), {wrap}, {f}: repeat of such a "
                  "size takes the fraction of the coordinate before scaling.",
                  [draw(quad(*full, (-1.25, -0.6), (2.5, 1.7)),
                        tex_state(min_filter=f, mag_filter=f, wrap_s=wrap, wrap_t=wrap,
                                  border=[0.0, 0.0, 0.0, 1.0]))],
                  {"tex": texture(w, h, "random", w * 100 + h)}))
    # 1x1 and 1xN.
    for (w, h) in [(1, 1), (1, 16), (16, 1)]:
        add(scene(f"size_{w}x{h}",
                  f"A {w}x{h} texture, bilinear with repeat: a single texel column or row "
                  "wraps onto itself.",
                  [draw(quad(*full, (-0.5, -0.5), (2.5, 2.5)), tex_state())],
                  {"tex": texture(w, h, "gradient", 3)}))
    # Texel centres and edges, exactly.
    add(scene("texel_centres_nearest",
              "A 16x16 texture mapped 2 pixels a texel with coordinates on texel centres and "
              "halfway points (a binary grid, exact in float): nearest reads each texel.",
              [draw(quad(0, 0, 32, 32, (0.0, 0.0), (1.0, 1.0)),
                    tex_state(min_filter="nearest", mag_filter="nearest"))],
              {"tex": texture(16, 16, "random", 21)}))
    add(scene("texel_centres_linear",
              "A 32x32 texture mapped one texel a pixel, texel centre on pixel centre: the 8.8 "
              "weights are 0 and bilinear returns each texel unfiltered.",
              [draw(quad(0, 0, 32, 32, (0.0, 0.0), (1.0, 1.0)), tex_state())],
              {"tex": texture(32, 32, "random", 22)}))
    add(scene("texel_edges_linear",
              "A 32x32 texture shifted half a texel: every pixel centre lies on a texel corner, "
              "weight 128/256 on both axes.",
              [draw(quad(0, 0, 32, 32, (0.015625, 0.015625), (1.015625, 1.015625)),
                    tex_state())],
              {"tex": texture(32, 32, "random", 23)}))
    add(scene("texel_edges_nearest_float_path",
              "A 16x16 texture, mirrored repeat (the float path), nearest, with pixel centres "
              "exactly on texel edges: floor picks the texel above the edge.",
              [draw(quad(0, 0, 32, 32, (-0.03125, -0.03125), (0.96875, 0.96875)),
                    tex_state(min_filter="nearest", mag_filter="nearest",
                              wrap_s="mirrored_repeat", wrap_t="mirrored_repeat"))],
              {"tex": texture(16, 16, "random", 24)}))
    add(scene("bilinear_weight_tie",
              "A 1:1 mapping of a 32x32 texture shifted by half of 1/256 texel: u*W*256 is "
              "exactly k + 0.5 at every pixel and rounds to even (weight 0).",
              [draw(quad(0, 0, 32, 32, (0.00006103515625, 0.00006103515625),
                         (1.00006103515625, 1.00006103515625)),
                    tex_state())],
              {"tex": texture(32, 32, "random", 25)}))
    # Perspective.
    for f in ["linear", "linear_mipmap_linear"]:
        add(scene(f"perspective_steep_{f}",
                  f"A floor receding with a w ratio of 8 across the quad, min filter {f}: the "
                  "coordinates are perspective-correct and the LOD changes per 2x2 quad.",
                  [draw(quad(0, 0, 32, 32, (0.0, 0.0), (2.0, 8.0), w=(1, 1, 8, 8)),
                        tex_state(min_filter=f, mag_filter="linear"))],
                  {"tex": texture(32, 32, "checker", 1, mipmaps=True)}, depth="z24"))
    add(scene("noperspective_coordinates",
              "The receding floor with noperspective shading: texture coordinates interpolate "
              "in screen space.",
              [draw(quad(0, 0, 32, 32, (0.0, 0.0), (2.0, 8.0), w=(1, 1, 8, 8)),
                    tex_state(), shade="noperspective")],
              {"tex": texture(16, 16, "random", 31)}))
    add(scene("flat_coordinates",
              "Flat shading: the provoking vertex's texture coordinate over the whole triangle "
              "(no derivatives, so the mag filter).",
              [draw(quad(0, 0, 32, 32, (0.1, 0.2), (0.9, 0.8)),
                    tex_state(min_filter="nearest_mipmap_nearest"), shade="flat")],
              {"tex": texture(8, 8, "random", 32, mipmaps=True)}))
    add(scene("projective_q",
              "Texture coordinates with q other than 1: sampled at (s * (1/q), t * (1/q)), the "
              "reciprocal a true division.",
              [draw([{"position": p, "color": [1, 1, 1, 1], "texcoord": tc} for p, tc in [
                  ([1, 1], [0.0, 0.0, 0.0, 1.0]), ([31, 1], [3.0, 0.0, 0.0, 3.0]),
                  ([31, 31], [1.5, 1.5, 0.0, 1.5]), ([1, 1], [0.0, 0.0, 0.0, 1.0]),
                  ([31, 31], [1.5, 1.5, 0.0, 1.5]), ([1, 31], [0.0, 0.7, 0.0, 0.7])]],
                    tex_state())],
              {"tex": texture(8, 8, "random", 33)}))
    # Mipmaps: level selection with distinct colours per level.
    given_levels = []
    for l in range(1, 7):
        n = 64 >> l
        given_levels.append({"width": n, "height": n,
                             "data": b64(solid(n, n, level_colour(l), jitter_seed=l))})
    base_levels = {"width": 64, "height": 64, "data": b64(solid(64, 64, level_colour(0), 0)),
                   "levels": given_levels}
    for f in ["nearest_mipmap_nearest", "linear_mipmap_nearest", "nearest_mipmap_linear",
              "linear_mipmap_linear"]:
        add(scene(f"mipmap_levels_{f}",
                  f"A 64x64 texture with given levels of distinct colours, min filter {f}, "
                  "on a receding quad: each 2x2 quad's level (or pair of levels and weight) "
                  "shows in its colour.",
                  [draw(quad(0, 0, 32, 32, (0.0, 0.0), (1.0, 16.0), w=(1, 1, 10, 10)),
                        tex_state(min_filter=f, mag_filter="nearest"))],
                  {"tex": dict(base_levels)}))
        add(scene(f"mipmap_generated_{f}",
                  f"A 32x32 random texture with glGenerateMipmap's levels, min filter {f}, "
                  "minified by 1 to 16 across the quad.",
                  [draw(quad(0, 0, 32, 32, (0.0, 0.0), (1.0, 16.0), w=(1, 1, 8, 8)),
                        tex_state(min_filter=f))],
                  {"tex": texture(32, 32, "random", 41, mipmaps=True)}))
    add(scene("mipmap_generated_odd_sizes",
              "glGenerateMipmap of a 7x13 texture (odd sizes: not a box filter), every level "
              "shown by scaling a quad per level (nearest_mipmap_nearest).",
              [draw(quad(i * 6, 0, i * 6 + 6, 32, (0.0, 0.0),
                         (7.0 * 2 ** i / 6.0 / 8.0 * 1.0, 13.0 * 2 ** i / 32.0)),
                    tex_state(min_filter="nearest_mipmap_nearest", mag_filter="nearest"))
               for i in range(5)],
              {"tex": texture(7, 13, "random", 42, mipmaps=True)}))
    add(scene("mipmap_partial_chain",
              "Given levels 1 and 2 only of a 16x16 texture: GL_TEXTURE_MAX_LEVEL is the last "
              "given level, so deeper minification stays on level 2.",
              [draw(quad(0, 0, 32, 32, (0.0, 0.0), (4.0, 32.0), w=(1, 1, 6, 6)),
                    tex_state(min_filter="nearest_mipmap_linear"))],
              {"tex": {"width": 16, "height": 16, "data": b64(solid(16, 16, (200, 50, 50), 5)),
                       "levels": [{"width": 8, "height": 8,
                                   "data": b64(solid(8, 8, (50, 200, 50), 6))},
                                  {"width": 4, "height": 4,
                                   "data": b64(solid(4, 4, (50, 50, 200), 7))}]}}))
    # LOD boundaries: affine quads whose rho is exactly around 2^(k - 1/2) and 2^k.
    draws = []
    for i, rho in enumerate([0.70703125, 0.70721435546875, 1.0, 1.4141845703125,
                             1.4143066406250, 2.0, 2.828125, 2.8284912109375]):
        x0 = (i % 4) * 8
        y0 = (i // 4) * 16
        span = rho * 8.0 / 16.0  # 8 pixels cover `span` of a 16-texel texture
        draws.append(draw(quad(x0, y0, x0 + 8, y0 + 16, (0.0, 0.0), (span, span * 2)),
                          tex_state(min_filter="nearest_mipmap_nearest",
                                    mag_filter="nearest")))
    add(scene("lod_boundaries",
              "Eight affine quads with rho at and around sqrt(2)^k (the nearest-level "
              "boundaries: level k for rho in [2^(k-1/2), 2^(k+1/2)), ties up) and at powers "
              "of two.",
              draws, {"tex": dict(base_levels, width=64, height=64)}))
    # Env and combinations.
    add(scene("env_replace",
              "env replace: the texel alone, whatever the vertex colours.",
              [draw(quad(*full, (0.0, 0.0), (1.0, 1.0), color=(0.2, 0.4, 0.6, 0.8)),
                    tex_state(env="replace"))],
              {"tex": texture(8, 8, "gradient", 51)}))
    add(scene("env_modulate_smooth_colours",
              "env modulate: the smooth vertex colour times the texel, in float, converted once.",
              [draw([{"position": p, "color": c, "texcoord": tc} for p, c, tc in [
                  ([0, 0], [1, 0, 0, 1], [0, 0]), ([32, 0], [0, 1, 0, 0.5], [1, 0]),
                  ([16, 32], [0, 0, 1, 0.25], [0.5, 1])]],
                    tex_state())],
              {"tex": texture(8, 8, "random", 52)}))
    add(scene("depth_and_texture",
              "Two overlapping textured quads with the depth test: the nearer one wins per "
              "pixel, textured with its own filter.",
              [draw(quad(0, 0, 24, 24, (0.0, 0.0), (1.0, 1.0), z=0.6),
                    tex_state(min_filter="nearest", mag_filter="nearest"), depth_test="less"),
               draw(quad(8, 8, 32, 32, (0.0, 0.0), (2.0, 2.0), z=0.3),
                    tex_state(), depth_test="less")],
              {"tex": texture(8, 8, "random", 53)}, depth="z24"))
    add(scene("blend_texture_alpha",
              "Alpha blending with the texture's alpha (a horizontal ramp) over a clear colour.",
              [draw(quad(*full, (0.0, 0.0), (1.0, 1.0)), tex_state(env="replace"),
                    blend="alpha")],
              {"tex": texture(16, 4, "alpha", 54)}, clear=(0.1, 0.5, 0.9, 1.0)))
    add(scene("two_textures",
              "Two draws with different textures and states in one scene.",
              [draw(quad(0, 0, 16, 32, (0.0, 0.0), (1.0, 2.0)),
                    tex_state(name="a", min_filter="nearest", mag_filter="nearest")),
               draw(quad(16, 0, 32, 32, (0.0, 0.0), (1.0, 2.0)),
                    tex_state(name="b", wrap_s="mirrored_repeat"))],
              {"a": texture(4, 8, "random", 55), "b": texture(6, 6, "gradient", 56)}))
    # Lines and points.
    add(scene("lines_textured",
              "Textured lines of width 1 and 3: the coordinate interpolates along each line "
              "with the line's planes.",
              [draw([{"position": p, "color": [1, 1, 1, 1], "texcoord": tc} for p, tc in [
                  ([2.5, 3.5], [0, 0]), ([29.5, 27.25], [1, 1]),
                  ([3.25, 28.5], [0, 1]), ([30.5, 4.75], [1, 0])]],
                    tex_state(min_filter="nearest", mag_filter="nearest"), primitive="lines"),
               draw([{"position": p, "color": [1, 1, 1, 1], "texcoord": tc} for p, tc in [
                   ([2.5, 16.5], [0, 0.5]), ([30.5, 17.5], [1.5, 0.5])]],
                    tex_state(), primitive="lines", line_width=3)],
              {"tex": texture(8, 8, "random", 61)}))
    add(scene("points_textured",
              "Textured points of sizes 1 and 5: each point samples its vertex's coordinate.",
              [draw([{"position": [4.5 + 6 * i, 4.5 + 5 * (i % 3)], "color": [1, 1, 1, 1],
                      "texcoord": [0.13 * i, 0.29 * i]} for i in range(5)],
                    tex_state(min_filter="nearest", mag_filter="nearest"), primitive="points"),
               draw([{"position": [5.5 + 7 * i, 24.5], "color": [1, 1, 1, 1],
                      "texcoord": [0.21 * i + 0.05, 0.6]} for i in range(4)],
                    tex_state(), primitive="points", point_size=5)],
              {"tex": texture(8, 8, "random", 62)}))
    # A texture from a PNG file.
    png = image(6, 5, "random", 71)
    with open(os.path.join(OUT, "png_texture.png"), "wb") as f:
        f.write(png_bytes(6, 5, png))
    add(scene("png_file",
              "A texture read from png_texture.png (top row first in the file): the same bytes "
              "as the data form, rows flipped to bottom-to-top.",
              [draw(quad(*full, (0.0, 0.0), (1.0, 1.0)),
                    tex_state(min_filter="nearest", mag_filter="nearest"))],
              {"tex": {"file": "png_texture.png"}}))
    # 4x multisampling.
    add(scene("msaa_4x_bilinear",
              "A textured triangle on a 4x target: the texture is sampled once a pixel at its "
              "centre, coverage and depth per sample.",
              [draw([{"position": p, "color": [1, 1, 1, 1], "texcoord": tc} for p, tc in [
                  ([1.3, 2.1], [0, 0]), ([30.2, 5.7], [2, 0.3]), ([12.6, 30.4], [0.4, 2.2])]],
                    tex_state())],
              {"tex": texture(8, 8, "random", 81)}, samples=4))
    add(scene("msaa_4x_mipmapped",
              "A receding textured quad on a 4x target with trilinear filtering.",
              [draw(quad(0, 0, 32, 32, (0.0, 0.0), (1.0, 8.0), w=(1, 1, 6, 6)),
                    tex_state(min_filter="linear_mipmap_linear"))],
              {"tex": texture(16, 16, "random", 82, mipmaps=True)}, samples=4))

    # Point sprite coordinates (state.texture.coord_replace).
    def sprite(origin="upper_left", **kw):
        st = tex_state(**kw)
        st["coord_replace"] = True
        st["point_coord_origin"] = origin
        return st

    def points(centres, **extra):
        return [dict({"position": list(c), "color": [1, 1, 1, 1]}, **extra) for c in centres]

    add(scene("sprite_upper_left_nearest",
              "Point sprites of sizes 8 and 5.5 with nearest filtering and GL's default origin: "
              "each point shows the whole 8x8 texture, its first row at the top.",
              [draw(points([(6.0, 6.0), (19.5, 7.25)]),
                    sprite(min_filter="nearest", mag_filter="nearest"), primitive="points",
                    point_size=8),
               draw(points([(7.3, 22.1), (22.0, 24.0)]),
                    sprite(min_filter="nearest", mag_filter="nearest"), primitive="points",
                    point_size=5.5)],
              {"tex": texture(8, 8, "random", 91)}))
    add(scene("sprite_lower_left_linear",
              "Point sprites with bilinear filtering and origin lower_left: t rises upwards; "
              "the repeat wrap blends the texture's opposite edges at the point's border.",
              [draw(points([(8.0, 8.0), (23.4, 9.1), (15.7, 23.3)]),
                    sprite(origin="lower_left"), primitive="points", point_size=12)],
              {"tex": texture(8, 8, "random", 92)}))
    add(scene("sprite_clamp_fractional_sizes",
              "Sprites of sizes 1, 1.5, 2.25, 3.7 and 6.7 (a side in 1/256 pixels, not whole "
              "pixels): s and t step by 256 / the snapped side, clamp_to_edge.",
              [draw(points([(3.0 + 6.0 * i + 0.3 * i, 8.0 + 3.1 * i)]),
                    sprite(wrap_s="clamp_to_edge", wrap_t="clamp_to_edge"), primitive="points",
                    point_size=size) for i, size in enumerate([1, 1.5, 2.25, 3.7, 6.7])],
              {"tex": texture(4, 4, "random", 93)}))
    add(scene("sprite_mipmapped",
              "Small sprites over a 32x32 mipmapped texture: the LOD comes from the sprite's "
              "own derivatives (1/size a pixel), trilinear and nearest-mipmap-nearest.",
              [draw(points([(4.0 + 7.0 * i, 6.0) for i in range(4)]),
                    sprite(min_filter="linear_mipmap_linear"), primitive="points",
                    point_size=3),
               draw(points([(5.5 + 7.0 * i, 20.5) for i in range(4)]),
                    sprite(min_filter="nearest_mipmap_nearest", mag_filter="nearest"),
                    primitive="points", point_size=5)],
              {"tex": texture(32, 32, "random", 94, mipmaps=True)}))
    add(scene("sprite_perspective_w",
              "Sprites whose vertices have w of 0.25, 3 and 7: gl_PointCoord is a perspective "
              "input in llvmpipe, its planes multiplied by 1/w and divided again per pixel.",
              [draw([{"position": [6.0 + 10.0 * i, 8.0 + 7.0 * i, 0.0, w],
                      "color": [1, 1, 1, 1]} for i, w in enumerate([0.25, 3.0, 7.0])],
                    sprite(), primitive="points", point_size=9.3)],
              {"tex": texture(16, 16, "random", 95)}))
    rng = random.Random(2024)
    add(scene("sprite_perspective_many",
              "1,200 bilinear sprites of sides 13.3 to 31 with w from 0.2 to 5 over a 64x64 "
              "texture: the rounding of the 1/w products and of the division shows.",
              [draw([{"position": [round(rng.uniform(4, 92), 3), round(rng.uniform(4, 92), 3),
                                   0.0, round(rng.uniform(0.2, 5.0), 3)],
                      "color": [1, 1, 1, 1]} for _ in range(40)],
                    sprite(name="big"), primitive="points",
                    point_size=rng.choice([13.3, 16, 24.6, 31])) for _ in range(30)],
              {"big": texture(64, 64, "random", 100)}, width=96, height=96))
    add(scene("sprite_polygon_mode_point",
              "Triangles drawn with polygon mode point: each vertex is a sprite.",
              [draw(points([(5.0, 5.0), (26.0, 6.5), (15.5, 26.0)], texcoord=[0.3, 0.3]),
                    sprite(min_filter="nearest", mag_filter="nearest"), polygon_mode="point",
                    point_size=7)],
              {"tex": texture(8, 8, "random", 96)}))
    add(scene("sprite_flat_modulate",
              "Flat-shaded coloured sprites with modulate: the colour is the vertex's, the "
              "coordinates the sprite's.",
              [draw([{"position": [6.0 + 9.0 * i, 16.0], "color": c}
                     for i, c in enumerate([[1, 0.2, 0.2, 1], [0.2, 1, 0.2, 1], [0.3, 0.3, 1, 1]])],
                    sprite(origin="lower_left"), primitive="points", point_size=8,
                    shade="flat")],
              {"tex": texture(8, 8, "random", 97)}))
    add(scene("sprite_msaa_4x",
              "Sprites on a 4x target: llvmpipe sets their coordinate planes up with the "
              "half-pixel offset and evaluates them at the pixel centre, half a pixel on.",
              [draw(points([(8.0, 8.0), (22.3, 21.6)]), sprite(), primitive="points",
                    point_size=10)],
              {"tex": texture(8, 8, "random", 98)}, samples=4))
    add(scene("sprite_ignored_off_points",
              "coord_replace on a triangle and a line: they sample at their texcoords, only "
              "points take sprite coordinates.",
              [draw([{"position": p, "color": [1, 1, 1, 1], "texcoord": tc} for p, tc in [
                  ([1.0, 1.0], [0, 0]), ([30.0, 3.0], [1, 0]), ([4.0, 20.0], [0, 1])]],
                    sprite()),
               draw([{"position": p, "color": [1, 1, 1, 1], "texcoord": tc} for p, tc in [
                   ([2.5, 27.5], [0, 0.5]), ([30.5, 25.5], [1.5, 0.5])]],
                    sprite(), primitive="lines", line_width=2)],
              {"tex": texture(8, 8, "random", 99)}))

    for s in scenes:
        path = os.path.join(OUT, s["name"].split(".", 1)[1] + ".json")
        with open(path, "w") as f:
            json.dump(s, f, indent=1)
            f.write("\n")
    print(f"{len(scenes)} scenes in {os.path.normpath(OUT)}")


if __name__ == "__main__":
    main()
