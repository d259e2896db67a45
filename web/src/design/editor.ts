// The Design tab: a 2-D drawing editor over the design file's own model (./model.ts).
// Points come from clicks (snapped to the grid, ends, middles, centres and crossings) or
// from the command line (./input.ts); a tool collects what it needs and changes the design
// as one undoable step. Offsets and the SVG / DXF exports are the server's (Rust,
// /api/design/*); fillet, chamfer and the moves are exact formulas in ./model.ts.

import { putFile, withToken } from '../api';
import { el, segDist, ViewMap, Pt } from '../view2d';
import { Design, Entity, Shape, emptyDesign, nextId, outline, snapPoints, transformed, translate, rotate, scale, mirror, cornered, nearestCorner, exploded, joined, polygon, endHeading, tangentArc } from './model';
import { trimmed, extended } from './trim';
import { readTyped } from './input';

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;
const W = 760, H = 480;
/// Snaps within this many pixels.
const SNAP_PX = 10;

type ToolName = 'line' | 'polyline' | 'rect' | 'circle' | 'arc' | 'arcc' | 'tarc' | 'point' | 'extend' | 'polygon' | 'spline' | 'text' | 'fillet' | 'chamfer' | 'offset' | 'trim' | 'calibrate' | 'digitise' | 'move' | 'copy' | 'rotate' | 'scale' | 'mirror';
const TOOLS: ToolName[] = ['line', 'polyline', 'rect', 'circle', 'arc', 'arcc', 'tarc', 'point', 'polygon', 'spline', 'text', 'fillet', 'chamfer', 'offset', 'trim', 'extend', 'move', 'copy', 'rotate', 'scale', 'mirror', 'calibrate', 'digitise'];
const ALIASES: Record<string, ToolName> = { l: 'line', pl: 'polyline', rec: 'rect', rectangle: 'rect', c: 'circle', a: 'arc', pol: 'polygon', spl: 'spline', t: 'text', tr: 'trim', cal: 'calibrate', dig: 'digitise', digitize: 'digitise', f: 'fillet', cha: 'chamfer', o: 'offset', m: 'move', co: 'copy', ro: 'rotate', sc: 'scale', mi: 'mirror', po: 'point', ex: 'extend', arct: 'tarc' };

let design: Design = emptyDesign();
let name = 'part';
const past: string[] = [];
let future: string[] = [];
let selected = new Set<number>();
let tool: ToolName | null = null;
let pts: Pt[] = [];
let num: number | null = null;
let cursor: Pt | null = null;
let snapped: { p: Pt; kind: string } | null = null;
let layer = '0';
/// The background photo or scan: its lower-left corner and size in drawing mm.
let bg: { href: string; x: number; y: number; w: number; h: number } | null = null;
/// The live fit of the digitised points: the contour and its deviation.
let fitted: { shape: Shape; max_deviation: number; blocks: number } | null = null;
/// The picked points of each contour kept from `digitise` (by entity id): what grading
/// scales, as `oficina sole` scales its point list.
const digitised = new Map<number, Pt[]>();
/// The tangent arc's heading at its current point.
let heading: Pt | null = null;
/// Box selection: where the drag started (drawing mm) and where it is.
let box: { from: Pt; to: Pt } | null = null;
const view = new ViewMap(W, H);
let hooks: { openInCam: (file: string) => void } = { openInCam: () => {} };

function status(msg: string, isError = false) {
  const s = $('de-status');
  s.textContent = msg;
  s.classList.toggle('error', isError);
}

/// One undoable step: the design before it is kept, the redo list is dropped.
function commit(change: (d: Design) => void, what: string) {
  past.push(JSON.stringify(design));
  future = [];
  change(design);
  status(what);
  draw();
}
function undo() {
  const before = past.pop();
  if (before === undefined) return status('nothing to undo');
  future.push(JSON.stringify(design));
  design = JSON.parse(before);
  selected.clear();
  status(`undone (${past.length} more)`); draw();
}
function redo() {
  const after = future.pop();
  if (after === undefined) return status('nothing to redo');
  past.push(JSON.stringify(design));
  design = JSON.parse(after);
  status('redone'); draw();
}

function add(shape: Shape) {
  commit((d) => d.entities.push({ ...shape, id: nextId(d), layer } as Entity), `${shape.type} added`);
}

/// What the current tool asks for next.
function prompt(): string {
  switch (tool) {
    case null: return 'click to select (shift adds), drag a box (rightwards: inside it, leftwards: touching it) · type a tool\'s name, or explode, join, delete, grade, fit, all, none, undo, redo';
    case 'line': return pts.length ? 'next point (Enter ends)' : 'first point';
    case 'polyline': return pts.length ? `next point · close · Enter ends (${pts.length} points)` : 'first point';
    case 'rect': return pts.length ? 'opposite corner' : 'first corner';
    case 'circle': return pts.length ? 'radius or a point on it' : 'centre';
    case 'arc': return ['start point', 'a point on the arc', 'end point'][pts.length];
    case 'tarc': return pts.length ? 'end of the arc (it leaves tangent to the piece before) · Enter ends' : 'the end of a line, arc or open polyline to continue from';
    case 'point': return 'where (each click a point)';
    case 'extend': return 'the end of a line, arc or open polyline to extend (a point on it near that end)';
    case 'arcc': return ['centre', 'start point (sets the radius)', 'end point (its angle; the arc runs counter-clockwise)'][pts.length];
    case 'polygon': return !pts.length ? 'centre' : num === null ? 'number of sides' : 'radius to the vertices, or a vertex';
    case 'spline': return pts.length ? `next point · Enter ends (${pts.length} points)` : 'first point';
    case 'text': return !pts.length ? 'start of the baseline' : num === null ? 'capital height' : 'the text';
    case 'fillet': case 'chamfer': return num === null ? (tool === 'fillet' ? 'radius' : 'distance') : `corner (a point near it) · ${tool} ${num}`;
    case 'calibrate': return pts.length < 2 ? `${pts.length ? 'second' : 'first'} point of a known distance on the background` : 'the distance between them, mm';
    case 'digitise': return `pick points around the contour (${pts.length}${fitted ? `, fitted: ${fitted.blocks} blocks, deviation ${fitted.max_deviation.toFixed(3)} mm` : ', 8 or more to fit'}) · Enter keeps the fit`;
    case 'trim': return 'the part of a line, arc, circle or polyline to cut away (a point on it)';
    case 'offset': return num === null ? 'distance (> 0 outwards, < 0 inwards)' : 'contour (a point on it) if none is selected';
    case 'move': case 'copy': return pts.length ? 'to point' : 'base point';
    case 'rotate': return pts.length ? 'angle, degrees' : 'centre';
    case 'scale': return pts.length ? 'factor' : 'base point';
    case 'mirror': return pts.length ? 'second point of the axis' : 'first point of the axis';
  }
}

