#!/usr/bin/env python3
"""Writes the DXF cases that the real files in crates/io/tests/data/dxf do not cover, with
ezdxf (an independent writer): rational and fit-point splines, arcs and circles in tilted
planes, an ellipse seen from below (extrusion -Z), nested block inserts with rotation and
scales, unequal ones on a circle and an arc (they become elliptical arcs), MINSERT arrays, HATCH edge paths with
clockwise arcs, an elliptic edge and a spline edge, SOLID, TRACE, 3-D POLYLINE, LWPOLYLINE with
widths under -Z, POINT and TEXT. Once as ASCII R2018, once as binary DXF.

Usage: scripts/ezdxf_make_cases.py [OUT_DIR]   (default crates/io/tests/data/dxf)
"""

import math
import os
import sys

import ezdxf
from ezdxf.math import Vec3


def build():
    doc = ezdxf.new("R2018", setup=False)
    doc.header["$INSUNITS"] = 4  # mm
    msp = doc.modelspace()

    # Splines: clamped cubic (exact), rational quadratic quarter circles, fit points.
    msp.add_spline(fit_points=None).apply_construction_tool(
        ezdxf.math.BSpline([(0, 0), (10, 30), (30, 30), (40, 0), (60, 10)], order=4)
    )
    w = math.sqrt(0.5)
    msp.add_rational_spline(
        control_points=[(100, 0), (100, 20), (80, 20)],
        weights=[1, w, 1],
        degree=2,
        knots=[0, 0, 0, 1, 1, 1],
    )
    msp.add_rational_spline(
        control_points=[(130, 0), (130, 40), (90, 40), (70, 10), (75, -5)],
        weights=[1, 3, 0.5, 2, 1],
        degree=3,
        knots=[0, 0, 0, 0, 0.4, 1, 1, 1, 1],
    )
    s = msp.add_spline([(0, 60), (20, 80), (40, 60), (60, 85), (80, 70)])
    s.dxf.start_tangent = Vec3(0, 1, 0)
    s.dxf.end_tangent = Vec3(1, -1, 0)
    msp.add_spline([(0, 100), (15, 120), (30, 100), (45, 110)])

    # Arcs and circles in tilted planes; an ellipse seen from below.
    tilt = Vec3(0.3, -0.4, 0.866).normalize()
    msp.add_arc((150, 20, 5), 15, 10, 250, dxfattribs={"extrusion": tilt})
    msp.add_circle((170, 40, -3), 8, dxfattribs={"extrusion": tilt})
    msp.add_circle((200, 40), 6, dxfattribs={"extrusion": (0, 0, -1)})
    msp.add_arc((-220, 40), 10, 30, 200, dxfattribs={"extrusion": (0, 0, -1)})
    msp.add_ellipse(
        (240, 40), major_axis=(20, 8), ratio=0.4, start_param=0.5, end_param=4.0,
        dxfattribs={"extrusion": (0, 0, -1)},
    )
    msp.add_ellipse((280, 40), major_axis=(0, 15), ratio=0.6)

    # Blocks: nested, rotated, scaled unequally; arrays.
    inner = doc.blocks.new("INNER", base_point=(1, 1))
    inner.add_circle((5, 5), 3)
    inner.add_lwpolyline([(0, 0, 0, 0, 0.5), (10, 0), (10, 10)], format="xyseb", close=True)
    inner.add_attdef("TAG", (0, 0))
    oval = doc.blocks.new("OVAL", base_point=(0, 0))
    oval.add_circle((0, 0), 4)
    oval.add_arc((0, 0), 6, 0, 120)
    outer = doc.blocks.new("OUTER", base_point=(0, 0))
    outer.add_blockref("INNER", (20, 0), dxfattribs={"rotation": 30, "xscale": 2, "yscale": 2})
    outer.add_blockref("OVAL", (60, 0), dxfattribs={"rotation": 20, "xscale": 2, "yscale": 0.5})
    outer.add_line((0, 0), (20, 0))
    msp.add_blockref("OUTER", (0, 150), dxfattribs={"rotation": -15, "xscale": 1.5, "yscale": 1.5})
    m = msp.add_blockref("INNER", (100, 150), dxfattribs={"rotation": 10})
    m.grid(size=(2, 3), spacing=(15, 20))

    # Hatch: edge path with a line, a clockwise arc, an elliptic edge and a spline edge; a
    # polyline path with a bulge.
    h = msp.add_hatch(color=3)
    ep = h.paths.add_edge_path()
    ep.add_line((300, 0), (340, 0))
    ep.add_arc((340, 10), 10, 270, 90, ccw=False)
    ep.add_line((340, 20), (320, 20))
    ep.add_ellipse((310, 20), major_axis=(10, 0), ratio=0.5, start_angle=0, end_angle=180)
    ep.add_spline(
        control_points=[(300, 20), (295, 12), (305, 6), (300, 0)],
        knot_values=[0, 0, 0, 0, 1, 1, 1, 1],
        degree=3,
    )
    h.paths.add_polyline_path([(350, 0, 0.4), (370, 0, 0), (370, 20, 0), (350, 20, 0)], is_closed=True)

    # Outlines of filled shapes, 3-D polyline, widths under -Z, point, text.
    msp.add_solid([(400, 0), (420, 0), (400, 20), (420, 25)])
    msp.add_trace([(430, 0), (450, 0), (430, 10), (450, 10)])
    msp.add_polyline3d([(400, 40, 0), (420, 50, 10), (440, 40, 20), (460, 60, 0)])
    msp.add_lwpolyline(
        [(-400, 80, 1, 2, 0), (-420, 80, 2, 1, -0.5), (-420, 100, 0, 0, 0)],
        format="xyseb",
        dxfattribs={"extrusion": (0, 0, -1), "elevation": 4},
    )
    msp.add_point((500, 0))
    msp.add_text("Oficina", dxfattribs={"insert": (500, 10), "height": 5})
    return doc


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "crates/io/tests/data/dxf"
    doc = build()
    doc.saveas(os.path.join(out, "made_by_ezdxf.dxf"))
    doc.saveas(os.path.join(out, "made_by_ezdxf_binary.dxf"), fmt="bin")


if __name__ == "__main__":
    main()
