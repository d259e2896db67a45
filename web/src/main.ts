// The workbench page: wires the editor, the preview and the machine panel to the server.
// Everything the page knows about G-code comes from the server's interpreter.

import { CheckReport, Live, LiveMessage, Snapshot, getJson, postJson, putFile, withToken } from './api';
import { Editor } from './editor';
import { Preview, View } from './preview';
import type { WorkerOut } from './worker';
import { MachinePanel } from './machine';
import { setupWorkshop } from './workshop';
import { setupSimulate } from './simulate';
import { setupProfileEditor, setupToolEditor } from './profile';
import { initCamJob, openDrawing } from './camjob';
import { Carved, carvedReport, clearCarved, hideModel, showModel } from './carve_model';
import { initDesignEditor } from './design/editor';
import { initStitchEditor, openPlan } from './stitches/editor';
import { PROCESSES, ProcessKind, STITCH_FILE, clearFieldErrors, readForm, renderForm, showFieldError } from './processes';

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;

/// Programs larger than this go to the job folder once and are checked there by name.
const INLINE_LIMIT = 4 * 1024 * 1024;
/// Typing pauses this long before the check and the preview run again, ms.
const EDIT_DEBOUNCE_MS = 350;

/// `from`: what the program was made from (a plot of a drawing, a relief of an image).
interface Program { name: string; text: string; saved: boolean; from?: string; }

const editor = new Editor();
const preview = new Preview($('viewport'));
const stats = { checks: 0, previews: 0, previewDone: 0, loadStartMs: 0, editorMs: 0, segments: 0, firstBatchMs: 0, previewMs: 0, lastCheck: null as CheckReport | null, checkedText: '' };
let program: Program = { name: 'untitled.nc', text: '', saved: false };
let worker: Worker | null = null;
let image: { name: string; bytes: ArrayBuffer } | null = null;
/// The design the mill, sole and plot processes read: its name in the job folder.
let design: { name: string; kind: ProcessKind } | null = null;
let uploadLimit = 64 * 1024 * 1024;
let editTimer = 0;
/// The preview holds an embroidery plan (not the editor's program).
let showingStitches = false;
/// The connected machine's name (the check reads the program for it).
let machineName = '';

function error(msg: string) {
  $('error').textContent = msg;
}

function safeName(name: string): string {
  const s = name.replace(/[^A-Za-z0-9._-]/g, '_').replace(/^\.+/, '').slice(0, 100);
  return s || 'program.nc';
}

function hms(s: number): string {
  if (!isFinite(s)) return '—';
  s = Math.max(0, Math.round(s));
  return `${Math.floor(s / 3600)}:${String(Math.floor(s / 60) % 60).padStart(2, '0')}:${String(s % 60).padStart(2, '0')}`;
}

async function ensureSaved(): Promise<void> {
  if (program.saved) return;
  await putFile(program.name, program.text);
  program.saved = true;
}

/// Where the check and the preview read the program: inline, or the saved file when big.
async function source(path: string): Promise<{ url: string; body: string | null }> {
  if (program.text.length > INLINE_LIMIT) {
    await ensureSaved();
    return { url: withToken(`${path}?file=${encodeURIComponent(program.name)}`), body: null };
  }
  return { url: withToken(path), body: program.text };
}

async function runCheck() {
  const gen = ++stats.checks;
  const text = program.text;
  try {
    const src = await source('/api/check');
    const r = await fetch(src.url, { method: 'POST', body: src.body });
    if (!r.ok) throw new Error(await r.text());
    const report: CheckReport = await r.json();
    if (gen !== stats.checks) return;
    stats.lastCheck = report;
    stats.checkedText = text;
    showCheck(report);
  } catch (e) {
    error(`check: ${(e as Error).message}`);
  }
}

/// The top bar while the preview shows stitches: the stitch file and its figures, not the
/// editor's program (which stays in the editor, untouched).
function showStitchBar(name: string, sheet: { stitches: number; threads: unknown[]; size: [number, number]; hoop?: string | null }) {
  $('program-name').textContent = name;
  const [w, h] = sheet.size;
  $('summary').textContent = `${sheet.stitches.toLocaleString()} stitches · ${sheet.threads.length} colour${sheet.threads.length === 1 ? '' : 's'} · ${w.toFixed(1)} × ${h.toFixed(1)} mm${sheet.hoop ? ' · hoop ' + sheet.hoop : ''}`;
  $('summary').dataset.extents = '';
}

