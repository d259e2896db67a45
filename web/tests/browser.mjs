// Browser tests of the workbench: Debian's chromium driven by playwright-core against a
// running `oficina serve` (URL in OFICINA_URL). Prints `N passed, M failed`; screenshots of
// each main view go to web/test-output/.

import { chromium } from 'playwright-core';
import { mkdirSync, readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import path from 'node:path';

const here = path.dirname(fileURLToPath(import.meta.url));
const out = process.env.OFICINA_TEST_OUTPUT || path.join(here, '..', 'test-output');
mkdirSync(out, { recursive: true });
const url = process.env.OFICINA_URL;
if (!url) { console.error('set OFICINA_URL to a running `oficina serve`'); process.exit(2); }

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking'],
});
const page = await browser.newPage({ viewport: { width: 1600, height: 900 } });
const consoleErrors = [];
page.on('pageerror', (e) => consoleErrors.push(String(e)));

let passed = 0, failed = 0;
async function test(name, fn) {
  const t0 = Date.now();
  try {
    await fn();
    passed++;
    console.log(`ok   ${name} (${Date.now() - t0} ms)`);
  } catch (e) {
    failed++;
    console.log(`FAIL ${name}: ${e.message.split('\n').slice(0, 6).join('\n     ')}`);
    await page.screenshot({ path: path.join(out, `failed-${name.replace(/\W+/g, '-')}.png`) }).catch(() => {});
  }
}
function assert(cond, msg) { if (!cond) throw new Error(msg); }
const shot = (name) => page.screenshot({ path: path.join(out, `${name}.png`) });
const segments = () => page.$eval('#viewport', (e) => Number(e.dataset.segments || 0));
const state = () => page.evaluate(() => document.body.dataset.state || '');
const extents = () => page.$eval('#summary', (e) => e.dataset.extents ? JSON.parse(e.dataset.extents) : null);
async function waitState(s, timeout = 30000) {
  await page.waitForFunction((s) => document.body.dataset.state === s, s, { timeout });
}

await test('the page opens on the virtual machine with the sample loaded', async () => {
  await page.goto(url);
  await page.waitForFunction(() => Number(document.getElementById('viewport').dataset.segments || 0) > 0, null, { timeout: 30000 });
  await page.waitForFunction(() => document.getElementById('summary').textContent.includes('0 errors'), null, { timeout: 30000 });
  assert((await page.textContent('#program-name')) === 'plate.nc', 'the sample is plate.nc');
  assert((await page.textContent('#machine-name')).includes('virtual machine'), 'connected to the virtual machine');
  assert((await page.textContent('#control')).includes('controlling'), 'the only page controls the machine');
  const e = await extents();
  // The outline is cut with a 3 mm tool around a 60 x 40 plate: 63 x 43 mm of tool centres.
  assert(Math.abs(e.max[0] - e.min[0] - 63) < 1e-6 && Math.abs(e.max[1] - e.min[1] - 43) < 1e-6, JSON.stringify(e));
  assert(await page.isVisible('.g'), 'G words are coloured');
  await page.click('#views button[data-view="iso"]');
  await page.waitForTimeout(300);
  await shot('view-iso');
});

await test('views XY, ZY and depth', async () => {
  for (const v of ['xy', 'zy', 'depth']) {
    await page.click(`#views button[data-view="${v}"]`);
    await page.waitForTimeout(300);
    await shot(`view-${v}`);
  }
  await page.click('#views button[data-view="iso"]');
});

await test('changing a parameter updates the check and the preview', async () => {
  const before = await extents();
  const segsBefore = await segments();
  await page.evaluate(() => {
    const t = document.getElementById('text');
    t.value = t.value.replaceAll('G1 X61.5 F1200', 'G1 X91.5 F1200').replaceAll('\nX-1.5\n', '\nX-1.5\n');
    t.value = t.value.replace(/\nY41\.5\nX-1\.5/g, '\nY41.5\nX-1.5');
    t.dispatchEvent(new Event('input'));
  });
  await page.waitForFunction((w) => {
    const e = document.getElementById('summary').dataset.extents;
    return e && JSON.parse(e).max[0] - JSON.parse(e).min[0] > w + 29;
  }, before.max[0] - before.min[0], { timeout: 20000 });
  await page.waitForFunction(() => {
    const b = window.__oficina.preview.bounds();
    return window.__oficina.stats.segments > 0 && b.max[0] - b.min[0] > 90;
  }, null, { timeout: 20000 });
  assert((await segments()) === segsBefore, 'same number of moves, longer ones');
  await shot('changed-parameter');
});

