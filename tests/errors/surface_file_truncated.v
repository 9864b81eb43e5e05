surface: truncated_leaf.s 1 4 4
