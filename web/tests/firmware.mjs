// The page drives real firmware: for each flavour (grbl 1.1, grblHAL, FluidNC, as Oficina's
// emulator speaks them over TCP) a user connects through the machine list, sees the board's
// position move, loads and starts a program, holds, resumes, changes the feed override,
// stops, closes the tab (the server keeps answering and the board keeps its state), comes
// back, and resumes from a line to the end. Clicks and keys only, as a user would.

import { startServer, startEmulator, launch, suite, assert, sleep, out, root } from './harness.mjs';
import { squareProgram, openPage as open, closeAndReopen, dro, waitState } from './harness.mjs';
import path from 'node:path';

const { test, state, finish } = suite('firmware');
const server = await startServer();
const browser = await launch();

// A square traced ten times at 1 mm deep: long enough (about two minutes at F900) to hold,
// resume and stop in the middle, and short lines near the end to resume from.
const { program, lines } = squareProgram(10, 900);
const openPage = () => open(browser, server, state);

/// Opens a drawing and makes a plot of it (the *Plot* process, its default plotter).
async function plot(page) {
  await page.setInputFiles('#file-input', path.join(root, 'samples', 'mill', 'plate.svg'));
  // The drawing is read before the form is used: a click on Make before that makes nothing.
  await page.waitForFunction(() => document.getElementById('process-input').textContent === 'plate.svg', null, { timeout: 20000 });
  await page.selectOption('#process', 'plot');
  await page.click('#make');
  await page.waitForFunction(() => document.getElementById('program-name').textContent.endsWith('.plot.ngc'), null, { timeout: 60000 });
}

await test('a plot borrows the virtual machine for its plotter, says so, and gives it back', async () => {
  const page = await openPage();
  await page.waitForFunction(() => document.getElementById('machine-name').textContent.includes('virtual machine'), null, { timeout: 15000 });
  const before = await page.textContent('#machine-name');
  await plot(page);
  await page.waitForFunction(() => document.getElementById('machine-name').textContent.includes('pen plotter'), null, { timeout: 20000 });
  assert((await page.textContent('#console')).includes('the plotter this plot was made for (it was virtual'), 'the console says what it was');
  // Another program: the machine goes back.
  await page.selectOption('#sample', 'plate.nc');
  await page.waitForFunction((b) => document.getElementById('machine-name').textContent === b, before, { timeout: 20000 });
  assert((await page.textContent('#console')).includes('is virtual again'), 'the console says it went back');
  await page.close();
});

for (const flavor of ['grbl', 'grblhal', 'fluidnc']) {
  const board = await startEmulator(flavor);
  let page;

  await test(`${flavor}: connect shows the board and a live position`, async () => {
    page = await openPage();
    // The machine list's last entry asks for an address.
    page.once('dialog', (d) => d.accept(board.uri));
    await page.selectOption('#machine-uri', '');
    await page.click('#connect');
    const address = board.uri.replace('tcp://', '');
    await page.waitForFunction((a) => document.getElementById('machine-name').textContent.includes(a), address, { timeout: 15000 })
      .catch(async () => { throw new Error(`the board's address is not shown: ${await page.textContent('#machine-name')}`); });
    await waitState(page, 'idle');
    const name = await page.textContent('#machine-name');
    assert(name.includes(flavor === 'fluidnc' ? 'FluidNC' : 'grbl 1.1'), `the firmware is named: ${name}`);
    const before = await dro(page);
    assert(before.every(Number.isFinite), `the DRO shows numbers: ${before}`);
    // A jog the board makes is seen on the DRO: the position is the board's, live.
    await page.selectOption('#jog-step', '10');
    await page.click('#jog button[data-jog="1,0,0"]');
    await page.waitForFunction((x0) => Math.abs(Number(document.getElementById('mx').textContent) - x0 - 10) < 1e-3,
      before[0], { timeout: 15000 });
    await waitState(page, 'idle');
    await page.screenshot({ path: path.join(out, `firmware-${flavor}-connected.png`) });
  });

  if (flavor === 'grbl') {
    await test('grbl: a plot made while firmware is connected leaves the board and says so', async () => {
      await plot(page);
      await sleep(1000);
      assert((await page.textContent('#machine-name')).includes(board.uri.replace('tcp://', '')), 'still the board');
      assert((await page.textContent('#console')).includes('this plot was made for virtual:pen-plotter, but the connected machine is'), 'the page says so');
    });
  }

  await test(`${flavor}: start, hold, resume, feed override and stop a program`, async () => {
    await page.fill('#text', program);
    await page.waitForFunction(() => document.getElementById('summary').textContent.includes('0 errors'), null, { timeout: 30000 });
    await page.click('#start');
    await waitState(page, 'run');
    await page.waitForFunction(() => Number(document.getElementById('line').textContent) > 4, null, { timeout: 15000 });
    await page.click('#hold');
    await page.waitForFunction(() => document.body.dataset.state === 'hold', null, { timeout: 15000 });
    const held = await dro(page);
    await sleep(700);
    const still = await dro(page);
    assert(held.every((v, i) => Math.abs(v - still[i]) < 1e-6), `nothing moves in a hold: ${held} then ${still}`);
    await page.click('#resume');
    await waitState(page, 'run');
    await page.$eval('#fo', (e) => { e.value = '150'; e.dispatchEvent(new Event('input')); e.dispatchEvent(new Event('change')); });
    await page.waitForFunction(() => document.body.dataset.feedOverride === '150', null, { timeout: 15000 });
    // Firmware runs at its own pace: wall-clock times, no speed factor.
    assert(await page.isDisabled('#speed'), 'the speed factor is the virtual machine\'s only');
    await page.waitForFunction(() => document.getElementById('elapsed').textContent >= '0:00:02', null, { timeout: 15000 });
    assert((await page.textContent('#remaining')) !== '—', 'a remaining time is shown');
    await page.screenshot({ path: path.join(out, `firmware-${flavor}-running.png`) });
    await page.click('#stop');
    await page.waitForFunction(() => document.body.dataset.jobDone === 'stopped', null, { timeout: 30000 });
    await waitState(page, 'idle');
  });

  await test(`${flavor}: the server answers once the tab is closed, and a new tab finds the board`, async () => {
    page = await closeAndReopen(page, server, openPage, board.uri, 'the board');
  });

  await test(`${flavor}: resume from a line runs to the end`, async () => {
    await page.fill('#text', program);
    await page.waitForFunction(() => document.getElementById('summary').textContent.includes('0 errors'), null, { timeout: 30000 });
    await page.fill('#from-line', String(lines - 6));
    await page.click('#start');
    await page.waitForFunction(() => document.body.dataset.jobDone === 'completed', null, { timeout: 60000 });
    await waitState(page, 'idle');
    const end = await dro(page);
    // The program ends at work X1 Y1 Z5; the board's work offset is zero.
    const work = await page.evaluate(() => ['x', 'y', 'z'].map((a) => Number(document.getElementById('w' + a).textContent)));
    assert(Math.abs(work[0] - 1) < 1e-3 && Math.abs(work[1] - 1) < 1e-3 && Math.abs(work[2] - 5) < 1e-3, `ends at X1 Y1 Z5: ${work} (machine ${end})`);
    assert((await page.inputValue('#from-line')) === '', 'from line resets after the job');
    await page.close();
  });

  board.stop();
}

await browser.close();
finish();
