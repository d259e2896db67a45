// Browser test of the Plot form's fills, hidden-line removal and passes (`oficina plot --fill
// --filled --occult --passes`): a real plotter file (AxiDraw's hatch-fill test sheet, from
// realworld/plot-svg) opened through the file control, plotted plain and then with fills and
// occult through the visible controls: the preview shows the hatch lines (many more pen-down
// moves) and the report's pen-down length grows by the area over the spacing. Starts its own
// `oficina serve` with web/dist. Prints `N passed, M failed`.

import { startServer, launch, suite, assert, out } from './harness.mjs';
import { existsSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
// Where oficina_testkit::realworld looks: $OFICINA_REALWORLD, beside the checkout, /work/shared.
const dirs = [process.env.OFICINA_REALWORLD, path.join(root, '../shared/data/realworld'), '/work/shared/data/realworld'];
const dir = dirs.find((d) => d && existsSync(path.join(d, 'plot-svg')));
const file = dir && path.join(dir, 'plot-svg', 'axidraw_Tests_for_Hatch_Fill.svg');
// Its closed shapes' area (holes taken out), mm², measured by shapely on svgelements' reading
// (crates/cli/tests/plot_peers.py `fill`): independent of our reader.
const AREA = 22209.7;

const { test, state, finish } = suite('plot fill');
if (!file || !existsSync(file)) {
  console.log('realworld/plot-svg is not here (set OFICINA_REALWORLD): plot fill test not run');
  finish();
  process.exit(0);
}
const server = await startServer();
const browser = await launch();

const report = async (page) => {
  const r = await page.textContent('#process-report');
  const m = r.match(/pen-down ([\d.]+) mm, pen-up ([\d.]+) mm/);
  assert(m, `the report says the pen-down length: ${r}`);
  return { down: Number(m[1]), up: Number(m[2]), text: r };
};

const plotted = async (page, n) => {
  await page.click('#make');
  await page.waitForFunction((n) => window.__oficina.stats.previews >= n && window.__oficina.stats.previewDone === window.__oficina.stats.previews && window.__oficina.preview.total > 0, n, { timeout: 120000 });
  return page.evaluate(() => window.__oficina.preview.kindCounts());
};

await test('a real plot SVG: plain, then hatch fill + occult through the form', async () => {
  const page = await browser.newPage({ viewport: { width: 1600, height: 900 } });
  state.page = page;
  await page.goto(server.url);
  await page.selectOption('#process', 'plot');
  await page.setInputFiles('#file-input', file);
  await page.waitForFunction(() => document.getElementById('process-input').textContent === 'axidraw_Tests_for_Hatch_Fill.svg', null, { timeout: 20000 });
  await page.fill('#process-fields [name="layout"]', 'a3');
  await page.check('#process-fields [name="landscape"]');
  await page.check('#process-fields [name="no_fit"]');
  const before = await page.evaluate(() => window.__oficina.stats.previews);
  const plain = await plotted(page, before + 1);
  const p = await report(page);
  // vpype reads 4864.4 mm of outline from this file (`vpype read F stat`).
  assert(Math.abs(p.down / 4864.4 - 1) < 0.005, `outlines as vpype reads them: ${p.text}`);

  await page.check('#process-fields [name="fill"]');
  await page.fill('#process-fields [name="fill_spacing"]', '2');
  await page.fill('#process-fields [name="fill_angle"]', '30');
  await page.selectOption('#process-fields [name="filled"]', 'closed');
  await page.check('#process-fields [name="occult"]');
  const n = await page.evaluate(() => window.__oficina.stats.previews);
  const filled = await plotted(page, n + 1);
  const f = await report(page);
  // Each hatch line is one pen-down stroke of one segment: the preview's pen-downs multiply.
  assert(filled.plunge > plain.plunge * 5 && filled.feed > plain.feed, `the preview shows the hatch lines: ${JSON.stringify({ plain, filled })}`);
  // Hatch lines 2 mm apart over the shapes: area / 2 of line, less what occult hides of
  // outlines (the shapes here do not overlap much: within 5 %).
  const hatch = f.down - p.down;
  assert(Math.abs(hatch / (AREA / 2) - 1) < 0.05, `hatch ${hatch.toFixed(1)} mm vs ${AREA / 2} mm: ${f.text}`);
  await page.click('#views button[data-view="xy"]');
  await page.waitForTimeout(300);
  await page.screenshot({ path: path.join(out, 'plot-fill.png') });

  // Two passes: twice the pen-down length, no more pen-up.
  await page.fill('#process-fields [name="passes"]', '2');
  await page.check('#process-fields [name="reloop"]');
  const m = await page.evaluate(() => window.__oficina.stats.previews);
  await plotted(page, m + 1);
  const two = await report(page);
  assert(Math.abs(two.down / f.down - 2) < 0.01, `two passes: ${two.text} after ${f.text}`);
});

await test('a hatch spacing too fine to draw is refused beside its field', async () => {
  const page = state.page;
  await page.fill('#process-fields [name="passes"]', '1');
  await page.fill('#process-fields [name="fill_spacing"]', '0.05');
  await page.fill('#process-fields [name="fill_angle"]', '0');
  // 0.05 mm over this sheet is within the line budget: allowed. The crop field: a bad box.
  await page.fill('#process-fields [name="crop"]', '1,2,3');
  await page.click('#make');
  await page.waitForFunction(() => document.querySelector('#process-fields .field-error[data-for="crop"]')?.textContent.includes('X0,Y0,X1,Y1'), null, { timeout: 30000 });
});

await browser.close();
finish();
