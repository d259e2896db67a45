// Trim and extend. An entity is walked as runs (its straight and circular pieces) with a
// position s = k + f: run k, fraction f along it (for an arc, of its sweep). Crossings with
// the other entities are positions, found by `crossings` (a run's line) and `circleHits`
// (a run's circle); trimming keeps what lies outside the two crossings around the pick.

import type { Pt } from '../view2d';
import { Entity, Shape, arcPoint, crossings, circleHits, exploded, rad, turnFrom } from './model';

/// A straight piece a → b, or (with `arc`) the arc from a to b: degrees, as the file has them.
type Run = { a: Pt; b: Pt; arc?: { center: Pt; radius: number; start: number; sweep: number } };

function runOf(s: Shape): Run {
  if (s.type === 'line') return { a: s.a, b: s.b };
  if (s.type !== 'arc') throw new Error(`a ${s.type} is not a run`);
  return { a: arcPoint(s.center, s.radius, s.start), b: arcPoint(s.center, s.radius, s.start + s.sweep), arc: s };
}

/// The runs of a line, arc, circle (one full turn from 0°) or polyline, and whether the
/// walk comes back to its start (circles, closed polylines); null for the other kinds.
function runsOf(e: Entity): { runs: Run[]; closed: boolean } | null {
  switch (e.type) {
    case 'line': case 'arc': return { runs: [runOf(e)], closed: false };
    case 'circle': return { runs: [runOf({ type: 'arc', center: e.center, radius: e.radius, start: 0, sweep: 360 })], closed: true };
    case 'polyline': return { runs: exploded(e)!.map(runOf), closed: e.closed };
    default: return null;
  }
}

/// The point at fraction f of a run; its own ends exactly at 0 and 1.
function at(r: Run, f: number): Pt {
  if (f <= 0) return r.a;
  if (f >= 1) return r.b;
  if (r.arc) return arcPoint(r.arc.center, r.arc.radius, r.arc.start + f * r.arc.sweep);
  return [r.a[0] + f * (r.b[0] - r.a[0]), r.a[1] + f * (r.b[1] - r.a[1])];
}

/// Fractions along a run where `o` crosses it: the line's parameters, or the turn from the
/// arc's start to each point on its circle over the sweep (kept when within the sweep).
function hits(r: Run, o: Shape): number[] {
  if (!r.arc) return crossings(r.a, r.b, o);
  const { center: c, radius, start, sweep } = r.arc, w = Math.abs(rad(sweep));
  return circleHits(c, radius, o).map((q) => turnFrom(Math.atan2(q[1] - c[1], q[0] - c[0]), rad(start), rad(sweep)) / w).filter((f) => f <= 1 + 1e-12);
}

/// The position on the runs nearest `p`.
function nearest(runs: Run[], p: Pt): number {
  let best = 0, bestD = Infinity;
  runs.forEach((r, k) => {
    let f: number;
    if (r.arc) {
      const { center: c, start, sweep } = r.arc;
      f = turnFrom(Math.atan2(p[1] - c[1], p[0] - c[0]), rad(start), rad(sweep)) / Math.abs(rad(sweep));
      // Past the sweep: the nearer end.
      if (f > 1) f = Math.hypot(p[0] - r.a[0], p[1] - r.a[1]) < Math.hypot(p[0] - r.b[0], p[1] - r.b[1]) ? 0 : 1;
    } else {
      const dx = r.b[0] - r.a[0], dy = r.b[1] - r.a[1];
      f = Math.max(0, Math.min(1, ((p[0] - r.a[0]) * dx + (p[1] - r.a[1]) * dy) / (dx * dx + dy * dy || 1)));
    }
    const q = at(r, f), d = Math.hypot(p[0] - q[0], p[1] - q[1]);
    if (d < bestD) { bestD = d; best = k + f; }
  });
  return best;
}

/// The runs between positions s0 < s1 (s1 may pass the last run's end on a closed walk:
/// the runs are taken round again).
function between(runs: Run[], s0: number, s1: number): Run[] {
  const out: Run[] = [], n = runs.length;
  for (let k = Math.floor(s0); k < s1; k++) {
    const r = runs[k % n], f0 = Math.max(0, s0 - k), f1 = Math.min(1, s1 - k);
    if (f1 - f0 < 1e-12) continue;
    const arc = r.arc && { ...r.arc, start: r.arc.start + f0 * r.arc.sweep, sweep: (f1 - f0) * r.arc.sweep };
    out.push({ a: at(r, f0), b: at(r, f1), arc });
  }
  return out;
}

/// Runs back as the kind trimmed: a line, an arc (also what a circle leaves), a polyline
/// (open: a closed one cut once is open) with the bulge tan(sweep/4) on each arc's start.
function shapeOf(kind: Entity['type'], runs: Run[]): Shape {
  const r = runs[0];
  if (kind === 'line') return { type: 'line', a: r.a, b: r.b };
  if (kind !== 'polyline') return { type: 'arc', ...r.arc! };
  const vertices = runs.map((q) => (q.arc ? [q.a[0], q.a[1], Math.tan(rad(q.arc.sweep) / 4)] : [q.a[0], q.a[1]]));
  const end = runs[runs.length - 1].b;
  return { type: 'polyline', closed: false, vertices: [...vertices, [end[0], end[1]]] };
}

