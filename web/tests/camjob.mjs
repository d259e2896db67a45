// Browser test of the CAM job page, as a new user: open a drawing through the visible file
// control, pick shapes by click, shift-click and box, add operations, Make, Save the job;
// then `oficina mill --job` on the saved TOML (and, for the NEMA 17 mount, on the
// hand-written tests/data/jobs/nema17-mount.toml) must give the page's program line for line
// (only the two comment lines naming the job file and the drawing's path differ). The shape
// ids the page shows must be the CLI import report's. Starts its own `oficina serve`.
// Prints `N passed, M failed`.

import { startServer, launch, suite, assert, out, root } from './harness.mjs';
import { execFileSync } from 'node:child_process';
import { copyFileSync, existsSync, mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';

const bin = path.resolve(process.env.OFICINA_BIN || path.join(root, 'target', 'debug', 'oficina'));
const jobs = path.join(root, 'tests', 'data', 'jobs');
const NEMA = '/work/shared/data/realworld/mill-dxf-svg/obcam_Motor NEMA17 - Mount.dxf';
const shots = path.join(root, 'docs', 'screenshots');

const server = await startServer();
const browser = await launch();
const { test, state, finish } = suite('cam job');

/// `oficina mill --job JOB -o x.nc` in JOB's folder: the program and the import report's
/// shape lines (`#3 Layer0 #000000 closed circle …`).
function cli(job) {
  const dir = path.dirname(job);
  const stdout = execFileSync(bin, ['mill', '--job', path.basename(job), '-o', 'x.nc'], { cwd: dir, encoding: 'utf8' });
  const shapes = stdout.split('\n').filter((l) => l.startsWith('shape:')).map((l) => l.replace(/^shape:\s+/, ''));
  return { program: readFileSync(path.join(dir, 'x.nc'), 'utf8'), shapes };
}

/// The program's lines but the two that name the job file and the drawing's path.
const body = (p) => p.split('\n').filter((l) => !/^\((job|drawing) = /.test(l));
function sameProgram(page, cliProgram, what) {
  const a = body(page), b = body(cliProgram);
  assert(a.length > 100, `a program: ${a.length} lines`);
  const k = a.findIndex((l, i) => l !== b[i]);
  assert(a.length === b.length && k < 0, `${what}: ${a.length} vs ${b.length} lines, first difference at ${k}: ${a[k]} | ${b[k]}`);
}

async function newPage() {
  const ctx = await browser.newContext({ viewport: { width: 1600, height: 1000 }, acceptDownloads: true });
  const page = await ctx.newPage();
  state.page = page;
  await page.goto(server.url);
  await page.waitForFunction(() => document.getElementById('summary').textContent.includes('errors'), null, { timeout: 30000 });
  await page.selectOption('#process', 'camjob');
  assert(await page.isVisible('#cj-drawing'), 'the drawing file control is visible');
  return page;
}

/// The shapes drawn: id → the import report's line (the path's tooltip).
const drawnShapes = (page) => page.$$eval('#cj-view .cj-shape', (els) => els.map((e) => [Number(e.dataset.id), e.querySelector('title').textContent]).sort((a, b) => a[0] - b[0]));
const selectedIds = (page) => page.$$eval('#cj-view .cj-shape.selected', (els) => els.map((e) => Number(e.dataset.id)).sort((a, b) => a - b));

async function clickShape(page, id, shift = false) {
  await page.locator('#cj-view').scrollIntoViewIfNeeded();
  const b = await page.locator(`#cj-view .cj-shape[data-id="${id}"]`).boundingBox();
  if (shift) await page.keyboard.down('Shift');
  await page.mouse.click(b.x + b.width / 2, b.y + b.height / 2);
  if (shift) await page.keyboard.up('Shift');
}

async function addOp(page, o) {
  await page.selectOption('#cj-kind', o.kind);
  await page.fill('#cj-name', o.name);
  await page.fill('#cj-tool', o.tool);
  for (const [k, v] of Object.entries(o.fields ?? {})) await page.fill(`#cj-${k}`, String(v));
  await page.click('#cj-add-op');
}

async function makeAndSave(page, dir) {
  await page.click('#cj-make');
  await page.waitForFunction(() => /operations, \d+ tool loads/.test(document.getElementById('cj-report').textContent) || document.getElementById('cj-status').classList.contains('error'), null, { timeout: 120000 });
  const report = await page.textContent('#cj-report');
  assert(!(await page.$eval('#cj-status', (e) => e.classList.contains('error'))), await page.textContent('#cj-status'));
  const program = await page.evaluate(() => window.__oficina.program());
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#cj-save')]);
  const saved = path.join(dir, download.suggestedFilename());
  await download.saveAs(saved);
  return { report, program, saved };
}

/// What the NEMA 17 test made: its page (the job still open) and program, for the stock test.
let nema = null;

await test('the NEMA 17 mount built by clicking shapes gives the CLI program', async () => {
  if (!existsSync(NEMA)) { console.log(`note: ${NEMA} is absent: the NEMA 17 test is skipped`); return; }
  const dir = mkdtempSync(path.join(os.tmpdir(), 'oficina-camjob-'));
  const page = await newPage();
  await page.locator('#cj-drawing').setInputFiles(NEMA);
  await page.waitForFunction(() => document.querySelectorAll('#cj-view .cj-shape').length === 5, null, { timeout: 30000 });
  await page.locator('#cj-library').setInputFiles(path.join(jobs, 'tools.toml'));
  await page.fill('#cj-material', 'aluminium');
  await page.fill('#cj-size', '50 50');
  await page.fill('#cj-corner', '-4 -4');
  await page.fill('#cj-thickness', '4');
  await page.fill('#cj-rect', '0 0 42 42');
  await page.fill('#cj-rect-r', '4');
  await page.click('#cj-add-rect');
  await page.waitForFunction(() => document.querySelectorAll('#cj-view .cj-shape').length === 6, null, { timeout: 30000 });

  // The ids and lines are the CLI import report's on the hand-written job.
  for (const f of ['nema17-mount.toml', 'tools.toml']) copyFileSync(path.join(jobs, f), path.join(dir, f));
  copyFileSync(NEMA, path.join(dir, path.basename(NEMA)));
  const hand = cli(path.join(dir, 'nema17-mount.toml'));
  const shown = await drawnShapes(page);
  assert(JSON.stringify(shown.map(([id, d]) => d)) === JSON.stringify(hand.shapes), `page ${JSON.stringify(shown)} vs CLI ${JSON.stringify(hand.shapes)}`);
  const small = shown.filter(([, d]) => /circle Ø3\.60/.test(d)).map(([id]) => id);
  const bore = shown.find(([, d]) => /circle Ø24\.00/.test(d))[0];
  const outline = shown.find(([, d]) => d.includes('OUTLINE'))[0];
  assert(small.length === 4, JSON.stringify(shown));

  // The four holes: a click, then shift-clicks; "circles under Ø 10" picks the same.
  await clickShape(page, small[0]);
  for (const id of small.slice(1)) await clickShape(page, id, true);
  assert(JSON.stringify(await selectedIds(page)) === JSON.stringify(small), `clicked ${await selectedIds(page)}`);
  await page.click('#cj-all');
  await page.click('#cj-circles');
  assert(JSON.stringify(await selectedIds(page)) === JSON.stringify(small), `circles under 10: ${await selectedIds(page)}`);
  await addOp(page, { kind: 'profile-in', name: 'M3 holes', tool: '1', fields: { depth: 4.2, stepdown: 1 } });
  // The chamfer on everything: a box around the whole drawing.
  await page.locator('#cj-view').scrollIntoViewIfNeeded();
  const v = await page.locator('#cj-view').boundingBox();
  await page.mouse.move(v.x + 3, v.y + 3);
  await page.mouse.down();
  await page.mouse.move(v.x + v.width / 2, v.y + v.height / 2, { steps: 4 });
  await page.mouse.move(v.x + v.width - 3, v.y + v.height - 3, { steps: 4 });
  await page.mouse.up();
  assert((await selectedIds(page)).length === 6, `box: ${await selectedIds(page)}`);
  await addOp(page, { kind: 'chamfer', name: 'chamfer', tool: '2', fields: { width: 0.5, tip: 0.2, stepdown: '' } });
  await clickShape(page, bore);
  await addOp(page, { kind: 'pocket', name: 'boss bore', tool: '1', fields: { depth: 4.2, stepdown: 1 } });
  // The plate: a click on its rim, away from the holes.
  const o = await page.locator(`#cj-view .cj-shape[data-id="${outline}"]`).boundingBox();
  await page.mouse.click(o.x + 1, o.y + o.height / 2);
  assert(JSON.stringify(await selectedIds(page)) === JSON.stringify([outline]), `outline: ${await selectedIds(page)}`);
  await addOp(page, { kind: 'profile-out', name: 'outline', tool: '1', fields: { depth: 4.2, stepdown: 1, tabs: 4, 'tab-width': 4, 'tab-height': 1 } });
  assert((await page.$$('#cj-ops tr')).length === 4, 'four operations listed');
  // Reorder: the bore up above the chamfer and back, then a spare op deleted.
  await page.click('#cj-ops tr:nth-child(3) .cj-move-up');
  assert((await page.textContent('#cj-ops tr:nth-child(2)')).includes('boss bore'), 'moved up');
  await page.click('#cj-ops tr:nth-child(2) .cj-move-down');
  assert((await page.textContent('#cj-ops tr:nth-child(3)')).includes('boss bore'), 'moved down');
  await addOp(page, { kind: 'engrave', name: 'spare', tool: 'flat:1', fields: { depth: 0.2 } });
  await page.click('#cj-ops tr:nth-child(5) .cj-delete');
  assert((await page.$$('#cj-ops tr')).length === 4, 'deleted');

  const { report, program, saved } = await makeAndSave(page, dir);
  assert(/4 operations, 2 tool loads \(1 tool changes\) · no gouge/.test(report), report);
  assert(/gouge:\s+none/.test(report), report);
  assert(program.name.endsWith('.ngc') && program.text.includes('T2 M6') && program.text.includes('T1 M6'), program.name);
  // The toolpath of an operation in its colour when its row is picked.
  await page.click('#cj-ops tr:nth-child(2)');
  assert((await page.$$('#cj-view .cj-toolpath.op-2')).length > 0, 'the chamfer toolpath drawn');
  await page.screenshot({ path: path.join(shots, 'workbench-camjob-nema17.png') });
  await page.locator('#cj-view').scrollIntoViewIfNeeded();
  await page.locator('#camjob').screenshot({ path: path.join(shots, 'workbench-camjob-nema17-view.png') });

  sameProgram(program.text, hand.program, 'the page vs the hand-written job');
  // The page uploaded the drawing under a plain name, which the saved job names.
  copyFileSync(NEMA, path.join(dir, 'obcam_Motor_NEMA17_-_Mount.dxf'));
  const mine = cli(saved);
  sameProgram(program.text, mine.program, 'the page vs its saved job');
  assert(JSON.stringify(mine.shapes) === JSON.stringify(hand.shapes), 'saved job: same shapes');
  nema = { page, program: program.text, dir };
});

/// `oficina simulate` on `program` cut before its (k+1)-th `(operation: …)` comment, each tool
/// with the shape the program's own operation comments name (`… with T2 v:6:90 …`).
function cliRemoved(program, k, dir, stockArgs) {
  const lines = program.split('\n');
  const starts = lines.flatMap((l, i) => (l.startsWith('(operation: ') ? [i] : []));
  const cut = lines.slice(0, k < starts.length ? starts[k] : lines.length).join('\n') + '\n';
  const file = path.join(dir, `upto-${k}.nc`);
  writeFileSync(file, cut);
  const tools = [...new Set([...program.matchAll(/^\(operation: .* with T(\d+) ([a-z]+:[0-9.:]+)/gm)].map((m) => `${m[1]}=${m[2]}`))];
  const json = execFileSync(bin, ['simulate', file, ...stockArgs, ...tools.flatMap((t) => ['--tool', t]), '--json', '-o', path.join(dir, `upto-${k}.png`)], { encoding: 'utf8' });
  return { report: JSON.parse(json), tools };
}

await test('the stock after each operation: removed volume grows and is oficina simulate\'s on the program cut there', async () => {
  if (!nema) { console.log('note: the NEMA 17 job was not made: the stock test is skipped'); return; }
  const { page, program, dir } = nema;
  state.page = page;
  assert(await page.isVisible('#cj-upto'), 'the stock slider is visible after Make');
  const n = Number(await page.getAttribute('#cj-upto', 'max'));
  assert(n === 4, `the slider runs over the 4 operations: max ${n}`);
  const stockAfter = async (k, how) => {
    await how();
    await page.waitForFunction((k) => document.body.dataset.cjStock === String(k) || document.body.dataset.cjStock === 'failed', k, { timeout: 120000 });
    const report = await page.textContent('#cj-stock-report');
    const shown = await page.evaluate(() => document.body.dataset.cjStock);
    assert(shown === String(k) && report.includes('removed'), `after ${k}: ${shown}: ${report}`);
    return { removed: Number(await page.getAttribute('#cj-stock-report', 'data-removed')), report };
  };
  let before = 0;
  for (let k = 1; k <= n; k++) {
    const got = await stockAfter(k, () => page.$eval('#cj-upto', (e, k) => { e.value = String(k); e.dispatchEvent(new Event('change')); }, k));
    assert(/no gouge/.test(got.report) && /gouge:\s+none/.test(got.report), `after ${k}: ${got.report}`);
    assert(got.removed > before + 1, `after ${k}: ${got.removed} mm³ removed, not more than ${before} after ${k - 1}`);
    const cell = Number(got.report.match(/cell ([\d.]+) mm/)[1]);
    const cli = cliRemoved(program, k, dir, ['--stock', '50x50x4', '--stock-origin=-4,-4,0', '--resolution', String(cell)]);
    assert(cli.tools.length === 2, `tools from the program's comments: ${cli.tools}`);
    assert(Math.abs(cli.report.removed_mm3 - got.removed) < 1e-6 * got.removed, `after ${k}: page ${got.removed} mm³, oficina simulate ${cli.report.removed_mm3} mm³`);
    console.log(`  after ${k}: ${got.removed.toFixed(1)} mm³ removed (oficina simulate: ${cli.report.removed_mm3.toFixed(1)})`);
    if (k === 2) {
      // The view, the slider and the report under it.
      await page.locator('#cj-view').scrollIntoViewIfNeeded();
      const [v, r] = [await page.locator('#cj-view').boundingBox(), await page.locator('#cj-stock-report').boundingBox()];
      await page.screenshot({ path: path.join(shots, 'workbench-camjob-stock-after-2.png'), clip: { x: v.x, y: v.y, width: Math.max(v.width, r.width), height: r.y + r.height - v.y } });
    }
    before = got.removed;
  }
  // A click on an operation's row shows the stock after it: the boss bore is third in the
  // cutting order (the chamfer's T2 first, then T1's holes, bore, outline).
  const bore = await stockAfter(3, () => page.click('#cj-ops tr:nth-child(3)'));
  assert(bore.report.includes('op 2, op 1, op 3 ') && Number(await page.inputValue('#cj-upto')) === 3, bore.report);
  assert(await page.$('#cj-stock-image'), 'the stock drawn under the shapes');
  // Two clicks in a row: the second waits for the first (the server computes one job at a
  // time) and is the one shown, the whole job's stock.
  await page.click('#cj-ops tr:nth-child(1)');
  const last = await stockAfter(4, () => page.click('#cj-ops tr:nth-child(4)'));
  assert(last.removed === before, `after two quick clicks: ${last.removed} mm³, the whole job's ${before}`);
});

await test('a self-contained SVG part: tools by spec, saved job gives the same program', async () => {
  const dir = mkdtempSync(path.join(os.tmpdir(), 'oficina-camjob-'));
  copyFileSync(path.join(jobs, 'nested-plate.svg'), path.join(dir, 'nested-plate.svg'));
  const page = await newPage();
  await page.locator('#cj-drawing').setInputFiles(path.join(jobs, 'nested-plate.svg'));
  await page.waitForFunction(() => document.querySelectorAll('#cj-view .cj-shape').length > 1, null, { timeout: 30000 });
  await page.fill('#cj-thickness', '5');
  await page.dispatchEvent('#cj-thickness', 'change');
  const shown = await drawnShapes(page);
  // The CLI's report on the same drawing (a job of one op on every shape).
  writeFileSync(path.join(dir, 'all.toml'), 'drawing = "nested-plate.svg"\n[stock]\nthickness = 5\n[[op]]\nkind = "engrave"\ntool = "flat:1"\ndepth = 0.1\n');
  assert(JSON.stringify(shown.map(([, d]) => d)) === JSON.stringify(cli(path.join(dir, 'all.toml')).shapes), JSON.stringify(shown));
  await page.fill('#cj-dia', '10');
  await page.click('#cj-circles');
  const holes = await selectedIds(page);
  assert(holes.length > 0, 'small circles');
  await addOp(page, { kind: 'profile-in', name: 'small holes', tool: 'flat:3', fields: { depth: 5.3, stepdown: 1.5, feed: 900, rpm: 18000 } });
  await page.click('#cj-all');
  await addOp(page, { kind: 'profile-out', name: 'cut-out', tool: 'flat:3', fields: { depth: 5.3, stepdown: 1.5, feed: 900, rpm: 18000, tabs: 3, 'tab-width': 4, 'tab-height': 1.2 } });
  const { report, program, saved } = await makeAndSave(page, dir);
  assert(/2 operations, 1 tool loads .* no gouge/.test(report), report);
  await page.locator('#cj-view').scrollIntoViewIfNeeded();
  await page.screenshot({ path: path.join(shots, 'workbench-camjob-svg.png') });
  sameProgram(program.text, cli(saved).program, 'the page vs its saved job');
  assert(program.text.includes('S18000 M3'), 'the spindle speed given');
});

await test('a bad job is a clear message in the page', async () => {
  const page = state.page;
  await addOp(page, { kind: 'pocket', name: 'bad', tool: 'wrench:3', fields: { depth: 1 } });
  await page.click('#cj-make');
  await page.waitForFunction(() => document.getElementById('cj-status').classList.contains('error'), null, { timeout: 60000 });
  const msg = await page.textContent('#cj-status');
  assert(/op 3 \(bad\)/.test(msg) && /wrench/.test(msg), msg);
});

await browser.close();
finish();
