// The design as the page holds it: the very schema of the `*.oficina.json` file that
// `oficina_io` reads (crates/io/src/design/model.rs), so saving is JSON.stringify and every
// command reads what the page wrote. Geometry here is what the page needs to draw and pick
// (arcs are flattened for display only); offsets and exports are the server's (Rust).

import type { Pt } from '../view2d';

export type Shape =
  | { type: 'line'; a: Pt; b: Pt }
  | { type: 'arc'; center: Pt; radius: number; start: number; sweep: number }
  | { type: 'circle'; center: Pt; radius: number }
  | { type: 'polyline'; vertices: number[][]; closed: boolean }
  | { type: 'spline'; points: Pt[] }
  | { type: 'point'; at: Pt }
  | { type: 'text'; at: Pt; height: number; angle: number; text: string };
export type Entity = Shape & { id: number; layer: string };
export interface Layer { name: string; color: string; }
export interface Design {
  format: 'oficina-design'; version: 1; layers: Layer[]; entities: Entity[];
  process?: Record<string, unknown>;
}

export function emptyDesign(): Design {
  return { format: 'oficina-design', version: 1, layers: [{ name: '0', color: '#000000' }], entities: [] };
}

export const nextId = (d: Design) => d.entities.reduce((m, e) => Math.max(m, e.id), 0) + 1;
export const rad = (deg: number) => (deg * Math.PI) / 180;
/// The point at `deg` degrees on the circle (c, r).
export const arcPoint = (c: Pt, r: number, deg: number): Pt => [c[0] + r * Math.cos(rad(deg)), c[1] + r * Math.sin(rad(deg))];

/// The arc a bulge makes from `a` to `b` (DXF: tan(sweep/4), > 0 counter-clockwise):
/// chord c, sweep θ = 4·atan(bulge), radius (c/2)/sin(θ/2), centre on the chord's left
/// normal at (c/2)/tan(θ/2) from its middle.
export function bulgeArc(a: Pt, b: Pt, bulge: number): { center: Pt; radius: number; start: number; sweep: number } {
  const cx = b[0] - a[0], cy = b[1] - a[1], c = Math.hypot(cx, cy);
  const th = 4 * Math.atan(bulge), d = c / 2 / Math.tan(th / 2);
  const center: Pt = [(a[0] + b[0]) / 2 - (cy / c) * d, (a[1] + b[1]) / 2 + (cx / c) * d];
  return { center, radius: Math.abs(c / 2 / Math.sin(th / 2)), start: Math.atan2(a[1] - center[1], a[0] - center[0]), sweep: th };
}

function arcPoints(center: Pt, r: number, start: number, sweep: number, out: Pt[]) {
  const n = Math.max(2, Math.ceil(Math.abs(sweep) / (Math.PI / 48)));
  for (let k = 1; k <= n; k++) { const t = start + (sweep * k) / n; out.push([center[0] + r * Math.cos(t), center[1] + r * Math.sin(t)]); }
}

