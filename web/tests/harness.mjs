// What the browser test files share: an `oficina serve` and `oficina emulate grbl` of their
// own (so a test that connects the machine to firmware leaves the other files' server
// alone), chromium, and the `ok` / `FAIL` lines with their count.

import { chromium } from 'playwright-core';
import { spawn } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import os from 'node:os';
import path from 'node:path';

const here = path.dirname(fileURLToPath(import.meta.url));
export const root = path.join(here, '..', '..');
export const out = process.env.OFICINA_TEST_OUTPUT || path.join(here, '..', 'test-output');
mkdirSync(out, { recursive: true });
const bin = path.resolve(process.env.OFICINA_BIN || path.join(root, 'target', 'debug', 'oficina'));

const children = [];
const scratch = [];
function cleanup() {
  for (const c of children) { try { c.kill('SIGKILL'); } catch { /* gone */ } }
  for (const d of scratch) rmSync(d, { recursive: true, force: true });
}
process.on('exit', cleanup);

/// Starts `oficina ARGS…` and resolves with the first match of `pattern` in what it prints.
function startPrinting(args, pattern, what, cwd = root) {
  return new Promise((resolve, reject) => {
    const p = spawn(bin, args, { stdio: ['ignore', 'pipe', 'pipe'], cwd });
    children.push(p);
    let seen = '';
    const timer = setTimeout(() => reject(new Error(`${what} did not start within 60 s: ${seen}`)), 60000);
    const look = (d) => {
      seen += d;
      const m = seen.match(pattern);
      if (m) { clearTimeout(timer); resolve({ proc: p, match: m }); }
    };
    p.stdout.on('data', look);
    p.stderr.on('data', look);
    p.on('exit', (code) => { clearTimeout(timer); reject(new Error(`${what} exited (${code}): ${seen}`)); });
    p.on('error', (e) => { clearTimeout(timer); reject(new Error(`${what}: ${e.message}`)); });
  });
}

/// A workbench server on a free loopback port with a fresh job folder. `embedded`: the page
/// the binary carries, served from outside the checkout (no `--web`), as a user runs it.
export async function startServer(extra = [], { embedded = false } = {}) {
  const dir = mkdtempSync(path.join(os.tmpdir(), 'oficina-web-'));
  scratch.push(dir);
  const web = embedded ? [] : ['--web', path.join(root, 'web', 'dist')];
  const { proc, match } = await startPrinting(
    ['serve', '--port', '0', '--jobs', path.join(dir, 'jobs'), ...web, ...extra],
    /http:\/\/[^\s]+/, 'oficina serve', embedded ? dir : root);
  const url = match[0];
  return { url, origin: new URL(url).origin, port: Number(new URL(url).port), proc, dir };
}

/// A software grbl board (`grbl`, `grblhal` or `fluidnc`) on a free loopback TCP port.
export async function startEmulator(flavor, extra = []) {
  const { proc, match } = await startPrinting(
    ['emulate', 'grbl', '--flavor', flavor, '--tcp', '127.0.0.1:0', ...extra],
    /tcp:\/\/[0-9.]+:\d+/, `the ${flavor} emulator`);
  return { uri: match[0], proc, stop: () => proc.kill('SIGKILL') };
}

export async function launch() {
  return chromium.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
      // The rebinding test names a host the system resolver does not know.
      '--host-resolver-rules=MAP rebound.test 127.0.0.1'],
  });
}

/// Test bookkeeping: `test(name, fn)` runs `fn`, prints `ok`/`FAIL`, and on a failure saves a
/// screenshot of `page()` when there is one.
export function suite(prefix) {
  let passed = 0, failed = 0;
  const state = { page: null };
  async function test(name, fn) {
    const t0 = Date.now();
    try {
      await fn();
      passed++;
      console.log(`ok   ${prefix}: ${name} (${Date.now() - t0} ms)`);
    } catch (e) {
      failed++;
      console.log(`FAIL ${prefix}: ${name}: ${String(e.message || e).split('\n').slice(0, 6).join('\n     ')}`);
      if (state.page) {
        await state.page.screenshot({ path: path.join(out, `failed-${prefix}-${name.replace(/\W+/g, '-')}.png`) }).catch(() => {});
      }
    }
  }
  return {
    test,
    state,
    counts: () => ({ passed, failed }),
    finish() {
      console.log(`${passed} passed, ${failed} failed`);
      cleanup();
      process.exit(failed ? 1 : 0);
    },
  };
}

