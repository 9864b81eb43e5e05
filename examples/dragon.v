// Dragon curve: flat pixel lines, colours from dragon.map.
projection: parallel
scale: 0.95
line style: pixel
corrected rotation: on
