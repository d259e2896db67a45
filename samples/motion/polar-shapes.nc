(Seed 003: a square and a hexagon drawn on the wall; Z5 = pen up, Z0 = pen down.)
(machine: polar-plotter)
G21 G90
G0 X600 Y0 Z5 (start from the reset position: the interpreter knows no other)
G0 X300 Y-500
G1 Z0 F600
G1 X500 Y-500 F2400
G1 X500 Y-300
G1 X300 Y-300
G1 X300 Y-500
G0 Z5
G0 X-400 Y400
G1 Z0 F600
G1 X-350 Y486.6 F2400
G1 X-250 Y486.6
G1 X-200 Y400
G1 X-250 Y313.4
G1 X-350 Y313.4
G1 X-400 Y400
G0 Z5
M2