function setTool(t: ToolName | null) {
  tool = t; pts = []; num = null; fitted = null; heading = null;
  document.querySelectorAll('#de-tools button').forEach((b) => b.classList.toggle('on', (b as HTMLElement).dataset.tool === t));
  $('de-prompt').textContent = prompt();
  draw();
}

/// Ends the current tool's input: a polyline or a chain of lines ends here.
function finish(close = false) {
  if (tool === 'digitise' && fitted) { digitised.set(nextId(design), pts.slice()); add(fitted.shape); }
  if (tool === 'spline' && pts.length >= 2) add({ type: 'spline', points: pts });
  if (tool === 'polyline' && pts.length >= 2) add({ type: 'polyline', vertices: pts.map((p) => [p[0], p[1]]), closed: close && pts.length >= 3 });
  setTool(null);
}

function targets(): Entity[] | string {
  const sel = design.entities.filter((e) => selected.has(e.id));
  return sel.length ? sel : 'select what to change first';
}

/// The selection changed by `m` (and copied when `copy`).
function transform(m: ReturnType<typeof translate>, what: string, copy = false) {
  const sel = targets();
  if (typeof sel === 'string') return status(sel, true);
  commit((d) => {
    if (copy) { let id = nextId(d); for (const e of sel) d.entities.push({ ...transformed(e, m), id: id++ }); }
    else d.entities = d.entities.map((e) => (selected.has(e.id) ? transformed(e, m) : e));
  }, `${what} ${sel.length} entit${sel.length === 1 ? 'y' : 'ies'}`);
}

function pick(p: Pt): Entity | null {
  let best: Entity | null = null, bestD = SNAP_PX / view.s;
  for (const e of design.entities) for (const line of outline(e)) for (let k = 1; k < line.length; k++) {
    const d = segDist(p, line[k - 1], line[k]);
    if (d < bestD) { bestD = d; best = e; }
  }
  return best;
}

async function offset(ids: number[], distance: number) {
  try {
    const r = await fetch(withToken('/api/design/offset'), { method: 'POST', headers: { 'content-type': 'application/json' }, body: JSON.stringify({ design, ids, distance }) });
    const v = await r.json();
    if (!r.ok) throw new Error(v.error ?? r.statusText);
    commit((d) => d.entities.push(...(v.entities as Entity[])), `offset ${distance} mm: ${v.entities.length} contour${v.entities.length === 1 ? '' : 's'}`);
  } catch (e) { status(`offset: ${(e as Error).message}`, true); }
}

/// Grades the selected closed contour to the sizes asked and mirrors it for the other foot,
/// by the server's `oficina sole` grading (`/api/design/grade`): the points graded are the
/// ones digitised for it, or else its outline's points. Each size's feet come back on their
/// own layers.
async function grade() {
  const sel = targets();
  if (typeof sel === 'string') return status('grade: select the digitised contour first', true);
  const e = sel[0];
  if (sel.length !== 1 || e.type !== 'polyline' || !e.closed) return status('grade: select one closed contour', true);
  const points = digitised.get(e.id) ?? outline(e)[0].slice(0, -1);
  const sizes = $<HTMLInputElement>('de-sizes').value.split(/[\s,;]+/).filter(Boolean).map(Number);
  const body = { design, points, from_size: Number($<HTMLInputElement>('de-from-size').value), sizes, system: $<HTMLSelectElement>('de-system').value, shrink: Number($<HTMLInputElement>('de-shrink').value), tol: Number($<HTMLInputElement>('de-fit-tol').value) };
  status('grading…');
  try {
    const r = await fetch(withToken('/api/design/grade'), { method: 'POST', headers: { 'content-type': 'application/json' }, body: JSON.stringify(body) });
    const v = await r.json();
    if (!r.ok) throw new Error(v.error ?? r.statusText);
    const report = (v.sizes as { size: number; method: string; blocks: number; max_deviation: number }[]).map((g) => `${g.size}: ${g.method}, ${g.blocks} blocks, ${g.max_deviation.toFixed(3)} mm`).join(' · ');
    commit((d) => { d.layers = v.design.layers; d.entities = v.design.entities; }, `graded and mirrored from ${points.length} points — ${report}`);
    renderLayers(); fit();
  } catch (err) { status(`grade: ${(err as Error).message}`, true); }
}

/// Selects by the box `box`: dragged rightwards (a window) what lies wholly inside it,
/// leftwards (crossing) what has a point inside it or a piece crossing its edges.
function selectBox(b: { from: Pt; to: Pt }, add: boolean) {
  const x0 = Math.min(b.from[0], b.to[0]), x1 = Math.max(b.from[0], b.to[0]), y0 = Math.min(b.from[1], b.to[1]), y1 = Math.max(b.from[1], b.to[1]);
  const inside = (p: Pt) => p[0] >= x0 && p[0] <= x1 && p[1] >= y0 && p[1] <= y1;
  const edges: [Pt, Pt][] = [[[x0, y0], [x1, y0]], [[x1, y0], [x1, y1]], [[x1, y1], [x0, y1]], [[x0, y1], [x0, y0]]];
  const inWindow = b.to[0] >= b.from[0];
  if (!add) selected.clear();
  for (const e of design.entities) {
    const lines = outline(e);
    const hit = inWindow ? lines.every((l) => l.every(inside))
      : lines.some((l) => l.some(inside) || l.some((p, k) => k > 0 && edges.some((g) => cross([l[k - 1], p], g) !== null)));
    if (hit) selected.add(e.id);
  }
  status(`${inWindow ? 'window' : 'crossing'}: ${selected.size ? `selected: ${[...selected].join(' ')}` : 'nothing selected'}`);
}

