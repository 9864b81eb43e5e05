// Sierpinski triangle: flat filled triangles, colours from sierpinski.map.
projection: parallel
scale: 0.95
corrected rotation: on
