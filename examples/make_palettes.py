#!/usr/bin/env python3
"""Writes the binary colour files of the example models (python3, standard library only).

Run it from anywhere; the files are written next to this script:

    python3 examples/make_palettes.py

Formats (vlab tools manual §3 and §4.4; read by runtime/files/Palette.cpp):
  .map  colormap: 256 RGB triplets, one unsigned byte per component (768 bytes per page).
        Colour 0 is the background.
  .mat  materials: 15-byte records, one per defined index: index, transparency, ambient rgb,
        diffuse rgb, emission rgb, specular rgb, shininess (all unsigned bytes, 0..255 = 0..1,
        shininess 0..128). Indices not listed are black. The emission of material 0 is the
        background colour. Lit with lpfg's default light (white ambient, diffuse and specular),
        so ambient colours are kept low or the picture washes out.
"""
import colorsys
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def byte(x):
    """0..1 float to 0..255 byte."""
    return max(0, min(255, int(round(x * 255))))


def lerp(a, b, t):
    return tuple(a[i] + (b[i] - a[i]) * t for i in range(3))


def ramp(stops, t):
    """Piecewise linear colour ramp; stops = [(t0, rgb0), (t1, rgb1), ...], t in 0..1."""
    if t <= stops[0][0]:
        return stops[0][1]
    for (t0, c0), (t1, c1) in zip(stops, stops[1:]):
        if t <= t1:
            return lerp(c0, c1, (t - t0) / (t1 - t0))
    return stops[-1][1]


def write_map(name, background, colour_of):
    """colour_of(i) gives the rgb (0..1 floats) of colour i, 1..255."""
    data = bytearray()
    for i in range(256):
        rgb = background if i == 0 else colour_of(i)
        data += bytes(byte(c) for c in rgb)
    assert len(data) == 768
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


def material(index, diffuse, ambient=None, specular=(0.1, 0.1, 0.1), shininess=10,
             emission=(0, 0, 0), transparency=0.0):
    """One 15-byte material record."""
    if ambient is None:
        ambient = tuple(0.15 * c for c in diffuse)
    rec = bytes([index, byte(transparency)])
    for rgb in (ambient, diffuse, emission, specular):
        rec += bytes(byte(c) for c in rgb)
    rec += bytes([max(0, min(128, int(shininess)))])
    assert len(rec) == 15
    return rec


def write_mat(name, background, records):
    """background: rgb of the emission of material 0 (the background colour)."""
    data = material(0, (0, 0, 0), ambient=(0, 0, 0), specular=(0, 0, 0), emission=background)
    for r in records:
        data += r
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


def hsv(h, s, v):
    return colorsys.hsv_to_rgb(h % 1.0, s, v)


# --- colormaps -------------------------------------------------------------------------------

# koch.map: colour = depth along the snowflake's outline; icy blues to white on midnight blue.
write_map("koch.map", (0.02, 0.03, 0.12),
          lambda i: ramp([(0, (0.1, 0.3, 0.9)), (0.5, (0.3, 0.9, 1.0)), (1, (1, 1, 1))], (i - 1) / 254))

# dragon.map: a full rainbow along the curve, on black.
write_map("dragon.map", (0, 0, 0), lambda i: hsv((i - 1) / 255 * 0.85, 0.85, 1.0))

# sierpinski.map: colour = recursion level (1..8), warm tones on cream.
write_map("sierpinski.map", (1.0, 0.97, 0.9),
          lambda i: ramp([(0, (0.45, 0.0, 0.1)), (0.5, (0.9, 0.35, 0.05)), (1, (1.0, 0.85, 0.2))],
                         min(i - 1, 7) / 7))

# bush.map: 1..8 = a brown-to-green ramp along the branching order, on pale sky blue.
write_map("bush.map", (0.85, 0.92, 1.0),
          lambda i: ramp([(0, (0.35, 0.2, 0.05)), (0.4, (0.3, 0.45, 0.1)), (1, (0.1, 0.75, 0.2))],
                         min(i - 1, 7) / 7))

# vogel.map: 1..21 the 21 parastichies in rainbow colours (florets coloured by n mod 21),
# 30 a dark seed colour, on white.
def vogel(i):
    if 1 <= i <= 21:
        return hsv((i - 1) / 21, 0.75, 0.95)
    return (0.25, 0.15, 0.05)


write_map("vogel.map", (1, 1, 1), vogel)

