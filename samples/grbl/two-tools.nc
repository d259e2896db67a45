%
(two-tools.nc)
(T1 D=3.175 CR=0 - ZMIN=-1 - flat end mill)
(T2 D=6 CR=3 - ZMIN=-0.5 - ball end mill)
G90 G94
G17
G21
(2D Contour1)
T1 M6
S10000 M3
G0 X0 Y0
G0 Z5
G1 Z-1 F300
G1 X20 F800
G1 Y10
G0 Z5
M5
(Parallel1)
T2 M6
S12000 M3
G0 X5 Y5
G1 Z-0.5 F300
G1 X15 F800
G0 Z5
M5
M30
%