/// Points to draw the entity with (display only; the geometry is the entity's numbers).
export function outline(e: Shape): Pt[][] {
  switch (e.type) {
    case 'line': return [[e.a, e.b]];
    // A point is a zero-length piece: picked and boxed like the rest, drawn as a marker.
    case 'point': return [[e.at, e.at]];
    case 'arc': { const s = rad(e.start), r = e.radius; const o: Pt[] = [[e.center[0] + r * Math.cos(s), e.center[1] + r * Math.sin(s)]]; arcPoints(e.center, r, s, rad(e.sweep), o); return [o]; }
    case 'circle': { const o: Pt[] = [[e.center[0] + e.radius, e.center[1]]]; arcPoints(e.center, e.radius, 0, 2 * Math.PI, o); return [o]; }
    case 'polyline': {
      const v = e.vertices, n = v.length, o: Pt[] = [[v[0][0], v[0][1]]];
      for (let k = 0; k < (e.closed ? n : n - 1); k++) {
        const a: Pt = [v[k][0], v[k][1]], b: Pt = [v[(k + 1) % n][0], v[(k + 1) % n][1]], g = v[k][2] ?? 0;
        if (g) { const arc = bulgeArc(a, b, g); arcPoints(arc.center, arc.radius, arc.start, arc.sweep, o); } else o.push(b);
      }
      return [o];
    }
    // Display: a uniform Catmull–Rom through the points; the file's curve is the
    // server's natural cubic (crates/io/src/dxf/spline.rs), within a fraction of a mm.
    case 'spline': {
      const p = e.points, o: Pt[] = [p[0]];
      for (let i = 0; i + 1 < p.length; i++) {
        const p0 = p[Math.max(0, i - 1)], p1 = p[i], p2 = p[i + 1], p3 = p[Math.min(p.length - 1, i + 2)];
        for (let k = 1; k <= 12; k++) {
          const t = k / 12, t2 = t * t, t3 = t2 * t;
          const f = (a: number, b: number, c: number, d: number) => 0.5 * (2 * b + (-a + c) * t + (2 * a - 5 * b + 4 * c - d) * t2 + (-a + 3 * b - 3 * c + d) * t3);
          o.push([f(p0[0], p1[0], p2[0], p3[0]), f(p0[1], p1[1], p2[1], p3[1])]);
        }
      }
      return [o];
    }
    // Display: a box on the baseline, capitals `height` tall, 0.8 per character.
    case 'text': {
      const w = e.height * 0.8 * e.text.length, c = Math.cos(rad(e.angle)), s = Math.sin(rad(e.angle));
      const q = (x: number, y: number): Pt => [e.at[0] + x * c - y * s, e.at[1] + x * s + y * c];
      return [[q(0, 0), q(w, 0), q(w, e.height), q(0, e.height), q(0, 0)]];
    }
  }
}

/// The points snapping looks for: ends, middles of straight pieces, centres.
export function snapPoints(e: Shape): { p: Pt; kind: 'end' | 'mid' | 'centre' }[] {
  const out: { p: Pt; kind: 'end' | 'mid' | 'centre' }[] = [];
  const mid = (a: Pt, b: Pt): Pt => [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2];
  switch (e.type) {
    case 'line': out.push({ p: e.a, kind: 'end' }, { p: e.b, kind: 'end' }, { p: mid(e.a, e.b), kind: 'mid' }); break;
    case 'circle': out.push({ p: e.center, kind: 'centre' }); break;
    case 'arc': { const o = outline(e)[0]; out.push({ p: o[0], kind: 'end' }, { p: o[o.length - 1], kind: 'end' }, { p: e.center, kind: 'centre' }); break; }
    case 'polyline': {
      const v = e.vertices, n = v.length;
      v.forEach((q) => out.push({ p: [q[0], q[1]], kind: 'end' }));
      for (let k = 0; k < (e.closed ? n : n - 1); k++) {
        const a: Pt = [v[k][0], v[k][1]], b: Pt = [v[(k + 1) % n][0], v[(k + 1) % n][1]];
        if (v[k][2]) out.push({ p: bulgeArc(a, b, v[k][2]).center, kind: 'centre' }); else out.push({ p: mid(a, b), kind: 'mid' });
      }
      break;
    }
    case 'spline': e.points.forEach((p) => out.push({ p, kind: 'end' })); break;
    case 'text': case 'point': out.push({ p: e.at, kind: 'end' }); break;
  }
  return out;
}

/// An affine map of the plane: x' = a·x + b·y + c, y' = d·x + e·y + f.
export type Affine = [number, number, number, number, number, number];
export const translate = (dx: number, dy: number): Affine => [1, 0, dx, 0, 1, dy];
export function rotate(c: Pt, deg: number): Affine {
  const t = rad(deg), k = Math.cos(t), s = Math.sin(t);
  return [k, -s, c[0] - k * c[0] + s * c[1], s, k, c[1] - s * c[0] - k * c[1]];
}
export const scale = (c: Pt, f: number): Affine => [f, 0, c[0] * (1 - f), 0, f, c[1] * (1 - f)];
/// Reflection across the line through `a` and `b`: with the axis at angle φ, the linear part
/// is [[cos 2φ, sin 2φ], [sin 2φ, −cos 2φ]], fixed on `a`.
export function mirror(a: Pt, b: Pt): Affine {
  const p = 2 * Math.atan2(b[1] - a[1], b[0] - a[0]), k = Math.cos(p), s = Math.sin(p);
  return [k, s, a[0] - k * a[0] - s * a[1], s, -k, a[1] - s * a[0] + k * a[1]];
}
const ap = (m: Affine, p: Pt): Pt => [m[0] * p[0] + m[1] * p[1] + m[2], m[3] * p[0] + m[4] * p[1] + m[5]];

