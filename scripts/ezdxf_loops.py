#!/usr/bin/env python3
"""ezdxf's figures for a DXF file, printed as JSON: the peer that Oficina's DXF import and
its close_and_chain are compared with (crates/cli/tests/realworld_mill.rs).

Usage: scripts/ezdxf_loops.py FILE.dxf [JOIN_TOL_MM]   (default 0.01 mm)

Figures, in mm (from $INSUNITS; unitless is mm, as Oficina reads it):
  loops            closed entities (ezdxf.edgesmith.is_closed_entity: CIRCLE, closed or
                   end-on-start polylines, full arcs/ellipses, closed splines) plus the loops
                   that ezdxf.edgeminer finds among the open entities of each layer
                   (find_all_simple_chains on a Deposit with gap_tol = the join tolerance)
  closed_entities, chained_loops, open_chains   the parts of that count
  length_mm        total length of the outline entities (paths flattened to 1 µm)
  extents_mm       [xmin, ymin, xmax, ymax] of those entities' curves flattened to 1 µm, in XY
  length_units, extents_units   the same in the file's own units (for comparing geometry
                   apart from how $INSUNITS is read)
Block references are exploded (disassemble.recursive_decompose); SOLID/TRACE/3DFACE outlines count
as closed loops (as Oficina's reader draws them); text, hatches, dimensions and points are not outlines and are left out, as Oficina's importer counts them apart.
"""
import json
import math
import sys

import ezdxf
from ezdxf import disassemble, units
from ezdxf import edgeminer as em
from ezdxf import edgesmith as es
from ezdxf.path import make_path

OUTLINES = {"LINE", "ARC", "CIRCLE", "ELLIPSE", "SPLINE", "LWPOLYLINE", "POLYLINE"}
# Outlines of filled faces: always closed, drawn by Oficina's reader as loops.
FACES = {"SOLID", "TRACE", "3DFACE"}


def outline_entities(doc):
    for e in disassemble.recursive_decompose(doc.modelspace()):
        if e.dxftype() not in OUTLINES | FACES:
            continue
        if e.dxftype() == "POLYLINE" and (e.is_polygon_mesh or e.is_poly_face_mesh):
            continue
        yield e


def figures(path, join_tol):
    doc = ezdxf.readfile(path)
    insunits = doc.header.get("$INSUNITS", 0)
    k = units.conversion_factor(insunits, units.MM) if insunits else 1.0
    gap = join_tol / k
    ents = list(outline_entities(doc))
    def is_closed(e):
        return e.dxftype() in FACES or es.is_closed_entity(e)

    closed = [e for e in ents if is_closed(e)]
    open_by_layer = {}
    for e in ents:
        if not is_closed(e):
            open_by_layer.setdefault(e.dxf.layer, []).append(e)
    chained = 0
    open_chains = 0
    for layer_ents in open_by_layer.values():
        edges = list(es.edges_from_entities_2d(layer_ents, gap_tol=gap))
        deposit = em.Deposit(edges, gap_tol=gap)
        for chain in em.find_all_simple_chains(deposit):
            if em.is_loop(chain, gap_tol=gap):
                chained += 1
            else:
                open_chains += 1
    length = 0.0
    xs, ys = [], []
    for e in ents:
        pts = list(make_path(e).flattening(0.001 / k))
        # Projected onto XY, as a drawing is read (entities in a tilted plane included).
        length += sum(math.hypot(b.x - a.x, b.y - a.y) for a, b in zip(pts, pts[1:]))
        xs += [p.x for p in pts]
        ys += [p.y for p in pts]

    class Box:  # the flattened curves' extents (ezdxf.bbox would take a 3-D box)
        has_data = bool(xs)
        extmin = type("V", (), {"x": min(xs, default=0), "y": min(ys, default=0)})
        extmax = type("V", (), {"x": max(xs, default=0), "y": max(ys, default=0)})

    box = Box
    return {
        "file": path,
        "ezdxf": ezdxf.__version__,
        "insunits": insunits,
        "mm_per_unit": k,
        "join_tol_mm": join_tol,
        "entities": len(ents),
        "closed_entities": len(closed),
        "chained_loops": chained,
        "loops": len(closed) + chained,
        "open_chains": open_chains,
        "length_units": length,
        "extents_units": [box.extmin.x, box.extmin.y, box.extmax.x, box.extmax.y]
        if box.has_data
        else None,
        "length_mm": length * k,
        "extents_mm": [box.extmin.x * k, box.extmin.y * k, box.extmax.x * k, box.extmax.y * k]
        if box.has_data
        else None,
    }


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    tol = float(sys.argv[2]) if len(sys.argv) == 3 else 0.01
    print(json.dumps(figures(sys.argv[1], tol)))
