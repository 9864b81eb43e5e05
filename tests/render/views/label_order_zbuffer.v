/* a label among other drawing (views/label_order.l); the b flag: lpfg applies winfont: only
   with flags */
projection: parallel
scale: 0.9
winfont: "DejaVu Sans" 24 b
z buffer: on
corrected rotation: on
