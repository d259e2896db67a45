// grblHAL's Simulator (`grblHAL_sim`, built by scripts/build-grblhal-sim) as a board on a
// loopback TCP port, for the page's tests against real firmware (web/tests/simulator.mjs).
//
// The simulator talks over stdin/stdout. Given a pipe it block-buffers its replies, so it
// gets a pseudo-terminal: one socat runs it on a pty (`EXEC:…,pty`) and links the other end
// to `DIR/tty`; a second socat listens on 127.0.0.1 and opens `DIR/tty` for each client.
// The simulator outlives its clients (a client that leaves cannot kill it with SIGPIPE: it
// writes to the pty, never to the socket), keeps its state between them, and runs in a
// private folder (fresh EEPROM.DAT: grblHAL's defaults). Its own `-p` telnet server binds
// every interface, so it is not used. One client at a time: two would share its replies.

import { spawn } from 'node:child_process';
import { createWriteStream, existsSync, mkdtempSync, rmSync } from 'node:fs';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

/// Starts `bin` behind a loopback port. Resolves with `{ uri, port, dir, raw, stop }`.
export async function startSimulator(bin, { socat = process.env.SOCAT || 'socat' } = {}) {
  const dir = mkdtempSync(path.join(os.tmpdir(), 'oficina-grblhal-sim-'));
  const tty = path.join(dir, 'tty');
  const procs = [];
  let simPid = null;
  const stop = () => {
    // The simulator ignores SIGTERM (it only saves its EEPROM file): killed by its pid.
    if (simPid) { try { process.kill(simPid, 'SIGKILL'); } catch { /* gone */ } }
    for (const p of procs) { try { p.kill('SIGKILL'); } catch { /* gone */ } }
    if (!process.env.OFICINA_KEEP_SIM_DIR && !trace) rmSync(dir, { recursive: true, force: true });
  };
  process.on('exit', stop);
  // OFICINA_SIM_TRACE=1: the bridge's traffic (socat -v) in DIR/bridge.log, and DIR kept.
  const trace = !!process.env.OFICINA_SIM_TRACE;
  const run = (args, what, verbose = false) => {
    const p = spawn(socat, ['-d', '-d', ...(verbose ? ['-v'] : []), ...args], { cwd: dir, stdio: ['ignore', 'ignore', 'pipe'] });
    procs.push(p);
    let log = '';
    const file = trace ? createWriteStream(path.join(dir, verbose ? 'bridge.log' : 'sim.log')) : null;
    p.stderr.on('data', (d) => { if (file) file.write(d); if (log.length < 100000) log += d; });
    p.on('error', (e) => { log += `\n${what}: ${e.message}`; });
    return { p, log: () => log };
  };
  // -n: replies without comment marks; -b: the planned blocks to a file (default: stdout,
  // which would mix them into the replies). The working directory holds EEPROM.DAT.
  const sim = run(['PTY,link=' + tty + ',raw,echo=0',
    `EXEC:'${bin}' -n -b ${path.join(dir, 'blocks.out')},pty,raw,echo=0`], 'the simulator');
  for (let i = 0; i < 100 && !(existsSync(tty) && /forked off child process (\d+)/.test(sim.log())); i++) await sleep(50);
  const m = sim.log().match(/forked off child process (\d+)/);
  if (!m || !existsSync(tty)) { stop(); throw new Error(`the simulator did not start: ${sim.log()}`); }
  simPid = Number(m[1]);
  const bridge = run(['TCP-LISTEN:0,bind=127.0.0.1,reuseaddr,fork', `FILE:${tty},raw,echo=0`], 'the bridge', trace);
  let port = null;
  for (let i = 0; i < 100 && !port; i++) {
    await sleep(50);
    const l = bridge.log().match(/listening on .*?127\.0\.0\.1:(\d+)/);
    if (l) port = Number(l[1]);
  }
  if (!port) { stop(); throw new Error(`the bridge did not listen: ${bridge.log()}`); }
  // The simulator reads nothing for its first simulated second.
  await sleep(1200);

  /// Talks to the simulator directly (only while no other client is connected): sends each
  /// item (`\x18` and `?` as they are, other text as lines) and waits `wait` ms after each.
  /// Resolves with everything it answered. A client leaving the bridge should likewise wait
  /// a second before the next one connects.
  function raw(items, wait = 400) {
    return new Promise((resolve, reject) => {
      const s = net.connect(port, '127.0.0.1');
      let got = '';
      s.on('data', (d) => { got += d; });
      s.on('error', reject);
      s.on('connect', async () => {
        for (const it of items) {
          s.write(it === '\x18' || it === '?' ? it : it + '\n');
          await sleep(wait);
        }
        s.end();
        // The bridge's child for this client lingers half a second after it leaves, and
        // would read what the simulator says next: the next client waits for it to go.
        await sleep(800);
        resolve(got.replace(/\r/g, ''));
      });
    });
  }

  return { uri: `tcp://127.0.0.1:${port}`, port, dir, pid: simPid, raw, stop,
    alive: () => { try { process.kill(simPid, 0); return true; } catch { return false; } } };
}
