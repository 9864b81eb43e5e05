tropism: T: 1 0 0.3 A: 20 E: 0.1 S: 0.07
