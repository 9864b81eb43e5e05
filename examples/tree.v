// The built-in example's view (manual §8.2).
projection: parallel
scale: 0.9
line style: cylinder
contour sides: 12
render mode: shaded
z buffer: on
corrected rotation: on
