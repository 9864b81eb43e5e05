// Birch: a textured generalized cylinder (texture: birch.png, CurrentTexture/TextureVCoeff in
// birch.l), shaded with materials (birch.mat).
projection: parallel
scale: 0.9
line style: cylinder
contour sides: 16
render mode: shaded
z buffer: on
light: V: 0.6 0.5 1
texture: birch.png
tropism: T: 0 -1 0 E: 0.04
corrected rotation: on
