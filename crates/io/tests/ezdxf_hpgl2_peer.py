# ezdxf's HP-GL/2 interpreter as a peer reader: extents (mm) and pen-down length (mm) of
# what it plots (polylines and outlined paths; filled paths are skipped as fills).
import sys, types
class Stub(types.ModuleType):
    __path__ = []
    def __getattr__(self, k): return None
try:
    import PIL.Image, PIL.ImageEnhance
except ImportError:  # ezdxf's drawing add-on imports Pillow for raster images only
    for m in ['PIL', 'PIL.Image', 'PIL.ImageEnhance', 'PIL.ImageDraw', 'PIL.ImageOps']:
        sys.modules[m] = Stub(m)
from ezdxf.addons.hpgl2 import api
from ezdxf.addons.hpgl2.backend import RecordType
player = api.record_plotter_output(open(sys.argv[1], 'rb').read(), api.MergeControl.NONE)
xs, ys, L = [], [], 0.0
for kind, _, data in player.recordings():
    if kind == RecordType.POLYLINE:
        lines = [list(data.vertices())]
    elif kind == RecordType.OUTLINE_PATHS:
        lines = [list(p.flattening(0.1)) for p in data]
    else:
        continue
    for pts in lines:
        xs += [p.x for p in pts]; ys += [p.y for p in pts]
        L += sum((a - b).magnitude for a, b in zip(pts, pts[1:]))
print(min(xs) / 40, min(ys) / 40, max(xs) / 40, max(ys) / 40, L / 40)