/// The header above the preview: what it shows, and for which machine it was read.
function showTitle() {
  const r = stats.lastCheck;
  const reading = r ? ` · read as ${({ grbl: 'grbl', marlin: 'Marlin' } as Record<string, string>)[r.dialect ?? ''] ?? 'LinuxCNC'}${machineName ? ` · ${machineName}` : ''}` : '';
  const title = showingStitches ? `stitches of ${stitchFile}`
    : !program.text.trim() ? 'nothing loaded'
      : `${program.name}${program.from ? ` (${program.from})` : ''}${reading}`;
  $('preview-title').textContent = title;
  $('preview-title').title = title;
}

function showCheck(r: CheckReport) {
  editor.setDiagnostics(r.diagnostics);
  const list = $('diagnostics');
  list.innerHTML = '';
  for (const d of r.diagnostics.slice(0, 500)) {
    const li = document.createElement('li');
    li.className = d.severity;
    li.textContent = `${d.line}:${d.col} ${d.message}${d.help ? ' — ' + d.help : ''}`;
    li.onclick = () => editor.goTo(d.line, d.col);
    list.appendChild(li);
  }
  const e = r.feed_extents;
  const size = e ? `${(e.max[0] - e.min[0]).toFixed(1)} × ${(e.max[1] - e.min[1]).toFixed(1)} × ${(e.max[2] - e.min[2]).toFixed(1)} mm` : 'no cutting moves';
  const time = r.time.Ok ? hms(r.time.Ok.seconds) : `no estimate (${r.time.Err})`;
  const tools = r.tool_table.map(([n, t]) => t ? `T${n} Ø${t.diameter} L${t.length}` : `T${n} not in the tool table`).join(', ');
  panel.setProgramErrors(r.errors);
  const reading = r.dialect === 'grbl' || r.dialect === 'marlin' ? ` · read as ${r.dialect === 'grbl' ? 'grbl' : 'Marlin'} reads it` : '';
  // While stitches are shown the bar describes them (showStitchBar), not the program.
  if (showingStitches) return showTitle();
  $('summary').textContent = `${r.errors} errors · ${r.warnings} warnings${reading} · extents ${size} · feed ${r.feed_length.toFixed(0)} mm · time ${time}${tools ? ' · ' + tools : ''}`;
  $('summary').dataset.extents = e ? JSON.stringify(e) : '';
  // The view frames the extents the summary names: where the program cuts (its rapids
  // when it has no cut), never where the tool stood before it.
  preview.frameOn(e ?? r.rapid_extents);
  showTitle();
}

function runPreview() {
  worker?.terminate();
  preview.clear();
  // About one segment per 25 bytes of G-code: enough to choose the level of detail early.
  preview.expect(program.text.length / 25);
  const gen = ++stats.previews;
  const t0 = performance.now();
  let first = true;
  const w = new Worker(new URL('./worker.ts', import.meta.url), { type: 'module' });
  worker = w;
  w.onmessage = (e: MessageEvent<WorkerOut>) => {
    if (gen !== stats.previews) return;
    const m = e.data;
    if (m.type === 'batch') {
      preview.add(m);
      if (first) { stats.firstBatchMs = performance.now() - t0; first = false; }
      $('preview-info').textContent = `${preview.total.toLocaleString()} segments…`;
    } else if (m.type === 'done') {
      preview.finished();
      stats.segments = m.segments;
      stats.previewDone = gen;
      stats.previewMs = performance.now() - t0;
      const scrub = $<HTMLInputElement>('scrub');
      scrub.max = String(preview.total);
      scrub.value = String(preview.total);
      $('preview-info').textContent = `${m.segments.toLocaleString()} segments in ${(stats.previewMs / 1000).toFixed(2)} s`;
      $('viewport').dataset.segments = String(m.segments);
      w.terminate();
    } else {
      error(`preview: ${m.message}`);
    }
  };
  source('/api/preview').then((src) => w.postMessage(src)).catch((e) => error(`preview: ${e.message}`));
}

