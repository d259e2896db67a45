// Issue #22's first "done when", in the workbench as a new user does it: the Embroidery
// process with its sample design (fills, satins, running stitches, three colours), a name typed
// in the Text field, made as PES, JEF, VP3 and DST in turn. Each time the report, the preview
// and the thread render show the stitches, and pyembroidery reads the downloaded file with the
// page's stitch count (skipped with a note when python3 lacks it). Starts its own
// `oficina serve` with web/dist. Screenshots land in web/test-output/; with
// OFICINA_DOCS_SCREENSHOTS=1 the page's one replaces docs/screenshots/
// workbench-embroidery-lettered.png. Prints `N passed, M failed`.

import { startServer, launch, suite, assert, out, root } from './harness.mjs';
import { spawnSync } from 'node:child_process';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';

const server = await startServer();
const browser = await launch();
const { test, state, finish } = suite('embroidery lettered');

const python = process.env.PYTHON || 'python3';
const hasPeer = spawnSync(python, ['-c', 'import pyembroidery']).status === 0;
if (!hasPeer) console.log(`note: pyembroidery checks skipped, ${python} lacks pyembroidery`);
// pyembroidery's sewn stitches, trims and colour changes. VP3's move after a trim is a
// stitch to pyembroidery and a jump to us (crates/stitch/tests/peer.rs): not counted here.
const COUNT = `
import sys, pyembroidery as P
p = P.read(sys.argv[1])
s = t = c = 0
prev = None
for x, y, cmd in p.stitches:
    k = cmd & P.COMMAND_MASK
    if k == P.STITCH and not (sys.argv[2] == 'vp3' and prev == P.TRIM):
        s += 1
    t += k == P.TRIM
    c += k == P.COLOR_CHANGE
    prev = k
print(s, t, c)
`;
const scratch = mkdtempSync(path.join(os.tmpdir(), 'oficina-lettered-'));

let page;
let plain = 0;
let plainHeight = 0;
const previewHeight = () => page.evaluate(() => { const b = window.__oficina.preview.bounds(); return b.max[1] - b.min[1]; });

await test('the embroidery process opens on its sample design', async () => {
  page = await browser.newPage({ viewport: { width: 1600, height: 900 } });
  state.page = page;
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(server.url);
  await page.selectOption('#process', 'embroider');
  await page.waitForFunction(() => document.getElementById('process-input').textContent === 'sunflower.svg', null, { timeout: 20000 });
  // Without a name first, to know what the name adds.
  await page.click('#make');
  await page.waitForFunction(() => document.getElementById('process-status').dataset.stitches && !document.getElementById('embroidery').hidden, null, { timeout: 60000 });
  plain = Number(await page.$eval('#process-status', (e) => e.dataset.stitches));
  assert(plain > 500, `${plain} stitches`);
  plainHeight = await previewHeight();
  assert(errors.length === 0, errors.join('\n'));
});