/// A point (clicked or typed) for the current tool.
function takePoint(p: Pt, shift = false) {
  switch (tool) {
    case null: {
      const e = pick(p);
      if (!shift) selected.clear();
      if (e) { if (shift && selected.has(e.id)) selected.delete(e.id); else selected.add(e.id); }
      status(selected.size ? `selected: ${[...selected].join(' ')}` : 'nothing selected');
      break;
    }
    case 'line': if (pts.length) add({ type: 'line', a: pts[pts.length - 1], b: p }); pts.push(p); break;
    case 'polyline': case 'spline': pts.push(p); break;
    case 'point': add({ type: 'point', at: p }); break;
    case 'tarc': {
      if (!pts.length) {
        const end = endHeading(design, p, SNAP_PX / view.s);
        if (!end) return status('tarc: start at the end of a line, arc or open polyline', true);
        pts.push(end.at); heading = end.heading; break;
      }
      const r = tangentArc(pts[pts.length - 1], heading!, p);
      if (typeof r === 'string') return status(r, true);
      add(r.arc); pts.push(p); heading = r.heading; break;
    }
    case 'extend': {
      const e = pick(p);
      if (!e || !(e.type === 'line' || e.type === 'arc' || (e.type === 'polyline' && !e.closed))) return status('extend: pick a line, arc or open polyline near the end to extend', true);
      const [a, b] = ((o) => [o[0], o[o.length - 1]])(outline(e)[0]);
      const atEnd = Math.hypot(p[0] - b[0], p[1] - b[1]) < Math.hypot(p[0] - a[0], p[1] - a[1]);
      const r = extended(e, design.entities.filter((o) => o.id !== e.id), atEnd);
      if (typeof r === 'string') return status(r, true);
      commit((d) => { d.entities = d.entities.map((o) => (o.id === e.id ? r : o)); }, `extended ${e.type} ${e.id}`);
      break;
    }
    case 'arcc': {
      pts.push(p);
      if (pts.length < 3) break;
      // Counter-clockwise from the start's angle to the end's, radius |start − centre|.
      const [c, a, b] = pts, ang = (q: Pt) => (Math.atan2(q[1] - c[1], q[0] - c[0]) * 180) / Math.PI;
      const r = Math.hypot(a[0] - c[0], a[1] - c[1]);
      let sweep = ang(b) - ang(a);
      if (sweep <= 0) sweep += 360;
      if (!(r > 0)) status('the start is on the centre', true); else add({ type: 'arc', center: c, radius: r, start: ang(a), sweep });
      setTool(null); return;
    }
    case 'calibrate': if (!bg) return status('open a background image first', true); if (pts.length < 2) pts.push(p); break;
    case 'digitise': pts.push(p); if (pts.length >= 8) refit(); break;
    case 'polygon': if (pts.length && num !== null) return takeNumber(Math.hypot(p[0] - pts[0][0], p[1] - pts[0][1])); if (!pts.length) pts.push(p); break;
    case 'text': if (!pts.length) pts.push(p); break;
    case 'rect': if (pts.length) { const a = pts[0]; add({ type: 'polyline', closed: true, vertices: [[a[0], a[1]], [p[0], a[1]], [p[0], p[1]], [a[0], p[1]]] }); setTool(null); return; } pts.push(p); break;
    case 'circle': if (pts.length) return takeNumber(Math.hypot(p[0] - pts[0][0], p[1] - pts[0][1])); pts.push(p); break;
    case 'arc': {
      pts.push(p);
      if (pts.length < 3) break;
      const arc = arcThrough(pts[0], pts[1], pts[2]);
      if (typeof arc === 'string') status(arc, true); else add(arc);
      setTool(null); return;
    }
    case 'fillet': case 'chamfer': {
      if (num === null) return status(`give the ${tool === 'fillet' ? 'radius' : 'distance'} first`, true);
      const c = nearestCorner(design, p);
      if (!c || c[2] > 20 / view.s + 1e-6) return status('no polyline corner near that point', true);
      const r = cornered(design.entities[c[0]], c[1], num, tool === 'fillet');
      if (typeof r === 'string') return status(r, true);
      const corner = (design.entities[c[0]] as { vertices: number[][] }).vertices[c[1]];
      const what = `${tool} ${num} at ${corner[0]},${corner[1]}`;
      commit((d) => { d.entities[c[0]] = r; }, what);
      break;
    }
    case 'trim': {
      const e = pick(p);
      if (!e) return status('trim: pick a line, arc, circle or polyline', true);
      const r = trimmed(e, design.entities.filter((o) => o.id !== e.id), p);
      if (typeof r === 'string') return status(r, true);
      commit((d) => {
        let id = nextId(d);
        const k = d.entities.findIndex((o) => o.id === e.id);
        d.entities.splice(k, 1, ...r.map((s) => ({ ...s, id: id++, layer: e.layer } as Entity)));
      }, `trimmed: ${r.length} piece${r.length === 1 ? '' : 's'} left`);
      break;
    }
    case 'offset': {
      if (num === null) return status('give the distance first', true);
      const e = pick(p);
      if (!e) return status('no contour there', true);
      offset([e.id], num); setTool(null); return;
    }
    case 'move': case 'copy':
      if (pts.length) { transform(translate(p[0] - pts[0][0], p[1] - pts[0][1]), tool === 'move' ? 'moved' : 'copied', tool === 'copy'); setTool(null); return; }
      pts.push(p); break;
    case 'rotate': case 'scale': pts.push(p); break;
    case 'mirror':
      if (pts.length) { transform(mirror(pts[0], p), 'mirrored'); setTool(null); return; }
      pts.push(p); break;
  }
  $('de-prompt').textContent = prompt();
  draw();
}

