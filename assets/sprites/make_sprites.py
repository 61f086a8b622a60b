#!/usr/bin/env python3
"""Writes Texel's sprite sheets and their maps (deterministic, Python 3 standard library only).

Run from anywhere:  python3 assets/sprites/make_sprites.py

Outputs, next to this script (RGBA8 PNG; colour sheets are sRGB with alpha 0 where there is
nothing, normal maps are tangent-space in the sprite's frame, glTF convention: red toward the
image's right, green toward its top, blue toward the viewer; depth maps are grey, 0 at the
sprite's quad and 255 at the relief's `depth` behind it). Every map is its sheet's size, cut
into the same frames.

* walker.png / walker_n.png  120x256 -- a walking figure seen from 8 directions: frames of
  24x32, 5 columns (0: standing, 1-4: a walk cycle) and 8 rows, one per direction d (the
  viewer at d x 45 degrees about +Y from the figure's front, +Z, toward +X: 0 front, 2 its
  left side, 4 its back, 6 its right side). Drawn by casting orthographic rays at a figure
  of capsules and ellipsoids (legs, arms, torso, head, a backpack), so the normal map is the
  figure's own surface seen from each direction.
* tablet.png / tablet_n.png  24x32 -- a carved stone tablet with a rounded top, three runes
  cut into it and moss at its foot: for bump mapping (the normal map from its height field:
  bevelled edges, grooves of the runes).
* ziggurat.png / ziggurat_depth.png / ziggurat_n.png  32x32 -- a stepped pyramid seen from
  its top, four steps of sandstone courses: for relief mapping (the top step at depth 0, each
  step down a quarter deeper).
* glass.png / glass_front.png / glass_back.png / glass_n.png  32x32 -- a glass sphere: a
  faint blue tint with a highlight, the front and back depth of the sphere (in units where
  255 is its diameter) and its normal map: for refraction (the relief is the front surface).
* grass_a.png, grass_b.png  32x16 -- grass tufts, two 16x16 frames each (swaying).
* bush.png  32x24 -- a round bush with berries, one frame.
"""

import math
import sys
from pathlib import Path

OUT = Path(__file__).resolve().parent
CLEAR = (0, 0, 0, 0)
FLAT = (128, 128, 255, 255)

# The PNG writer and the hash the textures are made with.
sys.path.insert(0, str(OUT.parent / "textures"))
from make_textures import hash2, png  # noqa: E402


def encode_normal(n):
    length = math.sqrt(sum(c * c for c in n))
    return tuple(int(round((c / length * 0.5 + 0.5) * 255)) for c in n) + (255,)


def grey(v):
    """A depth in 0..1 as an opaque grey pixel."""
    g = max(0, min(255, int(round(v * 255))))
    return (g, g, g, 255)


def blank(w, h, px=CLEAR):
    return [[px] * w for _ in range(h)]


def paste(sheet, frame, x0, y0):
    for y, row in enumerate(frame):
        sheet[y0 + y][x0 : x0 + len(row)] = row


def normals_from_height(height, scale):
    """A tangent-space normal map from a height field (rows top to bottom; higher is nearer
    the viewer): the surface tilts against the height's slope, green toward the image top."""
    h, w = len(height), len(height[0])

    def at(x, y):
        return height[min(h - 1, max(0, y))][min(w - 1, max(0, x))]

    rows = []
    for y in range(h):
        row = []
        for x in range(w):
            dx = (at(x + 1, y) - at(x - 1, y)) * 0.5
            dy_up = (at(x, y - 1) - at(x, y + 1)) * 0.5
            row.append(encode_normal((-dx * scale, -dy_up * scale, 1.0)))
        rows.append(row)
    return rows


# --- The walker -------------------------------------------------------------------------

FRAME_W, FRAME_H = 24, 32
UNIT = 0.06  # figure units per pixel: 32 pixels are 1.92 units, the figure 1.8 tall
SKIN, HAIR, SHIRT = (224, 172, 132), (92, 58, 34), (52, 104, 168)
TROUSERS, BOOTS, PACK, EYES = (70, 66, 60), (48, 36, 28), (140, 96, 52), (30, 24, 24)


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def mul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a):
    return mul(a, 1.0 / math.sqrt(dot(a, a)))


