// The machine panel: connect, DRO, jog (buttons, keys, gamepad), home, unlock, reset, work
// offsets, start / hold / resume / stop, resume from a line, feed override, progress with
// elapsed and remaining time, console with typed lines, macros and alarms. Any page may
// hold, stop and reset; moving and starting need control.

import type { LiveMessage, Snapshot } from './api';
import { Jogger, gamepadJog, keyboardJog } from './jog';
import { setupMacros } from './macros';
import { setupMdi } from './mdi';
import { setupOffsets, showOffsets } from './offsets';

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;

interface Hooks {
  send(cmd: Record<string, unknown>): void;
  prepareStart(): Promise<string>;
  error(msg: string): void;
  onStatus(s: Snapshot): void;
}

function hms(s: number | null): string {
  if (s === null || !isFinite(s)) return '—';
  s = Math.max(0, Math.round(s));
  return `${Math.floor(s / 3600)}:${String(Math.floor(s / 60) % 60).padStart(2, '0')}:${String(s % 60).padStart(2, '0')}`;
}

/// A Marlin board's URI (`marlin:PORT[@baud]`, `marlin+tcp://…`), as the server's `is_marlin`.
export const isMarlin = (uri: string) => /^marlin[:+]/.test(uri);

/// The machine list's entry that asks for a Marlin plotter's address.
const MARLIN_ENTRY = '?marlin';

/// A Marlin machine URI from what was typed: a port becomes `marlin:PORT`, `tcp://…`
/// becomes `marlin+tcp://…`, a `marlin…` URI stays; '' stays ''.
function marlinUri(typed: string): string {
  const a = typed.trim();
  if (a === '' || a.startsWith('marlin')) return a;
  return a.startsWith('tcp://') ? 'marlin+' + a : 'marlin:' + a;
}

/// Why a control is off on Marlin: its serial link carries G-code lines, hold
/// (no new line sent), resume and stop; none of grbl's real-time commands.
const ON_MARLIN: Record<string, string> = {
  jog: "Marlin has no jog over its link (grbl's $J): type G0/G91 moves in the console",
  home: 'Marlin homes with G28: the plot program starts with it, or type it in the console',
  unlock: "Marlin has no alarm lock to clear (grbl's $X); Reset sends M112, after which the board must be restarted",
  override: "Marlin takes no real-time feed or spindle override over its link (grbl's override bytes)",
  offsets: "work offsets here are grbl's (G10 L20, $#): Marlin's link has none; a plot starts from G28's home",
};

export class MachinePanel {
  private controls = false;
  private client = 0;
  private last: Snapshot | null = null;
  private programErrors = 0;
  /// The shown job's end as last seen (null while it runs or when there is none).
  private jobEnded: boolean | null = null;
  private macros: { refresh(): void };

  constructor(private hooks: Hooks) {
    const send = (cmd: Record<string, unknown>) => {
      try { hooks.send(cmd); } catch (e) { hooks.error((e as Error).message); }
    };
    $('connect').onclick = () => send({ cmd: 'connect', uri: $<HTMLSelectElement>('machine-uri').value });
    $('hold').onclick = () => send({ cmd: 'hold' });
    $('resume').onclick = () => send({ cmd: 'resume' });
    $('stop').onclick = () => send({ cmd: 'stop' });
    $('unlock').onclick = () => send({ cmd: 'unlock' });
    $('home').onclick = () => send({ cmd: 'home' });
    $('reset').onclick = () => send({ cmd: 'soft_reset' });
    setupOffsets(send);
    setupMdi(send);
    this.macros = setupMacros(send, () => this.controls);
    $('control').onclick = () => { if (!this.controls) send({ cmd: 'take_control' }); };
    $('start').onclick = async () => {
      try {
        const file = await hooks.prepareStart();
        const from = $<HTMLInputElement>('from-line').value;
        const speed = Number($<HTMLSelectElement>('speed').value);
        send({ cmd: 'start', file, from_line: from ? Number(from) : null, speed: speed > 0 ? speed : null });
      } catch (e) {
        hooks.error((e as Error).message);
      }
    };
    const jog = new Jogger(send, () => this.controls && (this.last?.state ?? 'idle') === 'idle');
    for (const b of Array.from(document.querySelectorAll<HTMLButtonElement>('#jog button'))) {
      const dir = b.dataset.jog!.split(',').map(Number);
      b.onclick = () => jog.step(dir);
      // Continuous: moves while held. The release is watched on the window (the button is
      // disabled while the machine moves).
      b.onpointerdown = (e) => {
        if (!jog.continuous || b.disabled) return;
        e.preventDefault();
        jog.start(dir);
      };
    }
    keyboardJog(jog);
    gamepadJog(jog);
    const so = $<HTMLInputElement>('so');
    so.oninput = () => { $('so-value').textContent = `${so.value} %`; };
    so.onchange = () => send({ cmd: 'spindle_override', value: Number(so.value) / 100 });
    const fo = $<HTMLInputElement>('fo');
    fo.oninput = () => { $('fo-value').textContent = `${fo.value} %`; };
    fo.onchange = () => send({ cmd: 'feed_override', value: Number(fo.value) / 100 });
  }