function loadProgram(name: string, text: string, saved = false, plot = false, from?: string) {
  // Another program than a plot: the machine a plot borrowed goes back.
  if (!plot) panel.restoreMachine();
  stats.loadStartMs = performance.now();
  showingStitches = false;
  program = { name: safeName(name), text, saved, from };
  stats.lastCheck = null;
  preview.frameOn(null);
  editor.value = text;
  stats.editorMs = performance.now() - stats.loadStartMs;
  editor.setCurrentLine(0);
  $('program-name').textContent = program.name;
  $('scrub-info').textContent = '';
  showTitle();
  error('');
  runCheck();
  runPreview();
}

editor.onChange = (text) => {
  program.text = text;
  program.saved = false;
  clearTimeout(editTimer);
  editTimer = window.setTimeout(() => { runCheck(); runPreview(); }, EDIT_DEBOUNCE_MS);
};

// Opening files: picker, drag and drop, samples.
const IMAGE = /\.(png|jpe?g|tiff?)$/i;
/// The process a design file goes to: the one chosen when it takes the file, else the first.
function processFor(name: string): ProcessKind | null {
  const current = $<HTMLSelectElement>('process').value as ProcessKind;
  if (PROCESSES[current]?.accept.test(name)) return current;
  for (const k of Object.keys(PROCESSES) as ProcessKind[]) if (PROCESSES[k].accept.test(name)) return k;
  return null;
}

/// Uploads a design into the job folder (refused here first when over the server's limit).
async function openDesign(name: string, body: Blob | string, kind: ProcessKind) {
  const size = typeof body === 'string' ? body.length : body.size;
  if (size > uploadLimit) return error(`${name}: ${size} bytes is over the upload limit of ${uploadLimit}`);
  const saved = safeName(name);
  try {
    await putFile(saved, body);
  } catch (e) {
    return error(`upload ${name}: ${(e as Error).message}`);
  }
  design = { name: saved, kind };
  error('');
  setProcess(kind);
  // A stitch file is shown as it is: read back, its sheet, its threads.
  if (kind === 'embroider' && STITCH_FILE.test(saved)) await make();
}

/// A picture goes to the relief form unless Plot (which hatches pictures) is chosen.
const toRelief = (name: string) => IMAGE.test(name) && $<HTMLSelectElement>('process').value !== 'plot';

async function openFile(f: File) {
  const kind = processFor(f.name);
  if (toRelief(f.name)) {
    image = { name: safeName(f.name), bytes: await f.arrayBuffer() };
    setProcess('relief');
  } else if (kind) {
    await openDesign(f.name, f, kind);
  } else {
    setProcess('gcode');
    loadProgram(f.name, await f.text());
  }
}
$<HTMLInputElement>('file-input').onchange = (e) => {
  const f = (e.target as HTMLInputElement).files?.[0];
  if (f) openFile(f);
};
let dragDepth = 0;
window.addEventListener('dragenter', (e) => { e.preventDefault(); dragDepth++; $('drop').hidden = false; });
window.addEventListener('dragleave', () => { if (--dragDepth <= 0) { dragDepth = 0; $('drop').hidden = true; } });
window.addEventListener('dragover', (e) => e.preventDefault());
window.addEventListener('drop', (e) => {
  e.preventDefault();
  dragDepth = 0;
  $('drop').hidden = true;
  const f = e.dataTransfer?.files[0];
  if (f) openFile(f);
});

async function openSample(name: string) {
  const r = await fetch(withToken('/api/samples/' + encodeURIComponent(name)));
  if (!r.ok) return error(await r.text());
  const kind = processFor(name);
  if (toRelief(name)) {
    image = { name, bytes: await r.arrayBuffer() };
    setProcess('relief');
  } else if (kind) {
    await openDesign(name, IMAGE.test(name) ? await r.blob() : await r.text(), kind);
  } else {
    setProcess('gcode');
    loadProgram(name, await r.text());
  }
}
$<HTMLSelectElement>('sample').onchange = (e) => {
  const v = (e.target as HTMLSelectElement).value;
  if (v) openSample(v);
};

