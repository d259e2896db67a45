// Browser test of the stitch editor, as a user: open two real embroidery files (a Janome JEF
// and a Tajima DST of ../shared/data/realworld/embroidery-files), select by box and by
// entry, rotate the first by 90°, delete one of its stitches (undo, redo), insert a colour
// stop, try a faster speed code on a section (undone), link the two and save a PES. The PES
// is read by pyembroidery and compared with what the library makes of the originals:
// `oficina embroider A.jef --rotate 90` (the library's rotation) read by pyembroidery, less
// the deleted stitch, then the DST read by pyembroidery moved to where the page placed it:
// the same sewn stitches in order (within 0.1 mm, the files' unit), 4 threads, 3 colour
// changes. The Embroidery process's plan opens in it too. Skipped with a note when the files or pyembroidery are missing. Starts its own
// `oficina serve`. Prints `N passed, M failed`. With OFICINA_DOCS_SCREENSHOTS=1 its
// screenshot replaces docs/screenshots/workbench-stitch-editor.png.

import { startServer, launch, suite, assert, root, out, realworld } from './harness.mjs';
import { spawnSync } from 'node:child_process';
import { mkdtempSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';

const bin = path.resolve(process.env.OFICINA_BIN || path.join(root, 'target', 'debug', 'oficina'));
const python = process.env.PYTHON || 'python3';
const A = 'emm_Star.JEF', B = 'pembr_Hello_PEmbroider.dst';
const folder = realworld('embroidery-files', A);
const { test, state, finish } = suite('stitch editor');
if (!folder || !realworld('embroidery-files', B)) {
  console.log(`SKIPPED stitch editor: ${A} and ${B} are not in the shared realworld folder`);
  finish();
}
const hasPeer = spawnSync(python, ['-c', 'import pyembroidery']).status === 0;
if (!hasPeer) console.log(`note: pyembroidery checks skipped, ${python} lacks pyembroidery`);

// Sewn stitches (0.1 mm, y up), thread count and colour changes as pyembroidery reads a file.
const READ = `
import sys, json, pyembroidery as P
p = P.read(sys.argv[1])
s = [(x, -y) for x, y, c in p.stitches if c & P.COMMAND_MASK == P.STITCH]
cc = sum(1 for _, _, c in p.stitches if c & P.COMMAND_MASK == P.COLOR_CHANGE)
print(json.dumps({"stitches": s, "threads": len(p.threadlist), "changes": cc}))
`;
function peer(file) {
  const r = spawnSync(python, ['-c', READ, file], { encoding: 'utf8' });
  assert(r.status === 0, `pyembroidery reads ${file}: ${r.stderr}`);
  return JSON.parse(r.stdout);
}

const server = await startServer();
const browser = await launch();
const page = await browser.newPage({ viewport: { width: 1600, height: 1000 } });
state.page = page;
const scratch = mkdtempSync(path.join(os.tmpdir(), 'oficina-stitch-editor-'));
const data = (k) => page.evaluate((k) => document.getElementById('se-view').dataset[k], k).then(Number);
const info = () => page.textContent('#se-info');
const statusText = () => page.textContent('#se-status');
async function selectEntry(i) {
  await page.fill('#se-entry', String(i));
  await page.dispatchEvent('#se-entry', 'change');
}
const placeB = { x: 0, y: 0 };
let deleted = null;

await test('two real files open in the stitch editor, drawn per colour with their jumps', async () => {
  await page.goto(server.url);
  await page.waitForFunction(() => document.getElementById('summary').textContent.includes('errors'), null, { timeout: 30000 });
  await page.selectOption('#process', 'stitches');
  assert(await page.isVisible('#se-view'), 'the stitch view is visible');
  await page.setInputFiles('#se-open', [path.join(folder, A), path.join(folder, B)]);
  await page.waitForFunction(() => document.getElementById('se-view').dataset.designs === '2', null, { timeout: 30000 });
  // B is active: where the page placed it (right of A) is what linking uses.
  placeB.x = Number(await page.inputValue('#se-at-x'));
  placeB.y = Number(await page.inputValue('#se-at-y'));
  assert(placeB.x > 20, `the second design is placed right of the first: ${placeB.x}`);
  const lines = await page.locator('#se-view polyline').count();
  const dashed = await page.locator('#se-view line[stroke-dasharray]').count();
  assert(lines > 2 && dashed >= 1, `stitch runs ${lines}, dashed jumps ${dashed}`);
  await page.selectOption('#se-designs', '0');
  assert((await data('colours')) === 2, `${A}: 2 colours, ${await data('colours')}`);
  assert(await page.locator('#se-view circle.se-colour').count() >= 1, 'the colour change is marked');
});

await test('a box drag selects entries, a click one, shift-click a range', async () => {
  const box = await page.locator('#se-view').boundingBox();
  await page.mouse.move(box.x + 5, box.y + 5);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width * 0.3, box.y + box.height * 0.6, { steps: 5 });
  await page.mouse.up();
  const boxed = await data('selected');
  assert(boxed > 10, `the box selects entries: ${boxed}`);
  await selectEntry(10);
  const dot = await page.locator('#se-view circle.se-selected').boundingBox();
  await page.mouse.click(dot.x + dot.width / 2, dot.y + dot.height / 2);
  assert((await data('selected')) === 1, `a click selects one entry: ${await data('selected')}`);
  await selectEntry(20);
  const d2 = await page.locator('#se-view circle.se-selected').boundingBox();
  await selectEntry(10);
  await page.keyboard.down('Shift');
  await page.mouse.click(d2.x + d2.width / 2, d2.y + d2.height / 2);
  await page.keyboard.up('Shift');
  const range = await data('selected');
  // Entry 20's dot may lie on a later entry's (stitches repeat points): a range from 10 on.
  assert(range >= 2, `shift-click selects a range from entry 10: ${range}`);
});