  setMachines(current: string, profiles: string[]) {
    const sel = $<HTMLSelectElement>('machine-uri');
    const options = ['virtual', ...profiles.map((p) => `virtual:${p}`)];
    if (!options.includes(current)) options.unshift(current);
    sel.innerHTML = options.map((o) => `<option${o === current ? ' selected' : ''}>${o}</option>`).join('');
    const custom = document.createElement('option');
    custom.textContent = 'grbl: or tcp://… (type)';
    custom.value = '';
    sel.appendChild(custom);
    // A Makelangelo or other Marlin 2.x plotter: its serial port or network bridge.
    const marlin = new Option('Marlin plotter: port or marlin+tcp://… (type)', MARLIN_ENTRY);
    sel.appendChild(marlin);
    sel.onchange = () => {
      const typed = sel.value === '' ? prompt('Machine address: grbl:/dev/ttyUSB0, tcp://HOST:PORT', 'tcp://127.0.0.1:2323')
        : sel.value === MARLIN_ENTRY ? marlinUri(prompt('Marlin plotter: a serial port (/dev/ttyUSB0, @baud for other than 250000) or marlin+tcp://HOST:PORT', '/dev/ttyUSB0') ?? '')
          : null;
      if (typed) { sel.insertBefore(new Option(typed, typed), custom); sel.value = typed; }
    };
  }

  /// The machine a plot borrowed the virtual machine from, given back by [`restoreMachine`].
  private borrowedFrom: string | null = null;

  /// A plot runs on the plotter it was made for: the virtual machine is put on `uri` (and
  /// the console says so, and what it was); real firmware is never swapped by a process —
  /// the page says the plot was made for another machine and leaves the choice to the user.
  useVirtual(uri: string) {
    const s = this.last;
    if (!s || s.uri === uri) return;
    if (!s.is_virtual) {
      const msg = `this plot was made for ${uri}, but the connected machine is ${s.machine} (${s.uri}): run it there only if that is the plotter, or connect ${uri} to try it on the virtual plotter`;
      this.log(msg);
      this.hooks.error(msg);
      return;
    }
    const sel = $<HTMLSelectElement>('machine-uri');
    if (!Array.from(sel.options).some((o) => o.value === uri)) sel.insertBefore(new Option(uri, uri), sel.options[0]);
    sel.value = uri;
    if (this.borrowedFrom === null) this.borrowedFrom = s.uri;
    this.log(`the virtual machine is now ${uri}, the plotter this plot was made for (it was ${this.borrowedFrom}; it goes back when another program is opened)`);
    try { this.hooks.send({ cmd: 'connect', uri }); } catch (e) { this.hooks.error((e as Error).message); }
  }

  /// Puts back the machine a plot borrowed, once it is idle (a job is never interrupted).
  restoreMachine() {
    const back = this.borrowedFrom;
    const s = this.last;
    if (back === null || !s || !s.is_virtual) { this.borrowedFrom = null; return; }
    if (s.state !== 'idle') return;
    this.borrowedFrom = null;
    if (s.uri === back) return;
    $<HTMLSelectElement>('machine-uri').value = back;
    this.log(`the virtual machine is ${back} again`);
    try { this.hooks.send({ cmd: 'connect', uri: back }); } catch (e) { this.hooks.error((e as Error).message); }
  }

  connected() {
    this.log('(connected to the server)');
  }

  private log(line: string) {
    const c = $('console');
    c.textContent += line + '\n';
    if (c.textContent!.length > 100_000) c.textContent = c.textContent!.slice(-50_000);
    c.scrollTop = c.scrollHeight;
  }

  private setControl(controls: boolean) {
    this.controls = controls;
    const pill = $('control');
    pill.textContent = controls ? 'controlling the machine' : 'watching (click to take control)';
    pill.classList.toggle('controls', controls);
    this.updateButtons();
  }

  handle(m: LiveMessage) {
    switch (m.type) {
      case 'hello': this.client = m.client; this.setControl(m.controller); break;
      case 'control': this.setControl(m.controller === this.client); break;
      case 'console': for (const l of m.lines) this.log(l); break;
      case 'status': if (m.status) this.status(m.status); break;
      case 'progress': $('carve-status').textContent = `${m.stage} ${(m.fraction * 100).toFixed(0)} %`; break;
      case 'error': this.hooks.error(m.message); this.log('! ' + m.message); break;
      case 'ok': this.hooks.error(''); break;
      case 'event': break;
    }
  }

  /// The loaded program's error count: Start stays disabled while it has errors.
  setProgramErrors(n: number) {
    this.programErrors = n;
    this.updateButtons();
  }

