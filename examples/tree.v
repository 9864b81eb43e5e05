// The built-in example's view (manual §8.2): shaded cylinders lit by the default light,
// materials from tree.mat.
projection: parallel
scale: 0.9
line style: cylinder
contour sides: 12
render mode: shaded
z buffer: on
corrected rotation: on
// A weak upward tropism: branches bend a little towards the light.
tropism: T: 0 1 0 E: 0.07