/// A number for the current tool.
function takeNumber(n: number) {
  switch (tool) {
    case 'circle': if (!pts.length) return status('give the centre first', true);
      if (!(n > 0)) return status('a radius above 0', true);
      add({ type: 'circle', center: pts[0], radius: n }); setTool(null); return;
    case 'polygon':
      if (!pts.length) return status('give the centre first', true);
      if (num === null) { if (!(Number.isInteger(n) && n >= 3 && n <= 1000)) return status('sides: a whole number from 3 to 1000', true); num = n; break; }
      if (!(n > 0)) return status('a radius above 0', true);
      add(polygon(pts[0], n, num)); setTool(null); return;
    case 'text':
      if (!pts.length) return status('give the start of the baseline first', true);
      if (num === null) { if (!(n > 0)) return status('a height above 0', true); num = n; break; }
      return takeText(String(n));
    case 'calibrate': {
      if (pts.length < 2 || !bg) return status('pick the two points first', true);
      const d = Math.hypot(pts[1][0] - pts[0][0], pts[1][1] - pts[0][1]);
      if (!(n > 0) || !(d > 0)) return status('a distance above 0 between two different points', true);
      // Scale the background about the first point: x' = p₁ + (x − p₁)·k, k = known / measured.
      const k = n / d, [px, py] = pts[0];
      bg = { ...bg, x: px + (bg.x - px) * k, y: py + (bg.y - py) * k, w: bg.w * k, h: bg.h * k };
      status(`calibrated: ${d.toFixed(3)} → ${n} mm (×${k.toFixed(6)})`);
      setTool(null); fit(); return;
    }
    case 'fillet': case 'chamfer': if (!(n > 0)) return status(`a ${tool} size above 0`, true); num = n; break;
    case 'offset':
      if (!n) return status('a non-zero distance', true);
      num = n;
      if (selected.size) { offset([...selected], n); setTool(null); return; }
      break;
    case 'rotate': if (!pts.length) return status('give the centre first', true); transform(rotate(pts[0], n), `rotated ${n}°`); setTool(null); return;
    case 'scale': if (!pts.length) return status('give the base point first', true);
      if (!(n > 0)) return status('a factor above 0', true);
      transform(scale(pts[0], n), `scaled ×${n}`); setTool(null); return;
    default: return status(`${tool ?? 'no tool'}: not a number here — ${prompt()}`, true);
  }
  $('de-prompt').textContent = prompt();
}

function takeText(t: string) {
  if (tool !== 'text' || !pts.length || num === null) return;
  add({ type: 'text', at: pts[0], height: num, angle: 0, text: t });
  setTool(null);
}

/// Fits the digitised points on the server (`oficina fit`'s methods) and shows the contour
/// and its deviation.
async function refit() {
  const points = pts.slice();
  try {
    const r = await fetch(withToken('/api/design/fit'), { method: 'POST', headers: { 'content-type': 'application/json' }, body: JSON.stringify({ points, method: $<HTMLSelectElement>('de-fit-method').value, tol: Number($<HTMLInputElement>('de-fit-tol').value) }) });
    const v = await r.json();
    if (!r.ok) throw new Error(v.error ?? r.statusText);
    if (tool !== 'digitise' || pts.length !== points.length) return; // a newer point is on its way
    fitted = v;
    $('de-prompt').textContent = prompt();
    $('de-fit-report').textContent = `${v.blocks} blocks, largest deviation ${v.max_deviation.toFixed(3)} mm from ${points.length} points`;
    draw();
  } catch (e) { status(`fit: ${(e as Error).message}`, true); }
}

/// The arc from `a` through `b` to `c`: its centre is the circumcentre; it turns
/// counter-clockwise when a → b → c does (cross product > 0).
function arcThrough(a: Pt, b: Pt, c: Pt): Shape | string {
  const d = 2 * (a[0] * (b[1] - c[1]) + b[0] * (c[1] - a[1]) + c[0] * (a[1] - b[1]));
  if (Math.abs(d) < 1e-12) return 'the three points are in line';
  const s = (p: Pt) => p[0] * p[0] + p[1] * p[1];
  const center: Pt = [(s(a) * (b[1] - c[1]) + s(b) * (c[1] - a[1]) + s(c) * (a[1] - b[1])) / d, (s(a) * (c[0] - b[0]) + s(b) * (a[0] - c[0]) + s(c) * (b[0] - a[0])) / d];
  const ang = (p: Pt) => (Math.atan2(p[1] - center[1], p[0] - center[0]) * 180) / Math.PI;
  const ccw = d > 0;
  let sweep = ang(c) - ang(a);
  if (ccw && sweep <= 0) sweep += 360;
  if (!ccw && sweep >= 0) sweep -= 360;
  return { type: 'arc', center, radius: Math.hypot(a[0] - center[0], a[1] - center[1]), start: ang(a), sweep };
}

/// The command line: a point, a number or a word.
function command(text: string) {
  if (!text.trim()) return finish();
  // The text tool's last entry is the words themselves, whatever they look like.
  if (tool === 'text' && pts.length && num !== null) return takeText(text.trim());
  const last = pts.length ? pts[pts.length - 1] : null;
  const t = readTyped(text, last);
  if ('error' in t) return status(t.error, true);
  if ('point' in t) return takePoint(t.point);
  if ('number' in t) return takeNumber(t.number);
  const w = t.word;
  if (w === 'undo' || w === 'u') return undo();
  if (w === 'redo') return redo();
  if (w === 'close' || (w === 'c' && tool === 'polyline')) return finish(true);
  if (w === 'delete' || w === 'del' || w === 'erase') return del();
  if (w === 'all') { selected = new Set(design.entities.map((e) => e.id)); status(`selected: ${selected.size}`); return draw(); }
  if (w === 'none') { selected.clear(); return draw(); }
  if (w === 'explode' || w === 'x') return explode();
  if (w === 'join' || w === 'j') return join();
  if (w === 'grade') { void grade(); return; }
  if (w === 'fit') return fit();
  if (w === 'esc' || w === 'cancel') return setTool(null);
  const next = (TOOLS as string[]).includes(w) ? (w as ToolName) : ALIASES[w];
  if (!next) return status(`'${w}' is not a command`, true);
  setTool(next);
}

