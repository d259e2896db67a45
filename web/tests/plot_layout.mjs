// Browser test of the Plot form's page layout (`oficina plot --layout/--landscape/--margin/
// --no-fit` in the form): the sample design laid out on A4 inside 20 mm margins lands centred
// on the sheet; a page the server cannot read is marked on its field. Starts its own
// `oficina serve` with web/dist. Prints `N passed, M failed`.

import { startServer, launch, suite, assert, out } from './harness.mjs';
import path from 'node:path';

const server = await startServer();
const browser = await launch();
const { test, state, finish } = suite('plot layout');

const drawn = async (page) => {
  const report = await page.textContent('#process-report');
  const m = report.match(/drawing: ([\d.]+) × ([\d.]+) mm at \(([-\d.]+), ([-\d.]+)\)/);
  assert(m, report);
  const [w, h, x, y] = m.slice(1).map(Number);
  return [x, y, x + w, y + h];
};

await test('A4 inside 20 mm margins: centred and fitted', async () => {
  const page = await browser.newPage({ viewport: { width: 1600, height: 900 } });
  state.page = page;
  await page.goto(server.url);
  await page.selectOption('#process', 'plot');
  await page.waitForFunction(() => document.getElementById('process-input').textContent === 'design.svg', null, { timeout: 20000 });
  await page.fill('#process-fields [name="layout"]', 'a4');
  await page.fill('#process-fields [name="margin"]', '20');
  await page.click('#make');
  await page.waitForFunction(() => document.getElementById('program-name').textContent === 'design.plot.ngc', null, { timeout: 60000 });
  const b = await drawn(page);
  // Portrait A4 (210 × 297) at the travel's corner: inside the margins, touching one pair,
  // centred on the sheet (the report rounds to 0.1 mm).
  assert(b[0] >= 19.9 && b[1] >= 19.9 && b[2] <= 190.1 && b[3] <= 277.1, JSON.stringify(b));
  assert(Math.abs(b[0] - 20) < 0.11 || Math.abs(b[1] - 20) < 0.11, `fitted: ${JSON.stringify(b)}`);
  assert(Math.abs((b[0] + b[2]) / 2 - 105) < 0.1 && Math.abs((b[1] + b[3]) / 2 - 148.5) < 0.1, `centred: ${JSON.stringify(b)}`);
  await page.screenshot({ path: path.join(out, 'plot-layout.png') });
});

await test('a page the server cannot read is marked on the Page field', async () => {
  const page = state.page;
  await page.fill('#process-fields [name="layout"]', 'a9');
  await page.click('#make');
  await page.waitForFunction(() => document.querySelector('#process-fields .field-error[data-for="layout"]')?.textContent.includes("page 'a9'"), null, { timeout: 30000 });
});

await browser.close();
finish();
