scale: 2
view: 0 dir: 0 0 -1 up: 0 1 0 pan: 0 0 0 scale: 0.5
