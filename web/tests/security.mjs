// Only the page may drive the machine. While the workbench is open, a page of another origin
// (a second local server on another port, as any site the user visits would be) tries to
// open the live channel, take control, start a job, jog and write a file; a page whose name
// was rebound to 127.0.0.1 (DNS rebinding) tries the same from the server's own address and
// port. Everything is refused, and the workbench itself keeps working.

import { startServer, launch, suite, assert, sleep, out, root } from './harness.mjs';
import { createServer } from 'node:http';
import { existsSync, readdirSync, readFileSync } from 'node:fs';
import path from 'node:path';

const { test, state, finish } = suite('security');
// The page the binary carries, from outside the checkout (issue #20 item 9 seen here too).
const server = await startServer([], { embedded: true });
const browser = await launch();

// A machine profile the attacker would put on the machine (a simple POST needs no preflight).
const profile = readFileSync(path.join(root, 'profiles', 'hotwire-xy.toml'), 'utf8');

// What an attacking page runs: every way in that a page has, results kept in `window.done`.
const attack = (target) => `
<!doctype html><title>innocent page</title><script>
const target = ${JSON.stringify(target)};
const results = { ws: 'pending', messages: [], put: null, check: null, form: null };
async function run() {
  await new Promise((resolve) => {
    let ws;
    try { ws = new WebSocket(target.replace('http', 'ws') + '/ws'); } catch (e) { results.ws = 'threw'; return resolve(); }
    ws.onopen = () => {
      results.ws = 'open';
      for (const c of [{ cmd: 'take_control' }, { cmd: 'start', file: 'plate.nc' }, { cmd: 'jog', delta: [50, 0, 0], feed: 3000 }, { cmd: 'home' }])
        ws.send(JSON.stringify(c));
      setTimeout(resolve, 1500);
    };
    ws.onmessage = (m) => results.messages.push(String(m.data).slice(0, 200));
    ws.onerror = () => { if (results.ws === 'pending') results.ws = 'refused'; };
    ws.onclose = () => { if (results.ws === 'pending') results.ws = 'refused'; resolve(); };
  });
  // Writes the page cannot read the answer of still reach a careless server.
  try { const r = await fetch(target + '/api/files/evil.nc', { method: 'PUT', body: 'G0 X100\\n', mode: 'no-cors' }); results.put = r.type === 'opaque' ? 'opaque' : String(r.status); } catch (e) { results.put = 'failed'; }
  try { const r = await fetch(target + '/api/files/evil2.nc', { method: 'PUT', body: 'G0 X100\\n' }); results.put2 = String(r.status); } catch (e) { results.put2 = 'failed'; }
  try { const r = await fetch(target + '/api/profiles/use', { method: 'POST', body: ${JSON.stringify(profile)}, mode: 'no-cors' }); results.profile = r.type; } catch (e) { results.profile = 'failed'; }
  try { const r = await fetch(target + '/api/check', { method: 'POST', body: 'G0 X1\\n', mode: 'no-cors' }); results.check = r.type; } catch (e) { results.check = 'failed'; }
  window.done = results;
}
run();
</script>`;

// The second local server, on another port: the "other origin".
const evil = createServer((req, res) => {
  res.writeHead(200, { 'content-type': 'text/html' });
  res.end(attack(server.origin));
});
await new Promise((r) => evil.listen(0, '127.0.0.1', r));
const evilUrl = `http://127.0.0.1:${evil.address().port}/`;

let bench;
const dro = () => bench.evaluate(() => ['x', 'y', 'z'].map((a) => Number(document.getElementById('m' + a).textContent)));

await test('the workbench opens and controls the virtual machine', async () => {
  bench = await browser.newPage({ viewport: { width: 1600, height: 900 } });
  state.page = bench;
  await bench.goto(server.url);
  await bench.waitForFunction(() => document.getElementById('summary').textContent.includes('0 errors'), null, { timeout: 30000 });
  await bench.waitForFunction(() => document.getElementById('control').textContent.includes('controlling'), null, { timeout: 15000 });
});

