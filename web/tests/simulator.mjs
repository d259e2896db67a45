// The page against grblHAL's real Simulator (OFICINA_GRBLHAL_SIM names `grblHAL_sim`, built
// by scripts/build-grblhal-sim; docs/grbl-link.md has the recipe and the results). Through
// the page's visible controls, as web/tests/firmware.mjs does with Oficina's emulator: connect
// through the machine list, see the firmware and its live position, jog, load a program,
// start, hold, resume, change the feed override, stop, close the tab and come back, resume
// from a line to the end. Then what the other controls do on the Simulator (probing, unlock,
// home, zero, spindle override, continuous jog) is recorded in `note` lines (and
// test-output/simulator-notes.txt), asserted only where the answer is the Simulator's to give.
// Without OFICINA_GRBLHAL_SIM it prints SKIPPED and passes.

import { startServer, launch, suite, assert, sleep, out } from './harness.mjs';
import { writeFileSync } from 'node:fs';
import path from 'node:path';

const bin = process.env.OFICINA_GRBLHAL_SIM;
if (!bin) {
  console.log('SKIPPED simulator: set OFICINA_GRBLHAL_SIM to a grblHAL Simulator binary (grblHAL_sim: scripts/build-grblhal-sim builds one) to run the page against real firmware');
  console.log('0 passed, 0 failed');
  process.exit(0);
}
const { startSimulator } = await import('./sim-bridge.mjs');

const { test, state, finish } = suite('simulator');
const notes = [];
function note(control, what) {
  const line = `${control}: ${what}`.replace(/\s+/g, ' ').trim();
  notes.push(line);
  console.log(`note simulator: ${line}`);
}

const sim = await startSimulator(bin);
const banner = await sim.raw(['$I']);
note('firmware', (banner.match(/\[VER:[^\]]*\]|\[DRIVER[^\]]*\]|\[FIRMWARE:[^\]]*\]/g) || [banner]).join(' '));
const server = await startServer();
const browser = await launch();

// grblHAL's defaults in the Simulator: 500 mm/min on every axis, 10 mm/s², 250 steps/mm. A
// 20 mm square three times at F400 (about half a minute), then short lines to resume from.
const laps = Array.from({ length: 3 }, () => 'G1 X20 F400\nY20\nX0\nY0').join('\n');
const program = `G21 G90\nG0 Z5\nG0 X0 Y0\nG1 Z-1 F300\n${laps}\nG0 Z5\nG0 X1 Y1\nM2\n`;
const lines = program.trimEnd().split('\n').length;

async function openPage() {
  const page = await browser.newPage({ viewport: { width: 1600, height: 900 } });
  state.page = page;
  await page.goto(server.url);
  await page.waitForFunction(() => document.getElementById('summary').textContent.includes('errors'), null, { timeout: 30000 });
  return page;
}
const dro = (page) => page.evaluate(() => ['x', 'y', 'z'].map((a) => Number(document.getElementById('m' + a).textContent)));
const work = (page) => page.evaluate(() => ['x', 'y', 'z'].map((a) => Number(document.getElementById('w' + a).textContent)));
const waitState = (page, s, timeout = 30000) =>
  page.waitForFunction((s) => document.body.dataset.state === s, s, { timeout });
const pageState = (page) => page.evaluate(() => ({
  state: document.body.dataset.state,
  alarm: document.getElementById('alarm').hidden ? null : document.getElementById('alarm-text').textContent,
  meaning: document.getElementById('alarm-meaning').textContent,
  error: document.getElementById('error').textContent,
  job: document.body.dataset.jobDone,
}));
const consoleText = (page) => page.textContent('#console');
/// What the console gained since `before` (its text then), on one line.
const consoleSince = async (page, before) => (await consoleText(page)).slice(before.length).trim().split('\n').slice(-8).join(' | ');

async function connect(page, uri) {
  page.once('dialog', (d) => d.accept(uri));
  await page.selectOption('#machine-uri', '');
  await page.click('#connect');
  await page.waitForFunction((a) => document.getElementById('machine-name').textContent.includes(a), uri.replace('tcp://', ''), { timeout: 20000 })
    .catch(async () => { throw new Error(`the board's address is not shown: ${await page.textContent('#machine-name')} ${await page.textContent('#error')}`); });
}