/// The selected polylines become their lines and arcs.
function explode() {
  const sel = targets();
  if (typeof sel === 'string') return status(sel, true);
  if (!sel.some((e) => e.type === 'polyline')) return status('explode: select polylines', true);
  commit((d) => {
    let id = nextId(d);
    d.entities = d.entities.flatMap((e) => {
      const parts = selected.has(e.id) ? exploded(e) : null;
      return parts ? parts.map((s) => ({ ...s, id: id++, layer: e.layer } as Entity)) : [e];
    });
  }, 'exploded');
  selected.clear(); draw();
}

/// The selected lines, arcs and open polylines become one polyline where their ends meet.
function join() {
  const sel = targets();
  if (typeof sel === 'string') return status(sel, true);
  const j = joined(sel);
  if (!j) return status('join: the selection is not one chain of lines, arcs and open polylines meeting end to end', true);
  commit((d) => {
    const first = d.entities.findIndex((e) => selected.has(e.id));
    const e = { ...j, id: nextId(d), layer: d.entities[first].layer } as Entity;
    d.entities = d.entities.filter((x) => !selected.has(x.id));
    d.entities.splice(first, 0, e);
  }, `joined ${sel.length} into a ${(j as { closed: boolean }).closed ? 'closed' : 'open'} polyline`);
  selected.clear(); draw();
}

function del() {
  const sel = targets();
  if (typeof sel === 'string') return status(sel, true);
  commit((d) => { d.entities = d.entities.filter((e) => !selected.has(e.id)); }, `deleted ${sel.length}`);
  selected.clear(); draw();
}

/// The point a cursor at `p` snaps to: an end, middle or centre within SNAP_PX, else a
/// crossing of two straight pieces there, else the grid when it is on.
function snap(p: Pt): { p: Pt; kind: string } | null {
  const r = SNAP_PX / view.s;
  let best: { p: Pt; kind: string } | null = null, bd = r;
  const candidates = design.entities.flatMap((e) => snapPoints(e) as { p: Pt; kind: string }[]);
  if (tool && pts.length) for (const e of design.entities) for (const q of tangentPoints(pts[pts.length - 1], e)) candidates.push({ p: q, kind: 'tangent' });
  for (const s of candidates) {
    const d = Math.hypot(s.p[0] - p[0], s.p[1] - p[1]);
    if (d < bd) { bd = d; best = s; }
  }
  if (best) return best;
  const near: [Pt, Pt][] = [];
  for (const e of design.entities) for (const line of outline(e)) for (let k = 1; k < line.length; k++) if (segDist(p, line[k - 1], line[k]) < r) near.push([line[k - 1], line[k]]);
  for (let i = 0; i < near.length; i++) for (let j = i + 1; j < near.length; j++) {
    const x = cross(near[i], near[j]);
    if (x && Math.hypot(x[0] - p[0], x[1] - p[1]) < r) return { p: x, kind: 'intersection' };
  }
  const g = Number($<HTMLInputElement>('de-grid').value);
  if ($<HTMLInputElement>('de-grid-on').checked && g > 0) return { p: [Math.round(p[0] / g) * g, Math.round(p[1] / g) * g], kind: 'grid' };
  return null;
}
/// Where a line from `from` touches the circle or arc `e` (arcs: within their sweep): with d
/// the distance to the centre C, the touching radii make α = acos(r/d) with C → from, so
/// the points are C + r·(from − C)/d turned by ±α.
function tangentPoints(from: Pt, e: Shape): Pt[] {
  const circles: { c: Pt; r: number; a0?: number; sw?: number }[] = [];
  if (e.type === 'circle') circles.push({ c: e.center, r: e.radius });
  if (e.type === 'arc') circles.push({ c: e.center, r: e.radius, a0: (e.start * Math.PI) / 180, sw: (e.sweep * Math.PI) / 180 });
  const out: Pt[] = [];
  for (const { c, r, a0, sw } of circles) {
    const dx = from[0] - c[0], dy = from[1] - c[1], d = Math.hypot(dx, dy);
    if (d <= r) continue;
    const base = Math.atan2(dy, dx), al = Math.acos(r / d);
    for (const t of [base + al, base - al]) {
      if (sw !== undefined && a0 !== undefined) {
        const rel = ((((t - a0) * Math.sign(sw)) % (2 * Math.PI)) + 2 * Math.PI) % (2 * Math.PI);
        if (rel > Math.abs(sw)) continue;
      }
      out.push([c[0] + r * Math.cos(t), c[1] + r * Math.sin(t)]);
    }
  }
  return out;
}

function cross([a, b]: [Pt, Pt], [c, d]: [Pt, Pt]): Pt | null {
  const den = (b[0] - a[0]) * (d[1] - c[1]) - (b[1] - a[1]) * (d[0] - c[0]);
  if (Math.abs(den) < 1e-12) return null;
  const t = ((c[0] - a[0]) * (d[1] - c[1]) - (c[1] - a[1]) * (d[0] - c[0])) / den;
  const u = ((c[0] - a[0]) * (b[1] - a[1]) - (c[1] - a[1]) * (b[0] - a[0])) / den;
  return t >= 0 && t <= 1 && u >= 0 && u <= 1 ? [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])] : null;
}

function shown(color: string) {
  // Black (the CAD default) on the dark view is drawn light.
  return /^#0{6}$/i.test(color) ? '#c8d0dc' : color;
}

