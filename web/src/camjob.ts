// The CAM job page: a drawing in 2D with the ids the import report gives its shapes, shapes
// picked by click, shift-click and box, operations added on them (kind, tool, depths,
// kind-specific fields), reordered and deleted; "Make" sends the job as the TOML that
// `oficina mill --job` reads to /api/mill-job, which builds it with the CLI's own call;
// "Save job" downloads the same TOML. No CAM knowledge here: the server numbers the shapes,
// builds, orders, checks and times.

import { withToken, putFile } from './api';
import { SVG, el, segDist } from './view2d';

interface Shape {
  id: number; layer: string; color: string | null; closed: boolean; circle: number | null;
  hole: boolean; describe: string; points: [number, number][];
}
interface Op {
  name: string; kind: string; ids: number[]; tool: string; depth: string; stepdown: string;
  feed: string; rpm: string; width: string; tip_offset: string; tabs: string; tab_width: string; tab_height: string;
}
interface BuiltOp { index: number; name: string; tool_number: number; tool: string; shapes: number[]; moves: number; depth: number; feed: number; feed_source: string; path: [number, number, number][][]; }
interface Built {
  name: string; text: string; report: string[]; gouged: boolean; ops: BuiltOp[]; tool_loads: number;
  warnings: string[]; imported: string[];
}
/// The stock after the first `upto` operations of the cutting order (`/api/mill-job/stock`).
interface StockAfter {
  upto: number; last: string; ops: number[]; judged: string[]; gouged: boolean; png: string;
  report: { stock_origin: [number, number]; stock_size: [number, number, number]; pixel: number; removed_mm3: number;
    lowest_z: number; machine_seconds: { Ok?: number; Err?: string }; tools: { number: number; spec: string }[];
    counts: [number, number, number] };
}
interface Plate { layer: string; rect: [number, number, number, number]; r: number; }

const KINDS = ['profile-in', 'profile-out', 'profile-on', 'engrave', 'pocket', 'drill', 'vcarve', 'chamfer'];
const COLOURS = ['#f0b45a', '#5ad1f0', '#9af05a', '#f05ad1', '#f06a5a', '#5a7af0', '#e0e05a', '#5af0a8'];

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;

let drawing: string | null = null;
let library: string | null = null;
let shapes: Shape[] = [];
let selected = new Set<number>();
const plates: Plate[] = [];
let ops: Op[] = [];
let built: Built | null = null;
let shownOp: number | null = null;
let stockAfter: StockAfter | null = null;
let view = { x0: 0, y0: 0, s: 1 };

const safe = (n: string) => n.replace(/[^A-Za-z0-9._-]/g, '_').replace(/^\.+/, '').slice(0, 100);
const str = (s: string) => JSON.stringify(s);
const num = (v: string) => String(Number(v));

function field(id: string): string { return ($<HTMLInputElement>(id).value ?? '').trim(); }