/// Types `text` into the editor and resolves with the check's summary (the old one cleared
/// first, so that it is this program's).
async function load(page, text) {
  await page.$eval('#summary', (e) => { e.textContent = ''; });
  await page.fill('#text', text);
  await page.waitForFunction(() => document.getElementById('summary').textContent.includes('errors'), null, { timeout: 30000 });
  return page.textContent('#summary');
}

let page;

await test('connect shows grblHAL and a live position; a jog moves it', async () => {
  page = await openPage();
  await connect(page, sim.uri);
  await waitState(page, 'idle');
  const name = await page.textContent('#machine-name');
  note('connect', `works: "${name}"`);
  assert(name.includes('grbl 1.1'), `the firmware is named: ${name}`);
  const before = await dro(page);
  assert(before.every(Number.isFinite), `the DRO shows numbers: ${before}`);
  await page.selectOption('#jog-step', '10');
  await page.click('#jog button[data-jog="1,0,0"]');
  await page.waitForFunction((x0) => Math.abs(Number(document.getElementById('mx').textContent) - x0 - 10) < 1e-3,
    before[0], { timeout: 20000 });
  await waitState(page, 'idle');
  await page.click('#jog button[data-jog="-1,0,0"]');
  await page.waitForFunction((x0) => Math.abs(Number(document.getElementById('mx').textContent) - x0) < 1e-3,
    before[0], { timeout: 20000 });
  await waitState(page, 'idle');
  note('jog (step)', 'works: X+10 then X-10, the DRO follows');
  await page.screenshot({ path: path.join(out, 'simulator-connected.png') });
});

await test('start, hold, resume, feed override and stop a program', async () => {
  const summary = await load(page, program);
  assert(summary.includes('0 errors'), `the program checks: ${summary}`);
  await page.click('#start');
  await waitState(page, 'run');
  // On firmware the page's line is the last one acknowledged: grblHAL takes the whole
  // program at once. The position says where the cut is: on the first side.
  const shownLine = await page.textContent('#line');
  await page.waitForFunction(() => Number(document.getElementById('mx').textContent) > 2, null, { timeout: 30000 });
  note('line shown while cutting line 5', `${await page.textContent('#line')} (just after start: ${shownLine})`);
  const t0 = Date.now();
  await page.click('#hold');
  // The Simulator may take long to report a finished hold (Hold:1 → Hold:0): see the notes.
  await waitState(page, 'hold', 90000);
  note('hold', `works: Hold:0 reported ${((Date.now() - t0) / 1000).toFixed(1)} s after the click`);
  const held = await dro(page);
  await sleep(1000);
  const still = await dro(page);
  assert(held.every((v, i) => Math.abs(v - still[i]) < 1e-6), `nothing moves in a hold: ${held} then ${still}`);
  await page.click('#resume');
  await waitState(page, 'run');
  await sleep(500);
  const moving = await dro(page);
  await sleep(700);
  const later = await dro(page);
  assert(moving.some((v, i) => Math.abs(v - later[i]) > 1e-3), `it moves again after resume: ${moving} then ${later}`);
  await page.$eval('#fo', (e) => { e.value = '150'; e.dispatchEvent(new Event('input')); e.dispatchEvent(new Event('change')); });
  await page.waitForFunction(() => document.body.dataset.feedOverride === '150', null, { timeout: 15000 });
  const feed = Number(await page.textContent('#feed'));
  note('feed override', `works: Ov 150 reported, F ${feed} (F400 × 1.5 is capped by $110=500)`);
  await page.screenshot({ path: path.join(out, 'simulator-running.png') });
  await page.$eval('#fo', (e) => { e.value = '100'; e.dispatchEvent(new Event('input')); e.dispatchEvent(new Event('change')); });
  await page.waitForFunction(() => document.body.dataset.feedOverride === '100', null, { timeout: 15000 });
  await page.click('#stop');
  await page.waitForFunction(() => document.body.dataset.jobDone === 'stopped', null, { timeout: 30000 });
  await waitState(page, 'idle');
  note('start / hold / resume / stop', `works; stopped at line ${await page.textContent('#line')}, machine ${await dro(page)}`);
});

