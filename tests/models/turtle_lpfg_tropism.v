tropism: T: 0.2 -1 0.1 A: 70 I: 1.3 E: 0.12 S: 0.05
tropism: T: 1 0 0 E: 0.08
torque: T: 0 0 1 E: 0.03
