// Lettering alone in the workbench, as a new user does it through the visible controls: the
// Embroidery process (it opens on its sample design), "Text alone" puts the design aside,
// "Ana|Maria" typed in the Text field at 16 mm, left aligned, made as PES, JEF, VP3 and DST in
// turn. Each time the report, the preview (two lines of satin letters, their height from the
// font's leading) and the thread render show the stitches; the top bar names the stitch
// file and its figures, not the editor's program; pyembroidery reads each downloaded file
// with the page's stitch count (skipped with a note when python3 lacks it). Starts its own
// `oficina serve` with web/dist. Screenshots land in web/test-output/; with
// OFICINA_DOCS_SCREENSHOTS=1 the page's one goes to docs/screenshots/
// workbench-embroidery-text-alone.png. Prints `N passed, M failed`.

import { startServer, launch, suite, assert, out, root } from './harness.mjs';
import { spawnSync } from 'node:child_process';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';

const server = await startServer();
const browser = await launch();
const { test, state, finish } = suite('embroidery text alone');

const python = process.env.PYTHON || 'python3';
const hasPeer = spawnSync(python, ['-c', 'import pyembroidery']).status === 0;
if (!hasPeer) console.log(`note: pyembroidery checks skipped, ${python} lacks pyembroidery`);
// pyembroidery's sewn stitches (VP3's move after a trim is a stitch to pyembroidery and a
// jump to us, as crates/stitch/tests/peer.rs says: not counted) and colour changes.
const COUNT = `
import sys, pyembroidery as P
p = P.read(sys.argv[1])
s = c = 0
prev = None
for x, y, cmd in p.stitches:
    k = cmd & P.COMMAND_MASK
    if k == P.STITCH and not (sys.argv[2] == 'vp3' and prev == P.TRIM):
        s += 1
    c += k == P.COLOR_CHANGE
    prev = k
print(s, c)
`;
const scratch = mkdtempSync(path.join(os.tmpdir(), 'oficina-text-alone-'));
const SIZE = 16;
// Masego: 100 units between lines over a 52.6-unit cap height.
const TALL = SIZE + SIZE * 100 / 52.6;

let page;
const errors = [];

await test('Text alone puts the sample design aside; Make with no text asks for one', async () => {
  page = await browser.newPage({ viewport: { width: 1600, height: 900 } });
  state.page = page;
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(server.url);
  await page.selectOption('#process', 'embroider');
  await page.waitForFunction(() => document.getElementById('process-input').textContent === 'sunflower.svg', null, { timeout: 20000 });
  assert(await page.isVisible('#text-alone'), 'the Text alone button is shown with a design');
  await page.click('#text-alone');
  const input = await page.textContent('#process-input');
  assert(/Text alone/.test(input), `the form says what it sews: ${input}`);
  assert(!(await page.isVisible('#text-alone')), 'the button goes once the design is aside');
  await page.click('#make');
  await page.waitForFunction(() => /type a Text/.test(document.getElementById('process-status').textContent), null, { timeout: 5000 });
});

for (const format of ['pes', 'jef', 'vp3', 'dst']) {
  await test(`"Ana|Maria" alone as ${format.toUpperCase()}: report, preview, render, top bar, and pyembroidery reads the page's count`, async () => {
    await page.fill('#process-fields input[name="text"]', 'Ana|Maria');
    await page.fill('#process-fields input[name="text_size"]', String(SIZE));
    await page.selectOption('#process-fields select[name="text_align"]', 'left');
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
    assert(sheet > 1000, `${sheet} stitches for two lines of letters`);
    const satins = Number((report.match(/shapes: \d+ fill, (\d+) satin/) || [])[1]);
    assert(satins >= 20, `satin columns: ${satins}\n${report}`);
    // Two lines: the preview is as tall as the caps of the first line down to the baseline of
    // the second (the font's leading), within the satins' width at the ends.
    const b = await page.evaluate(() => window.__oficina.preview.bounds());
    const h = b.max[1] - b.min[1];
    assert(Math.abs(h - TALL) < 2.5, `the preview is ${h.toFixed(1)} mm tall, ${TALL.toFixed(1)} expected`);
    const threads = await page.$$eval('#threads li', (l) => l.length);
    assert(threads === 1, `${threads} threads`);
    // The top bar says what the preview shows.
    const name = await page.getAttribute('#stitch-download', 'download');
    assert(name === `Ana-Maria.${format}`, name);
    const bar = await page.textContent('#bar');
    assert(bar.includes(name), `the top bar names ${name}: ${bar}`);
    assert(bar.includes(`${sheet.toLocaleString('en-US')} stitches`) && bar.includes('1 colour'), `the top bar: ${bar}`);
    assert(!/errors ·|feed \d+ mm/.test(bar), `the top bar still describes a G-code program: ${bar}`);
    assert((await page.textContent('#preview-title')) === `stitches of ${name}`, 'the preview title');
    // The render: an image of the job folder, loaded, with a size.
    await page.waitForFunction(() => { const i = document.getElementById('stitch-render'); return !i.hidden && i.complete && i.naturalWidth > 0; }, null, { timeout: 20000 });
    const img = await page.$eval('#stitch-render', (i) => ({ src: i.getAttribute('src'), w: i.naturalWidth, h: i.naturalHeight }));
    assert(img.src.includes('.png') && img.w > 100 && img.h > 100, JSON.stringify(img));
    // The file, downloaded through the page's link.
    const href = await page.getAttribute('#stitch-download', 'href');
    const bytes = await page.evaluate(async (h) => Array.from(new Uint8Array(await (await fetch(h)).arrayBuffer())), href);
    const file = path.join(scratch, name);
    writeFileSync(file, Buffer.from(bytes));
    if (format === 'pes') {
      await page.setViewportSize({ width: 1600, height: 1300 });
      await page.locator('#stitch-render').scrollIntoViewIfNeeded();
      // The taller viewport framed again on the design.
      await page.click('#views button[data-view="xy"]');
      await page.waitForTimeout(300);
      const dir = process.env.OFICINA_DOCS_SCREENSHOTS ? path.join(root, 'docs', 'screenshots') : out;
      await page.screenshot({ path: path.join(dir, 'workbench-embroidery-text-alone.png') });
      await page.setViewportSize({ width: 1600, height: 900 });
      const png = await page.evaluate(async (h) => Array.from(new Uint8Array(await (await fetch(h)).arrayBuffer())), img.src);
      writeFileSync(path.join(dir, 'embroidery-text-alone-render.png'), Buffer.from(png));
    }
    await page.screenshot({ path: path.join(out, `embroidery-text-alone-${format}.png`) });
    if (!hasPeer) return;
    const r = spawnSync(python, ['-c', COUNT, file, format], { encoding: 'utf8' });
    assert(r.status === 0, r.stderr);
    const [s, c] = r.stdout.trim().split(/\s+/).map(Number);
    assert(s === sheet, `${name}: pyembroidery reads ${s} stitches, the page says ${sheet}`);
    assert(c === 0, `${name}: pyembroidery reads ${c} colour changes for one thread`);
    console.log(`     ${name}: ${sheet} stitches; pyembroidery: ${s} stitches`);
  });
}

await test('no page errors', async () => {
  assert(errors.length === 0, errors.join('\n'));
});

await browser.close();
rmSync(scratch, { recursive: true, force: true });
finish();
