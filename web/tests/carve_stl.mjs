// Browser test of a 3D model carved in the workbench, as a user does it: real STL files
// (OpenCAMLib's test models, realworld/stl) opened through the page's Open… control, drawn in
// the 3D view, carved through the visible form, and run on the virtual machine. The page's
// program must be `oficina carve MODEL …`'s with the same settings line for line (only the
// header lines naming the command and the model's path differ), its gouge and times the
// CLI's, and the mesh it draws trimesh's (triangles and box). Without the shared data it
// prints SKIPPED and passes. Starts its own `oficina serve`. Prints `N passed, M failed`.

import { startServer, launch, suite, assert, root, realworld } from './harness.mjs';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';

const dir = realworld('stl', 'ocl_cone_on_side.stl');
if (!dir) {
  console.log('SKIPPED carve_stl: realworld/stl/ocl_cone_on_side.stl is absent');
  console.log('0 passed, 0 failed');
  process.exit(0);
}

const bin = path.resolve(process.env.OFICINA_BIN || path.join(root, 'target', 'debug', 'oficina'));
const shots = path.join(root, 'docs', 'screenshots');
const { test, state, finish } = suite('carve_stl');
const server = await startServer();
const browser = await launch();
const page = await browser.newPage({ viewport: { width: 1600, height: 1000 } });
state.page = page;
const scratch = mkdtempSync(path.join(os.tmpdir(), 'oficina-carve-stl-'));

/// trimesh's reading of the file (no merging or cleaning): triangles and box.
function trimesh(file) {
  const py = 'import sys, json, trimesh\nm = trimesh.load(sys.argv[1], process=False)\nprint(json.dumps([len(m.faces), m.bounds.tolist()]))';
  return JSON.parse(execFileSync('python3', ['-c', py, file], { encoding: 'utf8' }));
}

/// `oficina carve FILE ARGS -o OUT.nc`: the program and what it printed.
function cli(file, args) {
  const out = path.join(scratch, path.basename(file).replace(/\.[^.]*$/, '.nc'));
  const stdout = execFileSync(bin, ['carve', file, ...args, '-o', out], { encoding: 'utf8' });
  return { program: readFileSync(out, 'utf8'), stdout };
}

