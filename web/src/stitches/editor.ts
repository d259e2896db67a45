// The stitch editor: embroidery files (or the plan the embroidery process just made) shown
// stitch by stitch, coloured per block, jumps dashed, trims (×), stops (□) and colour
// changes (○) marked. A click selects an entry, shift-click a range, a drag a box; the
// selection is moved, deleted, a stitch inserted after it, a colour stop added or removed
// before it (./model.ts). The whole design is scaled, rotated, mirrored and shifted, several
// designs linked, a section sewn at a faster speed code and the result saved by the
// library through the server (/api/stitches/*, crates/server/src/stitches.rs).

import { putFile, withToken } from '../api';
import { el, ViewMap, Pt } from '../view2d';
import { Plan, Placed, STITCH, JUMP, TRIM, STOP, count, entry, bounds, moveEntries, insertAfter, deleteEntries, addColourStop, removeColourStop, blockStart } from './model';

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;
const W = 760, H = 480;
/// A click picks the nearest entry within this many pixels.
const PICK_PX = 8;

let designs: Placed[] = [];
let active = 0;
let selected = new Set<number>();
let anchor: number | null = null;
const past: string[] = [];
let future: string[] = [];
const view = new ViewMap(W, H);

/// POSTs `body` as JSON; the answer, or the server's message (its `error` field).
async function post<T>(route: string, body: unknown): Promise<T> {
  const r = await fetch(withToken(route), { method: 'POST', headers: { 'content-type': 'application/json' }, body: JSON.stringify(body) });
  if (r.ok) return r.json();
  const text = await r.text();
  let msg = text;
  try { msg = JSON.parse(text).error ?? text; } catch { /* plain text */ }
  throw new Error(msg || `${r.status} ${r.statusText}`);
}

interface PlanAnswer { plan: Plan; sections: [number, number, number | null][] }

function status(msg: string, isError = false) {
  const s = $('se-status');
  s.textContent = msg;
  s.classList.toggle('error', isError);
}
const snapshot = () => JSON.stringify({ designs, active });
function restore(s: string) { ({ designs, active } = JSON.parse(s)); selected = new Set(); anchor = null; }

/// One undoable step on the designs.
function commit(change: () => void, what: string) {
  past.push(snapshot());
  future = [];
  change();
  status(what);
  draw();
}
function undo() {
  const s = past.pop();
  if (s === undefined) return status('nothing to undo');
  future.push(snapshot()); restore(s); status(`undone (${past.length} more)`); draw();
}
function redo() {
  const s = future.pop();
  if (s === undefined) return status('nothing to redo');
  past.push(snapshot()); restore(s); status('redone'); draw();
}

const cur = (): Placed | undefined => designs[active];
const sorted = () => [...selected].sort((a, b) => a - b);

/// Adds a design (an answer of the server) and makes it the active one.
function add(name: string, a: PlanAnswer) {
  commit(() => {
    // A new design is placed right of the others, so linked designs do not overlap.
    const right = designs.reduce((m, d) => Math.max(m, bounds(d.plan, d.at)?.[2] ?? m), -Infinity);
    const b = bounds(a.plan);
    const x = designs.length && b ? Math.round(right + 10 - b[0]) : 0;
    designs.push({ plan: { ...a.plan, name }, at: [x, 0], sections: a.sections });
    active = designs.length - 1;
  }, `opened ${name}: ${count(a.plan)} entries, ${a.plan.blocks.length} colour${a.plan.blocks.length === 1 ? '' : 's'}`);
  fit();
}

/// The plan just made by the embroidery process, opened in the editor.
export function openPlan(name: string, plan: Plan) {
  post<PlanAnswer>('/api/stitches/alter', ({ plan }))
    .then((a) => add(name, a))
    .catch((e) => status(`${name}: ${(e as Error).message}`, true));
}

async function openFile(f: File) {
  try {
    await putFile(f.name, f);
    add(f.name, await post<PlanAnswer>('/api/stitches/open', ({ file: f.name })));
  } catch (e) { status(`${f.name}: ${serverMessage(e)}`, true); }
}

const serverMessage = (e: unknown) => (e as Error).message;

/// The active design replaced by what the server made of it (one undoable step).
async function viaServer(route: string, body: Record<string, unknown>, what: string) {
  const d = cur();
  if (!d) return status('open a design first', true);
  try {
    const a = await post<PlanAnswer>(route, ({ plan: d.plan, ...body }));
    commit(() => { designs[active] = { plan: { ...a.plan, name: d.plan.name }, at: d.at, sections: a.sections }; selected.clear(); }, what);
  } catch (e) { status(`${what}: ${serverMessage(e)}`, true); }
}