# colormap.map: the colormap example; 1..255 go once round the hue circle, the value dipping
# in eight bands so that neighbouring rings stand apart; a dark grey background.
write_map("colormap.map", (0.12, 0.12, 0.12),
          lambda i: hsv((i - 1) / 255, 0.8, 1.0 if ((i - 1) // 16) % 2 == 0 else 0.75))

# fibonacci.map: 1 text (near black), 2 adult rabbits (red), 3 young ones (blue), 4 edges
# (grey), 5 letters on the discs (white); white background.
def fib(i):
    return {1: (0.1, 0.1, 0.1), 2: (0.85, 0.2, 0.15), 3: (0.2, 0.35, 0.85), 4: (0.6, 0.6, 0.6),
            5: (1, 1, 1)}.get(i, (0, 0, 0))


write_map("fibonacci.map", (1, 1, 1), fib)

# --- materials -------------------------------------------------------------------------------

BARK = (0.42, 0.27, 0.14)
LEAF = (0.2, 0.55, 0.15)

# tree.mat: the built-in example. 1..8 blend brown bark into green tips (SetColor(order + 1)),
# background light grey-blue.
write_mat("tree.mat", (0.85, 0.9, 0.95),
          [material(i, lerp(BARK, (0.25, 0.65, 0.15), (i - 1) / 7), specular=(0.05, 0.05, 0.05))
           for i in range(1, 9)] +
          [material(9, (0.3, 0.75, 0.2), specular=(0.3, 0.3, 0.3), shininess=40)])   # leaf buds

# sunflower.mat: 1 disc florets (dark brown), 2 florets near the rim (olive), 3 ray petals
# (yellow), 4 stem/back (green), 5 = disc centre (darker); sky blue background.
write_mat("sunflower.mat", (0.6, 0.78, 0.95), [
    material(1, (0.25, 0.13, 0.05), specular=(0.3, 0.25, 0.2), shininess=30),
    material(2, (0.45, 0.4, 0.1), specular=(0.3, 0.3, 0.2), shininess=30),
    material(3, (1.0, 0.8, 0.05), specular=(0.2, 0.2, 0.1), shininess=10),
    material(4, (0.25, 0.5, 0.15)),
    material(5, (0.12, 0.06, 0.02), specular=(0.3, 0.25, 0.2), shininess=30),
])

# gcplant.mat: 1 stem (green-brown), 2 young stem (green), 3 leaf (green, shiny), 4 flower
# (white), 5 flower centre (yellow).
write_mat("gcplant.mat", (0.8, 0.87, 0.92), [
    material(1, (0.45, 0.5, 0.2)),
    material(2, (0.35, 0.65, 0.25)),
    material(3, (0.2, 0.6, 0.15), ambient=(0.06, 0.15, 0.04), specular=(0.3, 0.3, 0.25), shininess=40),
    material(4, (0.95, 0.95, 0.98), ambient=(0.5, 0.5, 0.5), specular=(0.2, 0.2, 0.2), shininess=20),
    material(5, (1.0, 0.8, 0.1), specular=(0.3, 0.3, 0.1), shininess=20),
])

# bspline.mat: 1 stem, 2 leaf, 3 textured leaf (light, so that veins.png shows), 4 petal (pink),
# 5 flower centre (yellow).
write_mat("bspline.mat", (0.86, 0.9, 0.95), [
    material(1, (0.35, 0.5, 0.2)),
    material(2, (0.2, 0.55, 0.15), ambient=(0.06, 0.15, 0.04), specular=(0.25, 0.25, 0.2), shininess=30),
    material(3, (0.9, 0.9, 0.9), ambient=(0.3, 0.3, 0.3), specular=(0.15, 0.15, 0.15), shininess=20),
    material(4, (0.95, 0.55, 0.7), ambient=(0.3, 0.15, 0.2), specular=(0.3, 0.3, 0.3), shininess=25),
    material(5, (1.0, 0.8, 0.15), specular=(0.3, 0.3, 0.1), shininess=20),
])

# materials.mat: the materials example, one sphere per material 1..8 (see materials.l).
write_mat("materials.mat", (0.15, 0.15, 0.18), [
    material(1, (0.8, 0.1, 0.1), specular=(0, 0, 0), shininess=0),                  # matte red
    material(2, (0.8, 0.1, 0.1), specular=(1, 1, 1), shininess=100),                # glossy red
    material(3, (0.1, 0.3, 0.8), specular=(0.6, 0.6, 0.6), shininess=20),          # satin blue
    material(4, (0.55, 0.45, 0.15), ambient=(0.2, 0.15, 0.05),
             specular=(1.0, 0.85, 0.4), shininess=80),                                # gold
    material(5, (0.1, 0.1, 0.1), emission=(0.2, 0.9, 0.3), specular=(0, 0, 0)),      # glowing green
    material(6, (0.5, 0.8, 1.0), specular=(1, 1, 1), shininess=120, transparency=0.6),  # glass
    material(7, (0.8, 0.8, 0.78), ambient=(0.2, 0.2, 0.2), specular=(0.1, 0.1, 0.1),
             shininess=10),                                                           # chalk
    material(8, (0.3, 0.3, 0.3), specular=(0.9, 0.9, 0.9), shininess=128),          # steel
    material(9, (0.5, 0.5, 0.5), emission=(1, 1, 1), specular=(0, 0, 0)),            # white labels
    material(10, (0.35, 0.35, 0.4), specular=(0.1, 0.1, 0.1), shininess=5),         # floor
])

# willow.mat: 1..6 bark from the old trunk (dark) to young branches (olive), 7 hanging twigs
# (yellow-green), 8 leaves.
write_mat("willow.mat", (0.9, 0.93, 0.85),
          [material(i, lerp((0.3, 0.22, 0.14), (0.55, 0.5, 0.2), (i - 1) / 5)) for i in range(1, 7)] +
          [material(7, (0.55, 0.65, 0.2)), material(8, (0.35, 0.6, 0.2), specular=(0.2, 0.2, 0.2),
                                                        shininess=30)])

# leaves.mat: 1 stem, 2 petiole, 3..5 leaves young to old, 6 berries.
write_mat("leaves.mat", (1, 1, 1), [
    material(1, (0.35, 0.25, 0.12)),
    material(2, (0.4, 0.55, 0.2)),
    material(3, (0.5, 0.8, 0.25), specular=(0.2, 0.2, 0.2), shininess=30),
    material(4, (0.25, 0.6, 0.2), specular=(0.2, 0.2, 0.2), shininess=30),
    material(5, (0.1, 0.4, 0.12), specular=(0.2, 0.2, 0.2), shininess=30),
    material(6, (0.7, 0.05, 0.15), specular=(0.9, 0.9, 0.9), shininess=90),
])

# cactus.mat: 1 cactus body, 2 spines, 3 pot (terracotta), 4 soil, 5 flowers.
write_mat("cactus.mat", (0.93, 0.9, 0.85), [
    material(1, (0.2, 0.5, 0.25), specular=(0.25, 0.3, 0.25), shininess=25),
    material(2, (0.95, 0.92, 0.8)),
    material(3, (0.75, 0.35, 0.2), specular=(0.15, 0.1, 0.1), shininess=10),
    material(4, (0.25, 0.17, 0.1)),
    material(5, (0.95, 0.3, 0.55), specular=(0.3, 0.3, 0.3), shininess=30),
])

# pinecone.mat: 1 scales (brown), 2 their tips (lighter), 3 the stalk.
write_mat("pinecone.mat", (0.95, 0.95, 0.95), [
    material(1, (0.55, 0.34, 0.15), ambient=(0.15, 0.09, 0.04), specular=(0.15, 0.1, 0.05), shininess=15),
    material(2, (0.7, 0.52, 0.3), ambient=(0.2, 0.14, 0.08), specular=(0.15, 0.1, 0.05), shininess=15),
    material(3, (0.3, 0.2, 0.1)),
])

# birch.mat: 1 bark (light, so the texture's own colours show through GL_MODULATE), 2 leaves;
# pale sky background.
write_mat("birch.mat", (0.8, 0.88, 0.95), [
    material(1, (0.95, 0.95, 0.92), ambient=(0.35, 0.35, 0.33), specular=(0.05, 0.05, 0.05)),
    material(2, (0.35, 0.7, 0.2), specular=(0.2, 0.2, 0.2), shininess=30),
])

# terrain.mat: 1 the ground (light, so that the texture's colours show through GL_MODULATE),
# 2 stems, 3 flower heads; a pale sky.
write_mat("terrain.mat", (0.78, 0.86, 0.95), [
    material(1, (0.95, 0.95, 0.9), ambient=(0.4, 0.4, 0.38), specular=(0.05, 0.05, 0.05)),
    material(2, (0.3, 0.55, 0.15), specular=(0.2, 0.2, 0.2), shininess=30),
    material(3, (0.95, 0.75, 0.1), specular=(0.3, 0.3, 0.2), shininess=30),
])
