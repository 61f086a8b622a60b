#!/usr/bin/env python3
"""Writes Texel's small glTF test meshes (deterministic, Python 3 standard library only).

Run from anywhere:  python3 assets/meshes/make_meshes.py

Outputs, next to this script:

* obelisk.gltf + obelisk.bin -- a tapered stone column (plinth, shaft, pyramidion), 24 flat-shaded
  triangles WITH normals, one grey material, indexed (u16). Scene 0 (the default) is a two-node
  hierarchy: a parent "ObeliskBase" with translation (10, 0, -4), a 90 degree rotation about +Y and
  scale (2, 1.5, 1), and a child "Obelisk" translated (0, 0.5, 0) that holds the mesh. Scene 1 (not
  the default) holds a far-away copy at x = 100 that an importer must NOT load.
  Local bounds: x, z in [-0.7, 0.7], y in [0, 3.8]; world bounds (what the importer must return):
  x in [9.3, 10.7], y in [0.75, 6.45], z in [-5.4, -2.6].
* arch.glb -- binary glTF of three boxes WITHOUT normals (the importer generates them), one node with
  no transform, two primitives: the two pillars (material "Sandstone", indexed u16, 8 shared corners
  per box) and the lintel (material "Slate", not indexed, COLOR_0 as normalized u8 RGBA: 255 on the
  top corners, 128 on the bottom ones). The lintel passes through the pillar tops; no corner of one
  box lies inside another. 36 triangles; bounds x in [-1.7, 1.7], y in [0, 2.4], z in [-0.4, 0.4].

Every face is wound counter-clockwise seen from outside (the script asserts it).
"""

import json
import struct
from pathlib import Path

OUT = Path(__file__).resolve().parent

# Arch boxes as (min, max) corners.
LEFT_PILLAR = ((-1.4, 0.0, -0.4), (-0.8, 2.0, 0.4))
RIGHT_PILLAR = ((0.8, 0.0, -0.4), (1.4, 2.0, 0.4))
LINTEL = ((-1.7, 1.8, -0.3), (1.7, 2.4, 0.3))
SANDSTONE = [0.8, 0.7, 0.5, 1.0]
SLATE = [0.3, 0.35, 0.4, 1.0]

# Obelisk dimensions.
PLINTH_HALF, PLINTH_TOP = 0.7, 0.3
SHAFT_BOTTOM_HALF, SHAFT_TOP_HALF, SHAFT_TOP = 0.45, 0.3, 3.3
APEX_Y = 3.8
STONE_GREY = [0.6, 0.6, 0.6, 1.0]


# --- small vector helpers -------------------------------------------------------------------

def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def normalize(v):
    length = dot(v, v) ** 0.5
    return tuple(x / length for x in v)


def centroid(points):
    return tuple(sum(c) / len(points) for c in zip(*points))