const num = (id: string) => Number($<HTMLInputElement>(id).value);

function alterDesign() {
  const mirror = $<HTMLSelectElement>('se-mirror').value;
  const body = { rotate: num('se-rotate'), scale: num('se-scale'), shift: [num('se-shift-x'), num('se-shift-y')], mirror: mirror || null };
  viaServer('/api/stitches/alter', body, `altered: rotate ${body.rotate}°, scale ${body.scale}, mirror ${mirror || 'none'}, shift ${body.shift.join(', ')} mm`);
}

async function linkAll() {
  if (designs.length < 2) return status('open two designs or more to link', true);
  try {
    const a = await post<PlanAnswer>('/api/stitches/link', ({ designs: designs.map((d) => ({ plan: d.plan, at: d.at })) }));
    const names = designs.map((d) => d.plan.name).join(' + ');
    commit(() => { designs = [{ plan: a.plan, at: designs[0].at, sections: a.sections }]; active = 0; selected.clear(); },
      `linked ${names}: ${count(a.plan)} entries, ${a.plan.blocks.length} colours`);
  } catch (e) { status(`link: ${serverMessage(e)}`, true); }
}

async function save() {
  const d = cur();
  if (!d) return status('open a design first', true);
  const name = `${$<HTMLInputElement>('se-name').value.trim() || 'edited'}.${$<HTMLSelectElement>('se-format').value}`;
  try {
    const r = await post<{ name: string; bytes: number; format: string; stitches: number; colours: number }>(
      '/api/stitches/save', ({ plan: d.plan, name }));
    const s = $('se-saved');
    s.dataset.name = r.name; s.dataset.stitches = String(r.stitches); s.dataset.colours = String(r.colours);
    status(`saved ${r.name} (${r.format}, ${r.bytes} bytes): ${r.stitches} stitches, ${r.colours} colours as the file reads back`);
  } catch (e) { status(`save: ${serverMessage(e)}`, true); }
}

function speedOfSelection() {
  const first = sorted()[0];
  if (first === undefined) return status('select a stitch of the section first', true);
  const code = Number($<HTMLSelectElement>('se-code').value);
  viaServer('/api/stitches/speed', { entry: first, code }, `section of entry ${first} sewn at speed code ${code}`);
}

function select(i: number, extend: boolean) {
  if (extend && anchor !== null) {
    const [a, b] = anchor < i ? [anchor, i] : [i, anchor];
    selected = new Set(Array.from({ length: b - a + 1 }, (_, k) => a + k));
  } else { selected = new Set([i]); anchor = i; }
  draw();
}

function nearest(p: Pt): number | null {
  const d = cur();
  if (!d) return null;
  let best: number | null = null, bd = PICK_PX / view.s;
  let i = 0;
  for (const b of d.plan.blocks) {
    for (let k = 0; k < b.points.length; k += 3, i++) {
      const e = Math.hypot(b.points[k] + d.at[0] - p[0], b.points[k + 1] + d.at[1] - p[1]);
      if (e < bd) { bd = e; best = i; }
    }
  }
  return best;
}

function boxSelect(a: Pt, b: Pt) {
  const d = cur();
  if (!d) return;
  const [x0, x1] = [Math.min(a[0], b[0]), Math.max(a[0], b[0])], [y0, y1] = [Math.min(a[1], b[1]), Math.max(a[1], b[1])];
  selected = new Set();
  let i = 0;
  for (const bl of d.plan.blocks) {
    for (let k = 0; k < bl.points.length; k += 3, i++) {
      const x = bl.points[k] + d.at[0], y = bl.points[k + 1] + d.at[1];
      if (x >= x0 && x <= x1 && y >= y0 && y <= y1) selected.add(i);
    }
  }
  anchor = sorted()[0] ?? null;
  draw();
}

function fit() {
  let b: [number, number, number, number] | null = null;
  for (const d of designs) {
    const q = bounds(d.plan, d.at);
    if (q) b = b ? [Math.min(b[0], q[0]), Math.min(b[1], q[1]), Math.max(b[2], q[2]), Math.max(b[3], q[3])] : q;
  }
  if (b) view.fit(b, 20);
  draw();
}