function draw() {
  const svg = $('de-view') as unknown as SVGSVGElement;
  if (!svg) return;
  svg.innerHTML = '';
  const g = Number($<HTMLInputElement>('de-grid').value);
  if (g > 0 && g * view.s >= 6) {
    const x0 = Math.ceil(view.x0 / g) * g, y0 = Math.ceil(view.y0 / g) * g;
    for (let x = x0; view.sx(x) < W; x += g) el('line', { x1: view.sx(x), y1: 0, x2: view.sx(x), y2: H, stroke: Math.abs(x) < 1e-9 ? '#4a5568' : '#232a35' }, svg);
    for (let y = y0; view.sy(y) > 0; y += g) el('line', { x1: 0, y1: view.sy(y), x2: W, y2: view.sy(y), stroke: Math.abs(y) < 1e-9 ? '#4a5568' : '#232a35' }, svg);
  }
  if (bg) el('image', { href: bg.href, x: view.sx(bg.x), y: view.sy(bg.y + bg.h), width: bg.w * view.s, height: bg.h * view.s, preserveAspectRatio: 'none', opacity: 0.55, id: 'de-bg', 'pointer-events': 'none' }, svg);
  if (tool === 'digitise') {
    for (const p of pts) el('circle', { cx: view.sx(p[0]), cy: view.sy(p[1]), r: 3, fill: '#f05ad1', class: 'de-picked' }, svg);
    if (fitted) for (const line of outline(fitted.shape)) el('polyline', { points: line.map((p) => `${view.sx(p[0])},${view.sy(p[1])}`).join(' '), fill: 'none', stroke: '#f05ad1', 'stroke-dasharray': '5 3', class: 'de-fit' }, svg);
  }
  const colour = (n: string) => shown(design.layers.find((l) => l.name === n)?.color ?? '#000000');
  for (const e of design.entities) {
    const sel = selected.has(e.id);
    if (e.type === 'point') {
      const [x, y] = [view.sx(e.at[0]), view.sy(e.at[1])];
      el('path', { d: `M${x - 4} ${y}L${x + 4} ${y}M${x} ${y - 4}L${x} ${y + 4}`, stroke: sel ? '#f0b45a' : colour(e.layer), 'stroke-width': sel ? 2.5 : 1.4, 'data-id': e.id, class: 'de-entity de-point' + (sel ? ' selected' : '') }, svg);
      continue;
    }
    for (const line of outline(e)) {
      el('polyline', { points: line.map((p) => `${view.sx(p[0]).toFixed(2)},${view.sy(p[1]).toFixed(2)}`).join(' '), fill: 'none', stroke: sel ? '#f0b45a' : colour(e.layer), 'stroke-width': sel ? 2.5 : 1.4, 'data-id': e.id, class: 'de-entity' + (sel ? ' selected' : '') }, svg);
    }
  }
  if (box) {
    const inWindow = box.to[0] >= box.from[0];
    el('rect', { x: Math.min(view.sx(box.from[0]), view.sx(box.to[0])), y: Math.min(view.sy(box.from[1]), view.sy(box.to[1])), width: Math.abs(view.sx(box.to[0]) - view.sx(box.from[0])), height: Math.abs(view.sy(box.to[1]) - view.sy(box.from[1])), fill: inWindow ? 'rgba(90,160,240,.12)' : 'rgba(90,240,140,.12)', stroke: inWindow ? '#5aa0f0' : '#5af08c', 'stroke-dasharray': inWindow ? '' : '5 3', class: 'de-box' }, svg);
  }
  // The tool's rubber band from its last point to the cursor.
  if (cursor && pts.length && tool) {
    const a = pts[pts.length - 1], b = snapped?.p ?? cursor;
    const band = tool === 'rect' ? [a, [b[0], a[1]], b, [a[0], b[1]], a] as Pt[] : [...(tool === 'polyline' ? pts : [a]), b];
    el('polyline', { points: band.map((p) => `${view.sx(p[0])},${view.sy(p[1])}`).join(' '), fill: 'none', stroke: '#5ad1f0', 'stroke-dasharray': '4 3' }, svg);
  }
  if (snapped) {
    const [x, y] = [view.sx(snapped.p[0]), view.sy(snapped.p[1])];
    const m = snapped.kind === 'centre' ? el('circle', { cx: x, cy: y, r: 6 }, svg) : snapped.kind === 'mid' ? el('polygon', { points: `${x},${y - 7} ${x - 6},${y + 5} ${x + 6},${y + 5}` }, svg) : snapped.kind === 'tangent' ? el('path', { d: `M${x - 7} ${y + 6}L${x + 7} ${y + 6}M${x + 6} ${y}A6 6 0 1 0 ${x - 6} ${y}A6 6 0 1 0 ${x + 6} ${y}` }, svg) : snapped.kind === 'intersection' ? el('path', { d: `M${x - 6} ${y - 6}L${x + 6} ${y + 6}M${x - 6} ${y + 6}L${x + 6} ${y - 6}` }, svg) : el('rect', { x: x - 5, y: y - 5, width: 10, height: 10 }, svg);
    m.setAttribute('fill', 'none'); m.setAttribute('stroke', '#9af05a'); m.setAttribute('class', `de-snap de-snap-${snapped.kind}`);
  }
  const xy = snapped?.p ?? cursor;
  $('de-xy').textContent = xy ? `${xy[0].toFixed(3)}, ${xy[1].toFixed(3)}${snapped ? ` (${snapped.kind})` : ''}` : '';
  $('de-count').textContent = `${design.entities.length} entities · ${past.length} undo · ${future.length} redo`;
}

function fit() {
  const all = design.entities.flatMap((e) => outline(e).flat());
  if (bg) all.push([bg.x, bg.y], [bg.x + bg.w, bg.y + bg.h]);
  if (!all.length) { view.fit([-10, -10, 100, 70]); return draw(); }
  const xs = all.map((p) => p[0]), ys = all.map((p) => p[1]);
  view.fit([Math.min(...xs), Math.min(...ys), Math.max(...xs), Math.max(...ys)], 30);
  draw();
}

function renderLayers() {
  const sel = $<HTMLSelectElement>('de-layer');
  sel.innerHTML = design.layers.map((l) => `<option value="${l.name.replace(/"/g, '&quot;')}">${l.name.replace(/</g, '&lt;')}</option>`).join('');
  if (!design.layers.some((l) => l.name === layer)) layer = design.layers[0]?.name ?? '0';
  sel.value = layer;
  $<HTMLInputElement>('de-layer-color').value = design.layers.find((l) => l.name === layer)?.color ?? '#000000';
}

