// terrain_lpfg_heights.patch (3 levels, width 6, the coarser levels' heights 0), scaled by 1.5.
terrain: terrain_lpfg_heights.patch 3 1.5 1 off -1 1 1
