(Seed 000: a running stitch around a 40 mm circle, 2.5 mm stitches, then a jump.)
(machine: embroidery-xy)
G21 G90
F7800
G0 X40 Y0
G3 X40 Y0 I-40 J0
G0 X-60 Y-60
G1 X-60 Y60
G1 X-57.5 Y-60
G1 X-55 Y60
G1 X-52.5 Y-60
G1 X-50 Y60
M2