const fileName = () => `${name.replace(/[^A-Za-z0-9._-]/g, '_').replace(/^\.+/, '').slice(0, 80) || 'part'}.oficina.json`;
function download(text: string, file: string, type: string) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(new Blob([text], { type }));
  a.download = file; a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}
const text = () => JSON.stringify(design, null, 1) + '\n';

/// Reads a design file's text (the server checks it fully when it is used).
function load(t: string, file: string) {
  let d: Design;
  try { d = JSON.parse(t); } catch (e) { return status(`${file}: not JSON: ${(e as Error).message}`, true); }
  if (d?.format !== 'oficina-design' || !Array.isArray(d.entities) || !Array.isArray(d.layers)) return status(`${file}: not an Oficina design file (format "oficina-design")`, true);
  past.push(JSON.stringify(design)); future = [];
  design = d; selected.clear();
  name = file.replace(/\.oficina\.json$|\.json$|\.dat$|\.g01$/i, '');
  $<HTMLInputElement>('de-name').value = name;
  renderLayers(); fit();
  status(`${file}: ${d.entities.length} entities on ${d.layers.length} layers`);
}

export function initDesignEditor(h: { openInCam: (file: string) => void }) {
  hooks = h;
  $('design').innerHTML = `
    <h3>Design <span class="muted">— draw and edit; the file (<code>.oficina.json</code>) is read by mill, plot and embroider</span></h3>
    <div class="form">
      <label>Name <input id="de-name" value="${name}" size="10"></label>
      <button id="de-new">New</button>
      <label class="btn">Open… <input id="de-open" type="file" accept=".json,.dat,.g01" hidden></label>
      <button id="de-save">Save</button>
      <button id="de-svg">Export SVG</button> <button id="de-dxf">Export DXF</button> <button id="de-seed001" title="seed 001's graphic file (.dat)">Export seed 001</button>
      <button id="de-cam">Send to CAM</button>
    </div>
    <div id="de-tools" class="form">
      ${TOOLS.map((t) => `<button data-tool="${t}" id="de-tool-${t}"${t === 'arcc' ? ' title="arc by centre, start, end"' : ''}>${t}</button>`).join('')}
      <button id="de-explode">explode</button> <button id="de-join">join</button> <button id="de-delete">delete</button> <button id="de-undo" title="undo (Ctrl+Z)">undo</button> <button id="de-redo" title="redo (Ctrl+Y)">redo</button>
      <button id="de-fit">fit</button>
    </div>
    <div class="form">
      <label>Layer <select id="de-layer"></select></label> <input id="de-layer-color" type="color" title="the layer's colour">
      <input id="de-new-layer" placeholder="new layer" size="8"><button id="de-add-layer">Add layer</button> <button id="de-to-layer">Selection to layer</button>
      <label><input id="de-grid-on" type="checkbox" checked> grid</label> <input id="de-grid" type="number" value="5" min="0" step="any" style="width:4em"> mm
    </div>
    <div class="form">
      <label class="btn">Background… <input id="de-bg-file" type="file" accept="image/*" hidden></label>
      <label>Fit <select id="de-fit-method"><option>biarc</option><option>tangent circles</option><option>B-spline (clamped cubic)</option><option>Bezier (seed)</option><option>interpolation (local cubic)</option></select></label>
      <label>within <input id="de-fit-tol" type="number" value="0.3" min="0.001" step="any"> mm</label>
    </div>
    <div class="form" title="grade the selected digitised sole to sizes and mirror it, as oficina sole does">
      <label>Sole size <input id="de-from-size" type="number" value="37" step="any"></label>
      <label>to sizes <input id="de-sizes" value="38,39,40" size="10"></label>
      <label>System <select id="de-system"><option value="br">br (Paris point)</option><option value="us">us</option></select></label>
      <label>shrink <input id="de-shrink" type="number" value="2" min="0" max="20" step="any"> %</label>
      <button id="de-grade">Grade + mirror</button>
    </div>
    <svg id="de-view" viewBox="0 0 ${W} ${H}" width="${W}" height="${H}" style="background:#141820;cursor:crosshair;width:100%"></svg>
    <div><span id="de-xy" class="muted"></span> · <span id="de-count" class="muted"></span> <span id="de-fit-report" class="muted"></span></div>
    <div class="form"><label><span id="de-prompt"></span> <input id="de-cmd" size="28" placeholder="10,20  @30<45  5  fillet" autocomplete="off"></label></div>
    <span id="de-status" class="muted"></span>`;
  const svg = $('de-view') as unknown as SVGSVGElement;
  let panFrom: [number, number] | null = null;
  svg.addEventListener('mousemove', (e) => {
    if (panFrom) { view.pan((e.clientX - panFrom[0]) * (W / svg.getBoundingClientRect().width), (e.clientY - panFrom[1]) * (W / svg.getBoundingClientRect().width)); panFrom = [e.clientX, e.clientY]; }
    cursor = view.at(e, svg); snapped = snap(cursor);
    if (box) box.to = cursor;
    draw();
  });
  // A left drag with no tool draws a selection box; the click that ends it selects nothing more.
  let boxed = false;
  svg.addEventListener('mousedown', (e) => {
    if (e.button === 1 || e.button === 2) { panFrom = [e.clientX, e.clientY]; e.preventDefault(); }
    if (e.button === 0 && tool === null) { const p = view.at(e, svg); box = { from: p, to: p }; }
  });
  window.addEventListener('mouseup', (e) => {
    panFrom = null;
    if (!box) return;
    const b = box; box = null;
    // A drag of at least 4 pixels is a box; less is a click, and the view is not redrawn
    // here: the click goes only where the press's element still is.
    if (Math.hypot(b.to[0] - b.from[0], b.to[1] - b.from[1]) * view.s >= 4) { selectBox(b, e.shiftKey); boxed = true; draw(); }
  });
  svg.addEventListener('contextmenu', (e) => e.preventDefault());
  // Digitising and calibrating take the point under the cursor as it is (no snapping).
  svg.addEventListener('click', (e) => { if (boxed) { boxed = false; return; } const p = view.at(e, svg); takePoint(tool === 'digitise' || tool === 'calibrate' ? p : snap(p)?.p ?? p, e.shiftKey); $('de-cmd').focus({ preventScroll: true }); });
  svg.addEventListener('wheel', (e) => { e.preventDefault(); view.zoom(e.deltaY < 0 ? 1.2 : 1 / 1.2, view.at(e, svg)); draw(); }, { passive: false });
  const cmd = $<HTMLInputElement>('de-cmd');
  cmd.addEventListener('keydown', (e) => {
    if (e.key === 'Enter') { const t = cmd.value; cmd.value = ''; command(t); }
    else if (e.key === 'Escape') { cmd.value = ''; setTool(null); }
    else if ((e.ctrlKey || e.metaKey) && e.key === 'z' && !cmd.value) { e.preventDefault(); undo(); }
    else if ((e.ctrlKey || e.metaKey) && e.key === 'y' && !cmd.value) { e.preventDefault(); redo(); }
  });
  document.querySelectorAll<HTMLButtonElement>('#de-tools button[data-tool]').forEach((b) => { b.onclick = () => { setTool(b.dataset.tool as ToolName); cmd.focus(); }; });
  $('de-grade').onclick = () => { void grade(); };
  $('de-delete').onclick = del; $('de-explode').onclick = explode; $('de-join').onclick = join; $('de-undo').onclick = undo; $('de-redo').onclick = redo; $('de-fit').onclick = fit;
  $<HTMLInputElement>('de-name').onchange = (e) => { name = (e.target as HTMLInputElement).value.trim() || 'part'; };
  $('de-new').onclick = () => { past.push(JSON.stringify(design)); future = []; design = emptyDesign(); selected.clear(); renderLayers(); fit(); };
  $<HTMLSelectElement>('de-layer').onchange = (e) => { layer = (e.target as HTMLSelectElement).value; renderLayers(); };
  $<HTMLInputElement>('de-layer-color').onchange = (e) => { const c = (e.target as HTMLInputElement).value; commit((d) => { const l = d.layers.find((x) => x.name === layer); if (l) l.color = c; }, `layer ${layer}: ${c}`); };
  $('de-add-layer').onclick = () => {
    const n = $<HTMLInputElement>('de-new-layer').value.trim();
    if (!n) return status('give the new layer a name', true);
    if (design.layers.some((l) => l.name === n)) return status(`layer ${n} exists`, true);
    commit((d) => d.layers.push({ name: n, color: '#5ad1f0' }), `layer ${n} added`);
    layer = n; renderLayers();
  };
  $('de-to-layer').onclick = () => { const sel = targets(); if (typeof sel === 'string') return status(sel, true); commit((d) => d.entities.forEach((e) => { if (selected.has(e.id)) e.layer = layer; }), `${sel.length} to layer ${layer}`); };
  $<HTMLInputElement>('de-bg-file').onchange = (e) => {
    const f = (e.target as HTMLInputElement).files?.[0];
    if (!f) return;
    const reader = new FileReader();
    reader.onload = () => {
      const img = new Image();
      img.onload = () => {
        // One pixel a millimetre until `calibrate` says otherwise.
        bg = { href: String(reader.result), x: 0, y: 0, w: img.naturalWidth, h: img.naturalHeight };
        status(`${f.name}: ${img.naturalWidth} × ${img.naturalHeight} px, 1 px = 1 mm until calibrated`); fit();
      };
      img.onerror = () => status(`${f.name}: not an image the browser reads`, true);
      img.src = String(reader.result);
    };
    reader.readAsDataURL(f);
  };
  $<HTMLInputElement>('de-open').onchange = async (e) => {
    const f = (e.target as HTMLInputElement).files?.[0];
    if (!f) return;
    if (!/\.(dat|g01)$/i.test(f.name)) return load(await f.text(), f.name);
    // Seed 001's graphic file: the server reads it into a design.
    try {
      const r = await fetch(withToken('/api/design/import'), { method: 'POST', headers: { 'content-type': 'application/json' }, body: JSON.stringify({ text: await f.text(), name: f.name }) });
      const v = await r.json();
      if (!r.ok) throw new Error(v.error ?? r.statusText);
      load(JSON.stringify(v.design), f.name);
    } catch (err) { status(`open ${f.name}: ${(err as Error).message}`, true); }
  };
  $('de-save').onclick = async () => {
    download(text(), fileName(), 'application/json');
    try { await putFile(fileName(), text()); status(`saved ${fileName()}`); } catch (err) { status(`save ${fileName()}: ${(err as Error).message}`, true); }
  };
  const extension: Record<string, string> = { svg: 'svg', dxf: 'dxf', seed001: 'dat' };
  for (const format of ['svg', 'dxf', 'seed001']) $(`de-${format}`).onclick = async () => {
    try {
      const r = await fetch(withToken('/api/design/export'), { method: 'POST', headers: { 'content-type': 'application/json' }, body: JSON.stringify({ design, format }) });
      const v = await r.json();
      if (!r.ok) throw new Error(v.error ?? r.statusText);
      download(v.text, fileName().replace(/\.oficina\.json$/, `.${extension[format]}`), format === 'svg' ? 'image/svg+xml' : format === 'dxf' ? 'application/dxf' : 'text/plain');
      status(`exported ${format === 'seed001' ? 'seed 001' : format.toUpperCase()}`);
    } catch (err) { status(`export: ${(err as Error).message}`, true); }
  };
  $('de-cam').onclick = async () => {
    if (!design.entities.length) return status('draw something first', true);
    try { await putFile(fileName(), text()); } catch (err) { return status(`send: ${(err as Error).message}`, true); }
    hooks.openInCam(fileName());
  };
  // For the browser test: the design, and where a drawing point is on the screen.
  (window as unknown as { __design: unknown }).__design = {
    design: () => design,
    background: () => bg,
    digitised: (id: number) => digitised.get(id),
    screen: (p: Pt) => { const r = svg.getBoundingClientRect(); return [r.left + (view.sx(p[0]) * r.width) / W, r.top + (view.sy(p[1]) * r.height) / H]; },
  };
  renderLayers(); setTool(null); fit();
}