/// The entity under a similarity `m` (moves, turns, uniform scales, mirrors: circles stay
/// circles). A mirror reverses the turning of arcs and bulges. Exact, so done here.
export function transformed(e: Entity, m: Affine): Entity {
  const det = m[0] * m[4] - m[1] * m[3], k = Math.sqrt(Math.abs(det)), flip = det < 0;
  const turn = (Math.atan2(m[3], m[0]) * 180) / Math.PI; // angle the x axis turns to
  switch (e.type) {
    case 'line': return { ...e, a: ap(m, e.a), b: ap(m, e.b) };
    case 'circle': return { ...e, center: ap(m, e.center), radius: e.radius * k };
    case 'arc': return { ...e, center: ap(m, e.center), radius: e.radius * k, start: flip ? turn - e.start : e.start + turn, sweep: flip ? -e.sweep : e.sweep };
    case 'polyline': return { ...e, vertices: e.vertices.map((v) => { const q = ap(m, [v[0], v[1]]); return v[2] ? [q[0], q[1], flip ? -v[2] : v[2]] : q; }) };
    case 'spline': return { ...e, points: e.points.map((p) => ap(m, p)) };
    case 'point': return { ...e, at: ap(m, e.at) };
    case 'text': return { ...e, at: ap(m, e.at), height: e.height * k, angle: e.angle + turn };
  }
}

/// A corner of a polyline rounded (`round`) or cut (`!round`), `size` the radius or the
/// chamfer's leg. No Rust fillet exists, and this one is exact and small, so it lives here:
/// with u, w the unit vectors from the corner V to its neighbours and θ the angle between
/// them, the tangent points are V + t·u and V + t·w with t = r / tan(θ/2) (a chamfer:
/// t = size); the arc turns by π − θ, so its bulge is ±tan((π − θ)/4), + where the
/// corner turns left. Both pieces at the corner must be straight and long enough.
export function cornered(e: Entity, k: number, size: number, round: boolean): Entity | string {
  if (e.type !== 'polyline') return 'fillet and chamfer work on polyline corners';
  const v = e.vertices, n = v.length;
  if (!e.closed && (k === 0 || k === n - 1)) return 'an open polyline has no corner at its ends';
  const ip = (k - 1 + n) % n, inx = (k + 1) % n;
  if (v[ip][2] || v[k][2]) return 'the corner joins an arc: only corners between straight pieces';
  const V: Pt = [v[k][0], v[k][1]];
  const ux = v[ip][0] - V[0], uy = v[ip][1] - V[1], wx = v[inx][0] - V[0], wy = v[inx][1] - V[1];
  const lu = Math.hypot(ux, uy), lw = Math.hypot(wx, wy);
  const th = Math.acos(Math.max(-1, Math.min(1, (ux * wx + uy * wy) / (lu * lw))));
  if (th < 1e-9 || Math.PI - th < 1e-9) return 'the pieces at this corner are in line';
  const t = round ? size / Math.tan(th / 2) : size;
  if (t > lu + 1e-9 || t > lw + 1e-9) return `${round ? 'radius' : 'chamfer'} ${size} needs ${t.toFixed(3)} mm of each piece; they are ${lu.toFixed(3)} and ${lw.toFixed(3)}`;
  const left = (V[0] - v[ip][0]) * (v[inx][1] - V[1]) - (V[1] - v[ip][1]) * (v[inx][0] - V[0]) > 0;
  const bulge = round ? (left ? 1 : -1) * Math.tan((Math.PI - th) / 4) : 0;
  const t1 = [V[0] + (ux / lu) * t, V[1] + (uy / lu) * t], t2 = [V[0] + (wx / lw) * t, V[1] + (wy / lw) * t];
  const vertices = [...v.slice(0, k), bulge ? [t1[0], t1[1], bulge] : t1, t2, ...v.slice(k + 1)];
  return { ...e, vertices };
}