await test('the server answers once the tab is closed, and a new tab finds the Simulator where it was', async () => {
  const where = await dro(page);
  await page.close();
  await sleep(500);
  for (let i = 0; i < 3; i++) {
    const r = await fetch(`${server.origin}/api/info`, { signal: AbortSignal.timeout(5000) });
    assert(r.ok, `the server answers: ${r.status}`);
    await sleep(200);
  }
  page = await openPage();
  await page.waitForFunction((a) => document.getElementById('machine-name').textContent.includes(a), sim.uri.replace('tcp://', ''), { timeout: 15000 });
  await waitState(page, 'idle');
  const again = await dro(page);
  assert(where.every((v, i) => Math.abs(v - again[i]) < 1e-3), `the Simulator is where it was: ${where} vs ${again}`);
});

await test('resume from a line runs to the end', async () => {
  await load(page, program);
  await page.fill('#from-line', String(lines - 6));
  await page.click('#start');
  await page.waitForFunction(() => document.body.dataset.jobDone === 'completed', null, { timeout: 120000 });
  await waitState(page, 'idle');
  const end = await work(page);
  assert(Math.abs(end[0] - 1) < 1e-3 && Math.abs(end[1] - 1) < 1e-3 && Math.abs(end[2] - 5) < 1e-3, `ends at X1 Y1 Z5: ${end}`);
  assert((await page.inputValue('#from-line')) === '', 'from line resets after the job');
  note('resume from a line', `works: from line ${lines - 6} to the end, at work ${end}`);
});

// The other controls: what the Simulator answers is recorded.

await test('probing (G38.2) in a program: the Simulator has no probe input and alarms', async () => {
  const summary = await load(page, 'G21 G91\nG38.2 Z-2 F100\nG90\nM2\n');
  note('probe: check', `the page's check of G38.2: ${summary}`);
  const before = await consoleText(page);
  await page.click('#start');
  await page.waitForFunction(() => document.body.dataset.state === 'alarm' || document.body.dataset.jobDone !== '', null, { timeout: 60000 });
  await sleep(1000);
  const s = await pageState(page);
  note('probe (G38.2 Z-2)', `state ${s.state}, alarm "${s.alarm}" (${s.meaning}), job ${s.job || 'running'}, error "${s.error}"; console: ${await consoleSince(page, before)}`);
  await page.screenshot({ path: path.join(out, 'simulator-probe.png') });
  assert(s.state === 'alarm' && /5/.test(s.alarm || ''), `a probe that touches nothing is grbl's ALARM:5: ${JSON.stringify(s)}`);
});

await test('unlock clears the alarm', async () => {
  const before = await consoleText(page);
  assert(await page.isVisible('#unlock'), 'the Unlock button shows in an alarm');
  await page.click('#unlock');
  await waitState(page, 'idle', 15000);
  note('unlock', `works: alarm cleared ($X); console: ${await consoleSince(page, before)}`);
});