/// The job as `oficina mill --job` reads it (`docs/cam-jobs.md`).
export function jobToml(withOps = true): string {
  const l: string[] = ['# Made in the Oficina workbench (CAM job).'];
  l.push(`drawing = ${str(drawing ?? '')}`);
  if (library) l.push(`library = ${str(library)}`);
  if (field('cj-material')) l.push(`material = ${str(field('cj-material'))}`);
  l.push(`order = ${str(field('cj-order') || 'by-tool')}`);
  l.push('', '[stock]', `thickness = ${num(field('cj-thickness') || '4')}`);
  if (field('cj-size')) l.push(`size = [${field('cj-size').split(/[ ,x×]+/).map(num).join(', ')}]`);
  if (field('cj-corner')) l.push(`corner = [${field('cj-corner').split(/[ ,]+/).map(num).join(', ')}]`);
  for (const p of plates) {
    l.push('', '[[shape]]', `layer = ${str(p.layer)}`, `rect = [${p.rect.join(', ')}]`);
    if (p.r) l.push(`corner_radius = ${p.r}`);
  }
  if (withOps) for (const o of ops) {
    l.push('', '[[op]]', `name = ${str(o.name)}`, `kind = ${str(o.kind)}`, `select = { ids = [${o.ids.join(', ')}] }`);
    l.push(`tool = ${/^\d+$/.test(o.tool) ? o.tool : str(o.tool)}`);
    if (o.kind === 'chamfer') {
      if (o.width) l.push(`width = ${num(o.width)}`);
      if (o.tip_offset) l.push(`tip_offset = ${num(o.tip_offset)}`);
    } else if (o.depth) l.push(`depth = ${num(o.depth)}`);
    if (o.stepdown) l.push(`stepdown = ${num(o.stepdown)}`);
    if (o.feed) l.push(`feed = ${num(o.feed)}`);
    if (o.rpm) l.push(`rpm = ${num(o.rpm)}`);
    if ((o.kind === 'profile-out' || o.kind === 'profile-in') && o.tabs && Number(o.tabs) > 0) {
      l.push(`tabs = { count = ${num(o.tabs)}, width = ${num(o.tab_width || '4')}, height = ${num(o.tab_height || '1')} }`);
    }
  }
  return l.join('\n') + '\n';
}

function jobName(): string {
  const stem = (drawing ?? 'job').replace(/\.[^.]*$/, '');
  return safe(`${stem}.job.toml`);
}

/// POSTs JSON; the server's `{error}` as the thrown message.
async function post<T>(path: string, body: unknown): Promise<T> {
  const r = await fetch(withToken(path), { method: 'POST', headers: { 'content-type': 'application/json' }, body: JSON.stringify(body) });
  const text = await r.text();
  let v: { error?: string } & T;
  try { v = JSON.parse(text); } catch { throw new Error(text || `${r.status} ${r.statusText}`); }
  if (!r.ok) throw new Error(v.error ?? text);
  return v;
}

function status(msg: string, isError = false) {
  const s = $('cj-status');
  s.textContent = msg;
  s.classList.toggle('error', isError);
}

async function loadShapes() {
  if (!drawing) return;
  try {
    const v = await post<{ shapes: Shape[]; warnings: string[] }>('/api/mill-job/shapes', { name: jobName(), toml: jobToml(false) });
    shapes = v.shapes;
    selected = new Set([...selected].filter((id) => shapes.some((s) => s.id === id)));
    status(`${drawing}: ${shapes.length} shapes${v.warnings.length ? ' · ' + v.warnings.join('; ') : ''}`);
  } catch (e) {
    shapes = [];
    status((e as Error).message, true);
  }
  draw();
}

const W = 560, H = 420, PAD = 16;
const sx = (x: number) => (x - view.x0) * view.s + PAD;
const sy = (y: number) => H - ((y - view.y0) * view.s + PAD);