/// The polyline vertex nearest `p` in the design: [entity index, vertex index, distance].
export function nearestCorner(d: Design, p: Pt): [number, number, number] | null {
  let best: [number, number, number] | null = null;
  d.entities.forEach((e, i) => {
    if (e.type !== 'polyline') return;
    e.vertices.forEach((v, k) => { const dist = Math.hypot(v[0] - p[0], v[1] - p[1]); if (!best || dist < best[2]) best = [i, k, dist]; });
  });
  return best;
}

/// A polyline as its pieces: lines and arcs (the arc of a bulge, see `bulgeArc`).
export function exploded(e: Entity): Shape[] | null {
  if (e.type !== 'polyline') return null;
  const v = e.vertices, n = v.length, out: Shape[] = [];
  for (let k = 0; k < (e.closed ? n : n - 1); k++) {
    const a: Pt = [v[k][0], v[k][1]], b: Pt = [v[(k + 1) % n][0], v[(k + 1) % n][1]];
    if (v[k][2]) {
      const arc = bulgeArc(a, b, v[k][2]);
      out.push({ type: 'arc', center: arc.center, radius: arc.radius, start: (arc.start * 180) / Math.PI, sweep: (arc.sweep * 180) / Math.PI });
    } else out.push({ type: 'line', a, b });
  }
  return out;
}

/// Lines, arcs and open polylines whose ends meet (within `tol`) chained into one polyline,
/// closed when the chain comes back to its start. A piece run backwards keeps its arc with
/// the bulge negated. Null when the pieces do not form one chain.
export function joined(es: Entity[], tol = 1e-6): Shape | null {
  type Piece = { a: Pt; b: Pt; bulge: number }[];
  const pieces: Piece[] = [];
  for (const e of es) {
    if (e.type === 'line') pieces.push([{ a: e.a, b: e.b, bulge: 0 }]);
    else if (e.type === 'arc') {
      pieces.push([{ a: arcPoint(e.center, e.radius, e.start), b: arcPoint(e.center, e.radius, e.start + e.sweep), bulge: Math.tan(rad(e.sweep) / 4) }]);
    } else if (e.type === 'polyline' && !e.closed) {
      const v = e.vertices;
      pieces.push(v.slice(0, -1).map((q, k) => ({ a: [q[0], q[1]] as Pt, b: [v[k + 1][0], v[k + 1][1]] as Pt, bulge: q[2] ?? 0 })));
    } else return null;
  }
  const near = (p: Pt, q: Pt) => Math.hypot(p[0] - q[0], p[1] - q[1]) <= tol;
  const rev = (p: Piece): Piece => p.slice().reverse().map((s) => ({ a: s.b, b: s.a, bulge: -s.bulge }));
  let chain = pieces.shift()!;
  while (pieces.length) {
    const end = chain[chain.length - 1].b, start = chain[0].a;
    const k = pieces.findIndex((p) => near(p[0].a, end) || near(p[p.length - 1].b, end) || near(p[p.length - 1].b, start) || near(p[0].a, start));
    if (k < 0) return null;
    const p = pieces.splice(k, 1)[0];
    if (near(p[0].a, end)) chain = [...chain, ...p];
    else if (near(p[p.length - 1].b, end)) chain = [...chain, ...rev(p)];
    else if (near(p[p.length - 1].b, start)) chain = [...p, ...chain];
    else chain = [...rev(p), ...chain];
  }
  const closed = chain.length > 1 && near(chain[chain.length - 1].b, chain[0].a);
  const vertices = chain.map((s) => (s.bulge ? [s.a[0], s.a[1], s.bulge] : [s.a[0], s.a[1]]));
  if (!closed) vertices.push([chain[chain.length - 1].b[0], chain[chain.length - 1].b[1]]);
  return { type: 'polyline', vertices, closed };
}

/// A regular polygon of `sides` about `c` with its vertices on the circle of radius `r`,
/// the first at angle `a0` degrees.
export function polygon(c: Pt, r: number, sides: number, a0 = 90): Shape {
  const vertices = Array.from({ length: sides }, (_, k) => { const t = rad(a0 + (360 * k) / sides); return [c[0] + r * Math.cos(t), c[1] + r * Math.sin(t)]; });
  return { type: 'polyline', vertices, closed: true };
}

