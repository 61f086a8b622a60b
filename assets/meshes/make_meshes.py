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
* crate.glb -- binary glTF of a textured wooden crate: a unit cube (x, z in [-0.5, 0.5], y in
  [0, 1]), 4 vertices per face with flat NORMALs and float TEXCOORD_0, every face showing the whole
  image upright (seen from outside; the top face has -Z at the image's top, the bottom face +Z; V
  grows down the image as in glTF). One node, no transform, one mesh of two primitives sharing
  material "CrateWood" (base colour factor white, baseColorTexture = texture 0, normalTexture =
  texture 1, both through sampler 0: magFilter NEAREST, minFilter NEAREST_MIPMAP_NEAREST, wrapS and
  wrapT CLAMP_TO_EDGE): the body (sides and bottom, 10 triangles, indexed u16) and the lid (top face,
  2 triangles, indexed u16, COLOR_0 float VEC3 = LID_TINT on every vertex). 12 triangles, 24
  vertices. The images are PNGs in the binary chunk (buffer views, mimeType image/png):
  - image 0 "CrateAlbedo", 16x16 RGBA pixel art; at column x, row y (0 = top) the first rule that
    holds wins: the outer ring (x or y in {0, 15}) is CRATE_BORDER, the next ring (x or y in
    {1, 14}) CRATE_FRAME, the diagonal brace (x == y or x == y + 1) CRATE_BRACE, the plank seams
    (y in {5, 10}) CRATE_SEAM, everything else CRATE_PLANK; alpha 255 everywhere;
  - image 1 "CrateNormal", 16x16 RGBA tangent-space normal map (glTF/OpenGL convention, red toward
    +U, green toward the image's top): a one-pixel bevel around the edge -- row 0 leans up (0, S, C),
    row 15 down (0, -S, C), then column 0 left (-S, 0, C), column 15 right (S, 0, C) (rows win at the
    corners) with S = 0.6, C = 0.8 -- and flat (0, 0, 1) inside; each component n is stored as
    floor(n * 127.5 + 128), so flat is (128, 128, 255) and row 0 is (128, 204, 230).

Every face is wound counter-clockwise seen from outside (the script asserts it).
"""

import json
import struct
import zlib
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

# Crate palette (RGB; alpha 255), lid tint and normal-map bevel.
CRATE_BORDER = (92, 58, 30)
CRATE_FRAME = (140, 94, 52)
CRATE_BRACE = (196, 146, 86)
CRATE_SEAM = (120, 80, 44)
CRATE_PLANK = (164, 112, 62)
LID_TINT = (1.0, 0.85, 0.7)
BEVEL_S, BEVEL_C = 0.6, 0.8
CRATE_SIZE = 16

# glTF sampler constants.
NEAREST, NEAREST_MIPMAP_NEAREST, CLAMP_TO_EDGE = 9728, 9984, 33071


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


def crate_albedo_pixel(x, y):
    last = CRATE_SIZE - 1
    if x in (0, last) or y in (0, last):
        rgb = CRATE_BORDER
    elif x in (1, last - 1) or y in (1, last - 1):
        rgb = CRATE_FRAME
    elif x == y or x == y + 1:
        rgb = CRATE_BRACE
    elif y in (5, 10):
        rgb = CRATE_SEAM
    else:
        rgb = CRATE_PLANK
    return rgb + (255,)


def crate_normal_pixel(x, y):
    last = CRATE_SIZE - 1
    if y == 0:
        n = (0.0, BEVEL_S, BEVEL_C)
    elif y == last:
        n = (0.0, -BEVEL_S, BEVEL_C)
    elif x == 0:
        n = (-BEVEL_S, 0.0, BEVEL_C)
    elif x == last:
        n = (BEVEL_S, 0.0, BEVEL_C)
    else:
        n = (0.0, 0.0, 1.0)
    return tuple(int(c * 127.5 + 128) for c in n) + (255,)


def crate_faces():
    """The cube's 6 faces as (outward normal, image-up vector, 4 corners CCW from outside)."""
    lo, hi = (-0.5, 0.0, -0.5), (0.5, 1.0, 0.5)
    corners = box_corners(lo, hi)
    center = centroid(corners)
    faces = []
    for quad in box_faces(lo, hi):
        pts = [corners[i] for i in quad]
        normal = normalize(cross(sub(pts[1], pts[0]), sub(pts[2], pts[0])))
        if normal[1] > 0.5:
            up = (0.0, 0.0, -1.0)
        elif normal[1] < -0.5:
            up = (0.0, 0.0, 1.0)
        else:
            up = (0.0, 1.0, 0.0)
        faces.append((normal, up, pts, center))
    return faces


def crate_arrays(want_top):
    """Positions, normals, UVs and u16 indices of the top face (want_top) or of the others."""
    positions, normals, uvs, indices = [], [], [], []
    for normal, up, pts, center in crate_faces():
        if (normal[1] > 0.5) != want_top:
            continue
        right = cross(tuple(-c for c in normal), up)
        base = len(positions)
        for p in pts:
            d = sub(p, center)
            uvs.append((dot(d, right) + 0.5, 0.5 - dot(d, up)))
        positions += pts
        normals += [normal] * 4
        indices += [base + i for tri in quad_tris([0, 1, 2, 3]) for i in tri]
    return positions, normals, uvs, indices


# --- PNG writing ------------------------------------------------------------------------------

def png_bytes(width, height, pixel):
    """An 8-bit RGBA PNG; pixel(x, y) gives (r, g, b, a), y = 0 at the top."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    rows = b"".join(
        b"\0" + b"".join(struct.pack("4B", *pixel(x, y)) for x in range(width))
        for y in range(height)
    )
    header = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
            + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


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

    def vec2(self, points):
        payload = b"".join(struct.pack("<2f", *p) for p in points)
        self.accessors.append({"bufferView": self._view(payload, 34962), "componentType": 5126,
                               "count": len(points), "type": "VEC2"})
        return len(self.accessors) - 1

    def image_view(self, payload):
        """A buffer view holding an encoded image (no target)."""
        view = self._view(payload, None)
        del self.views[view]["target"]
        return view

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


def crate_document(builder):
    body_pos, body_nrm, body_uv, body_idx = crate_arrays(want_top=False)
    lid_pos, lid_nrm, lid_uv, lid_idx = crate_arrays(want_top=True)
    assert len(body_idx) // 3 == 10 and len(lid_idx) // 3 == 2
    body = {"attributes": {"POSITION": builder.vec3(body_pos, True),
                           "NORMAL": builder.vec3(body_nrm),
                           "TEXCOORD_0": builder.vec2(body_uv)},
            "indices": builder.indices_u16(body_idx), "material": 0}
    lid = {"attributes": {"POSITION": builder.vec3(lid_pos, True),
                          "NORMAL": builder.vec3(lid_nrm),
                          "TEXCOORD_0": builder.vec2(lid_uv),
                          "COLOR_0": builder.vec3([LID_TINT] * len(lid_pos))},
           "indices": builder.indices_u16(lid_idx), "material": 0}
    albedo = builder.image_view(png_bytes(CRATE_SIZE, CRATE_SIZE, crate_albedo_pixel))
    normal = builder.image_view(png_bytes(CRATE_SIZE, CRATE_SIZE, crate_normal_pixel))
    return {
        "asset": asset_header(),
        "scene": 0,
        "scenes": [{"name": "Crate", "nodes": [0]}],
        "nodes": [{"name": "Crate", "mesh": 0}],
        "meshes": [{"name": "Crate", "primitives": [body, lid]}],
        "materials": [{"name": "CrateWood",
                       "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                                                "baseColorTexture": {"index": 0},
                                                "metallicFactor": 0.0},
                       "normalTexture": {"index": 1}}],
        "textures": [{"sampler": 0, "source": 0}, {"sampler": 0, "source": 1}],
        "samplers": [{"magFilter": NEAREST, "minFilter": NEAREST_MIPMAP_NEAREST,
                      "wrapS": CLAMP_TO_EDGE, "wrapT": CLAMP_TO_EDGE}],
        "images": [{"name": "CrateAlbedo", "bufferView": albedo, "mimeType": "image/png"},
                   {"name": "CrateNormal", "bufferView": normal, "mimeType": "image/png"}],
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

    builder = BinBuilder()
    doc = crate_document(builder)
    (OUT / "crate.glb").write_bytes(glb_bytes(doc, builder.data))
    for name in ("obelisk.gltf", "obelisk.bin", "arch.glb", "crate.glb"):
        print(f"wrote {OUT / name} ({(OUT / name).stat().st_size} bytes)")


if __name__ == "__main__":
    main()
