#!/usr/bin/env python3
"""Writes terrain.patch, the height field of the `terrain` example (standard library only), in
the layout of vlab's Terrain Editor that lpfg reads (runtime/files/TerrainPatches.h): the width,
then for each level, coarsest first, `numU numV` and numU·numV entries u-major, each a point
line `x y z` and a normal line `nx ny nz`; u runs along x, v along z, y is the height, and each
level doubles the previous one's resolution.

    make_terrain.py [OUT WIDTH SIZES [--flat-coarse]]

With no arguments: terrain.patch, width 8, levels 5,9,17,33 points per side. --flat-coarse
writes the coarser levels' heights as 0 (lpfg takes them from the finest level anyway; the
tests use that to see it does)."""
import math
import sys


def height(x, z):
    return 0.6 * math.sin(0.7 * x) * math.cos(0.5 * z) + 0.1 * x - 0.05 * z * z + 0.4


def normal(x, z):
    dx = 0.42 * math.cos(0.7 * x) * math.cos(0.5 * z) + 0.1
    dz = -0.3 * math.sin(0.7 * x) * math.sin(0.5 * z) - 0.1 * z
    n = (-dx, 1.0, -dz)
    length = math.sqrt(sum(c * c for c in n))
    return tuple(c / length for c in n)


def write(path, width, sizes, flat_coarse=False):
    with open(path, "w") as f:
        f.write("%g\n" % width)
        for level, n in enumerate(sizes):
            f.write("%d\n%d\n" % (n, n))
            for i in range(n):
                for j in range(n):
                    x = -width / 2 + width * i / (n - 1)
                    z = -width / 2 + width * j / (n - 1)
                    y = 0.0 if flat_coarse and level + 1 < len(sizes) else height(x, z)
                    f.write("%g %g %g\n%g %g %g\n" % ((x, y, z) + normal(x, z)))


if __name__ == "__main__":
    if len(sys.argv) >= 4:
        write(sys.argv[1], float(sys.argv[2]), [int(s) for s in sys.argv[3].split(",")], "--flat-coarse" in sys.argv)
    else:
        write("terrain.patch", 8, [5, 9, 17, 33])
