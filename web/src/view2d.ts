// What the 2-D drawing views share (the CAM job's shape view and the design editor):
// SVG elements, the distance from a point to a segment, and a pannable, zoomable mapping
// between drawing millimetres (y up) and the view's pixels (y down).

export const SVG = 'http://www.w3.org/2000/svg';

export function el(tag: string, attrs: Record<string, string | number>, parent: Element): SVGElement {
  const e = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, String(v));
  parent.appendChild(e);
  return e;
}

export type Pt = [number, number];

export function segDist(p: Pt, a: Pt, b: Pt): number {
  const dx = b[0] - a[0], dy = b[1] - a[1];
  const l = dx * dx + dy * dy;
  const t = l ? Math.max(0, Math.min(1, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l)) : 0;
  return Math.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy);
}

/// Drawing ↔ view pixels: x' = (x − x0)·s, y' = H − (y − y0)·s on a W × H view.
export class ViewMap {
  x0 = 0; y0 = 0; s = 1;
  constructor(public W: number, public H: number) {}
  sx(x: number) { return (x - this.x0) * this.s; }
  sy(y: number) { return this.H - (y - this.y0) * this.s; }
  /// Drawing coordinates of a mouse event on `svg` (its viewBox is W × H).
  at(e: MouseEvent, svg: Element): Pt {
    const r = svg.getBoundingClientRect();
    const px = (e.clientX - r.left) * (this.W / r.width), py = (e.clientY - r.top) * (this.H / r.height);
    return [px / this.s + this.x0, (this.H - py) / this.s + this.y0];
  }
  /// Shows the box [x0, y0, x1, y1] whole, with `pad` pixels around it.
  fit(b: [number, number, number, number], pad = 16) {
    this.s = Math.min((this.W - 2 * pad) / Math.max(b[2] - b[0], 1e-6), (this.H - 2 * pad) / Math.max(b[3] - b[1], 1e-6));
    this.x0 = b[0] - pad / this.s; this.y0 = b[1] - pad / this.s;
  }
  /// Zooms by `k` keeping the drawing point `p` where it is on the view.
  zoom(k: number, p: Pt) {
    this.x0 = p[0] - (p[0] - this.x0) / k; this.y0 = p[1] - (p[1] - this.y0) / k; this.s *= k;
  }
  /// Moves the view by pixels (dx right, dy down).
  pan(dx: number, dy: number) { this.x0 -= dx / this.s; this.y0 += dy / this.s; }
}