// Processes: a G-code program as it is, a relief carved from an image, or a design milled,
// made into sole molds or plotted.
type Process = 'gcode' | 'relief' | 'camjob' | 'design' | 'stitches' | ProcessKind;
let shownForm: ProcessKind | null = null;
function setProcess(p: Process) {
  $<HTMLSelectElement>('process').value = p;
  $('relief-form').hidden = p !== 'relief';
  $('camjob').hidden = p !== 'camjob';
  $('design').hidden = p !== 'design';
  $('stitch-editor').hidden = p !== 'stitches';
  $('relief-image').textContent = image ? image.name : 'an image (open one)';
  const isDesign = p === 'mill' || p === 'sole' || p === 'plot' || p === 'embroider' || p === 'model';
  $('process-form').hidden = !isDesign;
  if (isDesign && shownForm !== p) {
    renderForm(p);
    shownForm = p;
    $('process-report').textContent = '';
    $('process-status').textContent = '';
    $('embroidery').hidden = true;
  }
  $('make').textContent = p === 'embroider' ? 'Make the stitches' : 'Make the program';
  const hasDesign = !!design && design.kind === p;
  if (isDesign) $('process-input').textContent = hasDesign ? design!.name : p === 'embroider' ? 'its Text alone (or open a file)' : 'a file (open one)';
  // A model is drawn in the 3D view while its process is shown.
  if (p === 'model' && hasDesign) drawModel(); else hideModel(preview);
  // Embroidery letters the Text field by itself once the design is put aside.
  $('text-alone').hidden = p !== 'embroider' || !hasDesign;
  // Plots: rapid moves are the pen up, feeds the pen down; embroidery: jumps and stitches.
  $('legend-rapid').textContent = p === 'plot' ? 'pen up' : p === 'embroider' ? 'jump (grey)' : 'rapid';
  $('legend-feed').textContent = p === 'plot' ? 'pen down' : p === 'embroider' ? 'stitch (thread colour)' : 'feed';
}
/// The model of the model process drawn as its placement fields place it.
function drawModel() {
  if (!design || design.kind !== 'model') return;
  const form = readForm('model');
  const place = 'field' in form ? {} : form.params;
  showModel(preview, design.name, place)
    .then((what) => { if (what) $('process-status').textContent = what; })
    .catch((e) => showFieldError(null, `model: ${(e as Error).message}`));
}
$('process-fields').addEventListener('change', (e) => {
  const name = (e.target as HTMLInputElement).name;
  if ($<HTMLSelectElement>('process').value === 'model' && ['scale', 'rotate', 'size'].includes(name)) drawModel();
});
$('text-alone').onclick = () => {
  design = null;
  setProcess('embroider');
  document.querySelector<HTMLInputElement>('#process-fields input[name="text"]')?.focus();
};
$<HTMLSelectElement>('process').onchange = (e) => {
  const p = (e.target as HTMLSelectElement).value as Process;
  if (p === 'relief' && !image) openSample('dome.png');
  else if ((p === 'mill' || p === 'sole' || p === 'plot' || p === 'embroider') && (!design || design.kind !== p)) openSample(PROCESSES[p].sample).then(() => setProcess(p));
  else setProcess(p);
};