await test('home and zero on firmware (recorded)', async () => {
  const home = await page.$eval('#home', (b) => ({ disabled: b.disabled, title: b.title }));
  const zero = await page.$eval('#zero', (b) => ({ disabled: b.disabled, title: b.title }));
  note('home button', home.disabled ? 'disabled on firmware (the server: "home real firmware from its console ($H)")' : 'enabled');
  note('zero XYZ button', zero.disabled ? 'disabled on firmware (the server: "set real firmware\'s work zero from its console (G10 L20 P1 X0 Y0 Z0)")' : 'enabled');
  const speed = await page.$eval('#speed', (s) => s.disabled);
  note('speed select', speed ? 'disabled on firmware (it runs at its own pace)' : 'enabled');
  // $H as a program line, homing off ($22=0, grblHAL's default).
  let summary = await load(page, '$H\n');
  note('$H in a program: check', summary);
  let before = await consoleText(page);
  const startable = await page.$eval('#start', (b) => !b.disabled);
  if (startable) {
    await page.click('#start');
    await page.waitForFunction(() => document.body.dataset.jobDone !== '' || document.body.dataset.state === 'alarm', null, { timeout: 30000 }).catch(() => {});
    await sleep(1000);
    const s = await pageState(page);
    note('$H, homing off', `state ${s.state}, job ${s.job || 'running'}, error "${s.error}"; console: ${await consoleSince(page, before)}`);
  } else {
    note('$H, homing off', 'Start stays disabled: the page refuses the program');
  }
  // Homing on, with 10 mm of travel (a search of 15 mm per axis): set directly on the
  // Simulator while the page's server holds the virtual machine instead.
  await page.selectOption('#machine-uri', 'virtual');
  await page.click('#connect');
  await page.waitForFunction(() => !document.getElementById('machine-name').textContent.includes('tcp'), null, { timeout: 15000 });
  await sleep(1500);
  const set = await sim.raw(['$22=1', '$130=10', '$131=10', '$132=10', '\x18'], 500);
  note('homing settings', set.trim().split('\n').join(' | '));
  await connect(page, sim.uri);
  await page.waitForFunction(() => ['idle', 'alarm'].includes(document.body.dataset.state), null, { timeout: 15000 });
  const after = await pageState(page);
  note('reconnect with homing on', `state ${after.state}, alarm "${after.alarm}"`);
  if (after.state === 'alarm') { await page.click('#unlock'); await waitState(page, 'idle', 15000).catch(() => {}); }
  summary = await load(page, '$H\n');
  before = await consoleText(page);
  if (await page.$eval('#start', (b) => !b.disabled)) {
    const t0 = Date.now();
    await page.click('#start');
    await page.waitForFunction(() => document.body.dataset.jobDone !== '' || document.body.dataset.state === 'alarm', null, { timeout: 60000 }).catch(() => {});
    await sleep(1000);
    const s = await pageState(page);
    note('$H, homing on', `after ${((Date.now() - t0) / 1000).toFixed(1)} s: state ${s.state}, alarm "${s.alarm}", job ${s.job || 'running'}, machine ${await dro(page)}, error "${s.error}"; console: ${await consoleSince(page, before)}`);
    await page.screenshot({ path: path.join(out, 'simulator-home.png') });
    if (s.state === 'alarm') { await page.click('#unlock').catch(() => {}); await waitState(page, 'idle', 15000).catch(() => {}); }
  }
});

await test('spindle override and continuous jog (recorded)', async () => {
  await waitState(page, 'idle', 15000);
  let before = await consoleText(page);
  await page.$eval('#so', (e) => { e.value = '150'; e.dispatchEvent(new Event('input')); e.dispatchEvent(new Event('change')); });
  await sleep(1500);
  note('spindle override', `sent (150 %); the page shows no reported spindle override; error "${(await pageState(page)).error}"; console: ${await consoleSince(page, before)}`);
  await page.$eval('#so', (e) => { e.value = '100'; e.dispatchEvent(new Event('input')); e.dispatchEvent(new Event('change')); });
  await page.selectOption('#jog-step', 'continuous');
  const x0 = (await dro(page))[0];
  before = await consoleText(page);
  const b = await page.$('#jog button[data-jog="-1,0,0"]');
  const box = await b.boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  await sleep(1500);
  const during = await pageState(page);
  await page.mouse.up();
  await page.waitForFunction(() => document.body.dataset.state === 'idle', null, { timeout: 15000 }).catch(() => {});
  await sleep(500);
  const x1 = (await dro(page))[0];
  const s = await pageState(page);
  note('continuous jog (hold X− 1.5 s)', `state while held ${during.state}, then ${s.state}; X ${x0} → ${x1}; error "${s.error}"; console: ${await consoleSince(page, before)}`);
  assert(s.state === 'idle' && x1 < x0 - 0.1, `a held jog button moves and stops: X ${x0} → ${x1}, ${JSON.stringify(s)}`);
});

await test('the Simulator outlives the server leaving it', async () => {
  await page.close();
  await browser.close();
  server.proc.kill('SIGKILL');
  await sleep(1500);
  assert(sim.alive(), 'the Simulator still runs');
  const answer = await sim.raw(['?']);
  assert(/<(Idle|Alarm)\|/.test(answer), `it still answers: ${answer}`);
});

writeFileSync(path.join(out, 'simulator-notes.txt'), notes.join('\n') + '\n');
sim.stop();
finish();
