"""OpenCAMLib's Waterline as the peer of our waterline loops (tests).

usage: ocl_waterline.py MESH.stl SHAPE DIAMETER EXTRA Z SAMPLING
SHAPE as in ocl_drop.py (ball, flat, bull, v). Prints each loop of tip (CL) points at
height Z as "loop" followed by "x y z" lines.
"""
import math, os, sys
import opencamlib as ocl

mesh, shape, d, extra = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
z, sampling = float(sys.argv[5]), float(sys.argv[6])
surf = ocl.STLSurf()
ocl.STLReader(mesh, surf)
L = 100.0
cutter = {
    "ball": lambda: ocl.BallCutter(d, L),
    "flat": lambda: ocl.CylCutter(d, L),
    "bull": lambda: ocl.BullCutter(d, extra, L),
    "v": lambda: ocl.ConeCutter(d, math.radians(extra / 2.0), L),
}[shape]()
wl = ocl.Waterline()
wl.setSTL(surf)
wl.setCutter(cutter)
wl.setZ(z)
wl.setSampling(sampling)
wl.run()
out = []
for lp in wl.getLoops():
    out.append("loop")
    out.extend("%r %r %r" % (p.x, p.y, p.z) for p in lp)
sys.stdout.write("\n".join(out) + "\n")
sys.stdout.flush()
# OpenCAMLib's destructor prints "~Waterline_py()" on stdout: leave before it runs.
os._exit(0)