await test('a bad line gets a diagnostic with its line and column', async () => {
  await page.evaluate(() => {
    const t = document.getElementById('text');
    t.value = t.value.replace('G0 Z5\n', 'G0 Z5\nG1 X10 Q7\n');
    t.dispatchEvent(new Event('input'));
  });
  await page.waitForSelector('#diagnostics li.error', { timeout: 20000 });
  const d = await page.textContent('#diagnostics li.error');
  assert(/^7:\d+ /.test(d), `diagnostic on line 7: ${d}`);
  assert(await page.isVisible('#gutter .err'), 'the gutter marks the line');
  await shot('diagnostics');
  await page.evaluate(() => {
    const t = document.getElementById('text');
    t.value = t.value.replace('G0 Z5\nG1 X10 Q7\n', 'G0 Z5\n');
    t.dispatchEvent(new Event('input'));
  });
  await page.waitForFunction(() => document.querySelectorAll('#diagnostics li').length === 0, null, { timeout: 20000 });
});

await test('the timeline scrubs the path and highlights the line', async () => {
  await page.waitForFunction(() => window.__oficina.stats.previewDone === window.__oficina.stats.previews, null, { timeout: 20000 });
  const total = await segments();
  await page.$eval('#scrub', (s, v) => { s.value = String(v); s.dispatchEvent(new Event('input')); }, Math.floor(total / 2));
  const info = await page.textContent('#scrub-info');
  const line = Number(info.match(/line (\d+)/)[1]);
  assert(line > 5, info);
  // The editor draws on the next animation frame.
  await page.waitForFunction(() => getComputedStyle(document.getElementById('current-line')).display === 'block', null, { timeout: 5000 });
  await shot('timeline');
  await page.$eval('#scrub', (s) => { s.value = s.max; s.dispatchEvent(new Event('input')); });
});

await test('jog, zero and home on the virtual machine', async () => {
  await page.selectOption('#jog-step', '10');
  await page.fill('#jog-feed', '6000');
  await page.click('#jog button[data-jog="1,0,0"]');
  await page.waitForFunction(() => document.getElementById('mx').textContent === '10.000', null, { timeout: 20000 });
  await waitState('idle');
  await page.click('#zero');
  await page.waitForFunction(() => document.getElementById('wx').textContent === '0.000', null, { timeout: 10000 });
  await page.click('#home');
  await page.waitForFunction(() => document.getElementById('mx').textContent === '0.000', null, { timeout: 20000 });
  await waitState('idle');
  assert((await page.textContent('#wx')) === '-10.000', 'work X follows the new zero');
  // Put the stored work zero back for the job.
  await page.evaluate(() => document.getElementById('connect').click());
  await page.waitForFunction(() => document.getElementById('wx').textContent === '-10.000', null, { timeout: 10000 });
});

await test('run on the virtual machine, hold and resume', async () => {
  await page.selectOption('#speed', '5');
  await page.click('#start');
  await waitState('run');
  await page.waitForFunction(() => Number(document.getElementById('line').textContent) > 10, null, { timeout: 30000 });
  await shot('running');
  await page.click('#hold');
  await waitState('hold');
  const held = await page.textContent('#line');
  await page.waitForTimeout(800);
  assert((await page.textContent('#line')) === held, 'the line stays while held');
  await shot('held');
  await page.click('#resume');
  await waitState('run');
});

await test('reloading mid-job shows the job where it is', async () => {
  const lineBefore = Number(await page.textContent('#line'));
  await page.reload();
  await waitState('run');
  await page.waitForFunction(() => document.getElementById('program-name').textContent === 'plate.nc', null, { timeout: 20000 });
  const line = Number(await page.textContent('#line'));
  assert(line >= lineBefore, `line ${line} after ${lineBefore}`);
  await page.waitForFunction(() => getComputedStyle(document.getElementById('current-line')).display === 'block', null, { timeout: 20000 });
  assert((await page.textContent('#control')).includes('controlling'), 'the reloaded page controls again');
  await shot('reloaded-mid-job');
});

await test('a second page watches and cannot move the machine, but may stop it', async () => {
  const other = await browser.newPage({ viewport: { width: 1200, height: 800 } });
  await other.goto(url);
  await other.waitForFunction(() => document.getElementById('control').textContent.includes('watching'), null, { timeout: 20000 });
  await other.waitForFunction(() => document.body.dataset.state === 'run', null, { timeout: 20000 });
  assert(await other.isDisabled('#start') && await other.isDisabled('#jog button[data-jog="1,0,0"]'), 'a watcher cannot start or jog');
  assert(!(await other.isDisabled('#stop')) && !(await other.isDisabled('#hold')), 'a watcher can hold and stop the job');
  await other.close();
});