for (const format of ['pes', 'jef', 'vp3', 'dst']) {
  await test(`"Ana" on the sunflower as ${format.toUpperCase()}: report, preview, render, and pyembroidery reads the page's count`, async () => {
    // Only the name: "Text at" left empty sets it under the design, centred.
    await page.fill('#process-fields input[name="text"]', 'Ana');
    await page.selectOption('#process-fields select[name="format"]', format);
    await page.$eval('#process-status', (e) => { delete e.dataset.stitches; });
    await page.click('#make');
    await page.waitForFunction((f) => document.getElementById('process-status').dataset.stitches
      && document.getElementById('process-status').textContent.includes('.' + f), format, { timeout: 60000 });
    const sheet = Number(await page.$eval('#process-status', (e) => e.dataset.stitches));
    const drawn = Number(await page.$eval('#viewport', (e) => e.dataset.stitches));
    const report = await page.textContent('#process-report');
    const printed = Number((report.match(/Stitches\s+(\d+)/) || [])[1]);
    assert(sheet === drawn && sheet === printed, `sheet ${sheet}, drawn ${drawn}, report ${printed}`);
    assert(sheet > plain + 100, `the name adds stitches: ${sheet} against ${plain}`);
    // The preview draws the name below the flower: 15 mm letters, 7.5 mm under it.
    const h = await previewHeight();
    assert(h > plainHeight + 15, `the preview is ${h.toFixed(1)} mm tall with the name, ${plainHeight.toFixed(1)} without`);
    const threads = await page.$$eval('#threads li', (l) => l.length);
    assert(threads >= 2, `${threads} threads`);
    // The render: an image of the job folder, loaded, with a size.
    await page.waitForFunction(() => { const i = document.getElementById('stitch-render'); return !i.hidden && i.complete && i.naturalWidth > 0; }, null, { timeout: 20000 });
    const img = await page.$eval('#stitch-render', (i) => ({ src: i.getAttribute('src'), w: i.naturalWidth, h: i.naturalHeight, shown: i.getBoundingClientRect().width }));
    assert(img.src.includes('.png') && img.w > 100 && img.h > 100, JSON.stringify(img));
    assert(img.shown > 50, `the render is drawn on the page: ${JSON.stringify(img)}`);
    assert(!(await page.$eval('#stitch-sheet', (a) => a.hidden)), 'the production sheet link');
    // The printable sheet (A4) carries the same render.
    const sheetPage = await page.evaluate(async (h) => (await fetch(h)).text(), await page.getAttribute('#stitch-sheet', 'href'));
    assert(sheetPage.includes('size:A4') && /<img class=render[^>]*src="data:image\/png;base64,/.test(sheetPage), 'the sheet page has the render');
    // The file, downloaded through the page's link.
    const href = await page.getAttribute('#stitch-download', 'href');
    const name = await page.getAttribute('#stitch-download', 'download');
    assert(name.endsWith('.' + format), name);
    const bytes = await page.evaluate(async (h) => Array.from(new Uint8Array(await (await fetch(h)).arrayBuffer())), href);
    const file = path.join(scratch, name);
    writeFileSync(file, Buffer.from(bytes));
    if (format === 'pes') {
      // Tall enough for the form's render to show whole beside the preview.
      await page.setViewportSize({ width: 1600, height: 1500 });
      await page.locator('#stitch-render').scrollIntoViewIfNeeded();
      const dir = process.env.OFICINA_DOCS_SCREENSHOTS ? path.join(root, 'docs', 'screenshots') : out;
      await page.screenshot({ path: path.join(dir, 'workbench-embroidery-lettered.png') });
      await page.setViewportSize({ width: 1600, height: 900 });
      const png = await page.evaluate(async (h) => Array.from(new Uint8Array(await (await fetch(h)).arrayBuffer())), img.src);
      writeFileSync(path.join(out, 'embroidery-lettered-render.png'), Buffer.from(png));
    }
    await page.screenshot({ path: path.join(out, `embroidery-lettered-${format}.png`) });
    if (!hasPeer) return;
    const r = spawnSync(python, ['-c', COUNT, file, format], { encoding: 'utf8' });
    assert(r.status === 0, r.stderr);
    const [s, t, c] = r.stdout.trim().split(/\s+/).map(Number);
    assert(s === sheet, `${name}: pyembroidery reads ${s} stitches, the page says ${sheet}`);
    const trims = Number((report.match(/Trims\s+(\d+)/) || [])[1]);
    assert(t === trims, `${name}: pyembroidery reads ${t} trims, the report says ${trims}`);
    assert(c === threads - 1, `${name}: pyembroidery reads ${c} colour changes for ${threads} threads`);
    console.log(`     ${name}: ${sheet} stitches, ${threads} threads; pyembroidery: ${s} stitches, ${t} trims, ${c} colour changes`);
  });
}

await browser.close();
rmSync(scratch, { recursive: true, force: true });
finish();
