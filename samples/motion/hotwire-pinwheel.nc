(Seed 002, Test 1, program 1 in standard G-code: quarter arcs of 80 and 160 mm about the origin.)
(machine: hotwire-xy)
G21 G90 G17
F300
G1 Y-80
G2 X-80 Y0 I0 J80
G1 X-160 Y0
G2 X0 Y160 I160 J0
G1 Y80
G2 X80 Y0 I0 J-80
G1 X160
G2 X0 Y-160 I-160 J0
G1 Y-80
M2
