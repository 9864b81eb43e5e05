// Materials example: lit, shaded and z-buffered; materials.mat gives each index its ambient,
// diffuse, emission and specular colours, shininess and transparency. Seen from a little above.
projection: parallel
scale: 0.95
view: 0 dir: 0 -0.7 -1 up: 0 1 0
line style: cylinder
contour sides: 32
render mode: shaded
z buffer: on
light: V: 0.6 0.8 1
winfont: "DejaVu Sans" 18
corrected rotation: on
