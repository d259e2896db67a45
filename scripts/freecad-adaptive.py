# FreeCAD's adaptive clearing on given rings, posted to G-code by its LinuxCNC post.
#
# Run as `freecadcmd scripts/freecad-adaptive.py` with FC_ADAPTIVE_IN naming a JSON file
# {"rings": [[[x, y], ...], ...], "tool": diameter, "stepover": percent of the diameter,
#  "depth": mm below 0, "stepdown": mm, "feed": mm/min, "plunge": mm/min}
# and FC_ADAPTIVE_OUT the G-code file to write. The engine is the Path workbench's own
# (area.Adaptive2d, as PathAdaptive.Execute sets it up: clearing inside, finishing
# profile on, keep-tool-down ratio 3) and the moves are PathAdaptive.GenerateGCode's; only
# the document objects around them (job, stock, tool controller) are stand-ins.
import json
import os
import types

import FreeCAD
import Path
import area
from PathScripts import PathAdaptive
from PathScripts.post import linuxcnc_post

job = json.load(open(os.environ["FC_ADAPTIVE_IN"]))
rings = [[(float(x), float(y)) for x, y in ring] for ring in job["rings"]]
xs = [p[0] for r in rings for p in r]
ys = [p[1] for r in rings for p in r]
margin = job["tool"]
stock = [
    [
        (min(xs) - margin, min(ys) - margin),
        (max(xs) + margin, min(ys) - margin),
        (max(xs) + margin, max(ys) + margin),
        (min(xs) - margin, max(ys) + margin),
    ]
]

a2d = area.Adaptive2d()
a2d.stepOverFactor = 0.01 * job["stepover"]
a2d.toolDiameter = float(job["tool"])
a2d.helixRampDiameter = 0.0
a2d.keepToolDownDistRatio = 3.0
a2d.stockToLeave = 0.0
a2d.tolerance = 0.1
a2d.forceInsideOut = False
a2d.finishingProfile = True
a2d.opType = area.AdaptiveOperationType.ClearingInside
results = [
    {
        "HelixCenterPoint": r.HelixCenterPoint,
        "StartPoint": r.StartPoint,
        "AdaptivePaths": r.AdaptivePaths,
        "ReturnMotionType": r.ReturnMotionType,
    }
    for r in a2d.Execute(stock, rings, lambda paths: False)
]


def length(v):
    return types.SimpleNamespace(Value=float(v))


# The operation's properties at PathAdaptive's defaults (opSetDefaultValues), depths and
# heights as a job would set them.
obj = types.SimpleNamespace(
    StepDown=length(job["stepdown"]),
    StartDepth=length(0.0),
    FinalDepth=length(-job["depth"]),
    FinishDepth=length(0.0),
    ClearanceHeight=length(5.0),
    SafeHeight=length(3.0),
    LiftDistance=length(0.0),
    HelixAngle=5.0,
    HelixConeAngle=0.0,
    UseHelixArcs=False,
)
# Path feeds are mm/s; the post writes them per minute.
op = types.SimpleNamespace(
    commandlist=[], horizFeed=job["feed"] / 60.0, vertFeed=job["plunge"] / 60.0
)
PathAdaptive.GenerateGCode(op, obj, results, 0.0)

posted = types.SimpleNamespace(Path=Path.Path(op.commandlist), Label="Adaptive", Name="Adaptive")
text = linuxcnc_post.export([posted], "-", "--no-show-editor --no-header --no-comments")
# The post starts with G17 G54 G40 G49 G80 G90 / G21 and ends with M2; add the spindle.
with open(os.environ["FC_ADAPTIVE_OUT"], "w") as f:
    f.write("M3 S18000\n" + text)
FreeCAD.Console.PrintMessage("wrote %d commands\n" % len(op.commandlist))
