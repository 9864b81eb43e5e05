// Colormap example: flat colours from colormap.map; labels use the colormap too.
projection: parallel
scale: 0.85
contour sides: 40
winfont: "DejaVu Sans" 16
corrected rotation: on