  private status(s: Snapshot) {
    const changed = s.uri !== this.last?.uri;
    this.last = s;
    $('machine-name').textContent = `${s.machine} · ${s.firmware}`;
    // The select shows the machine connected when it changes (another page's connect too);
    // a choice not yet connected is left alone.
    const sel = $<HTMLSelectElement>('machine-uri');
    if (changed && sel.value !== s.uri && sel.options.length) {
      if (!Array.from(sel.options).some((o) => o.value === s.uri)) sel.insertBefore(new Option(s.uri, s.uri), sel.options[0]);
      sel.value = s.uri;
    }
    const f = (v: number) => v.toFixed(3);
    ['x', 'y', 'z'].forEach((a, i) => {
      $('w' + a).textContent = f(s.work_pos[i]);
      $('m' + a).textContent = f(s.machine_pos[i]);
    });
    $('state').textContent = s.state;
    $('line').textContent = String(s.line);
    $('feed').textContent = s.feed.toFixed(0);
    const p = $<HTMLProgressElement>('progress');
    p.value = s.total > 0 ? Math.min(1, s.elapsed / s.total) : 0;
    const speedSel = $<HTMLSelectElement>('speed');
    speedSel.disabled = !s.is_virtual;
    speedSel.title = s.is_virtual ? '' : 'firmware runs the job at its own pace';
    const speed = s.job?.speed ?? null;
    $('elapsed').textContent = hms(speed ? s.elapsed / speed : s.elapsed);
    $('remaining').textContent = hms(s.remaining);
    $('alarm').hidden = s.alarm === null;
    $('alarm-text').textContent = s.alarm ?? '';
    $('alarm-meaning').textContent = s.alarm_meaning ?? '';
    document.body.dataset.state = s.state;
    // The override the machine reports (grbl's `Ov:`), not the slider's wish.
    const ov = Math.round(s.feed_override * 100);
    document.body.dataset.feedOverride = String(ov);
    const fo = $<HTMLInputElement>('fo');
    if (document.activeElement !== fo) { fo.value = String(ov); $('fo-value').textContent = `${ov} %`; }
    // A job that ended (or a new one) leaves no stale "from line" for the next start.
    const ended = s.job?.completed ?? null;
    if (ended !== null && this.jobEnded === null) $<HTMLInputElement>('from-line').value = '';
    this.jobEnded = s.job ? ended : null;
    showOffsets(s.offsets);
    document.body.dataset.jobDone = s.job?.completed === true ? 'completed' : s.job?.completed === false ? 'stopped' : '';
    this.updateButtons();
    this.hooks.onStatus(s);
  }

  private updateButtons() {
    const s = this.last?.state ?? 'idle';
    const c = this.controls;
    const idle = s === 'idle';
    const rest = idle || s === 'alarm';
    const set = (id: string, on: boolean) => { $<HTMLButtonElement>(id).disabled = !(c && on); };
    // Stopping needs no control: any page may.
    const anyPage = (id: string, on: boolean) => { $<HTMLButtonElement>(id).disabled = !on; };
    set('start', idle && this.programErrors === 0);
    $('start').title = this.programErrors ? `the program has ${this.programErrors} errors: fix them first` : '';
    anyPage('hold', s === 'run' || s === 'jog');
    set('resume', s === 'hold' || s === 'holding' || s === 'paused');
    anyPage('stop', !idle && s !== 'alarm');
    anyPage('reset', this.last !== null);
    set('connect', rest);
    set('home', rest);
    set('unlock', s === 'alarm' || (idle && !this.last?.is_virtual));
    for (const id of ['zero-x', 'zero-y', 'zero-z', 'zero', 'goto-zero']) set(id, idle);
    set('read-offsets', rest);
    $<HTMLSelectElement>('wcs').disabled = !(c && idle);
    $<HTMLInputElement>('mdi').disabled = !c;
    set('mdi-send', true);
    this.macros.refresh();
    for (const b of Array.from(document.querySelectorAll<HTMLButtonElement>('#jog button'))) b.disabled = !(c && idle);
    this.marlinLimits();
  }

  /// On a Marlin plotter what its link cannot do is off, its tooltip saying why (and back
  /// on, without the tooltip, on another machine).
  private marlinLimits() {
    const marlin = isMarlin(this.last?.uri ?? '');
    document.body.dataset.marlin = marlin ? 'yes' : '';
    const byId = (...ids: string[]) => ids.map((id) => document.getElementById(id));
    const groups: [string, (HTMLElement | null)[]][] = [
      ['jog', [...byId('jog-step'), ...Array.from(document.querySelectorAll<HTMLElement>('#jog button'))]],
      ['home', byId('home')], ['unlock', byId('unlock')], ['override', byId('fo', 'so')],
      ['offsets', byId('zero-x', 'zero-y', 'zero-z', 'zero', 'goto-zero', 'read-offsets', 'wcs')],
    ];
    for (const [why, els] of groups) {
      for (const el of els) {
        if (!(el instanceof HTMLButtonElement || el instanceof HTMLInputElement || el instanceof HTMLSelectElement)) continue;
        if (marlin) {
          el.dataset.titleBefore ??= el.title;
          el.disabled = true;
          el.title = ON_MARLIN[why];
        } else if (el.dataset.titleBefore !== undefined) {
          el.title = el.dataset.titleBefore;
          delete el.dataset.titleBefore;
          // The rest are set by updateButtons on every status; these by nobody else.
          if (why === 'override' || el.id === 'jog-step') el.disabled = false;
        }
      }
    }
  }
}
