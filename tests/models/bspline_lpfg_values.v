bsurface: ../unit/data/bsplines/net17x10.s 1 8 6
bsurface: ../unit/data/bsplines/net6x7.s
bsurface: ../unit/data/bsplines/net4x4.s
bsurface: ../unit/data/bsplines/net5x6.s 2 4 4
bsurface: ../unit/data/bsplines/net7x9.s 1 8 8 0
bsurface: ../unit/data/bsplines/short.s
bsurface: bspline_lpfg_missing.s
