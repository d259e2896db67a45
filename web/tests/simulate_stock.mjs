// "Simulate stock" on a real program another CAM wrote (CAMotics' Botomata bottom, from
// realworld/gcode): opened through the page's Open… file input as a user would, simulated,
// and the shaded stock shown over the 3D view with its report. The render must have the
// stock's proportions and the report the program's lowest Z as the stock's lowest point.
// Without the shared data it prints SKIPPED and passes.

import { startServer, launch, suite, assert, out, realworld } from './harness.mjs';
import path from 'node:path';

const dir = realworld('gcode', 'camotics_botomata_bottom.nc');
if (!dir) {
  console.log('SKIPPED simulate_stock: realworld/gcode/camotics_botomata_bottom.nc is absent');
  console.log('0 passed, 0 failed');
  process.exit(0);
}

const { test, state, finish } = suite('simulate_stock');
const server = await startServer();
const browser = await launch();
const page = await browser.newPage({ viewport: { width: 1600, height: 1000 } });
state.page = page;

await test('a real program opened from disk is simulated and its stock shown', async () => {
  await page.goto(server.url);
  await page.waitForFunction(() => document.getElementById('summary').textContent.includes('errors'), null, { timeout: 30000 });
  await page.setInputFiles('#file-input', path.join(dir, 'camotics_botomata_bottom.nc'));
  await page.waitForFunction(() => document.getElementById('program-name').textContent.includes('botomata'), null, { timeout: 30000 });
  await page.fill('#stock-tool', 'flat:3.175');
  await page.click('#simulate');
  await page.waitForFunction(() => document.body.dataset.stock, null, { timeout: 120000 });
  const got = await page.evaluate(() => ({
    state: document.body.dataset.stock,
    status: document.getElementById('stock-status').textContent,
    report: document.getElementById('stock-report').textContent,
    w: document.getElementById('stock-render').naturalWidth,
    h: document.getElementById('stock-render').naturalHeight,
    visible: !document.getElementById('stock-view').hidden,
  }));
  assert(got.state === 'shown' && got.visible, `not shown: ${got.status}`);
  const size = got.report.match(/stock ([\d.]+) × ([\d.]+) × ([\d.]+) mm/);
  assert(size, `no stock size in ${got.report}`);
  const [sw, sh] = [Number(size[1]), Number(size[2])];
  // The render is the stock seen from above: width / height as the stock's, to a cell or two.
  assert(Math.abs(got.w / got.h - sw / sh) < 0.01, `render ${got.w}×${got.h} for a ${sw}×${sh} stock`);
  // The program cuts to Z-20 (its deepest pocket): the stock's lowest point is there.
  const z = got.report.match(/surface Z (-?[\d.]+) … (-?[\d.]+) \(program's lowest Z (-?[\d.]+)\)/);
  assert(z && Math.abs(Number(z[1]) - Number(z[3])) < 1e-3 && Number(z[3]) === -20, `depths: ${got.report}`);
  await page.screenshot({ path: path.join(out, 'simulate-stock.png') });
});

await browser.close();
finish();
