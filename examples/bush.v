// Bracketed bush: flat pixel lines of varying width, colours from bush.map.
projection: parallel
scale: 0.95
line style: pixel
corrected rotation: on
