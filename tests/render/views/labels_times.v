/* ten 16-point labels (21 pixels at 96 dpi) in Times, which Qt takes from Nimbus Roman's Type 1
   file; the b flag: lpfg applies winfont: only with flags, and b is its regular weight */
projection: parallel
scale: 0.9
winfont: "Times" 16 b
corrected rotation: on
