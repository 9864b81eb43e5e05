/* ten windows of 0.2 x 0.5, a 1-pixel border */
window: W0 0 0 0.2 0.5
window: W1 0.2 0 0.2 0.5
window: W2 0.4 0 0.2 0.5
window: W3 0.6 0 0.2 0.5
window: W4 0.8 0 0.2 0.5
window: W5 0 0.5 0.2 0.5
window: W6 0.2 0.5 0.2 0.5
window: W7 0.4 0.5 0.2 0.5
window: W8 0.6 0.5 0.2 0.5
window: W9 0.8 0.5 0.2 0.5
window border: 1 255 255 0
corrected rotation: on