await test('the job finishes', async () => {
  await page.waitForFunction(() => document.body.dataset.jobDone === 'completed', null, { timeout: 120000 });
  await waitState('idle');
  assert((await page.textContent('#console')).includes('job finished'), 'the console says so');
  await shot('finished');
});

await test('relief from an image: carve, change the depth, preview updates', async () => {
  await page.selectOption('#process', 'relief');
  await page.waitForFunction(() => document.getElementById('relief-image').textContent === 'dome.png', null, { timeout: 20000 });
  await page.fill('#relief-form input[name="width"]', '30');
  await page.fill('#relief-form input[name="stepover"]', '1.5');
  await page.click('#carve');
  await page.waitForFunction(() => document.getElementById('program-name').textContent === 'dome.nc' && Number(document.getElementById('viewport').dataset.segments || 0) > 0, null, { timeout: 120000 });
  await page.waitForFunction(() => window.__oficina.stats.segments > 0 && document.getElementById('summary').textContent.includes('0 errors'), null, { timeout: 60000 });
  const deep1 = (await extents()).min[2];
  await page.fill('#relief-form input[name="depth"]', '8');
  await page.click('#carve');
  await page.waitForFunction((d) => {
    const e = document.getElementById('summary').dataset.extents;
    return e && JSON.parse(e).min[2] < d - 1;
  }, deep1, { timeout: 120000 });
  await page.click('#views button[data-view="iso"]');
  await page.waitForTimeout(300);
  await shot('relief');
  // Invalid input is named before anything is sent.
  await page.fill('#relief-form input[name="width"]', '-4');
  await page.click('#carve');
  assert((await page.textContent('#error')).includes('width'), 'the bad field is named');
  await page.fill('#relief-form input[name="width"]', '30');
});

await test('a file dropped on the page opens', async () => {
  const text = 'G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F200\nG2 X20 Y0 I10 J0 F800\nG0 Z5\nM2\n';
  const dt = await page.evaluateHandle((t) => {
    const d = new DataTransfer();
    d.items.add(new File([t], 'dropped.nc', { type: 'text/plain' }));
    return d;
  }, text);
  await page.dispatchEvent('body', 'drop', { dataTransfer: dt });
  await page.waitForFunction(() => document.getElementById('program-name').textContent === 'dropped.nc', null, { timeout: 10000 });
  await page.waitForFunction(() => Number(document.getElementById('viewport').dataset.segments || 0) > 30, null, { timeout: 20000 });
});

await test('SVG → mill: a server-side error beside its field, then preview and run to the end', async () => {
  const svg = readFileSync(path.join(here, '..', '..', 'samples', 'mill', 'plate.svg'), 'utf8');
  await page.selectOption('#process', 'mill');
  await page.waitForFunction(() => !document.getElementById('process-form').hidden, null, { timeout: 10000 });
  // Dropped like a user would: uploaded into the job folder.
  const dt = await page.evaluateHandle((t) => {
    const d = new DataTransfer();
    d.items.add(new File([t], 'part.svg', { type: 'image/svg+xml' }));
    return d;
  }, svg);
  await page.dispatchEvent('body', 'drop', { dataTransfer: dt });
  await page.waitForFunction(() => document.getElementById('process-input').textContent === 'part.svg', null, { timeout: 10000 });
  await page.selectOption('#process-fields select[name="op"]', 'profile-out');
  await page.selectOption('#process-fields select[name="entry"]', 'plunge');
  await page.fill('#process-fields input[name="depth"]', '1');
  await page.fill('#process-fields input[name="safe_z"]', '2');
  await page.click('#make');
  await page.waitForFunction(() => document.querySelector('#process-fields .field-error[data-for="safe_z"]').textContent.includes('clear-z'), null, { timeout: 30000 });
  await shot('mill-field-error');
  await page.fill('#process-fields input[name="safe_z"]', '20');
  await page.click('#make');
  await page.waitForFunction(() => document.getElementById('program-name').textContent === 'part.profile-outside.ngc', null, { timeout: 60000 });
  assert((await page.textContent('.field-error[data-for="safe_z"]')) === '', 'the error is gone');
  await page.waitForFunction(() => window.__oficina.stats.previewDone === window.__oficina.stats.previews && window.__oficina.preview.total > 0 && document.getElementById('summary').textContent.includes('0 errors'), null, { timeout: 60000 });
  const report = await page.textContent('#process-report');
  assert(report.includes('gouge:    none') && report.includes('time:'), report);
  // The preview holds rapids, feeds and plunges, each coloured by kind.
  const kinds = await page.evaluate(() => window.__oficina.preview.kindCounts());
  assert(kinds.rapid > 0 && kinds.feed > 0 && kinds.plunge > 0, JSON.stringify(kinds));
  await page.click('#views button[data-view="iso"]');
  await page.waitForTimeout(300);
  await shot('mill');
  await page.selectOption('#speed', '0');
  await page.click('#start');
  // Finished after it started (the console keeps the earlier job's lines too).
  await page.waitForFunction(() => {
    const c = document.getElementById('console').textContent;
    const started = c.lastIndexOf('started part.profile-outside.ngc');
    return started >= 0 && c.lastIndexOf('job finished') > started;
  }, null, { timeout: 120000 });
  await waitState('idle');
});

