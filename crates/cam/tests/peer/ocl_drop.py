"""OpenCAMLib's BatchDropCutter as the peer of our drop-cutter (tests and `bench carve`).

usage: ocl_drop.py MESH.stl SHAPE DIAMETER EXTRA < points
SHAPE: ball, flat, bull (EXTRA = corner radius), v (EXTRA = included angle, degrees),
taper (EXTRA = flank angle per side, degrees; DIAMETER = tip ball's).
Points: "x y" per line. Prints "z" per line ("none" where no triangle is in reach), then
on stderr "seconds S peak_kb K" for the drop itself.
"""
import math, resource, sys, time
import opencamlib as ocl

mesh, shape, d, extra = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
surf = ocl.STLSurf()
ocl.STLReader(mesh, surf)
L = 100.0
if shape == "ball":
    cutter = ocl.BallCutter(d, L)
elif shape == "flat":
    cutter = ocl.CylCutter(d, L)
elif shape == "bull":
    cutter = ocl.BullCutter(d, extra, L)
elif shape == "v":
    cutter = ocl.ConeCutter(d, math.radians(extra / 2.0), L)
elif shape == "taper":
    # tip ball of diameter d, flanks at `extra` per side, widening to 4·d.
    cutter = ocl.BallConeCutter(d, 4.0 * d, math.radians(extra))
else:
    sys.exit("unknown shape " + shape)
FLOOR = -1e4
bdc = ocl.BatchDropCutter()
bdc.setSTL(surf)
bdc.setCutter(cutter)
for line in sys.stdin:
    x, y = map(float, line.split())
    bdc.appendPoint(ocl.CLPoint(x, y, FLOOR))
t = time.perf_counter()
bdc.run()
dt = time.perf_counter() - t
out = []
for p in bdc.getCLPoints():
    out.append("none" if p.z <= FLOOR + 1 else repr(p.z))
sys.stdout.write("\n".join(out) + "\n")
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
sys.stderr.write("seconds %.6f peak_kb %d triangles %d\n" % (dt, peak, surf.size()))
