#!/usr/bin/env python3
"""Where a program's cutter centre runs relative to the part, by shapely: the independent
check of a nested cut-out (crates/cli/tests/mill_job.rs).

Usage: scripts/job_cut_sides.py CANON.txt < spec.json

CANON.txt is `rs274 -g PROGRAM` (LinuxCNC's canonical calls). spec.json:
  {"ops": ["op 1 ", "op 3 "],          operations (COMMENT "operation: …" prefixes) to look at
   "rings": [[[x, y], …], …],          the part's outlines; even-odd: a ring inside another is
                                       a hole, inside that an island
   "dxf": "file.dxf",                  optional: its closed polylines added to the rings (ezdxf)
   "rounded_rects": [[x0, y0, x1, y1, r]],   optional: rectangles with rounded corners
   "probes": [[x, y], …],              points of waste regions (inside a hole, outside the part)
   "points": [[x, y], …],              optional: corners the cut should reach
   "below": -0.05}                     only moves below this Z cut

Prints JSON: {"samples": n, "min_distance": the least distance from a cutting centre point
to the part, "near": for each probe's waste region (the connected piece of the complement
holding it), how many samples lie in it, "reach": for each point, the least distance from a
cutting centre point to it}.
"""
import json
import math
import re
import sys

from shapely.geometry import Point, Polygon

CALL = re.compile(r"^\s*\d+\s+N\.+\s+(\w+)\((.*)\)\s*$")


def samples(canon, ops, below):
    at = [0.0, 0.0, 0.0]
    active = False
    out = []
    for line in canon.splitlines():
        m = CALL.match(line)
        if not m:
            continue
        name, args = m.group(1), m.group(2)
        if name == "COMMENT":
            text = args.strip('"')
            if text.startswith("operation: "):
                active = any(text[len("operation: "):].startswith(p) for p in ops)
            continue
        nums = [float(v) for v in args.split(",")] if name.endswith(("FEED", "TRAVERSE")) else []
        if name in ("STRAIGHT_FEED", "STRAIGHT_TRAVERSE"):
            to = nums[:3]
            if active and name == "STRAIGHT_FEED":
                n = max(1, int(math.dist(at[:2], to[:2]) / 0.1))
                for k in range(1, n + 1):
                    t = k / n
                    p = [at[i] + (to[i] - at[i]) * t for i in range(3)]
                    if p[2] < below:
                        out.append(p)
            at = to
        elif name == "ARC_FEED":
            ex, ey, cx, cy, rot, ez = nums[:6]
            a0 = math.atan2(at[1] - cy, at[0] - cx)
            a1 = math.atan2(ey - cy, ex - cx)
            r = math.hypot(at[0] - cx, at[1] - cy)
            turns = int(rot)
            if turns < 0:
                sweep = -((a0 - a1) % (2 * math.pi) or 2 * math.pi) - 2 * math.pi * (-turns - 1)
            else:
                sweep = ((a1 - a0) % (2 * math.pi) or 2 * math.pi) + 2 * math.pi * (turns - 1)
            if active:
                n = max(2, int(abs(sweep) * r / 0.1))
                for k in range(1, n + 1):
                    t = k / n
                    a = a0 + sweep * t
                    p = [cx + r * math.cos(a), cy + r * math.sin(a), at[2] + (ez - at[2]) * t]
                    if p[2] < below:
                        out.append(p)
            at = [ex, ey, ez]
    return out


def main():
    canon = open(sys.argv[1]).read()
    spec = json.load(sys.stdin)
    polygons = [Polygon(r) for r in spec.get("rings", [])]
    if "dxf" in spec:
        import ezdxf

        for e in ezdxf.readfile(spec["dxf"]).modelspace():
            if e.dxftype() == "POLYLINE":
                polygons.append(Polygon([(v.dxf.location[0], v.dxf.location[1]) for v in e.vertices]))
            elif e.dxftype() == "LWPOLYLINE":
                polygons.append(Polygon([(p[0], p[1]) for p in e.get_points()]))
    for x0, y0, x1, y1, r in spec.get("rounded_rects", []):
        inner = Polygon([(x0 + r, y0 + r), (x1 - r, y0 + r), (x1 - r, y1 - r), (x0 + r, y1 - r)])
        polygons.append(inner.buffer(r, quad_segs=256))
    part = Polygon()
    for p in polygons:
        part = part.symmetric_difference(p)
    pts = samples(canon, spec["ops"], spec.get("below", -0.05))
    geoms = [Point(p[0], p[1]) for p in pts]
    reach = [min((math.dist(p[:2], q) for p in pts), default=None) for q in spec.get("points", [])]
    if part.is_empty:
        print(json.dumps({"samples": len(pts), "min_distance": None, "near": [], "reach": reach}))
        return
    min_d = min((part.distance(g) for g in geoms), default=None)
    # The waste: everything within a large box that is not part, split into its pieces.
    x0, y0, x1, y1 = part.bounds
    box = Polygon([(x0 - 100, y0 - 100), (x1 + 100, y0 - 100), (x1 + 100, y1 + 100), (x0 - 100, y1 + 100)])
    waste = box.difference(part)
    pieces = list(waste.geoms) if hasattr(waste, "geoms") else [waste]
    near = []
    for probe in spec.get("probes", []):
        piece = next((w for w in pieces if w.contains(Point(probe))), None)
        near.append(0 if piece is None else sum(1 for g in geoms if piece.contains(g)))
    print(json.dumps({"samples": len(pts), "min_distance": min_d, "near": near, "reach": reach}))


if __name__ == "__main__":
    main()
