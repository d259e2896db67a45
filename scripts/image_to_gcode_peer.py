#!/usr/bin/python3
"""Runs LinuxCNC's image-to-gcode conversion headless, for `oficina bench carve`.

image-to-gcode's window is Tk; its conversion is the module's `Converter` class, which this
script drives with the options its `main()` would pass, on the same height image.

The image comes as raw 8-bit gray (row 0 = top), WIDTH x HEIGHT, because the Rust side
already decoded it; PIL is only imported by image-to-gcode for decoding, so a placeholder
module stands in for it when it is not installed. The entry cut is the module's
SimpleEntryCut (straight plunge) instead of ArcEntryCut, whose G18/G19 arcs a height-field
simulator cannot replay; it does not change the surface computation being timed.

usage: image_to_gcode_peer.py RAW WIDTH HEIGHT PIXEL_MM DEPTH_MM BALL_DIA_MM STEP_PX OUT.ngc
prints: SECONDS <conversion wall time>   CPU <its CPU time>   OFFSET <dx mm> <dy mm> (peer frame -> image grid frame)
"""

import importlib.machinery
import importlib.util
import sys
import time
import types

import numpy

if "PIL" not in sys.modules:
    try:
        import PIL  # noqa: F401
    except ImportError:
        sys.modules["PIL"] = types.ModuleType("PIL")
        sys.modules["PIL"].Image = None

loader = importlib.machinery.SourceFileLoader("image_to_gcode", "/usr/bin/image-to-gcode")
spec = importlib.util.spec_from_loader("image_to_gcode", loader)
i2g = importlib.util.module_from_spec(spec)
loader.exec_module(i2g)


def main():
    raw, w, h, pixel, depth, dia, step, out = sys.argv[1:9]
    w, h, pixel, depth, dia, step = int(w), int(h), float(pixel), float(depth), float(dia), int(step)
    nim = numpy.fromfile(raw, dtype=numpy.uint8).reshape((h, w)).astype(numpy.float32)
    # As main(): no normalize, no expand, no invert; white = 0, black = -depth.
    nim = nim / 255.0 * depth - depth
    tool = i2g.make_tool_shape(i2g.ball_tool, dia, pixel)
    rows = i2g.Convert_Scan_Alternating()
    with open(out, "w") as f:
        stdout, sys.stdout = sys.stdout, f
        start = time.perf_counter()
        cpu = time.process_time()
        try:
            # Tolerance 0.001 is image-to-gcode's own default.
            i2g.convert(nim, "G21", tool, pixel, step, 5.0, 0.001, 2000.0,
                        rows, None, False, i2g.SimpleEntryCut(500.0), 18000.0, 0, 0, 2000.0)
        finally:
            sys.stdout = stdout
        seconds = time.perf_counter() - start
        cpu = time.process_time() - cpu
    # The tool centre sits ts/2 pixels into each window; the peer's Y counts from row h-ts.
    ts = tool.shape[0]
    print("SECONDS %.6f" % seconds)
    print("CPU %.6f" % cpu)
    print("OFFSET %.9f %.9f" % (ts / 2 * pixel, (ts / 2 - 1) * pixel))


if __name__ == "__main__":
    main()
