// Browser tests of the machine panel's controls on real firmware (the grbl emulator as grbl,
// grblHAL and FluidNC) and on the virtual machine: typed lines, work offsets, home, unlock,
// soft reset, keyboard jog, macros, and a watching page that may hold and stop but not move.
// Starts its own `oficina serve` (fresh job folder) and `oficina emulate grbl` per flavour
// with harness.mjs; only the page's visible controls are used (clicks and keys). Prints
// `N passed, M failed`; screenshots go to web/test-output/.

import { startServer, startEmulator, launch, suite, assert, out, connectBoard, mdi } from './harness.mjs';
import path from 'node:path';

const flavours = (process.env.OFICINA_FLAVOURS || 'grbl,grblhal,fluidnc').split(',');

const { test, state, finish } = suite('controls');
let server;
try {
  server = await startServer();
} catch (e) {
  console.log(`FAIL the server starts: ${e.message}`);
  console.log('controls: 0 passed, 1 failed');
  process.exit(1);
}
const url = server.url;

const browser = await launch();
const page = await browser.newPage({ viewport: { width: 1600, height: 1000 } });
state.page = page;
const pageErrors = [];
page.on('pageerror', (e) => pageErrors.push(String(e)));

const shot = (p, name) => p.screenshot({ path: path.join(out, `${name}.png`) });
const num = (p, id) => p.$eval('#' + id, (e) => Number(e.textContent));
const near = (a, b) => Math.abs(a - b) < 1e-3;
async function waitDro(p, want, timeout = 20000) {
  // want: { wx: 5, my: 0, … }
  await p.waitForFunction((w) => Object.entries(w).every(([id, v]) => Math.abs(Number(document.getElementById(id).textContent) - v) < 1e-3)
    && document.body.dataset.state === 'idle', want, { timeout });
}
async function waitState(p, s, timeout = 20000) {
  await p.waitForFunction((s) => document.body.dataset.state === s, s, { timeout });
}
/// Presses a key with the focus on the page, outside any text field.
async function key(p, k) {
  await p.click('#dro');
  await p.keyboard.press(k);
}
const offsetRow = (p, name) => p.$$eval(`#offsets tr[data-row="${name}"] td`, (tds) => tds.map((t) => Number(t.textContent)));
const errorText = (p) => p.textContent('#error');

await test('the page opens and controls the machine', async () => {
  await page.goto(url);
  await page.waitForFunction(() => document.getElementById('control').textContent.includes('controlling'), null, { timeout: 20000 });
  assert(await page.isVisible('#mdi') && await page.isVisible('#jog-hint'), 'typed lines and the key hint are shown');
});

