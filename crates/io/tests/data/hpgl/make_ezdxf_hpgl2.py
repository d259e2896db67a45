# Writes the ezdxf_hpgl2_*.plt files here: HP-GL/2 as ezdxf's plotter backend writes it (PE
# with fractional bits, BR Béziers) from real DXF files of ../shared/data/realworld/mill-dxf-svg.
# Usage: python3 make_ezdxf_hpgl2.py ezdxf_forms.dxf camotics_border.dxf   (ezdxf 1.4.5)
import os
import sys, types
class Stub(types.ModuleType):
    __path__ = []
    def __getattr__(self, k): return None
for m in ['PIL', 'PIL.Image', 'PIL.ImageEnhance', 'PIL.ImageDraw', 'PIL.ImageOps']:
    sys.modules[m] = Stub(m)
import ezdxf
from ezdxf.addons.drawing import RenderContext, Frontend, layout
from ezdxf.addons.drawing.hpgl2 import PlotterBackend
for name in sys.argv[1:]:
    data = os.environ.get('OFICINA_REALWORLD', '/work/shared/data/realworld')
    doc = ezdxf.readfile(os.path.join(data, 'mill-dxf-svg', name))
    backend = PlotterBackend()
    Frontend(RenderContext(doc), backend).draw_layout(doc.modelspace())
    data = backend.get_bytes(layout.Page(0, 0))
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'ezdxf_hpgl2_') + name.rsplit('.', 1)[0].replace(' ', '_') + '.plt'
    open(out, 'wb').write(data)
    print(out, len(data), data[:100])
