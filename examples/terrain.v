// Terrain (manual §10.3): terrain.patch, 4 levels of detail, scale 1, level-of-detail offset 0.3
// (so that the levels change across the picture), the grid on, texture 0 tiled twice each way.
projection: parallel
scale: 0.9
view: 0 dir: 0 -1 -0.7 up: 0 1 0
line style: cylinder
contour sides: 8
render mode: shaded
z buffer: on
light: V: 0.4 1 0.5
corrected rotation: on
texture: ground.png
terrain: terrain.patch 4 1 0.3 on 0 2 2
