"""Peer side of crates/cli/tests/plot_peers.rs: measures our G-code against vpype (and its
occult plugin) or shapely, and prints one JSON object.

  geom OURS.gcode FILE.svg "PIPELINE"  vpype `read --no-crop FILE PIPELINE layout --landscape a3`
      → pen-down lengths (ours, vpype at its default 0.1 mm quantization, vpype at 0.005 mm) and
        the largest distance from our drawn points to vpype's lines and back.
  clip OURS.gcode FULL.gcode X0,Y0,X1,Y1  → shapely's clip of FULL's strokes to the box, ours.
  fill OURS.gcode PLAIN.gcode FILE.svg  → hatch length (ours with fill − without) and
        shapely's area of each element's closed subpaths read even-odd.
  strokes OURS.gcode  → the pen-down polylines, for the Rust side's own checks.
"""
import json
import sys

import numpy as np
import shapely
from shapely.geometry import LineString, MultiLineString, Polygon, box

PX = 25.4 / 96
PAGE_H = 297.0  # A3 landscape


def gcode_strokes(path):
    strokes, cur, down, pos = [], [], False, (0.0, 0.0)
    for raw in open(path):
        line = raw.split("(")[0].split(";")[0].strip()
        if not line:
            continue
        words = {w[0]: w[1:] for w in line.split() if w and w[0].isalpha()}
        if "Z" in words:
            now = float(words["Z"]) <= 0.0
            if now and not down:
                cur = [pos]
            if down and not now and len(cur) > 1:
                strokes.append(cur)
            down = now
        if "X" in words or "Y" in words:
            pos = (float(words.get("X", pos[0])), float(words.get("Y", pos[1])))
            if down:
                cur.append(pos)
    if down and len(cur) > 1:
        strokes.append(cur)
    return strokes


def length(strokes):
    return sum(LineString(s).length for s in strokes if len(s) > 1)


def vpype_lines(svg, pipeline, q):
    import vpype_cli

    doc = vpype_cli.execute(f'read --no-crop -q {q}mm "{svg}" {pipeline} layout --landscape a3')
    out = []
    for lc in doc.layers.values():
        for ln in lc:
            out.append([(z.real * PX, PAGE_H - z.imag * PX) for z in ln])
    return out


def seg_arrays(strokes):
    """Every segment's ends as two (n, 2) arrays."""
    a = [np.asarray(st, dtype=float) for st in strokes if len(st) > 1]
    if not a:
        return np.zeros((0, 2)), np.zeros((0, 2))
    return np.concatenate([x[:-1] for x in a]), np.concatenate([x[1:] for x in a])


def samples(strokes, step=0.25, most=100_000):
    """Points along the strokes every `step` mm (coarser on long drawings: at most about
    `most` points besides the vertices, which are always in)."""
    p, q = seg_arrays(strokes)
    if len(p) == 0:
        return p
    lens = np.hypot(*(q - p).T)
    step = max(step, lens.sum() / most)
    n = np.maximum(1, np.ceil(lens / step).astype(int))
    idx = np.repeat(np.arange(len(p)), n)
    t = (np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)) / n[idx]
    pts = p[idx] + (q - p)[idx] * t[:, None]
    return np.concatenate([pts, q])


def segments(strokes, piece=1.0):
    """The strokes' segments cut into pieces of at most `piece` mm (long segments' boxes
    would overlap each other everywhere and slow the nearest search)."""
    p, q = seg_arrays(strokes)
    keep = np.any(p != q, axis=1)
    p, q = p[keep], q[keep]
    n = np.maximum(1, np.ceil(np.hypot(*(q - p).T) / piece).astype(int))
    idx = np.repeat(np.arange(len(p)), n)
    k = np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)
    d = (q - p)[idx]
    a = p[idx] + d * (k / n[idx])[:, None]
    b = p[idx] + d * ((k + 1) / n[idx])[:, None]
    return shapely.linestrings(np.stack([a, b], axis=1))


def farthest(from_strokes, to_strokes, reach=1.0):
    """Largest distance from a point on `from_strokes` to the lines of `to_strokes`
    (infinity when some point has none within `reach` mm)."""
    pts = samples(from_strokes)
    segs = segments(to_strokes)
    if len(pts) == 0:
        return 0.0
    if len(segs) == 0:
        return float("inf")
    tree = shapely.STRtree(segs)
    (src, _), d = tree.query_nearest(
        shapely.points(pts), max_distance=reach, return_distance=True, all_matches=False
    )
    if len(np.unique(src)) < len(pts):
        return float("inf")
    return float(np.max(d))


def cmd_geom(ours, svg, pipeline):
    o = gcode_strokes(ours)
    v = vpype_lines(svg, pipeline, 0.1)
    fine = vpype_lines(svg, pipeline, 0.005)
    return {
        "ours": length(o),
        "vpype": length(v),
        "vpype_fine": length(fine),
        "ours_to_vpype": farthest(o, fine),
        "vpype_to_ours": farthest(fine, o),
    }


def cmd_clip(ours, full, b):
    x0, y0, x1, y1 = map(float, b.split(","))
    mls = MultiLineString([s for s in gcode_strokes(full) if len(s) > 1])
    o = gcode_strokes(ours)
    pts = samples(o)
    inside = bool(np.all((pts[:, 0] >= x0 - 1e-3) & (pts[:, 0] <= x1 + 1e-3)
                         & (pts[:, 1] >= y0 - 1e-3) & (pts[:, 1] <= y1 + 1e-3)))
    return {"ours": length(o), "shapely": mls.intersection(box(x0, y0, x1, y1)).length,
            "strokes": len(o), "all_inside": inside}


def cmd_fill(ours, plain, svg):
    """Area of each element's closed subpaths read even-odd (the file's holes are drawn
    against their outers, where nonzero agrees), from svgelements (vpype's SVG reader) and
    shapely."""
    import svgelements as se

    doc = se.SVG.parse(svg)
    area = 0.0
    for e in doc.elements():
        if not isinstance(e, se.Shape) or isinstance(e, se.Text):
            continue
        path = se.Path(e)
        path.reify()
        shape = Polygon()
        for sub in path.as_subpaths():
            sp = se.Path(sub)
            if not any(isinstance(s, se.Close) for s in sp) or sp.length(error=1e-4) == 0:
                continue
            n = max(8, int(sp.length(error=1e-4) / 0.05))
            pts = [sp.point(t) for t in np.linspace(0, 1, n)]
            ring = Polygon([(p.x * PX, p.y * PX) for p in pts]).buffer(0)
            shape = shape.symmetric_difference(ring)
        area += shape.area
    return {"hatch": length(gcode_strokes(ours)) - length(gcode_strokes(plain)), "area": area}


def main():
    cmd, args = sys.argv[1], sys.argv[2:]
    if cmd == "geom":
        r = cmd_geom(*args)
    elif cmd == "clip":
        r = cmd_clip(*args)
    elif cmd == "fill":
        r = cmd_fill(*args)
    elif cmd == "strokes":
        r = {"strokes": gcode_strokes(args[0])}
    else:
        raise SystemExit(f"unknown command {cmd}")
    print(json.dumps(r))


if __name__ == "__main__":
    main()
