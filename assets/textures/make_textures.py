#!/usr/bin/env python3
"""Writes Texel's pixel-art textures (deterministic, Python 3 standard library only).

Run from anywhere:  python3 assets/textures/make_textures.py

Outputs, next to this script (RGBA8 PNG; colour maps are sRGB, normal maps linear):

* grass.png     16x16 -- meadow: two greens dithered by a fixed hash, a few light blades.
* bricks.png    16x16 -- running-bond red bricks (4 rows of 8x4 bricks, 1-pixel grey mortar).
* bricks_n.png  16x16 -- the bricks' tangent-space normal map (glTF convention: red +U, green
  toward the image top): flat brick faces, mortar joints sunk, so their edges tilt.
* planks.png    16x16 -- three wooden planks along U with grain streaks and dark seams.
* cobble.png    32x32 -- irregular cobbles (Voronoi cells from 12 fixed seeds) in dark grout.
* displacement.png 32x32 -- a tileable greyscale displacement for terrain (smooth value noise
  over a 4x4 lattice that wraps, plus a little per-pixel grain), read by the red channel.
* checker.png   8x8   -- a one-pixel black/white checker (its first mip is uniform grey), for
  tests of sampling and density.
"""

import math
import struct
import zlib
from pathlib import Path

OUT = Path(__file__).resolve().parent


def png(path, w, h, pixels):
    """pixels: list of rows, each a list of (r, g, b, a) tuples."""
    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in pixels)

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    data = (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
        + chunk(b"IDAT", zlib.compress(raw, 9))
        + chunk(b"IEND", b"")
    )
    path.write_bytes(data)


def hash2(x, y, seed=0):
    h = (x * 374761393 + y * 668265263 + seed * 2246822519) & 0xFFFFFFFF
    h = ((h ^ (h >> 13)) * 1274126177) & 0xFFFFFFFF
    return (h ^ (h >> 16)) / 0xFFFFFFFF


def grass():
    dark, mid, light = (62, 110, 48, 255), (78, 134, 56, 255), (120, 170, 80, 255)
    rows = []
    for y in range(16):
        row = []
        for x in range(16):
            v = hash2(x, y, 1)
            row.append(light if v > 0.9 else mid if v > 0.45 else dark)
        rows.append(row)
    return rows


def brick_mortar(x, y):
    """Whether (x, y) of the 16x16 brick tile is mortar."""
    if y % 4 == 3:
        return True
    offset = 4 if (y // 4) % 2 else 0
    return (x + offset) % 8 == 7


def bricks():
    mortar = (150, 146, 138, 255)
    rows = []
    for y in range(16):
        row = []
        for x in range(16):
            if brick_mortar(x, y):
                row.append(mortar)
            else:
                offset = 4 if (y // 4) % 2 else 0
                brick = ((x + offset) // 8, y // 4)
                shade = hash2(*brick, 7)
                base = (150 + int(40 * shade), 62 + int(16 * shade), 48, 255)
                if hash2(x, y, 3) > 0.85:
                    base = tuple(max(0, c - 22) for c in base[:3]) + (255,)
                row.append(base)
        rows.append(row)
    return rows


def encode_normal(n):
    length = math.sqrt(sum(c * c for c in n))
    return tuple(int(round((c / length * 0.5 + 0.5) * 255)) for c in n) + (255,)


def bricks_normal():
    rows = []
    for y in range(16):
        row = []
        for x in range(16):
            if brick_mortar(x, y):
                row.append(encode_normal((0.0, 0.0, 1.0)))
                continue
            # Brick faces next to mortar tilt toward it (a bevel): +U to the right, green up.
            nx = ny = 0.0
            if brick_mortar((x + 1) % 16, y):
                nx += 0.6
            if brick_mortar((x - 1) % 16, y):
                nx -= 0.6
            if brick_mortar(x, (y - 1) % 16):
                ny += 0.6
            if brick_mortar(x, (y + 1) % 16):
                ny -= 0.6
            row.append(encode_normal((nx, ny, 1.0)))
        rows.append(row)
    return rows


def planks():
    rows = []
    for y in range(16):
        row = []
        plank = y // 5 if y < 15 else 2
        for x in range(16):
            seam = y % 5 == 4 or (x + 5 * plank) % 16 == 0
            if seam:
                row.append((70, 44, 26, 255))
                continue
            grain = hash2(x // 3, y, 11 + plank)
            tone = 128 + int(30 * hash2(plank, 0, 5))
            c = tone - (24 if grain > 0.7 else 0)
            row.append((c, int(c * 0.66), int(c * 0.4), 255))
        rows.append(row)
    return rows


def cobble():
    seeds = [(hash2(i, 0, 21) * 32, hash2(i, 1, 21) * 32) for i in range(12)]
    rows = []
    for y in range(32):
        row = []
        for x in range(32):
            dists = []
            for i, (sx, sy) in enumerate(seeds):
                dx = min(abs(x + 0.5 - sx), 32 - abs(x + 0.5 - sx))
                dy = min(abs(y + 0.5 - sy), 32 - abs(y + 0.5 - sy))
                dists.append((math.hypot(dx, dy), i))
            dists.sort()
            if dists[1][0] - dists[0][0] < 1.2:
                row.append((58, 56, 54, 255))
            else:
                t = hash2(dists[0][1], 3, 9)
                g = 112 + int(40 * t)
                row.append((g, g - 4, g - 12, 255))
        rows.append(row)
    return rows


def displacement():
    lattice = [[hash2(i, j, 31) for i in range(4)] for j in range(4)]

    def smooth(t):
        return t * t * (3 - 2 * t)

    rows = []
    for y in range(32):
        row = []
        for x in range(32):
            gx, gy = x / 8.0, y / 8.0
            i0, j0 = int(gx) % 4, int(gy) % 4
            i1, j1 = (i0 + 1) % 4, (j0 + 1) % 4
            fx, fy = smooth(gx - int(gx)), smooth(gy - int(gy))
            a = lattice[j0][i0] * (1 - fx) + lattice[j0][i1] * fx
            b = lattice[j1][i0] * (1 - fx) + lattice[j1][i1] * fx
            v = a * (1 - fy) + b * fy
            v = 0.8 * v + 0.2 * hash2(x, y, 33)
            g = int(round(v * 255))
            row.append((g, g, g, 255))
        rows.append(row)
    return rows


def checker():
    return [
        [(255, 255, 255, 255) if (x + y) % 2 == 0 else (0, 0, 0, 255) for x in range(8)]
        for y in range(8)
    ]


def main():
    for name, rows in [
        ("grass.png", grass()),
        ("bricks.png", bricks()),
        ("bricks_n.png", bricks_normal()),
        ("planks.png", planks()),
        ("cobble.png", cobble()),
        ("displacement.png", displacement()),
        ("checker.png", checker()),
    ]:
        png(OUT / name, len(rows[0]), len(rows), rows)
        print("wrote", OUT / name)


if __name__ == "__main__":
    main()
