surface: surface_lpfg_points.s 2.5