await test('point list → sole mold → preview', async () => {
  await page.selectOption('#process', 'sole');
  await page.waitForFunction(() => document.getElementById('process-input').textContent === 'size34.csv', null, { timeout: 20000 });
  await page.fill('#process-fields input[name="shrink"]', '2.5');
  await page.click('#make');
  await page.waitForFunction(() => /size34\.left-insert\.ngc|size34\.\w+-\w+\.ngc/.test(document.getElementById('program-name').textContent), null, { timeout: 180000 });
  await page.waitForFunction(() => Number(document.getElementById('viewport').dataset.segments || 0) > 100, null, { timeout: 60000 });
  const report = await page.textContent('#process-report');
  assert(report.includes('α = ') && (report.match(/gouge:/g) || []).length === 4, report);
  await page.click('#views button[data-view="xy"]');
  await page.waitForTimeout(300);
  await shot('sole');
});

await test('SVG → plot → preview with pen up and down → run on the virtual plotter to the end', async () => {
  await waitState('idle');
  await page.selectOption('#process', 'plot');
  await page.waitForFunction(() => document.getElementById('process-input').textContent === 'design.svg', null, { timeout: 20000 });
  await page.click('#make');
  await page.waitForFunction(() => document.getElementById('program-name').textContent === 'design.plot.ngc', null, { timeout: 60000 });
  const title = await page.textContent('#preview-title');
  assert(title.startsWith('design.plot.ngc (a plot of design.svg)'), `the header says it is a plot of the drawing: ${title}`);
  await page.waitForFunction(() => window.__oficina.stats.previewDone === window.__oficina.stats.previews && window.__oficina.preview.total > 0, null, { timeout: 60000 });
  assert((await page.textContent('#legend-rapid')) === 'pen up' && (await page.textContent('#legend-feed')) === 'pen down', 'the legend speaks of the pen');
  const kinds = await page.evaluate(() => window.__oficina.preview.kindCounts());
  assert(kinds.rapid > 0 && kinds.feed > 0, JSON.stringify(kinds));
  assert((await page.textContent('#process-report')).includes('strokes'), 'pens are reported');
  await page.click('#views button[data-view="xy"]');
  await page.waitForTimeout(300);
  await shot('plot');
  // The page puts the virtual machine on the plotter the plot was made for, and shows it.
  await page.waitForFunction(() => document.getElementById('machine-name').textContent.includes('pen plotter'), null, { timeout: 20000 });
  assert((await page.inputValue('#machine-uri')) === 'virtual:pen-plotter', 'the machine list shows the plotter');
  assert((await page.textContent('#console')).includes('connected to virtual:pen-plotter'), 'the console says so');
  await page.selectOption('#speed', '0');
  await page.click('#start');
  // Two pens: the program pauses (M0) for the pen change; Resume goes on to the end.
  await waitState('paused', 60000);
  assert((await page.textContent('#console')).includes('pen'), 'the pause names the pen');
  await page.click('#resume');
  await page.waitForFunction(() => {
    const c = document.getElementById('console').textContent;
    const started = c.lastIndexOf('started design.plot.ngc');
    return started >= 0 && c.lastIndexOf('job finished') > started;
  }, null, { timeout: 120000 });
  await waitState('idle');
  assert((await page.evaluate(() => document.body.dataset.jobDone)) === 'completed', 'the plot ran to its end');
  await shot('plot-run');
  // Back on the default router for the tests that follow.
  await page.selectOption('#machine-uri', 'virtual');
  await page.click('#connect');
  await page.waitForFunction(() => !document.getElementById('machine-name').textContent.includes('pen plotter'), null, { timeout: 20000 });
});

