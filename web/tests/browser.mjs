// Browser tests of the workbench: Debian's chromium driven by playwright-core against a
// running `oficina serve` (URL in OFICINA_URL). Prints `N passed, M failed`; screenshots of
// each main view go to web/test-output/.

import { chromium } from 'playwright-core';
import { mkdirSync } from 'node:fs';
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

await test('a second page watches and cannot move the machine', async () => {
  const other = await browser.newPage({ viewport: { width: 1200, height: 800 } });
  await other.goto(url);
  await other.waitForFunction(() => document.getElementById('control').textContent.includes('watching'), null, { timeout: 20000 });
  assert(await other.isDisabled('#stop'), 'a watcher cannot stop the job');
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

await test('no script errors in the page', async () => {
  assert(consoleErrors.length === 0, consoleErrors.join('\n'));
});

await browser.close();
console.log(`web: ${passed} passed, ${failed} failed`);
process.exit(failed > 0 || passed === 0 ? 1 : 0);