function draw() {
  const svg = $('cj-view') as unknown as SVGSVGElement;
  svg.innerHTML = '';
  const pts = shapes.flatMap((s) => s.points);
  if (!pts.length) return;
  const st = stockAfter?.report;
  if (st) pts.push(st.stock_origin, [st.stock_origin[0] + st.stock_size[0], st.stock_origin[1] + st.stock_size[1]]);
  const xs = pts.map((p) => p[0]), ys = pts.map((p) => p[1]);
  const x0 = Math.min(...xs), x1 = Math.max(...xs), y0 = Math.min(...ys), y1 = Math.max(...ys);
  const s = Math.min((W - 2 * PAD) / Math.max(x1 - x0, 1e-6), (H - 2 * PAD) / Math.max(y1 - y0, 1e-6));
  view = { x0, y0, s };
  // The simulated stock under the shapes, over its own box (the picture's top is its max Y).
  if (st && stockAfter) {
    const [ox, oy] = st.stock_origin, [w, h] = st.stock_size;
    el('image', { href: stockAfter.png, x: sx(ox), y: sy(oy + h), width: w * s, height: h * s, preserveAspectRatio: 'none', id: 'cj-stock-image', 'pointer-events': 'none' }, svg);
  }
  // Large shapes first: a small hole inside a plate stays on top, where a click finds it.
  const area = (sh: Shape) => { const b = box(sh); return (b[2] - b[0]) * (b[3] - b[1]); };
  for (const sh of [...shapes].sort((a, b) => area(b) - area(a))) {
    const d = sh.points.map((p, k) => `${k ? 'L' : 'M'}${sx(p[0]).toFixed(2)} ${sy(p[1]).toFixed(2)}`).join(' ') + (sh.closed ? ' Z' : '');
    const sel = selected.has(sh.id);
    const path = el('path', { d, fill: sel ? `rgba(240,180,90,${stockAfter ? 0.08 : 0.25})` : 'rgba(0,0,0,0)', stroke: sel ? '#f0b45a' : '#c8d0dc', 'stroke-width': sel ? 2.5 : 1.2, 'data-id': sh.id, class: 'cj-shape' + (sel ? ' selected' : '') }, svg);
    const t = document.createElementNS(SVG, 'title');
    t.textContent = sh.describe;
    path.appendChild(t);
    const b = box(sh);
    const label = el('text', { x: sx(b[0]) + 2, y: sy(b[3]) + 11, fill: sel ? '#f0b45a' : '#8a93a3', 'font-size': 11, class: 'cj-id' }, svg);
    label.textContent = `#${sh.id}`;
  }
  // The toolpaths over the shapes; the picked operation's bright, the others faint.
  const showOps = built ? built.ops : [];
  for (const o of showOps) {
    const on = shownOp === null || shownOp === o.index;
    const colour = COLOURS[(o.index - 1) % COLOURS.length];
    for (const line of o.path) {
      el('polyline', { points: line.map((p) => `${sx(p[0]).toFixed(2)},${sy(p[1]).toFixed(2)}`).join(' '), fill: 'none', stroke: colour, 'stroke-width': on ? 1.2 : 0.5, opacity: on ? 0.95 : 0.2, class: `cj-toolpath op-${o.index}`, 'pointer-events': 'none' }, svg);
    }
  }
  $('cj-selection').textContent = selected.size ? `selected: ${[...selected].sort((a, b) => a - b).map((i) => '#' + i).join(' ')}` : 'nothing selected: click a shape, shift-click to add, drag a box';
}

function box(sh: Shape): [number, number, number, number] {
  const xs = sh.points.map((p) => p[0]), ys = sh.points.map((p) => p[1]);
  return [Math.min(...xs), Math.min(...ys), Math.max(...xs), Math.max(...ys)];
}

/// Drawing coordinates of a mouse event on the view.
function at(e: MouseEvent): [number, number] {
  const r = ($('cj-view') as unknown as SVGSVGElement).getBoundingClientRect();
  const px = (e.clientX - r.left) * (W / r.width), py = (e.clientY - r.top) * (H / r.height);
  return [(px - PAD) / view.s + view.x0, (H - py - PAD) / view.s + view.y0];
}

