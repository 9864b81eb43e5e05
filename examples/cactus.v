// Potted cactus: the pot is mesh 0 (a triangle mesh in OBJ format); generalized cylinders need
// the cylinder line style; shaded, z-buffered, materials from cactus.mat; seen from a little above.
projection: parallel
scale: 0.9
view: 0 dir: 0 -0.35 -1 up: 0 1 0
line style: cylinder
contour sides: 16
render mode: shaded
z buffer: on
light: V: 0.5 0.8 1
mesh: pot.obj
corrected rotation: on
