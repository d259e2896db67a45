(Exported by FreeCAD)
(Post Processor: grbl_post)
(Output Time:2024-01-01 12:00:00.000000)
(Begin preamble)
G17 G90
G21
(Begin operation: TC: Endmill 3.175mm)
(Path: TC: Endmill 3.175mm)
(TC: Endmill 3.175mm)
(Begin toolchange)
( M6 T1 )
M3 S10000
(Finish operation: TC: Endmill 3.175mm)
(Begin operation: Fixture)
(Path: Fixture)
G54
(Finish operation: Fixture)
(Begin operation: Profile)
(Path: Profile)
(Profile)
(Compensated Tool Path. Diameter: 3.175)
G0 Z5.000
G0 X21.588 Y0.000
G0 Z3.000
G1 X21.588 Y0.000 Z-1.000 F200.000
G2 X20.000 Y-1.588 Z-1.000 I-1.588 J0.000 K0.000 F600.000
G1 X0.000 Y-1.588 Z-1.000 F600.000
G2 X-1.588 Y0.000 Z-1.000 I0.000 J1.588 K0.000 F600.000
G1 X-1.588 Y20.000 Z-1.000 F600.000
G2 X0.000 Y21.588 Z-1.000 I1.588 J0.000 K0.000 F600.000
G1 X20.000 Y21.588 Z-1.000 F600.000
G2 X21.588 Y20.000 Z-1.000 I0.000 J-1.588 K0.000 F600.000
G1 X21.588 Y0.000 Z-1.000 F600.000
G0 Z5.000
(Finish operation: Profile)
(Begin postamble)
M5
G17 G90
M2