/// Where the line a → b meets the entity `e`: parameters t ∈ [0, 1] along a → b. Exact for
/// every piece but splines and text (their display points are used). Lines: the 2 × 2
/// solve; circles and arcs: |a + t·d − c|² = r², a quadratic in t, kept where an arc
/// covers the angle.
export function crossings(a: Pt, b: Pt, e: Shape): number[] {
  const d: Pt = [b[0] - a[0], b[1] - a[1]], out: number[] = [];
  const withLine = (p: Pt, q: Pt) => {
    const den = d[0] * (q[1] - p[1]) - d[1] * (q[0] - p[0]);
    if (Math.abs(den) < 1e-12) return;
    const t = ((p[0] - a[0]) * (q[1] - p[1]) - (p[1] - a[1]) * (q[0] - p[0])) / den;
    const u = ((p[0] - a[0]) * d[1] - (p[1] - a[1]) * d[0]) / den;
    if (t >= -1e-12 && t <= 1 + 1e-12 && u >= -1e-12 && u <= 1 + 1e-12) out.push(t);
  };
  const withCircle = (c: Pt, r: number, start?: number, sweep?: number) => {
    const fx = a[0] - c[0], fy = a[1] - c[1], A = d[0] * d[0] + d[1] * d[1], B = 2 * (fx * d[0] + fy * d[1]), C = fx * fx + fy * fy - r * r;
    const disc = B * B - 4 * A * C;
    if (disc < 0 || A === 0) return;
    for (const t of [(-B - Math.sqrt(disc)) / (2 * A), (-B + Math.sqrt(disc)) / (2 * A)]) {
      if (t < -1e-12 || t > 1 + 1e-12) continue;
      if (sweep !== undefined && start !== undefined) {
        if (!onArc(Math.atan2(a[1] + t * d[1] - c[1], a[0] + t * d[0] - c[0]), start, sweep)) continue;
      }
      out.push(t);
    }
  };
  switch (e.type) {
    case 'line': withLine(e.a, e.b); break;
    case 'circle': withCircle(e.center, e.radius); break;
    case 'arc': withCircle(e.center, e.radius, rad(e.start), rad(e.sweep)); break;
    case 'polyline': {
      const v = e.vertices, n = v.length;
      for (let k = 0; k < (e.closed ? n : n - 1); k++) {
        const p: Pt = [v[k][0], v[k][1]], q: Pt = [v[(k + 1) % n][0], v[(k + 1) % n][1]];
        if (v[k][2]) { const arc = bulgeArc(p, q, v[k][2]); withCircle(arc.center, arc.radius, arc.start, arc.sweep); } else withLine(p, q);
      }
      break;
    }
    default: for (const line of outline(e)) for (let k = 1; k < line.length; k++) withLine(line[k - 1], line[k]);
  }
  return out;
}

const unit = (v: Pt): Pt => { const l = Math.hypot(v[0], v[1]); return [v[0] / l, v[1] / l]; };
/// Direction of travel on an arc (degrees, sweep sign) at angle `deg`: ±(−sin, cos).
const arcHeading = (deg: number, sweep: number): Pt => { const t = rad(deg), s = Math.sign(sweep); return [-s * Math.sin(t), s * Math.cos(t)]; };

/// The end of a line, arc or open polyline at `p` (within `tol`) and the direction leaving
/// the piece there (the way a chain continues from it); null when no such end is there.
export function endHeading(d: Design, p: Pt, tol: number): { at: Pt; heading: Pt } | null {
  const near = (q: Pt) => Math.hypot(q[0] - p[0], q[1] - p[1]) <= tol;
  for (const e of d.entities) {
    const pieces = e.type === 'polyline' ? (e.closed ? [] : exploded(e) ?? []) : [e];
    const first = pieces[0], last = pieces[pieces.length - 1];
    for (const [piece, atEnd] of [[last, true], [first, false]] as [Shape | undefined, boolean][]) {
      if (piece?.type === 'line') {
        const [from, to] = atEnd ? [piece.a, piece.b] : [piece.b, piece.a];
        if (near(to)) return { at: to, heading: unit([to[0] - from[0], to[1] - from[1]]) };
      } else if (piece?.type === 'arc') {
        const ang = atEnd ? piece.start + piece.sweep : piece.start;
        const at = arcPoint(piece.center, piece.radius, ang);
        const h = arcHeading(ang, piece.sweep);
        if (near(at)) return { at, heading: atEnd ? h : [-h[0], -h[1]] };
      }
    }
  }
  return null;
}