for (const flavour of flavours) {
  let emu = null;
  const t = (name, fn) => test(`${flavour}: ${name}`, fn);
  await t('connect to the emulator; a jog moves the DRO', async () => {
    emu = await startEmulator(flavour,
      ['--set', '110=6000', '--set', '111=6000', '--set', '112=3000', '--set', '120=800', '--set', '121=800', '--set', '122=800']);
    await connectBoard(page, emu.uri);
    await waitDro(page, { mx: 0, my: 0, mz: 0 });
    await page.selectOption('#jog-step', '1');
    await page.fill('#jog-feed', '3000');
    await page.click('#jog button[data-jog="1,0,0"]');
    await waitDro(page, { mx: 1, my: 0 });
  });
  await t('typed G0 X5 Y3 moves there and the console says ok', async () => {
    await mdi(page, 'G0 X5 Y3');
    await waitDro(page, { wx: 5, wy: 3, mx: 5 });
    await mdi(page, 'G1 X1', 'error:22 (Undefined feed rate');
  });
  await t('$# fills the offsets table', async () => {
    await mdi(page, '$#');
    assert((await page.textContent('#console')).includes('[G54:0.000,0.000,0.000]'), 'the reply is in the console');
    assert((await offsetRow(page, 'G54')).join() === '0,0,0', 'G54 row');
    assert((await page.$$('#offsets tr[data-row]')).length >= 6, 'six systems');
  });
  await t('zero X alone: work X 0, Y stays', async () => {
    await page.click('#zero-x');
    await waitDro(page, { wx: 0, wy: 3 });
    await page.waitForFunction(() => document.querySelector('#offsets tr[data-row="G54"] td').textContent === '5.000', null, { timeout: 10000 });
  });
  await t('G55 chosen and zeroed whole: G55 shown, G54 unchanged', async () => {
    await page.selectOption('#wcs', '1');
    await page.waitForFunction(() => document.querySelector('#offsets tr.active')?.dataset.row === 'G55', null, { timeout: 10000 });
    await mdi(page, 'G0 X2');
    await waitDro(page, { wx: 2, mx: 2 });
    await page.click('#zero');
    await waitDro(page, { wx: 0, wy: 0, wz: 0 });
    await page.waitForFunction(() => document.querySelector('#offsets tr[data-row="G55"] td').textContent === '2.000', null, { timeout: 10000 });
    assert((await offsetRow(page, 'G54')).join() === '5,0,0', `G54 stays: ${await offsetRow(page, 'G54')}`);
    assert((await offsetRow(page, 'G55')).join() === '2,3,0', `G55: ${await offsetRow(page, 'G55')}`);
    assert(await page.$eval('#wcs', (s) => s.value) === '1', 'the select shows G55');
    await shot(page, `controls-${flavour}-offsets`);
  });
  await t('go to zero: XY back to the work zero', async () => {
    await mdi(page, 'G0 X10 Y8');
    await waitDro(page, { wx: 10, wy: 8 });
    await page.click('#goto-zero');
    await waitDro(page, { wx: 0, wy: 0, mx: 2, my: 3 });
  });
  await t('home: refused with $22=0 and explained, then homes', async () => {
    await page.click('#home');
    await page.waitForFunction(() => document.getElementById('error').textContent.includes('$22=1'), null, { timeout: 10000 });
    assert((await errorText(page)).includes('homing is not enabled'), await errorText(page));
    await mdi(page, '$22=1');
    await page.click('#home');
    await waitDro(page, { mx: 0, my: 0, mz: 0 });
  });
  await t('soft reset while moving: alarm, then unlock', async () => {
    await mdi(page, 'G1 X-150 F300');
    await waitState(page, 'run');
    await page.click('#reset');
    await waitState(page, 'alarm');
    assert(await page.isVisible('#alarm'), 'the alarm is shown');
    await shot(page, `controls-${flavour}-alarm`);
    await page.click('#unlock');
    await waitState(page, 'idle');
    // The reset made G54 active again.
    await page.waitForFunction(() => document.getElementById('wcs').value === '0', null, { timeout: 10000 });
  });
  await t('keyboard jog: ArrowRight steps X+1; held ArrowUp moves until released', async () => {
    await page.selectOption('#jog-step', '1');
    const x0 = await num(page, 'mx'), y0 = await num(page, 'my');
    await key(page, 'ArrowRight');
    await waitDro(page, { mx: x0 + 1, my: y0 });
    // `]` twice: 10, then hold to move.
    await key(page, ']');
    await page.keyboard.press(']');
    assert(await page.$eval('#jog-step', (s) => s.value) === 'continuous', 'the step keys switch to hold to move');
    await page.fill('#jog-feed', '600');
    await page.click('#dro');
    await page.keyboard.down('ArrowUp');
    await page.waitForFunction((y) => Number(document.getElementById('my').textContent) > y + 1, y0, { timeout: 20000 });
    await page.keyboard.up('ArrowUp');
    await waitState(page, 'idle');
    const y1 = await num(page, 'my');
    await page.waitForTimeout(400);
    assert(near(await num(page, 'my'), y1), 'it stays where it stopped');
    assert(y1 - y0 > 1 && y1 - y0 < 100, `moved ${y1 - y0} mm`);
    // Typing in a field does not jog.
    await page.click('#mdi');
    await page.keyboard.press('ArrowRight');
    await page.waitForTimeout(300);
    assert(near(await num(page, 'mx'), x0 + 1), 'no jog while typing');
    await page.selectOption('#jog-step', '1');
  });
  await t('macros: saved, run with [x+1], unknown parameters refused', async () => {
    const details = await page.$('#macro-editor');
    if (!(await details.evaluate((d) => d.open))) await page.click('#macro-editor summary');
    const rows = await page.$$('#macro-list .macro-row');
    if (rows.length === 0) {
      await page.click('#macro-add');
      await page.fill('#macro-list .macro-row:last-child .macro-name', 'bad');
      await page.fill('#macro-list .macro-row:last-child .macro-text', 'G0 X[wx]');
      await page.click('#macro-save');
      await page.waitForFunction(() => document.getElementById('macro-message').textContent.includes('unknown parameter [wx]'), null, { timeout: 10000 });
      await page.fill('#macro-list .macro-row:last-child .macro-name', 'X plus 1');
      await page.fill('#macro-list .macro-row:last-child .macro-text', 'G0 X[x+1] Y[y]');
      await page.click('#macro-add');
      await page.fill('#macro-list .macro-row:last-child .macro-name', 'to probe');
      await page.fill('#macro-list .macro-row:last-child .macro-text', 'G0 X[prb_x]');
      await page.click('#macro-save');
      await page.waitForFunction(() => document.getElementById('macro-message').textContent === 'saved 2 macros', null, { timeout: 10000 });
    }
    await mdi(page, 'G0 X3 Y2');
    await waitDro(page, { wx: 3, wy: 2 });
    await page.click('#macro-buttons button[title^="G0 X[x+1]"]');
    await waitDro(page, { wx: 4, wy: 2 });
    assert((await page.textContent('#console')).includes('> G0 X4 Y2'), 'the expanded line is in the console');
    // The emulator has no probe touch: the macro says so and sends nothing.
    await page.click('#macro-buttons button[title^="G0 X[prb_x]"]');
    await page.waitForFunction(() => document.getElementById('error').textContent.includes('prb_x'), null, { timeout: 10000 });
    await shot(page, `controls-${flavour}-macros`);
  });
  await t('a watching page may hold and stop (reset) but not jog or type', async () => {
    const ctx = await browser.newContext({ viewport: { width: 1400, height: 1000 } });
    const other = await ctx.newPage();
    await other.goto(url);
    await other.waitForFunction(() => document.getElementById('control').textContent.includes('watching'), null, { timeout: 20000 });
    await other.waitForFunction(() => document.getElementById('mx').textContent !== '', null, { timeout: 20000 });
    assert(await other.isDisabled('#jog button[data-jog="1,0,0"]') && await other.isDisabled('#mdi') && await other.isDisabled('#home'), 'moving needs control');
    const x0 = await num(other, 'mx');
    await other.click('#dro');
    await other.keyboard.press('ArrowRight');
    await other.waitForTimeout(500);
    assert(near(await num(other, 'mx'), x0), 'a watcher\'s keys do not jog');
    await mdi(page, 'G1 X-100 F200');
    await waitState(other, 'run');
    assert(!(await other.isDisabled('#hold')), 'a watcher may hold');
    await other.click('#hold');
    await waitState(other, 'hold');
    await shot(other, `controls-${flavour}-watcher`);
    await other.click('#reset');
    await other.waitForFunction(() => ['idle', 'alarm'].includes(document.body.dataset.state), null, { timeout: 20000 });
    await ctx.close();
    if ((await page.evaluate(() => document.body.dataset.state)) === 'alarm') await page.click('#unlock');
    await waitState(page, 'idle');
  });
  if (emu) emu.stop();
}

