bsurface: bspline_lpfg_17x10.s 1 8 6
bsurface: bspline_lpfg_6x7.s
bsurface: bspline_lpfg_4x4.s
bsurface: bspline_lpfg_5x6.s 2 4 4
bsurface: bspline_lpfg_7x9.s 1 8 8 0
bsurface: bspline_lpfg_short.s
bsurface: bspline_lpfg_missing.s
