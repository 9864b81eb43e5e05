/* two half windows with a 4-pixel red border between them */
window: First 0 0 0.5 1
window: Second 0.5 0 0.5 1
window border: 4 255 0 0
corrected rotation: on
