#!/usr/bin/env python3
"""Writes the deliberately broken glTF files the importer tests expect to be rejected.

Deterministic, Python 3 standard library only. Run from anywhere:
    python3 crates/scene/tests/data/gltf/make_broken.py

Each file breaks exactly one thing (the rest is a valid one-triangle glTF):

truncated.glb            valid GLB cut short: the header declares more bytes than the file has
truncated_bin.gltf/.bin  the .bin holds fewer bytes than the buffer's byteLength
missing_bin.gltf         references missing_bin.bin, which does not exist
bad_json.gltf            JSON syntax error (missing comma) on line 6
garbage.glb              256 pseudo-random bytes (neither GLB nor JSON)
empty.gltf               0 bytes
lines_mode.gltf          a primitive in LINES mode (the importer takes triangle modes only)
required_extension.gltf  requires KHR_draco_mesh_compression
nan_position.gltf        a data: URI buffer whose second position has a NaN x
bad_accessor.gltf        POSITION accessor reads past the end of its buffer view
bad_index.gltf           an index (7) past the last vertex (2)
cycle.gltf               node 0 -> node 1 -> node 0
"""

import base64
import hashlib
import json
import struct
from pathlib import Path

OUT = Path(__file__).resolve().parent

TRIANGLE = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)]


def triangle_payload(points=TRIANGLE, indices=(0, 1, 2)):
    """Positions (3 x VEC3 f32 = 36 bytes) then u16 indices (padded to 8 bytes)."""
    data = b"".join(struct.pack("<3f", *p) for p in points)
    idx = struct.pack(f"<{len(indices)}H", *indices)
    return data + idx + b"\0" * ((4 - len(idx) % 4) % 4)


def triangle_document(buffer, mode=4, position_count=3, indices=True):
    prim = {"attributes": {"POSITION": 0}, "mode": mode}
    accessors = [{"bufferView": 0, "componentType": 5126, "count": position_count,
                  "type": "VEC3", "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]}]
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 36}]
    if indices:
        prim["indices"] = 1
        accessors.append({"bufferView": 1, "componentType": 5123, "count": 3,
                          "type": "SCALAR"})
        views.append({"buffer": 0, "byteOffset": 36, "byteLength": 6})
    return {
        "asset": {"version": "2.0", "generator": "Texel make_broken.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [prim]}],
        "buffers": [buffer],
        "bufferViews": views,
        "accessors": accessors,
    }


def data_uri(payload):
    return "data:application/octet-stream;base64," + base64.b64encode(payload).decode()


def embedded(payload, **kwargs):
    return triangle_document({"uri": data_uri(payload), "byteLength": len(payload)}, **kwargs)


def write_json(name, document):
    (OUT / name).write_text(json.dumps(document, indent=2) + "\n")


def glb(document, binary):
    js = json.dumps(document, separators=(",", ":")).encode()
    js += b" " * ((4 - len(js) % 4) % 4)
    chunks = struct.pack("<I4s", len(js), b"JSON") + js
    chunks += struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def garbage(length):
    out = b""
    block = b"texel garbage"
    while len(out) < length:
        block = hashlib.sha256(block).digest()
        out += block
    out = out[:length]
    assert not out.startswith(b"glTF") and out[:1] not in b" \t\r\n{\xef"
    return out


BAD_JSON = """{
  "asset": {
    "version": "2.0"
  },
  "scenes": [{"nodes": [0]}]
  "nodes": [{"mesh": 0}]
}
"""


def main():
    payload = triangle_payload()
    full = glb(triangle_document({"byteLength": len(payload)}), payload)
    (OUT / "truncated.glb").write_bytes(full[: len(full) - 20])

    write_json("truncated_bin.gltf",
               triangle_document({"uri": "truncated_bin.bin", "byteLength": len(payload)}))
    (OUT / "truncated_bin.bin").write_bytes(payload[:24])

    write_json("missing_bin.gltf",
               triangle_document({"uri": "missing_bin.bin", "byteLength": len(payload)}))
    assert BAD_JSON.splitlines()[5].startswith('  "nodes"')
    (OUT / "bad_json.gltf").write_text(BAD_JSON)
    (OUT / "garbage.glb").write_bytes(garbage(256))
    (OUT / "empty.gltf").write_bytes(b"")
    write_json("lines_mode.gltf", embedded(payload, mode=1, indices=False))

    doc = embedded(payload)
    doc["extensionsUsed"] = ["KHR_draco_mesh_compression"]
    doc["extensionsRequired"] = ["KHR_draco_mesh_compression"]
    write_json("required_extension.gltf", doc)

    nan = [(0.0, 0.0, 0.0), (float("nan"), 0.0, 0.0), (0.0, 1.0, 0.0)]
    write_json("nan_position.gltf", embedded(triangle_payload(nan)))
    write_json("bad_accessor.gltf", embedded(payload, position_count=30))
    write_json("bad_index.gltf", embedded(triangle_payload(indices=(0, 1, 7))))

    doc = embedded(payload)
    doc["nodes"] = [{"children": [1]}, {"mesh": 0, "children": [0]}]
    write_json("cycle.gltf", doc)
    print(f"wrote broken glTF files to {OUT}")


if __name__ == "__main__":
    main()
