// Fibonacci's rabbits: flat colours from fibonacci.map, pixel lines, discs facing the viewer,
// labels; the z buffer keeps discs in front of the lines.
projection: parallel
scale: 0.92
line style: pixel
contour sides: 24
z buffer: on
winfont: "DejaVu Sans" 16 b
corrected rotation: on
