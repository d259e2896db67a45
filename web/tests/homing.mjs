// Homing on firmware through the page, against the grbl emulator with homing on ($22=1): the
// cycle runs beside the server, so the DRO follows the machine home (Z first, then X and Y)
// and says `home`, the server answers other requests meanwhile, another page sees it and
// may stop it (ALARM:6); a board without limit switches fails its search with ALARM:9, said
// in words. Clicks and keys only.

import { startServer, startEmulator, launch, suite, assert, out, openPage, dro, waitState, connectBoard, mdi } from './harness.mjs';
import path from 'node:path';

const { test, state, finish } = suite('homing');
const server = await startServer();
// Homing on; seeking at 1500 mm/min, so a cycle from 40 mm down and 120 mm out takes ~6 s.
const fast = ['--set', '110=6000', '--set', '111=6000', '--set', '112=3000', '--set', '120=800', '--set', '121=800', '--set', '122=800'];
const board = await startEmulator('grbl', ['--set', '22=1', '--set', '25=1500', ...fast]);
const browser = await launch();
const page = await openPage(browser, server, state);
const near = (a, b) => Math.abs(a - b) < 1e-3;
/// The DRO at machine `want` and the machine idle.
const waitAt = (want, timeout = 30000) => page.waitForFunction((w) => document.body.dataset.state === 'idle'
  && ['mx', 'my', 'mz'].every((id, i) => Math.abs(Number(document.getElementById(id).textContent) - w[i]) < 1e-3), want, { timeout });

await test('a board with homing on starts in alarm; unlocked, it moves away', async () => {
  await connectBoard(page, board.uri);
  await waitState(page, 'alarm');
  assert(await page.isVisible('#alarm'), 'the alarm is shown');
  assert(!(await page.isDisabled('#home')), 'Home is offered in alarm');
  await page.click('#unlock');
  await waitState(page, 'idle');
  await mdi(page, 'G0 X-120 Y-80 Z-40');
  await waitAt([-120, -80, -40]);
});

await test('Home: the DRO follows the cycle, the server answers meanwhile, another page sees it', async () => {
  const other = await browser.newPage({ viewport: { width: 1400, height: 900 } });
  await other.goto(server.url);
  await other.waitForFunction(() => document.getElementById('control').textContent.includes('watching'), null, { timeout: 20000 });
  // What the page shows, sampled as it shows it.
  await page.evaluate(() => {
    window.__homing = [];
    window.__sampler = setInterval(() => window.__homing.push([document.body.dataset.state,
      ...['mx', 'my', 'mz'].map((id) => Number(document.getElementById(id).textContent))]), 50);
  });
  await page.click('#home');
  await waitState(page, 'home', 5000);
  // Another request while the cycle runs: the check takes the session, as every request does.
  const t0 = Date.now();
  const r = await fetch(`${server.origin}/api/check`, { method: 'POST', body: 'G21 G90\nG1 X10 F100\n', headers: { Origin: server.origin }, signal: AbortSignal.timeout(10000) });
  const took = Date.now() - t0;
  assert(r.ok && (await r.json()).errors === 0, `the check is answered: ${r.status}`);
  assert(took < 1500, `answered in ${took} ms while homing`);
  assert(await page.evaluate(() => document.body.dataset.state) === 'home', 'still homing when it was answered');
  await waitState(other, 'home', 5000);
  assert(!(await other.isDisabled('#stop')), 'a watching page may stop the cycle');
  // Mid-cycle: Z on its way up.
  await page.waitForFunction(() => document.body.dataset.state === 'home' && Number(document.getElementById('mz').textContent) > -30, null, { timeout: 10000 });
  await page.screenshot({ path: path.join(out, 'homing.png') });
  await waitAt([0, 0, 0]);
  const samples = await page.evaluate(() => { clearInterval(window.__sampler); return window.__homing; });
  const homing = samples.filter((s) => s[0] === 'home');
  const distinct = new Set(homing.map((s) => s.slice(1).join())).size;
  assert(distinct >= 5, `the DRO moved while homing: ${distinct} positions in ${homing.length} samples`);
  // Z first: X leaves -120 only once Z is home.
  const xMoving = homing.find((s) => s[1] > -119);
  assert(xMoving && near(xMoving[3], 0), `Z home before X moves: ${JSON.stringify(xMoving)}`);
  assert((await page.textContent('#console')).includes('home: homed'), 'the console says it is home');
  await other.close();
});

await test('Stop from another page during homing: ALARM:6 in words, then unlock', async () => {
  await mdi(page, 'G0 X-60 Z-40');
  await waitAt([-60, 0, -40]);
  const other = await browser.newPage({ viewport: { width: 1400, height: 900 } });
  await other.goto(server.url);
  await other.waitForFunction(() => document.getElementById('control').textContent.includes('watching'), null, { timeout: 20000 });
  await page.click('#home');
  await waitState(other, 'home', 5000);
  await other.click('#stop');
  await waitState(page, 'alarm');
  await page.waitForFunction(() => document.getElementById('alarm-text').textContent.includes('ALARM:6'), null, { timeout: 10000 })
    .catch(async () => { throw new Error(`the alarm: ${await page.textContent('#alarm-text')}`); });
  assert((await page.textContent('#alarm-meaning')).includes('Homing fail'), await page.textContent('#alarm-meaning'));
  assert((await page.textContent('#console')).includes('stopped by the operator'), 'the console says who stopped it');
  const [, , z] = await dro(page);
  assert(z > -40 && z < 0, `stopped on the way up: Z ${z}`);
  await other.close();
  await page.click('#unlock');
  await waitState(page, 'idle');
});

await test('a board without limit switches: the search fails with ALARM:9, said in words', async () => {
  const bare = await startEmulator('grbl', ['--no-limit-switches', '--set', '22=1', '--set', '25=1500', '--set', '132=20', ...fast]);
  try {
    await connectBoard(page, bare.uri);
    await waitState(page, 'alarm');
    await page.click('#home');
    await waitState(page, 'home', 5000);
    await page.waitForFunction(() => document.getElementById('alarm-text').textContent.includes('ALARM:9'), null, { timeout: 20000 })
      .catch(async () => { throw new Error(`the alarm: ${await page.textContent('#alarm-text')} (state ${await page.evaluate(() => document.body.dataset.state)})`); });
    await waitState(page, 'alarm');
    await page.waitForFunction(() => document.getElementById('error').textContent.includes('homing failed: ALARM:9 (Homing fail'), null, { timeout: 10000 })
      .catch(async () => { throw new Error(`the error line: ${await page.textContent('#error')}`); });
    assert((await page.textContent('#alarm-meaning')).includes('limit switch'), await page.textContent('#alarm-meaning'));
    await page.screenshot({ path: path.join(out, 'homing-alarm.png') });
  } finally {
    bare.stop();
  }
});

await browser.close();
board.stop();
finish();