await test('rotate by 90°, delete a stitch (undo, redo), insert a colour stop', async () => {
  await page.fill('#se-rotate', '90');
  await page.click('#se-alter');
  await page.waitForFunction(() => document.getElementById('se-status').textContent.startsWith('altered'), null, { timeout: 15000 });
  const entries = await data('entries');
  await selectEntry(100);
  const t = await info();
  const m = t.match(/entry 100 \(stitch at (-?[\d.]+), (-?[\d.]+) mm\)/);
  assert(m, `entry 100 is a sewn stitch: ${t}`);
  deleted = [Number(m[1]), Number(m[2])];
  await page.click('#se-delete');
  assert((await data('entries')) === entries - 1, `one entry fewer: ${await data('entries')}`);
  await page.click('#se-undo');
  assert((await data('entries')) === entries, 'undo brings it back');
  await page.click('#se-redo');
  assert((await data('entries')) === entries - 1, 'redo deletes it again');
  await selectEntry(500);
  await page.click('#se-colour');
  assert((await data('colours')) === 3, `a colour stop: 3 colours, ${await data('colours')}`);
  assert(await page.locator('#se-view circle.se-colour').count() >= 2, 'both colour changes are marked');
});

await test('a section sews at a faster speed code by the library (then undone)', async () => {
  const entries = await data('entries');
  await selectEntry(200);
  const code = Number((await info()).match(/speed code (\d+)/)?.[1]);
  assert(code >= 4 && code <= 12, `the section's code is shown: ${await info()}`);
  await page.selectOption('#se-code', String(Math.min(12, code + 1)));
  await page.click('#se-speed');
  await page.waitForFunction(() => /sewn at speed code|speed code/.test(document.getElementById('se-status').textContent), null, { timeout: 15000 });
  if (code < 12) {
    const split = await data('entries');
    await page.click('#se-undo');
    assert(split > entries, `the section's long stitches are split: ${split} > ${entries}; ${await statusText()}`);
    await page.click('#se-redo');
    await selectEntry(200);
    const now = await info();
    await page.click('#se-undo');
    assert(now.includes(`speed code ${code + 1}`), `the section now sews at ${code + 1}: ${now}`);
  }
  assert((await data('entries')) === entries, 'undone');
  // A slower code is refused by the library, by name.
  await selectEntry(200);
  await page.selectOption('#se-code', '4');
  await page.click('#se-speed');
  await page.waitForFunction(() => document.getElementById('se-status').classList.contains('error') || document.getElementById('se-status').textContent.includes('code 4'), null, { timeout: 15000 });
  if (code > 4) assert((await statusText()).includes('only a faster code'), `refused: ${await statusText()}`);
});

