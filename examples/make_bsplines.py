#!/usr/bin/env python3
"""Writes the B-spline nets of the bspline example (standard library only): bleaf.s, a leaf of
7 x 6 control points, and bpetal.s, a cupped petal of 6 x 6, in the format lpfg reads for
`bsurface:` ("rows columns", the degree 3, then the points row by row; rows run along the leaf).
Run from examples/; the output is kept here."""
import math


def write(path, rows, columns, point):
    lines = [f"{rows} {columns}", "3"]
    for i in range(rows):
        for j in range(columns):
            lines.append("%.6f %.6f %.6f" % point(i / (rows - 1), j / (columns - 1) * 2 - 1))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def leaf(t, s):
    """t along the leaf (0 base, 1 tip), s across it (-1..1): a pointed blade, folded along its
    midrib and bending down towards the tip."""
    width = 0.42 * math.sin(math.pi * min(max(t, 0.03), 0.97)) ** 0.7 * (1 - 0.35 * t)
    return (s * width, 1.5 * t, 0.25 * abs(s) * width - 0.45 * t * t)


def petal(t, s):
    """A rounded petal, cupped across and curling up at its end."""
    width = 0.38 * math.sin(math.pi * (0.15 + 0.85 * t)) ** 0.5
    return (s * width, 0.9 * t, 0.3 * s * s * width + 0.25 * t * t)


if __name__ == "__main__":
    write("bleaf.s", 7, 6, leaf)
    write("bpetal.s", 6, 6, petal)
