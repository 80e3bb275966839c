#!/usr/bin/env python3
"""usage: ppm_to_png.py IN.ppm OUT.png — a binary PPM (P6, 8 bits) as an RGB PNG, stdlib only."""

import struct
import sys
import zlib

data = open(sys.argv[1], "rb").read()
magic, width, height, depth, pixels = data.split(maxsplit=4)
assert magic == b"P6" and depth == b"255", "not an 8-bit binary PPM"
width, height = int(width), int(height)
stride = width * 3
rows = b"".join(b"\0" + pixels[y * stride : (y + 1) * stride] for y in range(height))


def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b"")
open(sys.argv[2], "wb").write(png)