/// Runs the chosen process on the design: the server's pipeline, its errors beside their
/// fields, its program loaded into the editor, the preview and the machine.
async function make() {
  const kind = $<HTMLSelectElement>('process').value as ProcessKind;
  clearFieldErrors();
  const form = readForm(kind);
  if (!design || design.kind !== kind) {
    // Embroidery without a design: its Text lettered alone, as `oficina embroider --text`.
    if (kind === 'embroider' && !('field' in form) && String(form.params.text ?? '').trim()) return embroider(null, form.params);
    return showFieldError(null, kind === 'embroider' ? 'type a Text to letter, or open a file' : `open a file for ${PROCESSES[kind].title} first`);
  }
  if ('field' in form) return showFieldError(form.field, form.message);
  if (kind === 'embroider') return embroider(design.name, form.params);
  // The plotter is the job's machine profile, not one of its parameters.
  const { machine: profile, ...params } = form.params as Record<string, unknown> & { machine?: string };
  busy(true);
  $('process-status').textContent = 'working…';
  clearCarved();
  try {
    const r = await fetch(withToken('/api/' + kind), {
      method: 'POST', headers: { 'content-type': 'application/json' },
      body: JSON.stringify({ file: design.name, params, profile }),
    });
    const text = await r.text();
    let body: { error?: string; field?: string | null; cancelled?: boolean; name?: string; text?: string; [k: string]: unknown };
    try { body = JSON.parse(text); } catch { body = { error: text || `${r.status} ${r.statusText}` }; }
    if (!r.ok) {
      $('process-status').textContent = body.cancelled ? 'cancelled' : '';
      if (!body.cancelled) showFieldError(body.field ?? null, body.error ?? text);
      return;
    }
    const lines: string[] = [];
    // What was imported (loops closed in the file, closed where their ends meet, chained;
    // what stayed open per layer with its largest gap; layers, units) before the program.
    if (kind === 'mill') lines.push(...((body.imported ?? []) as string[]), ...(body.report as string[]), ...(body.warning ? [String(body.warning)] : []));
    if (kind === 'sole') {
      lines.push(...(body.summary as string[]));
      for (const p of body.programs as { name: string; report: string[] }[]) lines.push(p.name, ...p.report.map((l) => '  ' + l));
    }
    if (kind === 'plot') {
      for (const p of body.pens as { name: string; strokes: number }[]) lines.push(`pen ${p.name}: ${p.strokes} strokes`);
      // Where the drawing lands (after the form's layout): what the page and margin did.
      const [x0, y0, x1, y1] = body.bounds as number[];
      lines.push(`drawing: ${(x1 - x0).toFixed(1)} × ${(y1 - y0).toFixed(1)} mm at (${x0.toFixed(1)}, ${y0.toFixed(1)})`);
      const l = body.lengths as { pen_down: number; pen_up: number } | undefined;
      if (l) lines.push(`pen-down ${l.pen_down.toFixed(1)} mm, pen-up ${l.pen_up.toFixed(1)} mm`);
      lines.push(`planned time: ${hms(body.seconds as number)}`, ...(body.notes as string[]));
    }
    if (kind === 'model') lines.push(...carvedReport(body as unknown as Carved));
    $('process-report').textContent = lines.join('\n');
    $('process-status').textContent = `${body.name}: ${body.text!.split('\n').length} lines`;
    const made = { plot: 'a plot', mill: 'milled', sole: 'a sole mold', model: 'a carving' }[kind as string] ?? kind;
    loadProgram(body.name!, body.text!, true, kind === 'plot', `${made} of ${design.name}`);
    // A plot runs on the virtual plotter it was made for (pen heights, travel, kinematics).
    // A Marlin program is for a Marlin board (connected in the machine panel): the virtual
    // machine does not read M280.
    if (kind === 'plot' && typeof body.machine === 'string' && params.format !== 'marlin') panel.useVirtual(body.machine);
  } catch (e) {
    $('process-status').textContent = '';
    error(`${kind}: ${(e as Error).message}`);
  } finally {
    busy(false);
  }
}
$('make').onclick = make;

/// A job's answer: the body, or the error shown beside its field (null).
async function job(path: string, body: unknown): Promise<Record<string, any> | null> {
  const r = await fetch(withToken(path), {
    method: 'POST', headers: { 'content-type': 'application/json' }, body: JSON.stringify(body),
  });
  const text = await r.text();
  let v: Record<string, any>;
  try { v = JSON.parse(text); } catch { v = { error: text || `${r.status} ${r.statusText}` }; }
  if (r.ok) return v;
  $('process-status').textContent = v.cancelled ? 'cancelled' : '';
  if (!v.cancelled) showFieldError(v.field ?? null, v.error ?? text);
  return null;
}

