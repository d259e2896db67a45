#!/usr/bin/env python3
"""What ezdxf reads in DXF files: the peer figures for Oficina's DXF reader.

Usage: scripts/ezdxf_figures.py [--curves] FILE.dxf...

Prints one JSON object per file (one line each) for model space with every INSERT exploded
(nested, arrays; ezdxf's recursive_decompose):

  counts       entities by type (after exploding; INSERT itself is not counted)
  length       total length in mm of every curve, flattened to 0.01 mm: LINE, ARC, CIRCLE,
               (LW)POLYLINE (centre line, widths ignored; meshes skipped), SPLINE, ELLIPSE,
               SOLID/TRACE/3DFACE outlines and HATCH boundary paths, projected onto XY
  hatch_dup    the part of `length` that is HATCH boundary paths drawn by their own source
               entities (associative boundaries whose source handles are in model space)
  hatch_dup_closed  how many of `closed` those are
  extents      [xmin, ymin, xmax, ymax] in mm of those flattened curves (XY)
  closed       how many of those curves are closed (start meets end within 1e-9 relative,
               length not zero), HATCH boundary paths counted as curves
  texts        [string, x, y, height] in mm of each TEXT and visible ATTRIB (its first
               alignment point, in WCS), sorted
  units        $INSUNITS, $MEASUREMENT and the mm per drawing unit used

With --curves, also `curves`: handle → points [x, y] in mm on each SPLINE and ELLIPSE of model
space (not inside blocks), from ezdxf's evaluation of the curve itself (flattened to 1 µm).

Units: $INSUNITS when it is set, else inches when $MEASUREMENT is 0 (imperial), else mm.
Files are read with ezdxf.recover, which also reads binary DXF and headerless R12.
"""

import json
import math
import sys
from collections import Counter

import ezdxf
from ezdxf import disassemble, recover, units
from ezdxf import path as epath

DRAWN = {
    "LINE", "ARC", "CIRCLE", "LWPOLYLINE", "POLYLINE", "SPLINE", "ELLIPSE",
    "SOLID", "TRACE", "3DFACE",
}


def mm_per_unit(doc):
    ins = doc.header.get("$INSUNITS", 0) or 0
    meas = doc.header.get("$MEASUREMENT", None)
    if ins:
        return units.conversion_factor(ins, units.MM), ins, meas
    if meas == 0:
        return 25.4, ins, meas
    return 1.0, ins, meas


def flat_length(path, dist):
    pts = list(path.flattening(dist))
    length = sum(math.hypot(b.x - a.x, b.y - a.y) for a, b in zip(pts, pts[1:]))
    return pts, length


def is_closed(path):
    if len(path) == 0:
        return False
    s, e = path.start, path.end
    size = max(1.0, max(abs(v) for v in (s.x, s.y, e.x, e.y)))
    return math.hypot(e.x - s.x, e.y - s.y) <= 1e-9 * size


def figures(name, curves=False):
    with open(name, "rb") as f:
        binary = f.read(22).startswith(b"AutoCAD Binary DXF")
    # recover reads damaged and headerless files but not binary ones; readfile reads binary.
    doc = ezdxf.readfile(name) if binary else recover.readfile(name)[0]
    msp = doc.modelspace()
    scale, ins, meas = mm_per_unit(doc)
    handles = {e.dxf.handle for e in msp}
    dist = 0.01 / scale
    counts = Counter()
    length = 0.0
    dup = 0.0
    dup_closed = 0
    closed = 0
    box = [math.inf, math.inf, -math.inf, -math.inf]
    texts = []

    def take(path):
        nonlocal length, closed
        pts, n = flat_length(path, dist)
        for p in pts:
            box[0] = min(box[0], p.x)
            box[1] = min(box[1], p.y)
            box[2] = max(box[2], p.x)
            box[3] = max(box[3], p.y)
        length += n
        if n > 0 and is_closed(path):  # a zero-length LINE is no loop
            closed += 1
        return n

    for e in disassemble.recursive_decompose(msp):
        kind = e.dxftype()
        counts[kind] += 1
        if kind == "HATCH":
            # make_path gives the boundary paths in WCS (from_hatch would give OCS).
            whole = epath.make_path(e)
            subs = list(whole.sub_paths()) if whole.has_sub_paths else [whole]
            subs = [p for p in subs if len(p)]
            if len(subs) != len(e.paths):  # a boundary of several loops: no pairing
                for p in subs:
                    take(p)
                continue
            for bp, p in zip(e.paths, subs):
                n = take(p)
                src = getattr(bp, "source_boundary_objects", []) or []
                if e.dxf.get("associative", 0) and src and all(h in handles for h in src):
                    dup += n
                    dup_closed += n > 0 and is_closed(p)
        elif kind == "POLYLINE" and (e.is_poly_face_mesh or e.is_polygon_mesh):
            continue
        elif kind in DRAWN:
            take(epath.make_path(e))
        elif kind in ("TEXT", "ATTRIB") and not (kind == "ATTRIB" and e.is_invisible):
            p = e.ocs().to_wcs(e.dxf.insert)
            texts.append([e.dxf.text, p.x * scale, p.y * scale, e.dxf.height * scale])
    ok = box[0] <= box[2]
    points = {}
    if curves:
        for e in msp.query("SPLINE ELLIPSE"):
            # The curve itself (NURBS evaluated with its weights), not a path approximating it.
            pts = e.construction_tool().flattening(0.001 / scale)
            points[e.dxf.handle] = [[v.x * scale, v.y * scale] for v in pts]
    return {
        "curves": points,
        "file": name,
        "counts": dict(sorted(counts.items())),
        "length": length * scale,
        "hatch_dup": dup * scale,
        "hatch_dup_closed": dup_closed,
        "extents": [v * scale for v in box] if ok else None,
        "closed": closed,
        "texts": sorted(texts),
        "units": {"insunits": ins, "measurement": meas, "mm_per_unit": scale},
        "ezdxf": ezdxf.__version__,
    }


def main():
    args = sys.argv[1:]
    curves = "--curves" in args
    for name in (a for a in args if a != "--curves"):
        try:
            print(json.dumps(figures(name, curves)), flush=True)
        except Exception as exc:  # one bad file must not hide the others' figures
            print(json.dumps({"file": name, "error": f"{type(exc).__name__}: {exc}"}), flush=True)


if __name__ == "__main__":
    main()