/// The arc leaving `p` along the unit heading `t` and ending at `q`. With d = q − p, the
/// centre is on the normal (−t_y, t_x) at the signed radius r = |d|² / (2 t×d) (the centre
/// is as far from q as from p), and the sweep is twice the angle from t to d (the tangent–
/// chord angle is half the arc's). Also returns the heading at `q` to chain the next arc.
export function tangentArc(p: Pt, t: Pt, q: Pt): { arc: Shape; heading: Pt } | string {
  const d: Pt = [q[0] - p[0], q[1] - p[1]], len2 = d[0] * d[0] + d[1] * d[1];
  const cr = t[0] * d[1] - t[1] * d[0], dot = t[0] * d[0] + t[1] * d[1];
  if (len2 === 0) return 'the end is the start';
  if (Math.abs(cr) <= 1e-12 * len2) return 'the end is straight along the tangent: draw a line';
  const r = len2 / (2 * cr), center: Pt = [p[0] - r * t[1], p[1] + r * t[0]];
  const start = (Math.atan2(p[1] - center[1], p[0] - center[0]) * 180) / Math.PI;
  const sweep = (2 * Math.atan2(cr, dot) * 180) / Math.PI;
  return { arc: { type: 'arc', center, radius: Math.abs(r), start, sweep }, heading: arcHeading(start + sweep, sweep) };
}

/// Where the circle (c, r) meets the entity `e`: straight pieces by `crossings` (the line's
/// quadratic); circles, arcs and bulges by the two-circle formula (along the centre line at
/// a = (r² − R² + D²) / 2D, then ±√(r² − a²) across it), kept where an arc covers them.
export function circleHits(c: Pt, r: number, e: Shape): Pt[] {
  const out: Pt[] = [], me: Shape = { type: 'circle', center: c, radius: r };
  const withArc = (C: Pt, R: number, start?: number, sweep?: number) => {
    const dx = C[0] - c[0], dy = C[1] - c[1], D = Math.hypot(dx, dy);
    if (D < 1e-12 || D > r + R + 1e-12 || D < Math.abs(r - R) - 1e-12) return;
    const a = (r * r - R * R + D * D) / (2 * D), h = Math.sqrt(Math.max(0, r * r - a * a));
    const bx = c[0] + (a * dx) / D, by = c[1] + (a * dy) / D;
    for (const q of [[bx - (h * dy) / D, by + (h * dx) / D], [bx + (h * dy) / D, by - (h * dx) / D]] as Pt[]) {
      if (start !== undefined && sweep !== undefined && !onArc(Math.atan2(q[1] - C[1], q[0] - C[0]), start, sweep)) continue;
      out.push(q);
    }
  };
  const pieces = e.type === 'polyline' ? exploded(e as Entity) ?? [] : [e];
  for (const s of pieces) {
    if (s.type === 'circle') withArc(s.center, s.radius);
    else if (s.type === 'arc') withArc(s.center, s.radius, rad(s.start), rad(s.sweep));
    else for (const line of outline(s)) for (let k = 1; k < line.length; k++) {
      const [a, b] = [line[k - 1], line[k]];
      for (const t of crossings(a, b, me)) out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
    }
  }
  return out;
}

/// The turn (radians, in [0, 2π)) from `start` to angle `t`, measured the way `sweep` turns.
export const turnFrom = (t: number, start: number, sweep: number) => ((((t - start) * Math.sign(sweep)) % (2 * Math.PI)) + 2 * Math.PI) % (2 * Math.PI);
/// Angle `t` (radians) is on the arc from `start` sweeping `sweep` (radians).
function onArc(t: number, start: number, sweep: number): boolean {
  return turnFrom(t, start, sweep) <= Math.abs(sweep) + 1e-12;
}
