g90
y-160
G2 x-160 y0 i0 j0
G90
x-80
G2 x0 y80 i0 j0
G90
y160
G2 x160 y0 i0 j0
G90
x80
G2 x0 y-80 i0 j0
