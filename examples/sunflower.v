// Sunflower: shaded, z-buffered, materials from sunflower.mat; the head looked at from a little
// below and to the side.
projection: parallel
scale: 0.9
line style: cylinder
contour sides: 10
render mode: shaded
z buffer: on
light: V: 0.4 0.6 1
corrected rotation: on