def capsule_hit(ro, rd, pa, pb, r):
    """Nearest ray parameter where the ray meets the capsule pa-pb of radius r (Quilez)."""
    ba, oa = sub(pb, pa), sub(ro, pa)
    baba, bard, baoa = dot(ba, ba), dot(ba, rd), dot(ba, oa)
    rdoa, oaoa = dot(rd, oa), dot(oa, oa)
    a = baba - bard * bard
    b = baba * rdoa - baoa * bard
    c = baba * oaoa - baoa * baoa - r * r * baba
    h = b * b - a * c
    if h < 0.0:
        return None
    if a > 1e-9:
        t = (-b - math.sqrt(h)) / a
        y = baoa + t * bard
        if 0.0 < y < baba:
            return t
    else:
        y = baoa
    oc = oa if y <= 0.0 else sub(ro, pb)
    b = dot(rd, oc)
    c = dot(oc, oc) - r * r
    h = b * b - c
    return -b - math.sqrt(h) if h > 0.0 else None


def capsule_normal(p, pa, pb):
    ba, pa_ = sub(pb, pa), sub(p, pa)
    k = max(0.0, min(1.0, dot(pa_, ba) / dot(ba, ba)))
    return norm(sub(pa_, mul(ba, k)))


def ellipsoid_hit(ro, rd, c, r):
    o = ((ro[0] - c[0]) / r[0], (ro[1] - c[1]) / r[1], (ro[2] - c[2]) / r[2])
    d = (rd[0] / r[0], rd[1] / r[1], rd[2] / r[2])
    a, b, cc = dot(d, d), dot(o, d), dot(o, o) - 1.0
    h = b * b - a * cc
    return (-b - math.sqrt(h)) / a if h >= 0.0 else None


def ellipsoid_normal(p, c, r):
    q = sub(p, c)
    return norm((q[0] / r[0] ** 2, q[1] / r[1] ** 2, q[2] / r[2] ** 2))


def figure(step):
    """The figure's parts for walk step 0-3 (None: standing), each (kind, shape..., paint),
    where paint(p) gives the albedo at a surface point p. The figure faces +Z, feet at y 0."""
    if step is None:
        swing, lift_l, lift_r, bob = 0.0, 0.0, 0.0, 0.0
    else:
        phase = step * math.pi / 2
        swing = math.radians(28) * math.cos(phase)
        lift_l = 0.1 * max(0.0, math.sin(phase))
        lift_r = 0.1 * max(0.0, -math.sin(phase))
        bob = 0.03 * abs(math.sin(phase))

    def leg_end(hip, angle, lift):
        return add(hip, (0.0, -0.82 * math.cos(angle) + lift, 0.82 * math.sin(angle)))

    def arm_end(shoulder, angle):
        return add(shoulder, (0.0, -0.58 * math.cos(angle), 0.58 * math.sin(angle)))

    def leg_paint(p):
        return BOOTS if p[1] < 0.2 else TROUSERS

    def arm_paint(p):
        return SKIN if p[1] < 0.98 + bob else SHIRT

    def head_paint(p):
        if p[1] > 1.73 + bob or (p[2] < 0.02 and p[1] > 1.56 + bob):
            return HAIR
        return SKIN

    hip_l, hip_r = (0.12, 0.92 + bob, 0.0), (-0.12, 0.92 + bob, 0.0)
    sh_l, sh_r = (0.31, 1.45 + bob, 0.0), (-0.31, 1.45 + bob, 0.0)
    head = (0.0, 1.66 + bob, 0.02)
    return [
        ("capsule", hip_l, leg_end(hip_l, swing, lift_l), 0.1, leg_paint),
        ("capsule", hip_r, leg_end(hip_r, -swing, lift_r), 0.1, leg_paint),
        ("capsule", sh_l, arm_end(sh_l, -0.8 * swing), 0.075, arm_paint),
        ("capsule", sh_r, arm_end(sh_r, 0.8 * swing), 0.075, arm_paint),
        ("ellipsoid", (0.0, 1.2 + bob, 0.0), (0.26, 0.34, 0.15), lambda p: SHIRT),
        ("ellipsoid", (0.0, 1.24 + bob, -0.16), (0.18, 0.22, 0.09), lambda p: PACK),
        ("ellipsoid", head, (0.17, 0.18, 0.17), head_paint),
        ("ellipsoid", (0.065, 1.68 + bob, 0.18), (0.04, 0.04, 0.03), lambda p: EYES),
        ("ellipsoid", (-0.065, 1.68 + bob, 0.18), (0.04, 0.04, 0.03), lambda p: EYES),
    ]