/// Embroidery: a design sewn into a stitch file by the server's pipeline, or a stitch file
/// read back; either way the plan is drawn in its threads beside its production sheet.
let stitchFile = '';
/// The plan last made or read, for the stitch editor's "Edit the stitches".
let lastPlan: { name: string; plan: Parameters<typeof openPlan>[1] } | null = null;
async function embroider(name: string | null, params: Record<string, unknown>) {
  const route = name && STITCH_FILE.test(name) ? '/api/stitches' : '/api/embroider';
  busy(true);
  $('process-status').textContent = 'working…';
  try {
    const body = await job(route, name ? { file: name, params } : { params });
    if (!body) return;
    const sheet = body.sheet;
    const sewn = preview.stitches(body.plan.blocks);
    showingStitches = true;
    stitchFile = body.name;
    lastPlan = { name: body.name, plan: body.plan };
    showTitle();
    showStitchBar(body.name, sheet);
    preview.setView('xy');
    document.querySelectorAll('#views button').forEach((x) => x.classList.toggle('active', (x as HTMLElement).dataset.view === 'xy'));
    const scrub = $<HTMLInputElement>('scrub');
    scrub.max = String(preview.total);
    scrub.value = String(preview.total);
    $('viewport').dataset.stitches = String(sewn);
    $('viewport').dataset.segments = String(preview.total);
    $('preview-info').textContent = `${sewn.toLocaleString()} stitches, ${(preview.total - sewn).toLocaleString()} jumps drawn`;
    const link = $<HTMLAnchorElement>('stitch-download');
    link.href = withToken('/api/files/' + encodeURIComponent(body.name));
    link.download = body.name;
    link.textContent = `Download ${body.name}`;
    const threads = $('threads');
    threads.innerHTML = '';
    for (const t of sheet.threads as { hex: string; name?: string; stitches: number; length_m: number }[]) {
      const li = document.createElement('li');
      li.innerHTML = `<i class="swatch" style="background:${t.hex}"></i> ${t.hex}${t.name ? ' ' + t.name.replace(/[<>&"]/g, '') : ''} · ${t.stitches} stitches · ${t.length_m.toFixed(2)} m`;
      threads.appendChild(li);
    }
    // The design drawn as thread, and the printable sheet with it (files of the job folder).
    const img = $<HTMLImageElement>('stitch-render');
    img.hidden = !body.render;
    if (body.render) img.src = withToken('/api/files/' + encodeURIComponent(body.render) + `?t=${Date.now()}`);
    const page = $<HTMLAnchorElement>('stitch-sheet');
    page.hidden = !body.sheet_page;
    if (body.sheet_page) {
      page.href = withToken('/api/files/' + encodeURIComponent(body.sheet_page));
      page.download = body.sheet_page;
    }
    $('embroidery').hidden = false;
    $('sew-status').textContent = '';
    delete $('sew-status').dataset.state;
    const lines = [...(body.notes ?? []) as string[]];
    if (body.shapes) lines.push(`shapes: ${body.shapes.fill} fill, ${body.shapes.satin} satin, ${body.shapes.running} running`);
    $('process-report').textContent = [...lines, sheet.text].join('\n');
    $('process-status').dataset.stitches = String(sheet.stitches);
    $('process-status').textContent = `${body.name}: ${sheet.stitches} stitches · ${sheet.threads.length} colours · ${sheet.thread_m.toFixed(2)} m of thread · hoop ${sheet.hoop ?? 'none'} · sewing ${hms(sheet.run.sewing_seconds)}, total ${hms(sheet.run.total_seconds)}`;
  } catch (e) {
    $('process-status').textContent = '';
    error(`embroider: ${(e as Error).message}`);
  } finally {
    busy(false);
  }
}

/// The stitch file made, sewn on the needle-synchronised table the form names: the
/// application's table run (needle as master, each hoop move inside its needle-up window).
/// It is not a G-code job, so it runs in the server's embroidery pipeline, not on the
/// machine panel's virtual machine; the timeline then plays the run to its end.
async function sew() {
  if (!stitchFile) return;
  const form = readForm('embroider');
  if ('field' in form) return showFieldError(form.field, form.message);
  const { machine, ppm, pieces, hoop } = form.params;
  const status = $('sew-status');
  status.dataset.state = 'running';
  status.textContent = `sewing on ${machine}…`;
  $<HTMLButtonElement>('sew').disabled = true;
  progressTo = 'sew-status';
  busy(true);
  try {
    const body = await job('/api/stitches', { file: stitchFile, params: { machine, ppm, pieces, hoop } });
    if (!body) { status.dataset.state = 'failed'; status.textContent = ''; return; }
    const run = body.sheet.run;
    await play(run.total_seconds);
    if (run.finished) {
      status.dataset.state = 'finished';
      status.textContent = `finished on ${body.sheet.table}: ${body.sheet.stitches} stitches, sewing ${hms(run.sewing_seconds)}, jumps ${hms(run.jump_seconds)}, trims and changes ${hms(run.pause_seconds)}, total ${hms(run.total_seconds)}`;
    } else {
      status.dataset.state = 'stopped';
      const f = run.first_faults[0];
      status.textContent = `stopped on ${body.sheet.table}: ${run.faults} stitch(es) too long for the needle-up window` +
        (f ? ` (first: stitch ${f.stitch}, ${f.length.toFixed(2)} mm at ${f.ppm} ppm needs ${f.move_ms.toFixed(1)} ms, the needle is up ${f.window_ms.toFixed(1)} ms)` : '') +
        (run.out_of_travel ? `, ${run.out_of_travel} point(s) beyond the travel` : '');
    }
  } catch (e) {
    status.dataset.state = 'failed';
    error(`sew: ${(e as Error).message}`);
  } finally {
    $<HTMLButtonElement>('sew').disabled = false;
    progressTo = 'process-status';
    busy(false);
  }
}
$('sew').onclick = sew;

