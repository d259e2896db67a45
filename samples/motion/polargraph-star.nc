(A five-pointed star on the hanging polargraph.)
(machine: polargraph-wall)
G21 G90
G0 X500 Y-400 Z5 (start from the reset position: the interpreter knows no other)
G0 X500 Y-250
G1 Z0 F600
G1 X617.6 Y-611.8 F3000
G1 X309.8 Y-388.2
G1 X690.2 Y-388.2
G1 X382.4 Y-611.8
G1 X500 Y-250
G0 Z5
M2
