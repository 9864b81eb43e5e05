// Vogel's phyllotaxis: flat circles (pixel style, filled), colours from vogel.map.
projection: parallel
scale: 0.95
contour sides: 20
corrected rotation: on