function setupView() {
  const svg = $('cj-view') as unknown as SVGSVGElement;
  let start: [number, number] | null = null;
  let startEvent: MouseEvent | null = null;
  let rubber: SVGElement | null = null;
  svg.addEventListener('mousedown', (e) => { start = at(e); startEvent = e; e.preventDefault(); });
  svg.addEventListener('mousemove', (e) => {
    if (!start || !startEvent) return;
    if (Math.hypot(e.clientX - startEvent.clientX, e.clientY - startEvent.clientY) < 4) return;
    const p = at(e);
    rubber?.remove();
    rubber = el('rect', { x: Math.min(sx(start[0]), sx(p[0])), y: Math.min(sy(start[1]), sy(p[1])), width: Math.abs(sx(p[0]) - sx(start[0])), height: Math.abs(sy(p[1]) - sy(start[1])), fill: 'rgba(90,209,240,0.1)', stroke: '#5ad1f0', 'stroke-dasharray': '4 3' }, svg);
  });
  // On the window: a box may end outside the view.
  window.addEventListener('mouseup', (e) => {
    if (!start || !startEvent) return;
    const moved = Math.hypot(e.clientX - startEvent.clientX, e.clientY - startEvent.clientY) >= 4;
    const p = at(e);
    if (!e.shiftKey) selected.clear();
    if (moved) {
      // A box takes the shapes wholly inside it.
      const [bx0, bx1] = [Math.min(start[0], p[0]), Math.max(start[0], p[0])];
      const [by0, by1] = [Math.min(start[1], p[1]), Math.max(start[1], p[1])];
      for (const sh of shapes) {
        const b = box(sh);
        if (b[0] >= bx0 && b[2] <= bx1 && b[1] >= by0 && b[3] <= by1) selected.add(sh.id);
      }
    } else {
      const target = (e.target as Element).closest?.('#cj-view [data-id]');
      const id = target ? Number(target.getAttribute('data-id')) : nearest(p);
      if (id !== null) {
        if (e.shiftKey && selected.has(id)) selected.delete(id);
        else selected.add(id);
      }
    }
    start = null; startEvent = null; rubber = null;
    draw();
  });
}

/// The shape whose outline passes nearest `p`, within 8 screen pixels.
function nearest(p: [number, number]): number | null {
  let best: number | null = null, bestD = 8 / view.s;
  for (const sh of shapes) {
    for (let k = 1; k < sh.points.length; k++) {
      const d = segDist(p, sh.points[k - 1], sh.points[k]);
      if (d < bestD) { bestD = d; best = sh.id; }
    }
  }
  return best;
}

function renderOps() {
  const tb = $('cj-ops');
  tb.innerHTML = '';
  ops.forEach((o, k) => {
    const tr = document.createElement('tr');
    tr.className = 'cj-op' + (shownOp === k + 1 ? ' shown' : '');
    const b = built?.ops.find((x) => x.index === k + 1);
    const bits = [o.kind, `T ${o.tool}`, o.kind === 'chamfer' ? `width ${o.width}` : `depth ${o.depth}`, `${o.ids.length} shapes`];
    if (o.tabs && Number(o.tabs) > 0) bits.push(`${o.tabs} tabs`);
    const cells = [`${k + 1}`, o.name, bits.join(' · '), b ? `T${b.tool_number} ${b.moves} moves, ${b.feed.toFixed(0)} mm/min` : ''];
    for (const c of cells) { const td = document.createElement('td'); td.textContent = c; tr.appendChild(td); }
    const swatch = tr.firstChild as HTMLElement;
    swatch.style.color = COLOURS[k % COLOURS.length];
    const act = document.createElement('td');
    for (const [label, title, fn] of [
      ['↑', 'move up', () => { if (k > 0) { [ops[k - 1], ops[k]] = [ops[k], ops[k - 1]]; changed(); } }],
      ['↓', 'move down', () => { if (k < ops.length - 1) { [ops[k + 1], ops[k]] = [ops[k], ops[k + 1]]; changed(); } }],
      ['✕', 'delete', () => { ops.splice(k, 1); changed(); }],
    ] as [string, string, () => void][]) {
      const btn = document.createElement('button');
      btn.textContent = label; btn.title = title; btn.className = 'cj-' + title.replace(' ', '-');
      btn.onclick = (e) => { e.stopPropagation(); fn(); };
      act.appendChild(btn);
    }
    tr.appendChild(act);
    tr.onclick = () => {
      shownOp = shownOp === k + 1 ? null : k + 1;
      selected = new Set(o.ids);
      renderOps(); draw();
      // With a program made: the stock after this operation (its place in the cutting order).
      const at = built ? built.ops.findIndex((x) => x.index === k + 1) + 1 : 0;
      if (shownOp !== null && at > 0) { $<HTMLInputElement>('cj-upto').value = String(at); showStock(at); }
    };
    tb.appendChild(tr);
  });
}

