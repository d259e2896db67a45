g90
y-80
G3 x80 y0 i0 j0
G90
x160
G3 x0 y160 i0 j0
G90
y80
G3 x-80 y0 i0 j0
G90
x-160
G3 x0 y-160 i0 j0
g90
y-80
