// Rowan shoot: polygons lit with the turtle's up vector as their normal; shaded, z-buffered,
// materials from leaves.mat; seen from a little above.
projection: parallel
scale: 0.9
view: 0 dir: 0 -0.4 -1 up: 0 1 0
line style: cylinder
contour sides: 10
render mode: shaded
z buffer: on
light: V: 0.3 1 0.6
corrected rotation: on