def walker_frame(step, direction):
    """One frame (colour rows, normal rows) of the figure at `step`, seen from `direction`."""
    theta = math.radians(45.0 * direction)
    to_viewer = (math.sin(theta), 0.0, math.cos(theta))
    right = (math.cos(theta), 0.0, -math.sin(theta))
    up = (0.0, 1.0, 0.0)
    rd = mul(to_viewer, -1.0)
    parts = figure(step)
    colour, normal = blank(FRAME_W, FRAME_H), blank(FRAME_W, FRAME_H, FLAT)
    for py in range(FRAME_H):
        for px in range(FRAME_W):
            u = (px + 0.5 - FRAME_W / 2) * UNIT
            v = (FRAME_H - py - 0.5) * UNIT
            ro = add(add(mul(right, u), mul(up, v)), mul(to_viewer, 5.0))
            best = None
            for part in parts:
                if part[0] == "capsule":
                    t = capsule_hit(ro, rd, part[1], part[2], part[3])
                else:
                    t = ellipsoid_hit(ro, rd, part[1], part[2])
                if t is not None and t > 0.0 and (best is None or t < best[0]):
                    best = (t, part)
            if best is None:
                continue
            t, part = best
            p = add(ro, mul(rd, t))
            if part[0] == "capsule":
                n = capsule_normal(p, part[1], part[2])
            else:
                n = ellipsoid_normal(p, part[1], part[2])
            colour[py][px] = part[-1](p) + (255,)
            normal[py][px] = encode_normal((dot(n, right), dot(n, up), dot(n, to_viewer)))
    return colour, normal


def walker():
    steps = [None, 0, 1, 2, 3]
    w, h = FRAME_W * len(steps), FRAME_H * 8
    colour, normal = blank(w, h), blank(w, h, FLAT)
    for d in range(8):
        for col, step in enumerate(steps):
            c, n = walker_frame(step, d)
            paste(colour, c, col * FRAME_W, d * FRAME_H)
            paste(normal, n, col * FRAME_W, d * FRAME_H)
    return colour, normal


# --- The tablet -------------------------------------------------------------------------

RUNES = [
    # Three runes as strokes in tablet pixels (x0, y0, x1, y1), top to bottom.
    [(9, 7, 9, 13), (9, 8, 13, 7), (9, 10, 13, 9)],
    [(8, 15, 8, 21), (15, 15, 15, 21), (8, 15, 15, 21)],
    [(11, 23, 11, 28), (8, 24, 11, 26), (14, 24, 11, 26)],
]


def tablet_inside(x, y):
    """Whether pixel (x, y) of the 24x32 tablet is stone: a slab with a round top."""
    cx, top, r = 11.5, 11.5, 9.0
    if not (2 <= x <= 21 and y <= 31):
        return False
    if y >= top:
        return 3 <= y
    return (x - cx) ** 2 + (y + 0.5 - top) ** 2 <= r * r + 4


def on_stroke(x, y):
    for rune in RUNES:
        for x0, y0, x1, y1 in rune:
            steps = max(abs(x1 - x0), abs(y1 - y0))
            for i in range(steps + 1):
                sx = round(x0 + (x1 - x0) * i / steps)
                sy = round(y0 + (y1 - y0) * i / steps)
                if (sx, sy) == (x, y):
                    return True
    return False


def tablet():
    w, h = 24, 32
    height = [[0.0] * w for _ in range(h)]
    colour = blank(w, h)
    for y in range(h):
        for x in range(w):
            if not tablet_inside(x, y):
                continue
            # Distance (in pixels, up to 2) to the silhouette: a bevel.
            edge = min(
                [2]
                + [
                    max(abs(dx), abs(dy))
                    for dx in range(-2, 3)
                    for dy in range(-2, 3)
                    if not tablet_inside(x + dx, y + dy)
                ]
            )
            carved = on_stroke(x, y)
            height[y][x] = 1.0 + 0.5 * edge - (0.8 if carved else 0.0)
            g = 132 + int(26 * hash2(x, y, 41)) - (56 if carved else 0) - (10 if edge < 2 else 0)
            c = (g, g - 2, g - 8)
            if y > 27 - 3 * hash2(x, 0, 43) and hash2(x, y, 45) > 0.35:
                c = (70 + int(20 * hash2(x, y, 47)), 108, 52)
            colour[y][x] = c + (255,)
    return colour, normals_from_height(height, 1.0)


# --- The ziggurat -----------------------------------------------------------------------