await test('virtual machine: typed lines, $ refused, offsets in G54 and G55, go to zero, home', async () => {
  await page.selectOption('#machine-uri', 'virtual');
  await page.click('#connect');
  await page.waitForFunction(() => document.getElementById('machine-name').textContent.includes('virtual machine'), null, { timeout: 20000 });
  await waitState(page, 'idle');
  const home = [await num(page, 'mx'), await num(page, 'my'), await num(page, 'mz')];
  await mdi(page, 'G0 X5 Y3');
  await waitDro(page, { wx: 5, wy: 3 });
  await page.click('#mdi');
  await page.keyboard.type('$$');
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => document.getElementById('error').textContent.includes('no firmware $ commands'), null, { timeout: 10000 });
  await page.click('#zero-x');
  await waitDro(page, { wx: 0, wy: 3 });
  const mx = await num(page, 'mx');
  await page.selectOption('#wcs', '1');
  await page.waitForFunction(() => document.querySelector('#offsets tr.active')?.dataset.row === 'G55', null, { timeout: 10000 });
  await mdi(page, 'G53 G0 X20');
  await page.click('#zero');
  await waitDro(page, { wx: 0, wy: 0, wz: 0, mx: 20 });
  assert(near((await offsetRow(page, 'G54'))[0], mx), `G54 X stays ${mx}: ${await offsetRow(page, 'G54')}`);
  assert(near((await offsetRow(page, 'G55'))[0], 20), `G55 X 20: ${await offsetRow(page, 'G55')}`);
  await mdi(page, 'G0 X4 Y-2');
  await waitDro(page, { wx: 4, wy: -2, mx: 24 });
  await page.click('#goto-zero');
  await waitDro(page, { wx: 0, wy: 0, mx: 20 }, 30000);
  await shot(page, 'controls-virtual');
  await page.click('#home');
  await waitDro(page, { mx: home[0], my: home[1], mz: home[2] }, 30000);
});