def f32(x):
    """Rounds a Python float to the nearest f32, as it will be stored."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def oriented(points, inside):
    """Returns the polygon wound CCW seen from outside (normal pointing away from `inside`)."""
    normal = cross(sub(points[1], points[0]), sub(points[2], points[0]))
    if dot(normal, sub(centroid(points), inside)) < 0:
        points = list(reversed(points))
    normal = cross(sub(points[1], points[0]), sub(points[2], points[0]))
    assert dot(normal, sub(centroid(points), inside)) > 0
    return list(points)


# --- geometry ---------------------------------------------------------------------------------

def box_corners(lo, hi):
    """8 corners; corner i takes x from bit 0, y from bit 1, z from bit 2."""
    return [
        (hi[0] if i & 1 else lo[0], hi[1] if i & 2 else lo[1], hi[2] if i & 4 else lo[2])
        for i in range(8)
    ]


def box_faces(lo, hi):
    """6 quads of corner indices (into box_corners), each CCW seen from outside."""
    corners = box_corners(lo, hi)
    inside = centroid(corners)
    faces = []
    for axis in range(3):
        for side in (0, 1):
            ids = [i for i in range(8) if (i >> axis) & 1 == side]
            a, b = [j for j in range(3) if j != axis]
            # Walk the face's 4 corners around its rim, then fix the winding.
            rim = sorted(ids, key=lambda i: ((i >> a) & 1, (i >> b) & 1))
            loop = [rim[0], rim[1], rim[3], rim[2]]
            pts = oriented([corners[i] for i in loop], inside)
            faces.append([corners.index(p) for p in pts])
    return faces


def quad_tris(quad):
    return [(quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])]


def obelisk_polygons():
    """Flat polygons (lists of points, CCW from outside) of plinth, shaft and pyramidion."""
    polys = []
    lo, hi = (-PLINTH_HALF, 0.0, -PLINTH_HALF), (PLINTH_HALF, PLINTH_TOP, PLINTH_HALF)
    corners = box_corners(lo, hi)
    polys += [[corners[i] for i in face] for face in box_faces(lo, hi)]
    inside = (0.0, 2.0, 0.0)  # inside the convex shaft + pyramidion
    ring = [(-1, -1), (1, -1), (1, 1), (-1, 1)]
    apex = (0.0, APEX_Y, 0.0)
    for k in range(4):
        (sx0, sz0), (sx1, sz1) = ring[k], ring[(k + 1) % 4]
        b0 = (sx0 * SHAFT_BOTTOM_HALF, PLINTH_TOP, sz0 * SHAFT_BOTTOM_HALF)
        b1 = (sx1 * SHAFT_BOTTOM_HALF, PLINTH_TOP, sz1 * SHAFT_BOTTOM_HALF)
        t0 = (sx0 * SHAFT_TOP_HALF, SHAFT_TOP, sz0 * SHAFT_TOP_HALF)
        t1 = (sx1 * SHAFT_TOP_HALF, SHAFT_TOP, sz1 * SHAFT_TOP_HALF)
        polys.append(oriented([b0, b1, t1, t0], inside))
        polys.append(oriented([t0, t1, apex], inside))
    return polys


def obelisk_arrays():
    positions, normals, indices = [], [], []
    for poly in obelisk_polygons():
        normal = normalize(cross(sub(poly[1], poly[0]), sub(poly[2], poly[0])))
        base = len(positions)
        positions += poly
        normals += [normal] * len(poly)
        fan = [(0, 1, 2)] if len(poly) == 3 else quad_tris([0, 1, 2, 3])
        indices += [base + i for tri in fan for i in tri]
    return positions, normals, indices


def pillar_arrays():
    positions, indices = [], []
    for lo, hi in (LEFT_PILLAR, RIGHT_PILLAR):
        base = len(positions)
        positions += box_corners(lo, hi)
        indices += [base + i for face in box_faces(lo, hi) for tri in quad_tris(face) for i in tri]
    return positions, indices


def lintel_arrays():
    lo, hi = LINTEL
    corners = box_corners(lo, hi)
    positions, colors = [], []
    for face in box_faces(lo, hi):
        for tri in quad_tris(face):
            for i in tri:
                positions.append(corners[i])
                shade = 255 if i & 2 else 128
                colors.append((shade, shade, shade, 255))
    return positions, colors


# --- glTF writing -----------------------------------------------------------------------------

class BinBuilder:
    """Accumulates one glTF buffer plus its bufferViews and accessors."""

    def __init__(self):
        self.data = bytearray()
        self.views = []
        self.accessors = []

    def _view(self, payload, target):
        while len(self.data) % 4:
            self.data.append(0)
        self.views.append({"buffer": 0, "byteOffset": len(self.data),
                           "byteLength": len(payload), "target": target})
        self.data += payload
        return len(self.views) - 1

    def vec3(self, points, with_bounds=False):
        payload = b"".join(struct.pack("<3f", *p) for p in points)
        acc = {"bufferView": self._view(payload, 34962), "componentType": 5126,
               "count": len(points), "type": "VEC3"}
        if with_bounds:
            stored = [[f32(c) for c in p] for p in points]
            acc["min"] = [min(p[k] for p in stored) for k in range(3)]
            acc["max"] = [max(p[k] for p in stored) for k in range(3)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def rgba8(self, colors):
        payload = b"".join(struct.pack("<4B", *c) for c in colors)
        self.accessors.append({"bufferView": self._view(payload, 34962), "componentType": 5121,
                               "normalized": True, "count": len(colors), "type": "VEC4"})
        return len(self.accessors) - 1

    def indices_u16(self, indices):
        payload = struct.pack(f"<{len(indices)}H", *indices)
        self.accessors.append({"bufferView": self._view(payload, 34963), "componentType": 5123,
                               "count": len(indices), "type": "SCALAR"})
        return len(self.accessors) - 1


def asset_header():
    return {"version": "2.0", "generator": "Texel assets/meshes/make_meshes.py"}


def obelisk_document(builder, bin_name):
    positions, normals, indices = obelisk_arrays()
    assert len(indices) // 3 == 24
    prim = {"attributes": {"POSITION": builder.vec3(positions, True),
                           "NORMAL": builder.vec3(normals)},
            "indices": builder.indices_u16(indices), "material": 0, "mode": 4}
    return {
        "asset": asset_header(),
        "scene": 0,
        "scenes": [{"name": "Main", "nodes": [0]}, {"name": "Unused", "nodes": [2]}],
        "nodes": [
            {"name": "ObeliskBase", "children": [1], "translation": [10.0, 0.0, -4.0],
             "rotation": [0.0, 0.70710678, 0.0, 0.70710678], "scale": [2.0, 1.5, 1.0]},
            {"name": "Obelisk", "mesh": 0, "translation": [0.0, 0.5, 0.0]},
            {"name": "GhostObelisk (scene 1, must not load)", "mesh": 0,
             "translation": [100.0, 0.0, 0.0]},
        ],
        "meshes": [{"name": "Obelisk", "primitives": [prim]}],
        "materials": [{"name": "Stone",
                       "pbrMetallicRoughness": {"baseColorFactor": STONE_GREY,
                                                "metallicFactor": 0.0}}],
        "buffers": [{"uri": bin_name, "byteLength": len(builder.data)}],
        "bufferViews": builder.views,
        "accessors": builder.accessors,
    }


def arch_document(builder):
    pillar_pos, pillar_idx = pillar_arrays()
    lintel_pos, lintel_col = lintel_arrays()
    pillars = {"attributes": {"POSITION": builder.vec3(pillar_pos, True)},
               "indices": builder.indices_u16(pillar_idx), "material": 0}
    lintel = {"attributes": {"POSITION": builder.vec3(lintel_pos, True),
                             "COLOR_0": builder.rgba8(lintel_col)}, "material": 1}
    assert len(pillar_idx) // 3 + len(lintel_pos) // 3 == 36
    return {
        "asset": asset_header(),
        "scene": 0,
        "scenes": [{"name": "Arch", "nodes": [0]}],
        "nodes": [{"name": "Arch", "mesh": 0}],
        "meshes": [{"name": "Arch", "primitives": [pillars, lintel]}],
        "materials": [
            {"name": "Sandstone", "pbrMetallicRoughness": {"baseColorFactor": SANDSTONE}},
            {"name": "Slate", "pbrMetallicRoughness": {"baseColorFactor": SLATE}},
        ],
        "buffers": [{"byteLength": len(builder.data)}],
        "bufferViews": builder.views,
        "accessors": builder.accessors,
    }


def pad(data, fill):
    return bytes(data) + fill * ((4 - len(data) % 4) % 4)


def glb_bytes(document, binary):
    json_chunk = pad(json.dumps(document, separators=(",", ":")).encode(), b" ")
    bin_chunk = pad(binary, b"\0")
    chunks = struct.pack("<I4s", len(json_chunk), b"JSON") + json_chunk
    chunks += struct.pack("<I4s", len(bin_chunk), b"BIN\0") + bin_chunk
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def main():
    builder = BinBuilder()
    doc = obelisk_document(builder, "obelisk.bin")
    (OUT / "obelisk.bin").write_bytes(bytes(builder.data))
    (OUT / "obelisk.gltf").write_text(json.dumps(doc, indent=2) + "\n")

    builder = BinBuilder()
    doc = arch_document(builder)
    (OUT / "arch.glb").write_bytes(glb_bytes(doc, builder.data))
    for name in ("obelisk.gltf", "obelisk.bin", "arch.glb"):
        print(f"wrote {OUT / name} ({(OUT / name).stat().st_size} bytes)")


if __name__ == "__main__":
    main()