/// The program's lines but the header's command and model path.
const body = (p) => p.split('\n').filter((l) => !/^\((command|model) = /.test(l));

async function fillForm(values) {
  for (const [name, v] of Object.entries(values)) {
    const sel = `#process-fields [name="${name}"]`;
    if (typeof v === 'boolean') await (v ? page.check(sel) : page.uncheck(sel));
    else if (await page.$eval(sel, (e) => e.tagName === 'SELECT')) await page.selectOption(sel, v);
    else await page.fill(sel, String(v));
  }
}

/// Opens `file` through Open…; checks the drawn mesh against trimesh's.
async function open(file) {
  await page.setInputFiles('#file-input', file);
  const [faces, bounds] = trimesh(file);
  await page.waitForFunction((n) => document.getElementById('viewport').dataset.model === String(n), faces, { timeout: 60000 });
  assert((await page.inputValue('#process')) === 'model', 'the model process is chosen');
  const what = await page.textContent('#process-status');
  assert(what.includes(`${faces.toLocaleString('en-US')} triangles`), `${what} vs trimesh's ${faces} triangles`);
  return { faces, bounds, what };
}

/// Carve: the form's values in, Make, the page's program and report out.
async function carve(values) {
  await fillForm(values);
  await page.click('#make');
  await page.waitForFunction(() => /\d+ lines$/.test(document.getElementById('process-status').textContent) || document.querySelector('#process-fields .field-error:not(:empty)') || document.getElementById('error').textContent, null, { timeout: 300000 });
  const status = await page.textContent('#process-status');
  assert(/ lines$/.test(status), `not carved: ${status} ${await page.textContent('#error')} ${await page.$$eval('#process-fields .field-error', (e) => e.map((x) => x.textContent).join(' '))}`);
  return { program: (await page.evaluate(() => window.__oficina.program())).text, report: await page.textContent('#process-report') };
}

function sameProgram(page, cliProgram) {
  const a = body(page), b = body(cliProgram);
  assert(a.length > 1000, `a program: ${a.length} lines`);
  const k = a.findIndex((l, i) => l !== b[i]);
  assert(a.length === b.length && k < 0, `page vs CLI: ${a.length} vs ${b.length} lines, first difference at ${k}: ${a[k]} | ${b[k]}`);
}

/// The CLI's gouge and planner time as the page words them.
function sameFigures(report, stdout) {
  const gouge = stdout.match(/max gouge: ([\d.]+) mm/)[1];
  const time = stdout.match(/time: planner (\d+:\d\d:\d\d)/)[1];
  assert(report.includes(`max gouge ${gouge} mm`), `gouge ${gouge}: ${report}`);
  assert(report.includes(`time: planner ${time}`), `planner ${time}: ${report}`);
  return { gouge: Number(gouge), time };
}

await test('a cone on its side: opened, drawn, carved with a roughing tool as the CLI carves it, and run', async () => {
  await page.goto(server.url);
  await page.waitForFunction(() => document.getElementById('summary').textContent.includes('errors'), null, { timeout: 30000 });
  const file = path.join(dir, 'ocl_cone_on_side.stl');
  const { bounds, what } = await open(file);
  // The box the page names is the file's own (no scale, no turn): trimesh's to the 0.01 mm shown.
  const box = what.match(/X (-?[\d.]+)…(-?[\d.]+) Y (-?[\d.]+)…(-?[\d.]+) Z (-?[\d.]+)…(-?[\d.]+)/).slice(1).map(Number);
  const want = [bounds[0][0], bounds[1][0], bounds[0][1], bounds[1][1], bounds[0][2], bounds[1][2]];
  assert(box.every((v, i) => Math.abs(v - want[i]) <= 0.006), `box ${box} vs trimesh ${want}`);
  await page.waitForTimeout(300);
  await page.screenshot({ path: path.join(shots, 'workbench-carve-stl-model.png') });
  const form = { tool: 'ball:3', rough_tool: 'flat:6', pixel_size: 0.1, stepdown: 5 };
  const got = await carve(form);
  const ref = cli(file, ['--tool', 'ball:3', '--rough-tool', 'flat:6', '--pixel-size', '0.1', '--stepdown', '5']);
  sameProgram(got.program, ref.program);
  const f = sameFigures(got.report, ref.stdout);
  assert(f.gouge < 0.01, `gouge ${f.gouge}`);
  assert(/roughing \(mesh z-level\): T1 flat:6/.test(got.report) && /finishing .*: T2 ball:3/.test(got.report), got.report);
  assert(await page.isVisible('#model-stock'), 'the simulated stock is shown');
  // The toolpath is drawn with the model.
  await page.waitForFunction(() => Number(document.getElementById('viewport').dataset.segments || 0) > 1000, null, { timeout: 60000 });
  assert((await page.getAttribute('#viewport', 'data-model')) === '676', 'the model stays drawn under the toolpath');
  await page.screenshot({ path: path.join(shots, 'workbench-carve-stl.png') });

  // On the virtual machine, as any program: the work zero moved as a user moves it (jog to
  // machine X30 Y30, zero X and Y) so the model's own coordinates (Y from -13 with the tool)
  // lie in the travel; instant speed, through the tool change's pause.
  await page.selectOption('#jog-step', '10');
  await page.fill('#jog-feed', '6000');
  for (const [axis, id] of [['1,0,0', 'mx'], ['0,1,0', 'my']]) {
    for (let k = 1; k <= 3; k++) {
      await page.click(`#jog button[data-jog="${axis}"]`);
      await page.waitForFunction(([id, v]) => document.getElementById(id).textContent === v && document.body.dataset.state === 'idle', [id, `${10 * k}.000`], { timeout: 20000 });
    }
  }
  await page.click('#zero-x');
  await page.click('#zero-y');
  await page.waitForFunction(() => document.getElementById('wx').textContent === '0.000' && document.getElementById('wy').textContent === '0.000', null, { timeout: 10000 });
  await page.selectOption('#speed', '0');
  await page.click('#start');
  const name = got.program && (await page.textContent('#program-name')).trim();
  for (let k = 0; k < 5; k++) {
    await page.waitForFunction(() => document.body.dataset.state === 'paused' || document.body.dataset.jobDone === 'completed', null, { timeout: 300000 });
    if ((await page.evaluate(() => document.body.dataset.jobDone)) === 'completed') break;
    await page.click('#resume');
    await page.waitForFunction(() => document.body.dataset.state !== 'paused', null, { timeout: 30000 });
  }
  assert((await page.evaluate(() => document.body.dataset.jobDone)) === 'completed', 'the carving ran to its end');
  // The console says so too (its line may come a moment after the status).
  await page.waitForFunction((name) => {
    const c = document.getElementById('console').textContent;
    const started = c.lastIndexOf(`started ${name}`);
    return started >= 0 && c.lastIndexOf('job finished') > started;
  }, name, { timeout: 30000 }).catch(() => { throw new Error(`no 'job finished' after 'started ${name}'`); });
});

await test('a mold cavity turned and scaled, finish only, LinuxCNC post: the CLI\'s program', async () => {
  const file = path.join(dir, 'ocl_ktoolcav.stl');
  if (!existsSync(file)) { console.log(`note: ${file} is absent: skipped`); return; }
  const { faces } = await open(file);
  await fillForm({ rough_tool: '', size: 40, rotate: 30 });
  await page.dispatchEvent('#process-fields [name="rotate"]', 'change');
  // The page draws the model as placed: its largest dimension 40 mm.
  await page.waitForFunction(() => {
    const m = document.getElementById('process-status').textContent.match(/X (-?[\d.]+)…(-?[\d.]+) Y (-?[\d.]+)…(-?[\d.]+) Z (-?[\d.]+)…(-?[\d.]+)/);
    if (!m) return false;
    const v = m.slice(1).map(Number);
    return Math.abs(Math.max(v[1] - v[0], v[3] - v[2], v[5] - v[4]) - 40) < 0.02;
  }, null, { timeout: 30000 });
  const got = await carve({ tool: 'ball:2', pixel_size: 0.15, post: 'linuxcnc', direction: 'both', scallop: 0.01 });
  const ref = cli(file, ['--tool', 'ball:2', '--size', '40', '--rotate', '30', '--pixel-size', '0.15', '--post', 'linuxcnc', '--direction', 'both', '--scallop', '0.01']);
  sameProgram(got.program, ref.program);
  sameFigures(got.report, ref.stdout);
  assert(got.report.includes(`${faces.toLocaleString('en-US')} triangles carved in 1 operations`), got.report);
});

await test('the cone as OBJ (trimesh writes it): drawn and carved as the CLI carves the OBJ', async () => {
  const obj = path.join(scratch, 'cone.obj');
  execFileSync('python3', ['-c', 'import sys, trimesh\ntrimesh.load(sys.argv[1], process=False).export(sys.argv[2])', path.join(dir, 'ocl_cone_on_side.stl'), obj]);
  const { faces } = await open(obj);
  assert(faces === 676, `${faces} faces`);
  await fillForm({ size: '', rotate: 0 });
  await page.dispatchEvent('#process-fields [name="rotate"]', 'change');
  const got = await carve({ tool: 'ball:6', rough_tool: '', pixel_size: 0.2, post: 'grbl', direction: 'x', scallop: 0.02 });
  const ref = cli(obj, ['--tool', 'ball:6', '--pixel-size', '0.2']);
  sameProgram(got.program, ref.program);
  sameFigures(got.report, ref.stdout);
});

await test('the cone, mix chosen in the visible form (steep 40°, raster at 30°, z-level roughing): the CLI\'s program', async () => {
  const file = path.join(dir, 'ocl_cone_on_side.stl');
  await open(file);
  await fillForm({ size: '', rotate: 0 });
  // The controls a user sees: the finishing strategy, the slope limit, the raster angle.
  for (const name of ['strategy', 'steep', 'angle', 'roughing', 'rough_tool']) {
    assert(await page.isVisible(`#process-fields [name="${name}"]`), `${name} is shown`);
  }
  const got = await carve({ tool: 'ball:3', rough_tool: 'flat:6', roughing: 'zlevel', strategy: 'mix', steep: 40, angle: 30, pixel_size: 0.2, post: 'grbl', direction: 'x', scallop: 0.02 });
  const ref = cli(file, ['--tool', 'ball:3', '--rough-tool', 'flat:6', '--roughing', 'zlevel', '--strategy', 'mix', '--steep', '40', '--angle', '30', '--pixel-size', '0.2']);
  sameProgram(got.program, ref.program);
  // The mix's first row starts a hair below X 0, outside grbl-router's travel: no planner
  // time on either side, so the gouge and the feed-only time.
  const gouge = ref.stdout.match(/max gouge: ([\d.]+) mm/)[1];
  const feedOnly = ref.stdout.match(/feed-only (\d+:\d\d:\d\d)/)[1];
  assert(got.report.includes(`max gouge ${gouge} mm`) && got.report.includes(`feed-only ${feedOnly}`), `${gouge}, ${feedOnly}: ${got.report}`);
  assert(/roughing \(mesh z-level\): T1 flat:6/.test(got.report), got.report);
  assert(/finishing \(mesh raster on flats, waterline on steeps\): T2 ball:3/.test(got.report), got.report);
});

await test('a large carving cancelled midway: the page says so and carves the next one', async () => {
  const file = path.join(dir, 'ocl_sphere_on_plate.stl');
  if (!existsSync(file)) { console.log(`note: ${file} is absent: skipped`); return; }
  await open(file);
  // A fine grid and a tiny scallop with the mix: minutes of work were it not cancelled.
  await fillForm({ tool: 'ball:1', rough_tool: 'flat:6', strategy: 'mix', steep: 45, angle: '', pixel_size: 0.05, scallop: 0.0005 });
  await page.click('#make');
  const cancel = '#process-form .cancel-job';
  await page.waitForSelector(`${cancel}:not([hidden])`, { timeout: 120000 });
  await page.click(cancel);
  await page.waitForFunction(() => document.getElementById('process-status').textContent === 'cancelled', null, { timeout: 120000 });
  assert(!(await page.textContent('#error')), `no error: ${await page.textContent('#error')}`);
  // Usable at once: the cone, carved as the CLI carves it.
  const cone = path.join(dir, 'ocl_cone_on_side.stl');
  await open(cone);
  const got = await carve({ tool: 'ball:6', rough_tool: '', strategy: 'raster', pixel_size: 0.2, scallop: 0.02 });
  const ref = cli(cone, ['--tool', 'ball:6', '--pixel-size', '0.2']);
  sameProgram(got.program, ref.program);
});

await test('a bad tool is a clear message beside its field', async () => {
  await fillForm({ tool: 'wrench:3' });
  await page.click('#make');
  await page.waitForFunction(() => document.querySelector('#process-fields .field-error:not(:empty)') || document.getElementById('error').textContent || /wrench/.test(document.getElementById('process-status').textContent), null, { timeout: 60000 });
  const msg = [await page.textContent('#process-status'), await page.textContent('#error'), ...(await page.$$eval('#process-fields .field-error', (e) => e.map((x) => x.textContent)))].join(' ');
  assert(/wrench/.test(msg), msg);
});

await browser.close();
finish();