let box: [Pt, Pt] | null = null;

/// Draws every design: each block's runs of stitches as one polyline in its thread, jumps
/// dashed grey, trims ×, stops □, colour changes ○; the active design's selection in white.
function draw() {
  const svg = $('se-view');
  svg.innerHTML = '';
  designs.forEach((d, di) => {
    const g = el('g', { opacity: di === active ? 1 : 0.45 }, svg);
    let prev: Pt | null = null;
    d.plan.blocks.forEach((b, bi) => {
      let run: string[] = [];
      const flush = () => { if (run.length > 1) el('polyline', { points: run.join(' '), fill: 'none', stroke: b.thread, 'stroke-width': 1 }, g); run = []; };
      for (let k = 0; k < b.points.length; k += 3) {
        const x = view.sx(b.points[k] + d.at[0]), y = view.sy(b.points[k + 1] + d.at[1]), kind = b.points[k + 2];
        if (k === 0 && bi > 0) el('circle', { cx: x, cy: y, r: 5, fill: 'none', stroke: b.thread, 'stroke-width': 2, class: 'se-colour' }, g);
        if (kind === STITCH) {
          if (!run.length && prev) run.push(`${prev[0]},${prev[1]}`);
          run.push(`${x},${y}`);
        } else {
          flush();
          if (kind === JUMP && prev) el('line', { x1: prev[0], y1: prev[1], x2: x, y2: y, stroke: '#333', 'stroke-dasharray': '4 3', 'stroke-width': 1 }, g);
          if (kind === TRIM) el('path', { d: `M${x - 4},${y - 4}L${x + 4},${y + 4}M${x - 4},${y + 4}L${x + 4},${y - 4}`, stroke: '#f55', 'stroke-width': 2, class: 'se-trim' }, g);
          if (kind === STOP) el('rect', { x: x - 4, y: y - 4, width: 8, height: 8, fill: 'none', stroke: '#fc3', 'stroke-width': 2, class: 'se-stop' }, g);
        }
        prev = [x, y];
      }
      flush();
    });
    const bb = bounds(d.plan, d.at);
    if (bb) el('text', { x: view.sx(bb[0]), y: view.sy(bb[3]) - 4, fill: di === active ? '#000' : '#333', 'font-size': 11 }, svg).textContent = `${di + 1}. ${d.plan.name}`;
  });
  const d = cur();
  if (d) {
    for (const i of selected) {
      const e = entry(d.plan, i);
      if (e) el('circle', { cx: view.sx(e[0] + d.at[0]), cy: view.sy(e[1] + d.at[1]), r: 3, fill: '#fff', class: 'se-selected' }, svg);
    }
  }
  if (box) {
    const [a, b] = box;
    el('rect', { x: Math.min(view.sx(a[0]), view.sx(b[0])), y: Math.min(view.sy(a[1]), view.sy(b[1])), width: Math.abs(view.sx(b[0]) - view.sx(a[0])), height: Math.abs(view.sy(b[1]) - view.sy(a[1])), fill: 'none', stroke: '#fff', 'stroke-dasharray': '3 3' }, svg);
  }
  info();
}

/// The active design's figures, the selection and its section's speed code.
function info() {
  const d = cur();
  const v = $('se-view');
  v.dataset.designs = String(designs.length);
  v.dataset.entries = d ? String(count(d.plan)) : '0';
  v.dataset.colours = d ? String(d.plan.blocks.length) : '0';
  v.dataset.selected = String(selected.size);
  $('se-designs').innerHTML = '';
  designs.forEach((x, i) => $<HTMLSelectElement>('se-designs').add(new Option(`${i + 1}. ${x.plan.name} at ${x.at[0]}, ${x.at[1]} mm`, String(i), false, i === active)));
  if (!d) { $('se-info').textContent = 'open an embroidery file'; return; }
  $<HTMLInputElement>('se-at-x').value = String(d.at[0]); $<HTMLInputElement>('se-at-y').value = String(d.at[1]);
  const s = sorted();
  let sel = '';
  if (s.length) {
    const e = entry(d.plan, s[0])!;
    const sec = d.sections.find(([a, b]) => s[0] >= a && s[0] < b);
    const kinds = ['stitch', 'jump', 'trim', 'stop'];
    sel = ` · selected ${s.length === 1 ? `entry ${s[0]} (${kinds[e[2]]} at ${e[0].toFixed(1)}, ${e[1].toFixed(1)} mm)` : `${s.length} entries from ${s[0]}`}`
      + (sec ? ` · its section ${sec[0]}–${sec[1] - 1} sews at speed code ${sec[2] ?? 'none (a stitch over 12.4 mm)'}` : '');
  }
  $('se-info').textContent = `${d.plan.name}: ${count(d.plan)} entries, ${d.plan.blocks.length} colours${sel}`;
}

