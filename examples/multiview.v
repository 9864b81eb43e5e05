/* three windows: the top half and two quarters below, with a 10-pixel border */
window: Whole 0.0 0.0 1.0 0.5
window: Branches 0.0 0.5 0.5 0.5
window: Buds 0.5 0.5 0.5 0.5
window border: 10 60 60 60
line style: pixel
corrected rotation: on