/// The timeline drawn from the first stitch to the last, the needle marker following (about
/// two seconds whatever the run's length: a replay, the times are the run's report's).
function play(seconds: number): Promise<void> {
  const total = preview.total, scrub = $<HTMLInputElement>('scrub');
  const t0 = performance.now(), span = 2000;
  return new Promise((done) => {
    const step = () => {
      const f = Math.min(1, (performance.now() - t0) / span);
      const s = Math.round(total * f);
      const entry = preview.scrubTo(s);
      scrub.value = String(s);
      $('scrub-info').textContent = `stitch entry ${entry} · ${hms(seconds * f)} of ${hms(seconds)}`;
      if (f < 1) requestAnimationFrame(step); else done();
    };
    requestAnimationFrame(step);
  });
}

/// While a job is computed: its buttons off, Cancel on.
let computing = false;
/// Where a job's progress is written: under the form, or beside Sew while it sews.
let progressTo = 'process-status';
function busy(on: boolean) {
  computing = on;
  $<HTMLButtonElement>('make').disabled = on;
  $<HTMLButtonElement>('carve').disabled = on;
  // Cancel appears with the job's first progress message: the server is then working on it.
  if (!on) document.querySelectorAll<HTMLButtonElement>('.cancel-job').forEach((b) => { b.hidden = true; });
  $('job-progress').hidden = !on;
}
document.querySelectorAll<HTMLButtonElement>('.cancel-job').forEach((b) => {
  b.onclick = () => postJson('/api/cancel', '').catch((e) => error(`cancel: ${e.message}`));
});

async function carve() {
  if (!image) return error('open an image first');
  const form = $('relief-form');
  const params = new URLSearchParams({ name: image.name });
  for (const input of Array.from(form.querySelectorAll('input'))) {
    if (!input.checkValidity()) {
      input.focus();
      return error(`${input.name}: ${input.validationMessage}`);
    }
    if (input.value !== '') params.set(input.name, input.value);
  }
  busy(true);
  $('carve-status').textContent = 'carving…';
  try {
    const r = await fetch(withToken('/api/carve?' + params), { method: 'POST', body: image.bytes });
    const body = await r.json().catch(() => ({ error: `${r.status} ${r.statusText}` }));
    if (!r.ok) {
      $('carve-status').textContent = body.cancelled ? 'cancelled' : '';
      if (!body.cancelled) error(`carve: ${body.error}`);
      return;
    }
    $('carve-status').textContent = `${body.name}: ${body.text.split('\n').length} lines`;
    loadProgram(body.name, body.text, true, false, `a relief of ${image.name}`);
  } catch (e) {
    $('carve-status').textContent = '';
    error(`carve: ${(e as Error).message}`);
  } finally {
    busy(false);
  }
}
$('carve').onclick = carve;
setupSimulate(source);

// Views and the timeline.
for (const b of Array.from(document.querySelectorAll<HTMLButtonElement>('#views button'))) {
  b.onclick = () => {
    preview.setView(b.dataset.view as View);
    document.querySelectorAll('#views button').forEach((x) => x.classList.toggle('active', x === b));
  };
}
$<HTMLInputElement>('scrub').oninput = (e) => {
  const s = Number((e.target as HTMLInputElement).value);
  const line = preview.scrubTo(s);
  // A stitch plan's segments are numbered by plan entry, not by the editor's lines.
  if (showingStitches) return void ($('scrub-info').textContent = `stitch entry ${line}`);
  editor.setCurrentLine(line);
  $('scrub-info').textContent = `segment ${s.toLocaleString()} · line ${line}`;
};

