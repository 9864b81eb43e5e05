#!/usr/bin/env python3
"""Writes the example textures (standard library only): birch.png, a birch-bark pattern — white
bark with dark horizontal lenticels — 64x128 RGB; veins.png, a leaf's midrib and veins, 64x64
(x runs along the leaf, y across it: a B-spline surface maps (i/uDiv, j/vDiv) of its rows and
columns); ground.png, grass with patches of bare soil (the terrain example), 64x64 RGB. Run from
examples/; the output is kept here."""
import math, random, struct, zlib


def png(path, width, height, pixel):
    rows = b"".join(b"\x00" + b"".join(bytes(pixel(x, y)) for x in range(width)) for y in range(height))
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(rows, 9)))
        f.write(chunk(b"IEND", b""))


def birch():
    rnd = random.Random(7)
    marks = [(rnd.randrange(128), rnd.randrange(64), rnd.randrange(6, 24), rnd.randrange(1, 3)) for _ in range(40)]
    def pixel(x, y):
        v = 232 + int(12 * math.sin(x * 0.7) * math.sin(y * 0.3))
        for (my, mx, length, thick) in marks:
            if 0 <= y - my < thick and (x - mx) % 64 < length:
                v = 40 + (x * 7 + y * 3) % 30
        return (v, v - 4 if v > 100 else v, v - 12 if v > 100 else v)
    png("birch.png", 64, 128, pixel)


def veins():
    def pixel(x, y):
        across = abs(y - 31.5) / 32          # 0 on the midrib, 1 at the margin
        along = x / 63                        # 0 at the base, 1 at the tip
        g = 150 + int(70 * along)
        shade = (int(70 + 60 * along), g, int(40 + 30 * along))
        if across < 0.06:
            return (225, 235, 170)            # the midrib
        if abs(((x - 2.2 * abs(y - 31.5)) % 12) - 6) < 1:
            return (190, 220, 140)            # veins, slanting towards the tip
        return shade
    png("veins.png", 64, 64, pixel)
def ground():
    rnd = random.Random(11)
    soil = [(rnd.randrange(64), rnd.randrange(64), rnd.randrange(5, 12)) for _ in range(6)]
    def pixel(x, y):
        bare = any(min(abs(x - sx), 64 - abs(x - sx)) ** 2 + min(abs(y - sy), 64 - abs(y - sy)) ** 2 < r * r
                   for (sx, sy, r) in soil)
        n = (x * 37 + y * 91 + (x * y) % 13) % 23
        if bare:
            return (150 + n, 115 + n, 70 + n // 2)
        return (70 + n, 140 + 2 * n, 40 + n)
    png("ground.png", 64, 64, pixel)


if __name__ == "__main__":
    birch()
    veins()
    ground()
