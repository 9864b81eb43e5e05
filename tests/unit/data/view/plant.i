# 1 "plant.v"
# 1 "<built-in>"
# 1 "<command-line>"
# 1 "/usr/include/stdc-predef.h" 1 3 4
# 1 "<command-line>" 2
# 1 "plant.v"

projection: perspective
scale: 1.5
corrected rotation: on
# 1 "lights.vh" 1
light: V: 0 1 0 D: 0.3 0.5 0.3
light: O: 10 10 -5 X: 1 2 3

# 6 "plant.v" 2
window: left 0 0 0.5 1
window: right 0.5 0 0.5 1

z buffer: maybe
view: 1 dir: 0 0 1 up: 0 1 0 fov: 30
