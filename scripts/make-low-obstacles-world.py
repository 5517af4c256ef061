#!/usr/bin/env python3
"""Writes datasets/low_obstacles/low_obstacles.png: a 2.5D demo world for the sim2d source.

Two rooms (8 m x 6 m in all, 0.04 m/px = 200 x 150 px) joined by a 1 m door, with low boxes
that a horizontal laser at 0.3 m does not see. Gray levels are height classes for sim2d's
`obstacle_heights = 0:2.0, 64:0.25, 112:0.2`:

    0    walls and a pillar, 2.0 m
    64   boxes, 0.25 m
    112  low boxes, 0.20 m
    255  free floor

Only the standard library (zlib) is used; the output is byte-for-byte reproducible.
Usage: scripts/make-low-obstacles-world.py [OUTPUT.png]
"""
import os
import struct
import sys
import zlib

RES = 0.04           # metres per pixel
W, H = 200, 150      # pixels: 8 m x 6 m

# Rectangles in metres (x0, y0, x1, y1), world frame: x right, y up, origin at the lower-left
# corner of the image. A pixel belongs to a rectangle when its centre is inside.
WALL = 0
BOX = 64
LOW_BOX = 112
SHAPES = [
    # outer wall, 0.12 m thick
    (WALL, (0.0, 0.0, 8.0, 0.12)),
    (WALL, (0.0, 5.88, 8.0, 6.0)),
    (WALL, (0.0, 0.0, 0.12, 6.0)),
    (WALL, (7.88, 0.0, 8.0, 6.0)),
    # the wall between the rooms at x = 4 m, with a 1 m door at y in [2.5, 3.5]
    (WALL, (3.94, 0.0, 4.06, 2.5)),
    (WALL, (3.94, 3.5, 4.06, 6.0)),
    # a pillar in the right room
    (WALL, (5.0, 4.5, 5.3, 4.8)),
    # boxes (0.25 m) and low boxes (0.2 m)
    (BOX, (2.0, 1.2, 2.4, 1.6)),
    (BOX, (5.5, 2.0, 6.0, 2.5)),
    (LOW_BOX, (1.0, 4.2, 1.6, 4.5)),
    (LOW_BOX, (6.6, 4.0, 6.9, 4.8)),
    (LOW_BOX, (2.8, 2.8, 3.1, 3.1)),
]


def gray(col, row):
    x = (col + 0.5) * RES
    y = (H - 1 - row + 0.5) * RES  # image rows go down, y goes up
    for level, (x0, y0, x1, y1) in SHAPES:
        if x0 < x < x1 and y0 < y < y1:
            return level
    return 255


def png_chunk(kind, data):
    body = kind + data
    return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.normpath(os.path.join(
        here, "..", "datasets", "low_obstacles", "low_obstacles.png"))
    raw = b"".join(b"\x00" + bytes(gray(c, r) for c in range(W)) for r in range(H))
    png = (b"\x89PNG\r\n\x1a\n"
           + png_chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 0, 0, 0, 0))  # 8-bit gray
           + png_chunk(b"IDAT", zlib.compress(raw, 9))
           + png_chunk(b"IEND", b""))
    with open(out, "wb") as f:
        f.write(png)
    print(f"wrote {out}: {W} x {H} px at {RES} m/px")


if __name__ == "__main__":
    main()
