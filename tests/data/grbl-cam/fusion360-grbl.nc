%
(1001)
(Machine)
(  vendor: Generic)
(  description: grbl router)
(T1  D=3.175 CR=0. - ZMIN=-2. - flat end mill)
G90 G94
G17
G21

(2D Contour1)
T1 M6
S12000 M3
G54
G0 X12.5 Y-1.588
Z15.
Z5.
G1 Z1. F333.3
Z-2.
G1 Y0. F1000.
G3 X10.912 Y1.588 I-1.588 J0.
G1 X-10.912
G3 X-12.5 Y0. I0. J-1.588
G1 Y10.
X12.5
Y-1.588
G0 Z15.

(Drill1)
G0 X0. Y5.
Z15.
Z5.
G1 Z-3. F200.
G0 Z5.
G0 Z15.
M5
G28 G91 Z0.
G90
G28 G91 X0. Y0.
G90
M30
%
