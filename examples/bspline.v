// B-spline surfaces (manual §10.1): ids 0 and 1 are the leaf net bleaf.s, plain at 8 × 6
// divisions and mapped with veins.png at 10 × 8; id 2 is the petal net bpetal.s, which the model
// reshapes (GetBsurfaceS, Set, Scale, operator*, operator+, Interpolate) and draws with DBSurfaceS.
projection: parallel
scale: 0.9
line style: cylinder
contour sides: 12
render mode: shaded
z buffer: on
light: V: 0.4 0.8 1
texture: veins.png
bsurface: bleaf.s 1 8 6
bsurface: bleaf.s 1 10 8 0
bsurface: bpetal.s
corrected rotation: on