await test('a long carve shows progress and is cancelled', async () => {
  await page.selectOption('#process', 'relief');
  await page.waitForFunction(() => !document.getElementById('relief-form').hidden, null, { timeout: 10000 });
  // A picture large enough that the carve is still being computed when Cancel is clicked
  // (the 120 × 80 sample finishes within a second on an idle machine): drawn in the page,
  // dropped like a user's file.
  const dt = await page.evaluateHandle(async () => {
    const c = document.createElement('canvas');
    c.width = 600;
    c.height = 600;
    const g = c.getContext('2d');
    const grad = g.createRadialGradient(300, 300, 10, 300, 300, 300);
    grad.addColorStop(0, '#fff');
    grad.addColorStop(1, '#000');
    g.fillStyle = grad;
    g.fillRect(0, 0, 600, 600);
    const blob = await new Promise((r) => c.toBlob(r, 'image/png'));
    const d = new DataTransfer();
    d.items.add(new File([blob], 'big.png', { type: 'image/png' }));
    return d;
  });
  await page.dispatchEvent('body', 'drop', { dataTransfer: dt });
  await page.waitForFunction(() => document.getElementById('relief-image').textContent === 'big.png', null, { timeout: 10000 });
  const nameBefore = await page.textContent('#program-name');
  await page.fill('#relief-form input[name="width"]', '400');
  await page.fill('#relief-form input[name="tool"]', 'ball:1');
  await page.fill('#relief-form input[name="rough_tool"]', 'flat:3');
  await page.fill('#relief-form input[name="stepover"]', '0.02');
  await page.fill('#relief-form input[name="stepdown"]', '1');
  await page.click('#carve');
  // Cancel shows with the first progress message; clicked at once.
  await page.click('#relief-form .cancel-job', { timeout: 20000 });
  await page.waitForFunction(() => document.getElementById('carve-status').textContent === 'cancelled', null, { timeout: 20000 });
  await shot('carve-cancelled');
  assert(!(await page.isVisible('#relief-form .cancel-job')), 'Cancel hides');
  assert((await page.textContent('#console')).includes('cancelled the job being computed'), 'the console says so');
  assert((await page.textContent('#program-name')) === nameBefore, 'no program was loaded');
  assert(!(await page.isDisabled('#carve')), 'another carve can start');
});

await test('continuous jog moves while held and stops on release; spindle override', async () => {
  await waitState('idle');
  await page.selectOption('#jog-step', 'continuous');
  await page.fill('#jog-feed', '600');
  const x0 = Number(await page.textContent('#mx'));
  const b = await page.$('#jog button[data-jog="0,1,0"]');
  const box = await b.boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  const y0 = Number(await page.textContent('#my'));
  await page.mouse.down();
  await page.waitForFunction((y) => Number(document.getElementById('my').textContent) > y + 2, y0, { timeout: 20000 });
  await shot('jog');
  await page.mouse.up();
  await waitState('idle', 20000);
  const y1 = Number(await page.textContent('#my'));
  await page.waitForTimeout(500);
  assert(Number(await page.textContent('#my')) === y1, 'it stays where it stopped');
  assert(Number(await page.textContent('#mx')) === x0, 'only Y moved');
  // 600 mm/min is 10 mm/s: a press of a second or two, far from the end of travel.
  assert(y1 - y0 > 2 && y1 - y0 < 100, `moved ${y1 - y0} mm`);
  await page.$eval('#so', (s) => { s.value = '120'; s.dispatchEvent(new Event('input')); s.dispatchEvent(new Event('change')); });
  await page.waitForFunction(() => document.getElementById('console').textContent.includes('spindle override 120 %'), null, { timeout: 10000 });
  await page.selectOption('#jog-step', '1');
});

await test('the profile editor shows the profile\'s own validation and uses a good one', async () => {
  await waitState('idle');
  await page.click('#profile-editor summary');
  await page.waitForFunction(() => document.getElementById('profile-text').value.includes('[travel]'), null, { timeout: 10000 });
  const good = await page.inputValue('#profile-text');
  await page.fill('#profile-text', good.replace(/\nx = \[[^\]]*\]/, '\nx = [9999.0, 0.0]'));
  await page.click('#profile-check');
  await page.waitForFunction(() => document.getElementById('profile-message').textContent.includes('travel'), null, { timeout: 10000 });
  assert((await page.getAttribute('#profile-message', 'class')) === 'error', 'shown as an error');
  await shot('profile-editor');
  await page.fill('#profile-text', good.replace(/name = "[^"]*"/, 'name = "edited router"'));
  await page.click('#profile-use');
  await page.waitForFunction(() => document.getElementById('machine-name').textContent.includes('edited router'), null, { timeout: 20000 });
});

