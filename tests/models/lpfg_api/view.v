surface: leaf.s 1 4 4
corrected rotation: on