export function assert(cond, msg) { if (!cond) throw new Error(msg); }
export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// What the firmware files do to the page the same way.

/// A square of 20 mm traced `laps` times at 1 mm deep at `feed`, then short lines to resume
/// from (ends at work X1 Y1 Z5); its text and its line count.
export function squareProgram(laps, feed) {
  const sides = Array.from({ length: laps }, () => `G1 X20 F${feed}\nY20\nX0\nY0`).join('\n');
  const program = `G21 G90\nG0 Z5\nG0 X0 Y0\nG1 Z-1 F300\n${sides}\nG0 Z5\nG0 X1 Y1\nM2\n`;
  return { program, lines: program.trimEnd().split('\n').length };
}

/// A new page of `server`, once its first check is shown; kept in `state` for screenshots.
export async function openPage(browser, server, state) {
  const page = await browser.newPage({ viewport: { width: 1600, height: 900 } });
  state.page = page;
  await page.goto(server.url);
  await page.waitForFunction(() => document.getElementById('summary').textContent.includes('errors'), null, { timeout: 30000 });
  return page;
}

/// Closes the tab, checks the server still answers, opens a new one (`reopen()`) and waits
/// until it names the board at `uri` again, idle and where it was (`what` in the message);
/// the new page.
export async function closeAndReopen(page, server, reopen, uri, what) {
  const where = await dro(page);
  await page.close();
  await sleep(500);
  for (let i = 0; i < 3; i++) {
    const r = await fetch(`${server.origin}/api/info`, { signal: AbortSignal.timeout(5000) });
    assert(r.ok, `the server answers: ${r.status}`);
    await sleep(200);
  }
  const again = await reopen();
  await again.waitForFunction((a) => document.getElementById('machine-name').textContent.includes(a), uri.replace('tcp://', ''), { timeout: 15000 });
  await waitState(again, 'idle');
  const there = await dro(again);
  assert(where.every((v, i) => Math.abs(v - there[i]) < 1e-3), `${what} is where it was: ${where} vs ${there}`);
  return again;
}

/// The DRO's machine (`m`) or work (`w`) position.
export const dro = (page, kind = 'm') =>
  page.evaluate((k) => ['x', 'y', 'z'].map((a) => Number(document.getElementById(k + a).textContent)), kind);
export const waitState = (page, s, timeout = 30000) =>
  page.waitForFunction((s) => document.body.dataset.state === s, s, { timeout });

/// Connects the page to the board at `uri` through the machine list's "type an address"
/// entry, as a user does; resolves once the page names it.
export async function connectBoard(page, uri) {
  page.once('dialog', (d) => d.accept(uri));
  await page.selectOption('#machine-uri', '');
  await page.click('#connect');
  await page.waitForFunction((a) => document.getElementById('machine-name').textContent.includes(a), uri.replace('tcp://', ''), { timeout: 15000 })
    .catch(async () => { throw new Error(`the board's address is not shown: ${await page.textContent('#machine-name')}`); });
}

/// Types `line` into the typed-line field and presses Enter; waits for the reply (`ok` or
/// the start of an error) after it in the console.
export async function mdi(page, line, reply = 'ok') {
  const before = (await page.textContent('#console')).length;
  await page.fill('#mdi', line);
  await page.press('#mdi', 'Enter');
  await page.waitForFunction(([before, line, reply]) => {
    const c = document.getElementById('console').textContent.slice(before);
    const at = c.indexOf('> ' + line + '\n');
    return at >= 0 && c.slice(at).includes('\n' + reply);
  }, [before, line, reply], { timeout: 20000 });
}

/// The folder of real users' files of `kind` (`$OFICINA_REALWORLD/KIND`, else the shared
/// data's) that holds `file`; null when neither does (the test then prints SKIPPED).
export function realworld(kind, file) {
  const dirs = [
    process.env.OFICINA_REALWORLD && path.join(process.env.OFICINA_REALWORLD, kind),
    path.join('/work/shared/data/realworld', kind),
  ].filter(Boolean);
  return dirs.find((d) => existsSync(path.join(d, file))) ?? null;
}