await test('the tool table editor places a bad line and saves a good table', async () => {
  await page.click('#tool-editor summary');
  await page.fill('#tools-text', 'T1 P1 D6 Z12.5 ;flat 6\nT2 P2 Dx\n');
  await page.click('#tools-save');
  await page.waitForFunction(() => document.getElementById('tools-message').textContent.startsWith('line 2'), null, { timeout: 10000 });
  await page.fill('#tools-text', 'T1 P1 D6 Z12.5 ;flat 6\nT2 P2 D3.175 Z20 ;ball\n');
  await page.click('#tools-save');
  await page.waitForFunction(() => document.getElementById('tools-message').textContent === 'saved 2 tools', null, { timeout: 10000 });
  assert((await page.textContent('#tools-table')).includes('3.175'), 'the table shows the tools');
  await shot('tool-table');
});

await test('the saved tool table reaches the check and the run (G43 H, tool diameters)', async () => {
  await waitState('idle');
  const save = async (table, saved) => {
    await page.fill('#tools-text', table);
    await page.click('#tools-save');
    await page.waitForFunction((m) => document.getElementById('tools-message').textContent === m, saved, { timeout: 10000 });
  };
  await save('T1 P1 D6 Z0 ;flat 6\n', 'saved 1 tools');
  const text = 'G21 G90 G54\nT1 M6\nG43 H1\nG0 X0 Y0 Z5\nG1 Z-1 F300\nX10\nG0 Z5\nM2\n';
  const dt = await page.evaluateHandle((t) => {
    const d = new DataTransfer();
    d.items.add(new File([t], 'tooled.nc', { type: 'text/plain' }));
    return d;
  }, text);
  await page.dispatchEvent('body', 'drop', { dataTransfer: dt });
  await page.waitForFunction(() => document.getElementById('summary').textContent.includes('T1 Ø6 L0'), null, { timeout: 20000 });
  const e0 = await extents();
  // A longer tool: the page checks again, the checked path rises by its length.
  await save('T1 P1 D6 Z12.5 ;flat 6\n', 'saved 1 tools');
  await page.waitForFunction(() => document.getElementById('summary').textContent.includes('T1 Ø6 L12.5'), null, { timeout: 20000 });
  const e1 = await extents();
  assert(Math.abs(e1.min[2] - e0.min[2] - 12.5) < 1e-6, `${JSON.stringify(e0)} → ${JSON.stringify(e1)}`);
  await shot('tool-table-check');
  // The run uses it too: the job ends at Z5 plus the tool's length, where the check put it.
  await page.selectOption('#speed', '0');
  await page.click('#start');
  await page.waitForFunction(() => {
    const c = document.getElementById('console').textContent;
    const started = c.lastIndexOf('started tooled.nc');
    return started >= 0 && c.lastIndexOf('job finished') > started;
  }, null, { timeout: 60000 });
  await waitState('idle');
  const mz = Number(await page.textContent('#mz'));
  assert(Math.abs(mz - e1.max[2]) < 1e-3, `machine Z ${mz}, checked ${e1.max[2]}`);
});