def ziggurat():
    w = h = 32
    colour, depth = blank(w, h), blank(w, h)
    height = [[0.0] * w for _ in range(h)]
    for y in range(h):
        for x in range(w):
            # Steps 0 (the top, at the quad) to 3 (the base), 4 pixels wide each.
            level = min(3, int(max(abs(x + 0.5 - 16), abs(y + 0.5 - 16)) // 4))
            d = level / 3.0
            depth[y][x] = grey(d)
            height[y][x] = -d * 6.0
            # Sandstone courses: a darker joint every other row, blocks offset by course.
            course = y // 2
            joint = y % 2 == 1 or (x + 3 * course) % 6 == 0
            shade = 180 + int(20 * hash2(x // 3, course, 51)) - 22 * level
            if joint:
                shade -= 24
            ring = max(abs(x + 0.5 - 16), abs(y + 0.5 - 16))
            if level < 3 and ring > 4 * level + 3:
                shade -= 40  # each step's rim, where it drops to the next
            colour[y][x] = (shade, int(shade * 0.78), int(shade * 0.52), 255)
    return colour, depth, normals_from_height(height, 1.0)


# --- The glass sphere -------------------------------------------------------------------


def glass():
    w = h = 32
    colour, front, back, normal = blank(w, h), blank(w, h), blank(w, h), blank(w, h, FLAT)
    for y in range(h):
        for x in range(w):
            nx, ny = (x + 0.5 - 16) / 15.5, (16 - y - 0.5) / 15.5
            r2 = nx * nx + ny * ny
            if r2 > 1.0:
                front[y][x] = back[y][x] = grey(1.0)
                continue
            nz = math.sqrt(1.0 - r2)
            front[y][x] = grey(0.5 * (1.0 - nz))
            back[y][x] = grey(0.5 * (1.0 + nz))
            normal[y][x] = encode_normal((nx, ny, nz))
            highlight = (nx + 0.4) ** 2 + (ny - 0.45) ** 2 < 0.03
            if highlight:
                colour[y][x] = (255, 255, 255, 230)
            elif r2 > 0.82:
                colour[y][x] = (120, 170, 210, 170)
            else:
                colour[y][x] = (190, 225, 250, 70)
    return colour, front, back, normal


# --- Foliage ----------------------------------------------------------------------------

GREENS = [(46, 92, 38, 255), (70, 128, 50, 255), (112, 168, 72, 255)]


def grass(seed, blades):
    w, h = 16, 16
    sheet = blank(2 * w, h)
    for frame in range(2):
        for b in range(blades):
            base = 2 + int(12 * hash2(b, 0, seed))
            tall = 7 + int(8 * hash2(b, 1, seed))
            lean = (hash2(b, 2, seed) - 0.5) * 6
            sway = 1.0 if frame == 1 else 0.0
            colour = GREENS[int(3 * hash2(b, 3, seed)) % 3]
            for i in range(tall):
                s = i / max(1, tall - 1)
                x = round(base + (lean + sway) * s * s)
                y = h - 1 - i
                if 0 <= x < w:
                    sheet[y][frame * w + x] = colour if i < tall - 1 else GREENS[2]
    return sheet


def bush():
    w, h = 32, 24
    rows = blank(w, h)
    lobes = [(16, 13, 9.5), (9, 16, 7), (23, 16, 7), (12, 9, 6), (20, 9, 6.5)]
    for y in range(h):
        for x in range(w):
            inside = [(x + 0.5 - cx) ** 2 + (y + 0.5 - cy) ** 2 <= r * r for cx, cy, r in lobes]
            if not any(inside) or y >= h - 1:
                continue
            leaf = hash2(x // 2, y // 2, 61)
            lit = 0 if y > 17 else (2 if leaf > 0.7 and y < 12 else 1)
            if hash2(x, y, 63) > 0.93:
                rows[y][x] = (176, 40, 52, 255)  # a berry
            else:
                rows[y][x] = GREENS[lit]
    return rows


def main():
    walker_colour, walker_normal = walker()
    tablet_colour, tablet_normal = tablet()
    zig_colour, zig_depth, zig_normal = ziggurat()
    glass_colour, glass_front, glass_back, glass_normal = glass()
    for name, rows in [
        ("walker.png", walker_colour),
        ("walker_n.png", walker_normal),
        ("tablet.png", tablet_colour),
        ("tablet_n.png", tablet_normal),
        ("ziggurat.png", zig_colour),
        ("ziggurat_depth.png", zig_depth),
        ("ziggurat_n.png", zig_normal),
        ("glass.png", glass_colour),
        ("glass_front.png", glass_front),
        ("glass_back.png", glass_back),
        ("glass_n.png", glass_normal),
        ("grass_a.png", grass(71, 9)),
        ("grass_b.png", grass(73, 14)),
        ("bush.png", bush()),
    ]:
        png(OUT / name, len(rows[0]), len(rows), rows)
        print("wrote", OUT / name)


if __name__ == "__main__":
    main()