/// `e` trimmed where it is picked at `p`: the part between the crossings with `others` on
/// either side of the pick goes (to the end where there is none on that side of an open
/// one; a circle or closed polyline needs two crossings and keeps the rest, from the one
/// after the pick round to the one before it). Returns what stays (none, one or two
/// entities of e's kind, a circle's rest an arc), or a message.
export function trimmed(e: Entity, others: Shape[], p: Pt): Shape[] | string {
  const walk = runsOf(e);
  if (!walk) return 'trim works on lines, arcs, circles and polylines';
  const { runs, closed } = walk, n = runs.length;
  const ss = runs.flatMap((r, k) => others.flatMap((o) => hits(r, o)).map((f) => k + f));
  const sc = nearest(runs, p);
  if (!closed) {
    const inside = ss.filter((s) => s > 1e-9 && s < n - 1e-9);
    if (!inside.length) return `nothing crosses this ${e.type}: delete it instead`;
    const before = Math.max(0, ...inside.filter((s) => s < sc)), after = Math.min(n, ...inside.filter((s) => s > sc));
    const keep: Shape[] = [];
    if (before > 1e-9) keep.push(shapeOf(e.type, between(runs, 0, before)));
    if (after < n - 1e-9) keep.push(shapeOf(e.type, between(runs, after, n)));
    return keep;
  }
  // Round a closed walk: positions taken modulo n, the pick between the last crossing
  // before it and the first after it (either may be reached across the start).
  const round = ss.map((s) => ((s % n) + n) % n);
  if (new Set(round.map((s) => Math.round(s * 1e9))).size < 2) return `trim: a ${e.type} needs two crossings (it has ${round.length ? 'one' : 'none'})`;
  const lower = round.filter((s) => s < sc), upper = round.filter((s) => s > sc);
  const before = lower.length ? Math.max(...lower) : Math.max(...round) - n;
  const after = upper.length ? Math.min(...upper) : Math.min(...round) + n;
  return [shapeOf(e.type, between(runs, after, before + n))];
}

/// The line, arc or open polyline `e` extended at one end (`atEnd`: b / the sweep's end /
/// the last vertex, else the start) to the nearest crossing with `others` beyond it: a line
/// along its own direction (crossings of the ray, as `trim` finds them), an arc along its
/// circle (`circleHits`, measured as the turn past the end); a polyline by its end piece,
/// the new end vertex (and bulge tan(sweep/4) of an arc piece) written back. A message when
/// nothing is met.
export function extended(e: Entity, others: Shape[], atEnd: boolean): Entity | string {
  if (e.type === 'line') {
    const [fixed, moving] = atEnd ? [e.a, e.b] : [e.b, e.a];
    // The ray as a long segment: far beyond any coordinate a design file holds (1e6 mm).
    const K = 1e7 / Math.max(1e-9, Math.hypot(moving[0] - fixed[0], moving[1] - fixed[1]));
    const far: Pt = [fixed[0] + K * (moving[0] - fixed[0]), fixed[1] + K * (moving[1] - fixed[1])];
    const ts = others.flatMap((o) => crossings(fixed, far, o)).map((t) => t * K).filter((t) => t > 1 + 1e-9);
    if (!ts.length) return 'extend: nothing lies ahead of that end';
    const t = Math.min(...ts), to: Pt = [fixed[0] + t * (moving[0] - fixed[0]), fixed[1] + t * (moving[1] - fixed[1])];
    return atEnd ? { ...e, b: to } : { ...e, a: to };
  }
  if (e.type === 'arc') {
    const s = Math.sign(e.sweep), end = atEnd ? e.start + e.sweep : e.start;
    // The turn past the end, in the arc's direction at its end, away from the arc at its start.
    const ahead = (h: Pt) => {
      const ang = (Math.atan2(h[1] - e.center[1], h[0] - e.center[0]) * 180) / Math.PI;
      return ((((ang - end) * (atEnd ? s : -s)) % 360) + 360) % 360;
    };
    const turns = others.flatMap((o) => circleHits(e.center, e.radius, o)).map(ahead).filter((t) => t > 1e-9 && Math.abs(e.sweep) + t < 360);
    if (!turns.length) return 'extend: nothing lies ahead of that end on the arc\'s circle';
    const t = Math.min(...turns);
    return atEnd ? { ...e, sweep: e.sweep + s * t } : { ...e, start: e.start - s * t, sweep: e.sweep + s * t };
  }
  if (e.type === 'polyline') {
    if (e.closed) return 'extend: a closed polyline has no end';
    const pieces = exploded(e)!, piece = atEnd ? pieces[pieces.length - 1] : pieces[0];
    const r = extended({ ...piece, id: e.id, layer: e.layer } as Entity, others, atEnd);
    if (typeof r === 'string') return r;
    const v = e.vertices.map((q) => q.slice()), last = v.length - 1;
    if (r.type === 'line') {
      if (atEnd) v[last] = [r.b[0], r.b[1]]; else v[0] = [r.a[0], r.a[1]];
    } else if (r.type === 'arc') {
      const bulge = Math.tan(rad(r.sweep) / 4);
      if (atEnd) { v[last] = arcPoint(r.center, r.radius, r.start + r.sweep); v[last - 1][2] = bulge; } else v[0] = [...arcPoint(r.center, r.radius, r.start), bulge];
    }
    return { ...e, vertices: v };
  }
  return 'extend works on lines, arcs and open polylines';
}