/// Asks for the stock after the first `upto` operations of the cutting order and shows it
/// under the drawing with its report. One request at a time (the server computes one job
/// at a time): a click while one runs waits for it, and only the newest is sent.
let stockAsked = 0;
let stockRunning: Promise<void> = Promise.resolve();
async function showStock(upto: number) {
  if (!built) return;
  const ask = ++stockAsked;
  const op = built.ops[upto - 1];
  $('cj-upto-label').textContent = `after ${upto} of ${built.ops.length}: ${op.name}`;
  $('cj-stock-report').textContent = 'simulating…';
  delete document.body.dataset.cjStock;
  const cell = Number(field('cj-cell'));
  const before = stockRunning;
  let finished = () => {};
  stockRunning = new Promise((done) => { finished = done; });
  await before;
  if (ask !== stockAsked) return finished();
  try {
    const v = await post<StockAfter>('/api/mill-job/stock', { name: jobName(), toml: jobToml(), upto, resolution: cell > 0 ? cell : null });
    if (ask !== stockAsked) return;
    stockAfter = v;
    shownOp = op.index;
    const r = v.report;
    const time = r.machine_seconds.Ok != null ? `, ${(r.machine_seconds.Ok / 60).toFixed(1)} min on the machine (planner)` : '';
    $('cj-stock-report').textContent = [
      `stock after op ${v.ops.join(', op ')} (cutting order): ${r.removed_mm3.toFixed(1)} mm³ removed · ${v.gouged ? 'GOUGE' : 'no gouge'}${time}`,
      `stock ${r.stock_size.map((x) => x.toFixed(1)).join(' × ')} mm at (${r.stock_origin.map((x) => x.toFixed(2)).join(', ')}) · cell ${r.pixel} mm · lowest Z ${r.lowest_z.toFixed(3)} · tools ${r.tools.map((t) => `T${t.number} ${t.spec}`).join(', ')}`,
      ...(r.counts[0] ? [`RAPID INTO MATERIAL ×${r.counts[0]}`] : []),
      ...v.judged,
    ].join('\n');
    $('cj-stock-report').dataset.removed = String(r.removed_mm3);
    document.body.dataset.cjStock = String(upto);
    renderOps(); draw();
  } catch (e) {
    if (ask !== stockAsked) return;
    $('cj-stock-report').textContent = `stock after op ${op.index}: ${(e as Error).message}`;
    document.body.dataset.cjStock = 'failed';
  } finally {
    finished();
  }
}

/// The job changed: the toolpaths made before no longer answer it.
function changed() {
  built = null; shownOp = null; stockAfter = null; stockAsked++;
  $('cj-report').textContent = '';
  $('cj-stock-report').textContent = '';
  $('cj-stock-ctl').hidden = true;
  renderOps(); draw();
}

function addOp() {
  if (!drawing) return status('open a drawing first', true);
  if (!selected.size) return status('select the shapes of the operation first', true);
  const kind = field('cj-kind');
  const o: Op = {
    name: field('cj-name') || kind, kind, ids: [...selected].sort((a, b) => a - b), tool: field('cj-tool'),
    depth: field('cj-depth'), stepdown: field('cj-stepdown'), feed: field('cj-feed'), rpm: field('cj-rpm'), width: field('cj-width'),
    tip_offset: field('cj-tip'), tabs: field('cj-tabs'), tab_width: field('cj-tab-width'), tab_height: field('cj-tab-height'),
  };
  if (!o.tool) return status('give a tool: a library number or a spec such as flat:2, v:6:90', true);
  if (kind !== 'chamfer' && !o.depth) return status('give the depth', true);
  if (kind === 'chamfer' && !o.width) return status('a chamfer needs its width', true);
  ops.push(o);
  $<HTMLInputElement>('cj-name').value = '';
  status(`added ${o.name} on ${o.ids.length} shapes`);
  changed();
}

/// Opens a drawing already in the job folder (the file control's, the design editor's Send to CAM).
export async function openDrawing(name: string) {
  drawing = name; selected.clear(); ops = []; plates.length = 0;
  changed();
  await loadShapes();
}

