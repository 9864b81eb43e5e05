/* ten 24-point labels (32 pixels at 96 dpi) in DejaVu Sans, whose vertical stems show the hinting;
   the b flag: lpfg applies winfont: only with flags, and b is its regular weight */
projection: parallel
scale: 0.9
winfont: "DejaVu Sans" 24 b
corrected rotation: on
