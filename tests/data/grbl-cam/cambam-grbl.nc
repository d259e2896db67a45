( Made using CamBam - http://www.cambam.co.uk )
( part 1/1/2024 12:00:00 PM )
( Post processor: GRBL )
( T1 : 3.175 )
G21 G90 G40
G0 Z3.0
( T1 : 3.175 )
T1 M6
( Profile1 )
G17
M3 S10000
G0 X0.0 Y0.0
G0 Z1.0
G1 F300.0 Z-1.0
G1 F800.0 X30.0
G3 X40.0 Y10.0 I0.0 J10.0
G1 Y30.0
G1 X0.0
G1 Y0.0
G0 Z3.0
M5
M30