let saved = null;
await test('link the two and save a PES; pyembroidery reads the library\'s rotation of the originals', async () => {
  await page.click('#se-link');
  await page.waitForFunction(() => document.getElementById('se-view').dataset.designs === '1', null, { timeout: 15000 });
  assert((await data('colours')) === 4, `linked: 4 colours, ${await data('colours')}`);
  await page.fill('#se-name', 'linked');
  await page.selectOption('#se-format', 'pes');
  await page.click('#se-save');
  await page.waitForFunction(() => document.getElementById('se-status').textContent.startsWith('saved'), null, { timeout: 15000 });
  saved = path.join(server.dir, 'jobs', 'linked.pes');
  const shot = process.env.OFICINA_DOCS_SCREENSHOTS ? path.join(root, 'docs', 'screenshots') : out;
  await page.screenshot({ path: path.join(shot, 'workbench-stitch-editor.png') });
  if (!hasPeer) return;
  const a90 = path.join(scratch, 'a90.pes');
  const r = spawnSync(bin, ['embroider', path.join(folder, A), '--rotate', '90', '-o', a90], { encoding: 'utf8' });
  assert(r.status === 0, `oficina embroider --rotate 90: ${r.stderr}`);
  const a = peer(a90).stitches, b = peer(path.join(folder, B)).stitches;
  const near = (p, q) => Math.abs(p[0] - q[0]) <= 1 && Math.abs(p[1] - q[1]) <= 1;
  const gone = a.findIndex((p) => near(p, [deleted[0] * 10, deleted[1] * 10]));
  assert(gone >= 0, `the deleted stitch ${deleted} is one of the rotated design's`);
  a.splice(gone, 1);
  const moved = b.map(([x, y]) => [x + placeB.x * 10, y + placeB.y * 10]);
  const got = peer(saved);
  // The joint is one point to the second design's origin: sewn only when 12.4 mm or less.
  const joint = got.stitches.length === a.length + moved.length + 1 ? [[placeB.x * 10, placeB.y * 10]] : [];
  const want = [...a, ...joint, ...moved];
  assert(got.stitches.length === want.length, `stitch count: ${got.stitches.length} in the PES, ${want.length} expected`);
  const bad = got.stitches.findIndex((p, i) => !near(p, want[i]));
  assert(bad < 0, `stitch ${bad}: ${got.stitches[bad]} in the PES, ${want[bad]} expected (0.1 mm)`);
  assert(got.threads === 4 && got.changes === 3, `threads ${got.threads}, colour changes ${got.changes}`);
  console.log(`     linked.pes: ${got.stitches.length} stitches (${a.length} + ${moved.length}${joint.length ? ' + 1 joint' : ''}), ${got.threads} threads, every stitch within 0.1 mm of pyembroidery's reading of the library's rotation`);
});

await test('the plan the Embroidery process makes opens in the editor with its stitch count', async () => {
  await page.selectOption('#process', 'embroider');
  await page.waitForFunction(() => document.getElementById('process-input').textContent === 'sunflower.svg', null, { timeout: 20000 });
  await page.click('#make');
  await page.waitForFunction(() => document.getElementById('process-status').dataset.stitches, null, { timeout: 120000 });
  const made = Number(await page.$eval('#process-status', (e) => e.dataset.stitches));
  await page.click('#edit-stitches');
  await page.waitForFunction(() => document.getElementById('se-view').dataset.designs === '2', null, { timeout: 15000 });
  assert(await page.isVisible('#se-view'), 'the stitch editor is shown');
  // The editor counts every entry (jumps, trims too): at least the sewn stitches the sheet counts.
  const entries = await data('entries');
  assert(entries >= made && made > 100, `${entries} entries for ${made} stitches made`);
});

await test('bad input is refused by name: a plan with a bad kind, a bad save name', async () => {
  const plan = { name: 'x', blocks: [{ thread: '#ff0000', name: '', points: [0, 0, 7] }] };
  let r = await fetch(`${server.origin}/api/stitches/save`, { method: 'POST', body: JSON.stringify({ plan, name: 'x.pes' }), headers: { 'content-type': 'application/json' } });
  assert(r.status === 400 && (await r.text()).includes('block 1, entry 1: kind 7'), 'a bad kind is named');
  plan.blocks[0].points = [0, 0, 0, 1, 1, 0];
  r = await fetch(`${server.origin}/api/stitches/save`, { method: 'POST', body: JSON.stringify({ plan, name: 'x.txt' }), headers: { 'content-type': 'application/json' } });
  assert(r.status === 400 && (await r.text()).includes('cannot write'), 'an unwritable extension is refused');
  r = await fetch(`${server.origin}/api/stitches/link`, { method: 'POST', body: JSON.stringify({ designs: [{ plan }] }), headers: { 'content-type': 'application/json' } });
  assert(r.status === 400 && (await r.text()).includes('two designs'), 'linking one design is refused');
});

await browser.close();
finish();