export function initCamJob(hooks: { loadProgram: (name: string, text: string, saved: boolean, plot: boolean, from: string) => void }) {
  $('camjob').innerHTML = `
    <h3>CAM job <span class="muted">— shapes → operations → one program (as <code>oficina mill --job</code>)</span></h3>
    <div class="form cj-files">
      <label>Drawing <input id="cj-drawing" type="file" accept=".svg,.dxf,.json"></label>
      <label>Tool library <input id="cj-library" type="file" accept=".toml"></label>
      <label>Material <input id="cj-material" placeholder="aluminium" size="9"></label>
      <label>Stock thickness <input id="cj-thickness" type="number" value="4" min="0.01" step="any"> mm</label>
      <label>Stock size <input id="cj-size" placeholder="50 50" size="7"></label>
      <label>Stock corner <input id="cj-corner" placeholder="0 0" size="7"></label>
      <label>Order <select id="cj-order"><option>by-tool</option><option>as-written</option></select></label>
    </div>
    <div class="form">
      <label>Add a plate: rect <input id="cj-rect" placeholder="x0 y0 x1 y1" size="12"></label>
      <label>corner radius <input id="cj-rect-r" type="number" value="0" min="0" step="any"></label>
      <label>layer <input id="cj-rect-layer" value="OUTLINE" size="8"></label>
      <button id="cj-add-rect">Add shape</button>
    </div>
    <svg id="cj-view" viewBox="0 0 ${W} ${H}" width="${W}" height="${H}"></svg>
    <div id="cj-stock-ctl" class="form" hidden>
      <label>Stock after operation <input id="cj-upto" type="range" min="1" max="1" step="1" value="1"></label>
      <span id="cj-upto-label" class="muted"></span>
      <label>cell <input id="cj-cell" type="number" value="0.1" min="0" step="any" title="grid cell of the simulation, mm (0: chosen from the memory budget)"> mm</label>
    </div>
    <pre id="cj-stock-report"></pre>
    <div><span id="cj-selection" class="muted"></span></div>
    <div class="form">
      <button id="cj-all">Select all</button>
      <button id="cj-same-layer">Same layer</button>
      <label>Circles under Ø <input id="cj-dia" type="number" value="10" min="0" step="any"></label><button id="cj-circles">Select</button>
    </div>
    <div class="form cj-opform">
      <label>Operation <select id="cj-kind">${KINDS.map((k) => `<option>${k}</option>`).join('')}</select></label>
      <label>Name <input id="cj-name" size="10"></label>
      <label>Tool <input id="cj-tool" value="flat:2" size="8" title="a library number, or flat:D, ball:D, v:D:ANGLE"></label>
      <label>Depth <input id="cj-depth" type="number" value="4.2" step="any"> mm</label>
      <label>Step-down <input id="cj-stepdown" type="number" value="1" step="any"> mm</label>
      <label>Feed <input id="cj-feed" type="number" step="any" placeholder="library/default"> mm/min</label>
      <label>Spindle <input id="cj-rpm" type="number" step="any" placeholder="library/default"> rpm</label>
      <label>Chamfer width <input id="cj-width" type="number" value="0.5" step="any"> mm</label>
      <label>tip offset <input id="cj-tip" type="number" value="0.2" step="any"> mm</label>
      <label>Tabs <input id="cj-tabs" type="number" value="0" min="0" step="1"></label>
      <label>tab width <input id="cj-tab-width" type="number" value="4" step="any"></label>
      <label>tab height <input id="cj-tab-height" type="number" value="1" step="any"></label>
      <button id="cj-add-op">Add operation</button>
    </div>
    <table id="cj-table"><tbody id="cj-ops"></tbody></table>
    <button id="cj-make">Make the program</button> <button id="cj-save">Save job</button>
    <span id="cj-status" class="muted"></span>
    <pre id="cj-report"></pre>`;
  setupView();
  $('cj-upto').addEventListener('change', () => showStock(Number(field('cj-upto'))));
  $('cj-cell').addEventListener('change', () => { if (stockAfter) showStock(stockAfter.upto); });
  $<HTMLInputElement>('cj-drawing').onchange = async (e) => {
    const f = (e.target as HTMLInputElement).files?.[0];
    if (!f) return;
    const name = safe(f.name);
    try { await putFile(name, f); } catch (err) { return status(`upload ${f.name}: ${(err as Error).message}`, true); }
    await openDrawing(name);
  };
  $<HTMLInputElement>('cj-library').onchange = async (e) => {
    const f = (e.target as HTMLInputElement).files?.[0];
    if (!f) return;
    const name = safe(f.name);
    try { await putFile(name, f); library = name; status(`tool library ${name}: tools by their numbers`); } catch (err) { status(`upload ${f.name}: ${(err as Error).message}`, true); }
  };
  for (const id of ['cj-corner', 'cj-thickness']) $(id).addEventListener('change', () => { changed(); loadShapes(); });
  $('cj-add-rect').onclick = () => {
    const v = field('cj-rect').split(/[ ,]+/).map(Number);
    if (v.length !== 4 || v.some((x) => !Number.isFinite(x))) return status('rect: four numbers x0 y0 x1 y1', true);
    plates.push({ layer: field('cj-rect-layer') || 'OUTLINE', rect: v as [number, number, number, number], r: Number(field('cj-rect-r')) || 0 });
    changed();
    loadShapes();
  };
  $('cj-all').onclick = () => { selected = new Set(shapes.map((s) => s.id)); draw(); };
  $('cj-same-layer').onclick = () => {
    const layers = new Set(shapes.filter((s) => selected.has(s.id)).map((s) => s.layer.toLowerCase()));
    selected = new Set(shapes.filter((s) => layers.has(s.layer.toLowerCase())).map((s) => s.id));
    draw();
  };
  $('cj-circles').onclick = () => {
    const d = Number(field('cj-dia'));
    selected = new Set(shapes.filter((s) => s.circle !== null && s.circle < d).map((s) => s.id));
    draw();
  };
  $('cj-add-op').onclick = addOp;
  $('cj-save').onclick = () => {
    if (!drawing) return status('open a drawing first', true);
    const a = document.createElement('a');
    a.href = URL.createObjectURL(new Blob([jobToml()], { type: 'application/toml' }));
    a.download = jobName();
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 1000);
  };
  $('cj-make').onclick = async () => {
    if (!drawing) return status('open a drawing first', true);
    if (!ops.length) return status('add an operation first', true);
    status('working…');
    try {
      const b = await post<Built>('/api/mill-job', { name: jobName(), toml: jobToml() });
      built = b;
      const changes = Math.max(0, b.tool_loads - 1);
      const lines = [
        `${b.name}: ${b.ops.length} operations, ${b.tool_loads} tool loads (${changes} tool changes) · ${b.gouged ? 'GOUGE' : 'no gouge'}`,
        'cutting order:',
        ...b.ops.map((o) => `  ${o.index}. ${o.name}: T${o.tool_number} ${o.tool}, ${o.shapes.length} shapes, depth ${o.depth.toFixed(2)} mm, ${o.moves} moves, feed ${o.feed.toFixed(0)} mm/min (${o.feed_source})`),
        ...b.report, ...b.warnings.map((w) => 'warning: ' + w),
        'The stock after an operation: click its row, or move the slider under the drawing.',
      ];
      $('cj-report').textContent = lines.join('\n');
      status(`${b.name}: ${b.text.split('\n').length} lines`);
      const upto = $<HTMLInputElement>('cj-upto');
      upto.max = String(b.ops.length); upto.value = String(b.ops.length);
      $('cj-stock-ctl').hidden = false;
      renderOps(); draw();
      hooks.loadProgram(b.name, b.text, true, false, `a CAM job on ${drawing}`);
    } catch (e) {
      status((e as Error).message, true);
    }
  };
  draw();
}