await test('typed lines: Up and Down browse the history, kept across a reload', async () => {
  await page.reload();
  await page.waitForFunction(() => document.getElementById('control').textContent.includes('controlling'), null, { timeout: 20000 });
  await page.click('#mdi');
  await page.keyboard.press('ArrowUp');
  assert(await page.inputValue('#mdi') === 'G0 X4 Y-2', `last line: ${await page.inputValue('#mdi')}`);
  await page.keyboard.press('ArrowUp');
  assert(await page.inputValue('#mdi') === 'G53 G0 X20', `the one before: ${await page.inputValue('#mdi')}`);
  await page.keyboard.press('ArrowDown');
  await page.keyboard.press('ArrowDown');
  assert(await page.inputValue('#mdi') === '', 'back to an empty line');
});

await test('gamepad: the left stick pushed right jogs X+, released it stops', async () => {
  await waitState(page, 'idle');
  await page.fill('#jog-feed', '600');
  const x0 = await num(page, 'mx');
  await page.evaluate(() => {
    const pad = { id: 'test pad', axes: [0, 0, 0, 0], buttons: [] };
    window.__pad = pad;
    navigator.getGamepads = () => [pad];
    window.dispatchEvent(Object.assign(new Event('gamepadconnected'), { gamepad: pad }));
  });
  assert((await page.textContent('#gamepad-hint')).includes('test pad'), 'the hint names the gamepad');
  await page.evaluate(() => { window.__pad.axes[0] = 1; });
  await page.waitForFunction((x) => Number(document.getElementById('mx').textContent) > x + 1, x0, { timeout: 20000 });
  await page.evaluate(() => { window.__pad.axes[0] = 0; });
  await waitState(page, 'idle');
  const x1 = await num(page, 'mx');
  await page.waitForTimeout(400);
  assert(near(await num(page, 'mx'), x1) && x1 - x0 < 100, `stopped at ${x1} from ${x0}`);
});

await test('virtual machine: a watching page stops the running job', async () => {
  await waitState(page, 'idle');
  await page.selectOption('#speed', '1');
  await page.click('#start');
  await waitState(page, 'run');
  const ctx = await browser.newContext({ viewport: { width: 1400, height: 1000 } });
  const other = await ctx.newPage();
  await other.goto(url);
  await other.waitForFunction(() => document.getElementById('control').textContent.includes('watching') && document.body.dataset.state === 'run', null, { timeout: 20000 });
  assert(await other.isDisabled('#start') && await other.isDisabled('#mdi'), 'a watcher cannot start or type');
  await other.click('#stop');
  await page.waitForFunction(() => document.body.dataset.jobDone === 'stopped', null, { timeout: 20000 });
  await waitState(page, 'idle');
  await ctx.close();
});

await test('no script errors in the page', async () => {
  assert(pageErrors.length === 0, pageErrors.join('\n'));
});

await browser.close();
finish();
