// Pine cone: shaded, z-buffered, materials from pinecone.mat; seen from a little above.
projection: parallel
scale: 0.9
view: 0 dir: 0 -0.3 -1 up: 0 1 0
line style: cylinder
contour sides: 12
render mode: shaded
z buffer: on
light: V: 0.4 0.2 1
corrected rotation: on
