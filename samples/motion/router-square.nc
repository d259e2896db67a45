(Seed 004, Fig. 15: a 10 mm square pocket wall cut with a 3 mm tool, tool centre at 1.5 mm.)
(The work zero sits at X100 Y100 and 20 mm below the machine's top: Z is positive above it.)
G21 G90 G17
G10 L2 P1 X100 Y100 Z-20
G54
G0 X1.5 Y1.5 Z10
G1 Z5 F3000
G1 X8.5 Y1.5 F4560
Y8.5
X1.5
Y1.5
G0 Z10
G2 X8.5 Y1.5 I3.5 J0 F2000 (a half circle over the square, at safe height)
G0 X0 Y0
M30
