// The Plot form makes a Marlin program and the machine panel runs it on a Marlin board: a
// real user's drawing (realworld plot-svg) plotted for Marlin through the visible form must
// be exactly `oficina plot … --format marlin` for the same options; the page connects to
// `oficina emulate marlin` (which corrupts line 50 once and makes G28 take 2 s) through the
// machine list's Marlin entry, holds during G28, resumes, and the job runs to the end with
// every line acknowledged; a second start is stopped during G28; back on the virtual machine
// the controls are on again. Starts its own server and emulator. Prints `N passed, M failed`.

import { startServer, launch, suite, assert, openPage, waitState, realworld, out, root } from './harness.mjs';
import { spawn, execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';

const { test, state, finish } = suite('plot marlin');
const bin = path.resolve(process.env.OFICINA_BIN || path.join(root, 'target', 'debug', 'oficina'));
const FILE = 'axidraw_AxiDraw_First.svg';
const dir = realworld('plot-svg', FILE);
if (!dir) {
  console.log(`SKIPPED plot marlin: ${FILE} is not in the realworld plot-svg folder`);
  console.log('0 passed, 0 failed');
  process.exit(0);
}

/// `oficina emulate marlin` on a free loopback port; resolves with its `host:port`.
function startMarlin(extra) {
  return new Promise((resolve, reject) => {
    const p = spawn(bin, ['emulate', 'marlin', '--tcp', '127.0.0.1:0', ...extra], { stdio: ['ignore', 'pipe', 'pipe'] });
    process.on('exit', () => p.kill('SIGKILL'));
    let seen = '';
    const look = (d) => {
      seen += d;
      const m = seen.match(/tcp:\/\/([0-9.]+:\d+)/);
      if (m) resolve({ addr: m[1], proc: p });
    };
    p.stdout.on('data', look);
    p.stderr.on('data', look);
    p.on('exit', (code) => reject(new Error(`the Marlin emulator exited (${code}): ${seen}`)));
  });
}

const server = await startServer();
const board = await startMarlin(['--corrupt-line', '50', '--busy-ms', '2000']);
const browser = await launch();
let page;
let made = '';

await test('the Plot form makes what `oficina plot --format marlin` makes', async () => {
  page = await openPage(browser, server, state);
  await page.selectOption('#process', 'plot');
  await page.setInputFiles('#file-input', path.join(dir, FILE));
  await page.waitForFunction((f) => document.getElementById('process-input').textContent === f, FILE, { timeout: 20000 });
  await page.selectOption('#process-fields [name="format"]', 'marlin');
  assert(await page.inputValue('#process-fields [name="pen"]') === 'servo', 'Marlin lifts the pen with a servo, as the CLI defaults');
  await page.fill('#process-fields [name="layout"]', 'a4');
  await page.click('#make');
  await page.waitForFunction(() => document.getElementById('program-name').textContent.endsWith('.plot.ngc'), null, { timeout: 60000 });
  made = await page.inputValue('#text');
  const scratch = mkdtempSync(path.join(os.tmpdir(), 'oficina-marlin-'));
  const cli = path.join(scratch, 'cli.gcode');
  execFileSync(bin, ['plot', path.join(dir, FILE), '--format', 'marlin', '--layout', 'a4', '-o', cli], { stdio: 'ignore' });
  const expected = readFileSync(cli, 'utf8');
  assert(made.length > 0 && made === expected,
    `the page's program (${made.split('\n').length} lines) differs from the CLI's (${expected.split('\n').length} lines)`);
  assert(made.includes('M280 P0 S') && made.includes('G28'), 'a Marlin program: servo pen lifts and G28');
  assert(made.split('\n').length > 50, 'long enough to reach the corrupted line 50');
});

await test('the Marlin entry connects the board; jog and overrides are off, saying why', async () => {
  // The user types the bridge's tcp:// address: the Marlin entry makes it marlin+tcp://.
  page.once('dialog', (d) => d.accept(`tcp://${board.addr}`));
  await page.selectOption('#machine-uri', '?marlin');
  assert(await page.inputValue('#machine-uri') === `marlin+tcp://${board.addr}`, `the address becomes marlin+tcp: ${await page.inputValue('#machine-uri')}`);
  await page.click('#connect');
  await page.waitForFunction((a) => document.getElementById('machine-name').textContent.includes(a), board.addr, { timeout: 15000 });
  await waitState(page, 'idle');
  assert((await page.textContent('#machine-name')).includes('Marlin'), await page.textContent('#machine-name'));
  for (const sel of ['#jog button[data-jog="1,0,0"]', '#fo', '#so', '#home', '#unlock', '#zero']) {
    assert(await page.isDisabled(sel), `${sel} is off on Marlin`);
    const why = await page.getAttribute(sel, 'title');
    assert(why && why.includes('Marlin'), `${sel} says why: ${why}`);
  }
  // Checked again as Marlin reads it: M280 and G4 P in ms are no errors there.
  await page.waitForFunction(() => /^0 errors .*read as Marlin/.test(document.getElementById('summary').textContent), null, { timeout: 30000 })
    .catch(async () => { throw new Error(`not checked as Marlin: ${await page.textContent('#summary')}`); });
});

await test('start, hold during G28, resume: the job runs to the end, every line acknowledged', async () => {
  await page.click('#start');
  await page.click('#hold');
  await waitState(page, 'hold', 15000);
  await page.click('#resume');
  // Marlin waits at each pen change (M0) until the user resumes, as at the plotter.
  let pauses = 0;
  for (;;) {
    await page.waitForFunction(() => document.body.dataset.jobDone === 'completed' || document.body.dataset.state === 'paused', null, { timeout: 120000 });
    if (await page.evaluate(() => document.body.dataset.jobDone === 'completed')) break;
    pauses++;
    assert(pauses <= (made.match(/^M0 /gm) ?? []).length, `paused more often than the program has M0: ${pauses}`);
    await page.click('#resume');
    await page.waitForFunction(() => document.body.dataset.state !== 'paused', null, { timeout: 15000 });
  }
  assert(pauses === (made.match(/^M0 /gm) ?? []).length, `one pause per pen change: ${pauses}`);
  await waitState(page, 'idle');
  const lines = made.split('\n').filter((l) => l.trim() && !l.trim().startsWith(';')).length;
  const c = await page.textContent('#console');
  const m = c.match(/(\d+) of (\d+) lines acknowledged, (\d+) resent on request/);
  assert(m, `the job's summary is in the console: ${c.slice(-600)}`);
  assert(m[1] === m[2] && Number(m[2]) === lines, `every one of the ${lines} command lines acknowledged: ${m[0]}`);
  assert(Number(m[3]) >= 1, `the corrupted line was sent again: ${m[0]}`);
  console.log(`     the link: ${m[0]}`);
  await page.screenshot({ path: path.join(root, 'docs', 'screenshots', 'workbench-plot-marlin.png') });
  await page.screenshot({ path: path.join(out, 'plot-marlin.png') });
});

await test('Stop during G28 ends the job stopped, the board idle', async () => {
  await page.click('#start');
  await waitState(page, 'run');
  await page.click('#stop');
  await page.waitForFunction(() => document.body.dataset.jobDone === 'stopped', null, { timeout: 60000 });
  await waitState(page, 'idle');
  const c = await page.textContent('#console');
  assert(/job stopped/.test(c), `the console says it stopped: ${c.slice(-400)}`);
});

await test('back on the virtual machine, jog and overrides are on again, grbl tooltips back', async () => {
  await page.selectOption('#machine-uri', 'virtual');
  await page.click('#connect');
  await page.waitForFunction(() => document.getElementById('machine-name').textContent.includes('virtual machine'), null, { timeout: 15000 });
  await waitState(page, 'idle');
  for (const sel of ['#jog button[data-jog="1,0,0"]', '#fo', '#so', '#jog-step']) assert(!(await page.isDisabled(sel)), `${sel} is on again`);
  assert(await page.getAttribute('#home', 'title') === 'grbl: $H', `Home's own tooltip: ${await page.getAttribute('#home', 'title')}`);
});

await browser.close();
board.proc.kill('SIGKILL');
finish();
