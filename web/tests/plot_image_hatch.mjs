// Browser test of the Plot form's picture hatching (`oficina plot PICTURE --fill
// --fill-concentric/--fill-cross --fill-angle --fill-spacing --hatch-layers --image-pens`): a
// real picture (realworld/relief-images) opened while Plot is chosen goes to the Plot form,
// not the relief form; hatched through the visible controls, concentric and then cross-hatched
// on two pens, the page's program is `oficina plot`'s for the same settings byte for byte, and
// the preview draws its pen-down moves. Starts its own `oficina serve`. Prints `N passed, M failed`.

import { startServer, launch, suite, assert, openPage, realworld, out, root } from './harness.mjs';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';

const { test, state, finish } = suite('plot image hatch');
const bin = path.resolve(process.env.OFICINA_BIN || path.join(root, 'target', 'debug', 'oficina'));
const FILE = 'osc_smiley.png';
const dir = realworld('relief-images', FILE);
if (!dir) {
  console.log(`SKIPPED plot image hatch: ${FILE} is not in the realworld relief-images folder`);
  console.log('0 passed, 0 failed');
  process.exit(0);
}
const scratch = mkdtempSync(path.join(os.tmpdir(), 'oficina-image-hatch-'));

/// `oficina plot FILE args…`'s program.
function cli(args) {
  const f = path.join(scratch, 'cli.ngc');
  execFileSync(bin, ['plot', path.join(dir, FILE), ...args, '-o', f], { stdio: 'ignore' });
  return readFileSync(f, 'utf8');
}

/// Makes the program from the form; resolves with it and the preview's move counts.
async function make(page) {
  const n = await page.evaluate(() => window.__oficina.stats.previews);
  await page.click('#make');
  await page.waitForFunction((n) => window.__oficina.stats.previews > n && window.__oficina.stats.previewDone === window.__oficina.stats.previews && window.__oficina.preview.total > 0, n, { timeout: 120000 });
  return { text: await page.inputValue('#text'), kinds: await page.evaluate(() => window.__oficina.preview.kindCounts()) };
}

const same = (made, expected, what) => assert(made.length > 0 && made === expected,
  `${what}: the page's program (${made.split('\n').length} lines) differs from the CLI's (${expected.split('\n').length} lines)`);

const server = await startServer();
const browser = await launch();
let page;

await test('a picture opened on the Plot form is hatched in concentric rings as the CLI does', async () => {
  page = await openPage(browser, server, state);
  await page.selectOption('#process', 'plot');
  await page.setInputFiles('#file-input', path.join(dir, FILE));
  await page.waitForFunction((f) => document.getElementById('process-input').textContent === f, FILE, { timeout: 20000 });
  assert(await page.isHidden('#relief-form'), 'the picture went to the Plot form, not the relief form');
  await page.check('#process-fields [name="fill"]');
  await page.check('#process-fields [name="fill_concentric"]');
  await page.fill('#process-fields [name="fill_spacing"]', '1.5');
  await page.fill('#process-fields [name="pixel"]', '0.4');
  await page.fill('#process-fields [name="hatch_layers"]', '4');
  const { text, kinds } = await make(page);
  same(text, cli(['--fill', '--fill-concentric', '--fill-spacing', '1.5', '--fill-angle', '45', '--pixel', '0.4', '--hatch-layers', '4']), 'concentric');
  // Rings are closed polylines of many points: far more pen-down moves than pen lifts.
  assert(kinds.feed > kinds.plunge * 20, `the preview draws the rings: ${JSON.stringify(kinds)}`);
  await page.click('#views button[data-view="xy"]');
  await page.waitForTimeout(300);
  await page.screenshot({ path: path.join(out, 'plot-image-concentric.png') });
});

await test('cross-hatched at an angle on two pens, as the CLI does', async () => {
  await page.uncheck('#process-fields [name="fill_concentric"]');
  await page.check('#process-fields [name="fill_cross"]');
  await page.fill('#process-fields [name="fill_angle"]', '30');
  await page.fill('#process-fields [name="hatch_layers"]', '3');
  await page.fill('#process-fields [name="image_pens"]', '#999999,#000000');
  const { text } = await make(page);
  same(text, cli(['--fill', '--fill-cross', '--fill-spacing', '1.5', '--fill-angle', '30', '--pixel', '0.4', '--hatch-layers', '3', '--image-pens', '#999999,#000000']), 'cross on two pens');
  assert(text.includes('(pen 1: #999999)') && text.includes('pen 2: #000000'), 'the bands on their pens');
  await page.screenshot({ path: path.join(out, 'plot-image-cross.png') });
});

await test('more pens than layers is refused beside the field', async () => {
  await page.fill('#process-fields [name="image_pens"]', 'a,b,c,d');
  await page.click('#make');
  await page.waitForFunction(() => (document.getElementById('process-status').textContent + document.querySelector('#process-fields .field-error[data-for="image_pens"]')?.textContent).includes('image-pens'), null, { timeout: 30000 });
});

await browser.close();
finish();
