"""OpenCAMLib's BatchDropCutter as the peer of our drop-cutter (tests and `bench carve`).

usage: ocl_drop.py MESH.stl SHAPE DIAMETER EXTRA < points
SHAPE: ball, flat, bull (EXTRA = corner radius), v (EXTRA = included angle, degrees),
taper (EXTRA = flank angle per side, degrees; DIAMETER = tip ball's).
Points: "x y" per line. Prints "z" per line ("none" where no triangle is in reach), then
on stderr "seconds S cpu C peak_kb K base_kb B triangles N": wall and CPU seconds of
building the search tree and dropping (the work our `DropCutter::new` + `drop_all` do),
the process's peak resident memory and what it was before the mesh was read.
"""
import math, resource, sys, time
import opencamlib as ocl

mesh, shape, d, extra = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
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
points = [tuple(map(float, line.split())) for line in sys.stdin]
t, c = time.perf_counter(), time.process_time()
bdc = ocl.BatchDropCutter()
bdc.setSTL(surf)
bdc.setCutter(cutter)
for x, y in points:
    bdc.appendPoint(ocl.CLPoint(x, y, FLOOR))
bdc.run()
dt, dc = time.perf_counter() - t, time.process_time() - c
out = []
for p in bdc.getCLPoints():
    out.append("none" if p.z <= FLOOR + 1 else repr(p.z))
sys.stdout.write("\n".join(out) + "\n")
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
sys.stderr.write(
    "seconds %.6f cpu %.6f peak_kb %d base_kb %d triangles %d\n"
    % (dt, dc, peak, base, surf.size())
)
