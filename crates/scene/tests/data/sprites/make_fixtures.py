#!/usr/bin/env python3
"""Writes the images the sprite fixtures in ../levels name (deterministic, standard library only).

Run from anywhere:  python3 crates/scene/tests/data/sprites/make_fixtures.py

sheet.png         48x32 RGBA: 3 x 2 frames of 16x16, each frame its own colour
normal_small.png  16x16 flat normal map (not the sheet's size)
broken.png        text, not an image
"""

import struct
import zlib
from pathlib import Path

OUT = Path(__file__).resolve().parent


def png(path, w, h, pixel):
    raw = b"".join(b"\x00" + bytes(c for x in range(w) for c in pixel(x, y)) for y in range(h))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    path.write_bytes(
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
        + chunk(b"IDAT", zlib.compress(raw, 9))
        + chunk(b"IEND", b"")
    )


def main():
    png(OUT / "sheet.png", 48, 32, lambda x, y: (40 * (x // 16 + 1), 60 * (y // 16 + 1), 90, 255))
    png(OUT / "normal_small.png", 16, 16, lambda x, y: (128, 128, 255, 255))
    (OUT / "broken.png").write_text("not an image\n")


if __name__ == "__main__":
    main()