export function initStitchEditor() {
  const codes = [12, 11, 10, 9, 8, 7, 6, 5, 4].map((c) => `<option>${c}</option>`).join('');
  const formats = ['pes', 'dst', 'jef', 'exp', 'vp3', 'xxx', 'u01', 'pec'].map((f) => `<option>${f}</option>`).join('');
  // Its rows flow like the design editor's (the page's .form is a two-column grid).
  $('stitch-editor').innerHTML = `
    <style>
      #stitch-editor .form { display: flex; flex-wrap: wrap; gap: 3px 6px; align-items: center; }
      #stitch-editor .form label { display: inline-flex; align-items: center; gap: 3px; }
      #stitch-editor .form button { padding: 2px 7px; }
    </style>
    <h3>Stitch editor <span class="muted">— embroidery files stitch by stitch; alter, link and save by the library</span></h3>
    <div class="form">
      <label class="btn">Open… <input id="se-open" type="file" accept=".pes,.dst,.jef,.exp,.vp3,.xxx,.u01,.pec,.ram,.bor" multiple hidden></label>
      <select id="se-designs" title="the design edited"></select>
      <label>place at <input id="se-at-x" type="number" step="any" style="width:5em">,<input id="se-at-y" type="number" step="any" style="width:5em"> mm</label>
      <button id="se-close">Close design</button> <button id="se-link" title="join the designs in order, each at its place (the seed's LINKA)">Link all</button>
      <button id="se-undo" title="Ctrl+Z">undo</button> <button id="se-redo" title="Ctrl+Y">redo</button> <button id="se-fit">fit</button>
    </div>
    <div class="form">
      <label>select entry <input id="se-entry" type="number" min="0" step="1" style="width:6em"></label>
      <label>move by <input id="se-dx" type="number" value="0" step="any" style="width:4em">,<input id="se-dy" type="number" value="0" step="any" style="width:4em"> mm</label><button id="se-move">Move</button>
      <button id="se-insert" title="a stitch halfway to the next">Insert stitch</button> <button id="se-delete">Delete</button>
      <button id="se-colour" title="a colour change before the selection">Insert colour stop</button> <button id="se-uncolour" title="the colour change that starts the selection's block">Delete colour stop</button>
      <label>speed code <select id="se-code">${codes}</select></label><button id="se-speed">Sew section at</button>
    </div>
    <div class="form">
      <label>rotate <input id="se-rotate" type="number" value="0" step="any" style="width:4em"> °</label>
      <label>scale <input id="se-scale" type="number" value="1" min="0.01" step="any" style="width:4em"></label>
      <label>mirror <select id="se-mirror"><option value="">none</option><option value="x">about x</option><option value="y">about y</option></select></label>
      <label>shift <input id="se-shift-x" type="number" value="0" step="any" style="width:4em">,<input id="se-shift-y" type="number" value="0" step="any" style="width:4em"> mm</label>
      <button id="se-alter">Alter design</button>
      <label>save as <input id="se-name" value="edited" size="10"></label><select id="se-format">${formats}</select><button id="se-save">Save</button><span id="se-saved"></span>
    </div>
    <svg id="se-view" viewBox="0 0 ${W} ${H}" width="${W}" height="${H}" style="background:#80858e;cursor:crosshair;width:100%"></svg>
    <div id="se-info" class="muted"></div>
    <span id="se-status" class="muted"></span>`;
  const svg = $('se-view');
  let down: { p: Pt; px: [number, number]; pan: boolean } | null = null;
  svg.addEventListener('mousedown', (e) => { down = { p: view.at(e, svg), px: [e.clientX, e.clientY], pan: e.button !== 0 }; e.preventDefault(); });
  svg.addEventListener('mousemove', (e) => {
    if (!down) return;
    if (down.pan) {
      const k = W / svg.getBoundingClientRect().width;
      view.pan((e.clientX - down.px[0]) * k, (e.clientY - down.px[1]) * k); down.px = [e.clientX, e.clientY]; draw();
    } else if (Math.hypot(e.clientX - down.px[0], e.clientY - down.px[1]) > 4) { box = [down.p, view.at(e, svg)]; draw(); }
  });
  window.addEventListener('mouseup', (e) => {
    if (!down) return;
    const d = down; down = null;
    if (d.pan) return;
    if (box) { const b = box; box = null; boxSelect(b[0], b[1]); return; }
    if (e.target !== svg && !svg.contains(e.target as Node)) return;
    const i = nearest(view.at(e, svg));
    if (i === null) { selected.clear(); draw(); } else select(i, e.shiftKey);
  });
  svg.addEventListener('contextmenu', (e) => e.preventDefault());
  svg.addEventListener('wheel', (e) => { e.preventDefault(); view.zoom(e.deltaY < 0 ? 1.2 : 1 / 1.2, view.at(e, svg)); draw(); }, { passive: false });
  $<HTMLInputElement>('se-open').onchange = async (e) => {
    const input = e.target as HTMLInputElement;
    for (const f of Array.from(input.files ?? [])) await openFile(f);
    input.value = '';
  };
  $<HTMLSelectElement>('se-designs').onchange = (e) => { active = Number((e.target as HTMLSelectElement).value); selected.clear(); draw(); };
  const place = () => { const d = cur(); if (d) commit(() => { d.at = [num('se-at-x'), num('se-at-y')]; }, `${d.plan.name} placed at ${num('se-at-x')}, ${num('se-at-y')} mm`); };
  $('se-at-x').onchange = place; $('se-at-y').onchange = place;
  $('se-close').onclick = () => { if (cur()) commit(() => { designs.splice(active, 1); active = Math.max(0, active - 1); selected.clear(); }, 'design closed'); };
  $('se-link').onclick = linkAll;
  $('se-undo').onclick = undo; $('se-redo').onclick = redo; $('se-fit').onclick = fit;
  $<HTMLInputElement>('se-entry').onchange = (e) => {
    const i = Number((e.target as HTMLInputElement).value), d = cur();
    if (!d || !Number.isInteger(i) || i < 0 || i >= count(d.plan)) return status(`entry ${i}: the design has entries 0 to ${d ? count(d.plan) - 1 : '—'}`, true);
    select(i, false);
  };
  const needSel = (f: (d: Placed, s: number[]) => void) => () => { const d = cur(), s = sorted(); if (!d || !s.length) return status('select stitches first', true); f(d, s); };
  $('se-move').onclick = needSel((d, s) => commit(() => moveEntries(d.plan, s, num('se-dx'), num('se-dy')), `${s.length} entries moved by ${num('se-dx')}, ${num('se-dy')} mm`));
  $('se-insert').onclick = needSel((d, s) => commit(() => { const i = insertAfter(d.plan, s[s.length - 1]); selected = new Set(i === null ? [] : [i]); }, `a stitch inserted after entry ${s[s.length - 1]}`));
  $('se-delete').onclick = needSel((d, s) => commit(() => { deleteEntries(d.plan, new Set(s)); selected.clear(); }, `${s.length} entries deleted`));
  $('se-colour').onclick = needSel((d, s) => {
    const probe = JSON.parse(JSON.stringify(d.plan)) as Plan;
    if (!addColourStop(probe, s[0])) return status(`entry ${s[0]} already starts a colour`, true);
    commit(() => { d.plan = probe; }, `a colour stop before entry ${s[0]}: ${d.plan.blocks.length} colours`);
  });
  $('se-uncolour').onclick = needSel((d, s) => {
    const probe = JSON.parse(JSON.stringify(d.plan)) as Plan;
    if (!removeColourStop(probe, s[0])) return status('the first colour has no colour stop before it', true);
    commit(() => { d.plan = probe; }, `the colour stop before entry ${blockStart(d.plan, 0)} removed`);
  });
  $('se-speed').onclick = speedOfSelection;
  $('se-alter').onclick = alterDesign;
  $('se-save').onclick = save;
  $('stitch-editor').addEventListener('keydown', (e) => {
    if ((e.target as HTMLElement).tagName === 'INPUT') return;
    if ((e.ctrlKey || e.metaKey) && e.key === 'z') { e.preventDefault(); undo(); }
    else if ((e.ctrlKey || e.metaKey) && e.key === 'y') { e.preventDefault(); redo(); }
    else if (e.key === 'Delete') $('se-delete').click();
  });
  draw();
}