await test('a page of another origin can neither connect, control, start, jog nor write', async () => {
  const before = await dro();
  const machine = await bench.textContent('#machine-name');
  const page = await browser.newPage();
  state.page = page;
  await page.goto(evilUrl);
  await page.waitForFunction(() => window.done, null, { timeout: 30000 });
  const r = await page.evaluate(() => window.done);
  await page.screenshot({ path: path.join(out, 'security-other-origin.png') });
  assert(r.ws === 'refused', `the live channel is refused: ${JSON.stringify(r)}`);
  assert(r.messages.length === 0, `no message reached the page: ${r.messages}`);
  assert(r.put2 === 'failed', `a readable PUT fails (no CORS, refused): ${r.put2}`);
  const files = existsSync(path.join(server.dir, 'jobs')) ? readdirSync(path.join(server.dir, 'jobs')) : [];
  assert(!files.some((f) => f.startsWith('evil')), `no file was written: ${files}`);
  await sleep(500);
  const after = await dro();
  assert(before.every((v, i) => Math.abs(v - after[i]) < 1e-9), `the machine did not move: ${before} → ${after}`);
  assert(!(await bench.textContent('#console')).includes('started'), 'no job was started');
  assert((await bench.textContent('#machine-name')) === machine, `the machine was not replaced: ${await bench.textContent('#machine-name')}`);
  assert((await bench.textContent('#control')).includes('controlling'), 'the workbench still controls the machine');
  // The server says why, to whoever looks.
  const why = await fetch(`${server.origin}/api/files/x.nc`, { method: 'PUT', body: 'M2', headers: { origin: evilUrl.slice(0, -1) } });
  assert(why.status === 403 && (await why.text()).includes('own page'), 'refused with a reason');
  await page.close();
});

await test('a rebound name (DNS rebinding) reaches nothing, not even the page', async () => {
  const page = await browser.newPage();
  state.page = page;
  const rebound = `http://rebound.test:${server.port}`;
  const resp = await page.goto(rebound + '/');
  assert(resp.status() === 403, `the page is refused under another name: ${resp.status()}`);
  assert((await page.textContent('body')).includes('rebound.test'), 'the refusal names the host');
  // From that origin, the server's own address and port are same-origin for the attacker.
  await page.setContent(attack(rebound));
  await page.waitForFunction(() => window.done, null, { timeout: 30000 });
  const r = await page.evaluate(() => window.done);
  assert(r.ws === 'refused', `the live channel is refused: ${JSON.stringify(r)}`);
  const files = readdirSync(path.join(server.dir, 'jobs'));
  assert(!files.some((f) => f.startsWith('evil')), `no file was written: ${files}`);
  await page.close();
});

await test('the workbench keeps working, under 127.0.0.1 and under localhost', async () => {
  state.page = bench;
  await bench.selectOption('#jog-step', '10');
  const before = await dro();
  await bench.click('#jog button[data-jog="1,0,0"]');
  await bench.waitForFunction((x0) => Math.abs(Number(document.getElementById('mx').textContent) - x0 - 10) < 1e-6, before[0], { timeout: 15000 });
  const local = await browser.newPage({ viewport: { width: 1600, height: 900 } });
  state.page = local;
  await local.goto(`http://localhost:${server.port}/`);
  await local.waitForFunction(() => document.getElementById('summary').textContent.includes('0 errors'), null, { timeout: 30000 });
  await local.waitForFunction(() => document.getElementById('control').textContent.includes('watching'), null, { timeout: 15000 });
  await local.click('#control');
  await local.waitForFunction(() => document.getElementById('control').textContent.includes('controlling'), null, { timeout: 15000 });
  await local.screenshot({ path: path.join(out, 'security-localhost.png') });
  await local.close();
});

evil.close();
await browser.close();
finish();