await test('SVG → embroidery: field errors, stitches in thread colours = the sheet\'s count, download, sew on the table to finished', async () => {
  const svg = readFileSync(path.join(here, '..', '..', 'samples', 'embroidery', 'sunflower.svg'), 'utf8');
  await page.selectOption('#process', 'embroider');
  await page.waitForFunction(() => document.getElementById('process-input').textContent === 'sunflower.svg', null, { timeout: 20000 });
  // The user's own design, dropped on the page.
  const dt = await page.evaluateHandle((t) => {
    const d = new DataTransfer();
    d.items.add(new File([t], 'flower.svg', { type: 'image/svg+xml' }));
    return d;
  }, svg);
  await page.dispatchEvent('body', 'drop', { dataTransfer: dt });
  await page.waitForFunction(() => document.getElementById('process-input').textContent === 'flower.svg', null, { timeout: 10000 });
  assert((await page.textContent('#legend-rapid')).startsWith('jump'), 'the legend speaks of jumps');
  // Refused by the browser (the stitch crate's range), then by the server (no such hoop).
  await page.fill('#process-fields input[name="stitch_length"]', '20');
  await page.click('#make');
  assert((await page.textContent('.field-error[data-for="stitch_length"]')) !== '', 'the browser names the field');
  await page.fill('#process-fields input[name="stitch_length"]', '3');
  await page.fill('#process-fields input[name="hoop"]', 'square-9');
  await page.click('#make');
  await page.waitForFunction(() => document.querySelector('#process-fields .field-error[data-for="hoop"]').textContent.includes('no such hoop'), null, { timeout: 30000 });
  await page.fill('#process-fields input[name="hoop"]', '');
  await page.click('#make');
  await page.waitForFunction(() => document.getElementById('process-status').dataset.stitches && !document.getElementById('embroidery').hidden, null, { timeout: 60000 });
  // The preview's sewn stitches (counted from the plan's points) are the sheet's count.
  const sheet = Number(await page.$eval('#process-status', (e) => e.dataset.stitches));
  const drawn = Number(await page.$eval('#viewport', (e) => e.dataset.stitches));
  const kinds = await page.evaluate(() => window.__oficina.preview.kindCounts());
  const report = await page.textContent('#process-report');
  const printed = Number((report.match(/Stitches\s+(\d+)/) || [])[1]);
  assert(sheet > 500 && drawn === sheet && kinds.feed === sheet && printed === sheet, `sheet ${sheet}, drawn ${drawn}, kinds ${JSON.stringify(kinds)}, printed ${printed}`);
  assert(kinds.rapid > 0, 'jumps are drawn');
  assert(report.includes('Sewing time') && report.includes('Hoop'), report);
  // Thread colours: one list entry per colour block, each a different thread.
  const threads = await page.$$eval('#threads li', (l) => l.map((e) => e.textContent.trim().split(' ')[0]));
  assert(threads.length === 3 && new Set(threads).size === 3, JSON.stringify(threads));
  const status = await page.textContent('#process-status');
  assert(status.includes('flower.dst') && status.includes('m of thread') && status.includes('sewing'), status);
  // The file to download is a DST (its header starts with the design's label).
  const href = await page.getAttribute('#stitch-download', 'href');
  const head = await page.evaluate(async (h) => {
    const b = new Uint8Array(await (await fetch(h)).arrayBuffer());
    return { n: b.length, label: new TextDecoder().decode(b.slice(0, 3)) };
  }, href);
  assert(head.n > 512 && head.label === 'LA:', JSON.stringify(head));
  // Sewn on the needle-synchronised table to its end.
  await page.click('#sew');
  await page.waitForFunction(() => ['finished', 'stopped', 'failed'].includes(document.getElementById('sew-status').dataset.state), null, { timeout: 60000 });
  const sewn = await page.textContent('#sew-status');
  assert((await page.$eval('#sew-status', (e) => e.dataset.state)) === 'finished', sewn);
  assert(sewn.includes(`${sheet} stitches`) && sewn.includes('sewing'), sewn);
  assert(Number(await page.inputValue('#scrub')) === (await segments()), 'the timeline played to the end');
  assert((await page.textContent('#process-status')).startsWith('flower.dst'), 'the sheet line stays after the run');
  // Scrubbing the stitches leaves the editor's program alone.
  const editorLine = await page.evaluate(() => window.__oficina.editor.currentLine ?? null);
  await page.$eval('#scrub', (e) => { e.value = '10'; e.dispatchEvent(new Event('input')); });
  assert((await page.textContent('#scrub-info')).startsWith('stitch entry'), await page.textContent('#scrub-info'));
  assert((await page.evaluate(() => window.__oficina.editor.currentLine ?? null)) === editorLine, 'the editor line stays');
  await page.$eval('#scrub', (e) => { e.value = e.max; e.dispatchEvent(new Event('input')); });
  await page.waitForTimeout(300);
  await shot('embroidery');
  // On the slower table of the embroidery-xy profile the run stops at the first stitch
  // too long for its needle-up window, and says which.
  await page.selectOption('#process-fields select[name="machine"]', 'embroidery-xy');
  await page.click('#sew');
  await page.waitForFunction(() => ['finished', 'stopped', 'failed'].includes(document.getElementById('sew-status').dataset.state), null, { timeout: 60000 });
  const stopped = await page.textContent('#sew-status');
  assert((await page.$eval('#sew-status', (e) => e.dataset.state)) === 'stopped' && stopped.includes('needle is up'), stopped);
  await page.selectOption('#process-fields select[name="machine"]', 'embroidery-table');
});