// The machine.
const panel = new MachinePanel({
  send: (cmd) => live.send(cmd),
  prepareStart: async () => { await ensureSaved(); return program.name; },
  error,
  onStatus: (s: Snapshot) => followJob(s),
});
// Probing, tool changes and levelling (after the panel: they listen to Start before it).
const workshop = setupWorkshop({ send: (cmd) => live.send(cmd), prepareStart: async () => { await ensureSaved(); return program.name; }, error });

/// While the loaded program runs, the editor and the preview follow the machine.
let shownEnd = '';
let checkedFor = '';
function followJob(s: Snapshot) {
  if (s.machine !== machineName) { machineName = s.machine; showTitle(); }
  // Another machine reads the program another way (grbl's dialect on firmware): check again.
  if (s.uri !== checkedFor) {
    const first = checkedFor === '';
    checkedFor = s.uri;
    if (!first && program.text) runCheck();
  }
  // A finished job shows its whole path again (once: the user may scrub after).
  const ended = s.job && s.job.completed === true && s.job.name === program.name;
  if (ended && shownEnd !== program.name) {
    shownEnd = program.name;
    preview.scrubTo(preview.total);
    $<HTMLInputElement>('scrub').value = String(preview.total);
  }
  if (s.job && s.job.completed === null) shownEnd = '';
  const running = s.job && s.job.completed === null && s.job.name === program.name && !showingStitches;
  if (!running || s.line <= 0) return;
  editor.setCurrentLine(s.line);
  const seg = preview.segmentOfLine(s.line);
  preview.scrubTo(seg);
  preview.placeMarker(s.machine_pos[0], s.machine_pos[1], s.machine_pos[2]);
  $<HTMLInputElement>('scrub').value = String(seg);
  $('scrub-info').textContent = `line ${s.line}`;
}

/// A page that opens (or reloads) while a job runs shows that job, where it is.
let joined = false;
async function onLive(m: LiveMessage) {
  panel.handle(m);
  workshop.handle(m);
  // A new tool-change policy on the board: the check's M6 notes name the one in force.
  if (m.type === 'ok' && m.cmd === 'tool_change' && program.text) runCheck();
  if (m.type === 'progress') {
    if (computing) document.querySelectorAll<HTMLButtonElement>('.cancel-job').forEach((b) => { b.hidden = false; });
    $<HTMLProgressElement>('job-progress').value = m.fraction;
    // Only while a job is computed: a late message never overwrites its answer.
    if (computing && !$('process-form').hidden) $(progressTo).textContent = `${m.stage} ${(m.fraction * 100).toFixed(0)} %`;
  }
  if (m.type === 'status' && m.status && !joined) {
    joined = true;
    const job = m.status.job;
    if (job && job.completed === null) {
      const j = await getJson<{ name: string; text: string }>('/api/job');
      loadProgram(j.name, j.text, true);
    } else {
      const o = await getJson<{ name: string; text: string; saved: boolean }>('/api/open');
      loadProgram(o.name, o.text, o.saved);
    }
  }
}
const live = new Live(onLive, () => panel.connected());

async function init() {
  const info = await getJson<{ machine: string; profiles: string[]; samples: string[]; images: string[]; designs: string[]; upload_limit: number }>('/api/info');
  uploadLimit = info.upload_limit;
  const sample = $<HTMLSelectElement>('sample');
  sample.innerHTML = '<option value="">Samples…</option>' + [...info.samples, ...info.images, ...info.designs].map((n) => `<option>${n}</option>`).join('');
  panel.setMachines(info.machine, info.profiles);
  setupProfileEditor(info.profiles);
  setupToolEditor(() => { if (program.text) runCheck(); });
}
initCamJob({ loadProgram });
// Send to CAM: the saved design opened in the CAM job page.
initStitchEditor();
$('edit-stitches').onclick = () => { if (lastPlan) { setProcess('stitches'); openPlan(lastPlan.name, lastPlan.plan); } };
initDesignEditor({ openInCam: (file) => { setProcess('camjob'); openDrawing(file); } });
init().catch((e) => error(String(e.message || e)));

// For the browser tests and the benchmark: the page's state, read-only.
(window as unknown as { __oficina: unknown }).__oficina = { preview, editor, stats, program: () => program };
