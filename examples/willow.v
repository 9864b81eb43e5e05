// Weeping willow. Tropism 0 is gravity (down), tropism 1 a wind from the left; the model sets
// the elasticities per branch with SetElasticity(id, e).
projection: parallel
scale: 0.9
line style: cylinder
contour sides: 8
render mode: shaded
z buffer: on
light: V: 0.3 0.8 1
tropism: T: 0 -1 0 E: 0.0
tropism: T: 1 0 0 E: 0.0
corrected rotation: on