await test('a .dst file opened shows its stitches and sheet', async () => {
  const bytes = await page.evaluate(async () => Array.from(new Uint8Array(await (await fetch('/api/files/flower.dst')).arrayBuffer())));
  const before = Number(await page.$eval('#process-status', (e) => e.dataset.stitches));
  const dt = await page.evaluateHandle((b) => {
    const d = new DataTransfer();
    d.items.add(new File([new Uint8Array(b)], 'again.dst', { type: 'application/octet-stream' }));
    return d;
  }, bytes);
  await page.dispatchEvent('body', 'drop', { dataTransfer: dt });
  await page.waitForFunction(() => document.getElementById('process-status').textContent.startsWith('again.dst'), null, { timeout: 30000 });
  const sheet = Number(await page.$eval('#process-status', (e) => e.dataset.stitches));
  const drawn = Number(await page.$eval('#viewport', (e) => e.dataset.stitches));
  assert(sheet === before && drawn === sheet, `read back ${sheet}, drawn ${drawn}, made ${before}`);
  await page.selectOption('#process', 'gcode');
});

await test('the header names what the preview shows; the extents and the framing are the program\'s, wherever the tool is', async () => {
  const title = () => page.textContent('#preview-title');
  // The last thing shown: the stitch file read back.
  assert((await title()) === 'stitches of again.dst', `the header names the stitches: ${await title()}`);
  await page.selectOption('#sample', 'plate.nc');
  await page.waitForFunction(() => document.getElementById('preview-title').textContent.startsWith('plate.nc · read as'), null, { timeout: 20000 });
  const machine = (await page.textContent('#machine-name')).split(' · ')[0];
  assert((await title()) === `plate.nc · read as LinuxCNC · ${machine}`, `the header: ${await title()}`);
  await page.waitForFunction(() => window.__oficina.stats.previewDone === window.__oficina.stats.previews && window.__oficina.preview.total > 0, null, { timeout: 30000 });
  const e0 = await extents();
  const framed = await page.evaluate(() => window.__oficina.preview.framed());
  const drawn = await page.evaluate(() => window.__oficina.preview.bounds());
  assert(JSON.stringify(framed) === JSON.stringify(e0), `the view frames the extents the summary names: ${JSON.stringify(framed)} vs ${JSON.stringify(e0)}`);
  // The first rapid leaves from where the tool stood (the machine's start, X0 Y0): drawn,
  // but not the program's extents.
  assert(drawn.min[0] < e0.min[0] - 1 && drawn.min[1] < e0.min[1] - 1, `the approach is drawn (${JSON.stringify(drawn)}) outside the extents ${JSON.stringify(e0)}`);
  // The machine goes far away; the program checked again has the same extents.
  await waitState('idle');
  await page.selectOption('#jog-step', '10');
  await page.fill('#jog-feed', '6000');
  const x0 = Number(await page.textContent('#mx'));
  for (let i = 1; i <= 4; i++) {
    await page.click('#jog button[data-jog="1,0,0"]');
    await page.waitForFunction(([x, d]) => Number(document.getElementById('mx').textContent) > x + d - 0.01, [x0, 10 * i], { timeout: 20000 });
    await waitState('idle');
  }
  const checks = await page.evaluate(() => window.__oficina.stats.checks);
  await page.evaluate(() => document.getElementById('text').dispatchEvent(new Event('input')));
  await page.waitForFunction((n) => window.__oficina.stats.checks > n && window.__oficina.stats.lastCheck, checks, { timeout: 20000 });
  await page.waitForFunction(() => document.getElementById('summary').textContent.includes('0 errors'), null, { timeout: 20000 });
  assert(JSON.stringify(await extents()) === JSON.stringify(e0), `the extents stay the program's: ${JSON.stringify(await extents())}`);
  assert(JSON.stringify(await page.evaluate(() => window.__oficina.preview.framed())) === JSON.stringify(e0), 'so does the framing');
  await page.click('#views button[data-view="iso"]');
  await page.waitForFunction(() => window.__oficina.stats.previewDone === window.__oficina.stats.previews, null, { timeout: 30000 });
  await shot('header-and-extents');
  // Another program: another header; an empty editor: nothing.
  await page.selectOption('#sample', 'router-square.nc');
  await page.waitForFunction(() => document.getElementById('preview-title').textContent.startsWith('router-square.nc · read as'), null, { timeout: 20000 });
  await page.fill('#text', '');
  await page.waitForFunction(() => document.getElementById('preview-title').textContent === 'nothing loaded', null, { timeout: 20000 });
  for (let i = 0; i < 4; i++) {
    await page.click('#jog button[data-jog="-1,0,0"]');
    await page.waitForTimeout(100);
    await waitState('idle');
  }
});

await test('no script errors in the page', async () => {
  assert(consoleErrors.length === 0, consoleErrors.join('\n'));
});

await browser.close();
console.log(`web: ${passed} passed, ${failed} failed`);
process.exit(failed > 0 || passed === 0 ? 1 : 0);
