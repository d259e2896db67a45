// Jogging, from the buttons, the keyboard and a gamepad alike: a step, or a continuous jog
// that moves until released (grbl's `$J=` then jog cancel 0x85). A release that never comes
// (the window loses focus, the tab is hidden, the pointer leaves) stops it all the same; a
// page that goes away stops it on the server.

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;

export class Jogger {
  private moving = false;

  constructor(private send: (cmd: Record<string, unknown>) => void, private canMove: () => boolean) {
    const release = () => this.stop();
    window.addEventListener('pointerup', release);
    window.addEventListener('pointercancel', release);
    window.addEventListener('blur', release);
    document.addEventListener('visibilitychange', () => { if (document.hidden) release(); });
  }

  get continuous(): boolean { return $<HTMLSelectElement>('jog-step').value === 'continuous'; }
  get active(): boolean { return this.moving; }
  private feed(): number { return Number($<HTMLInputElement>('jog-feed').value); }

  /// One step of the chosen size along `dir` (each -1, 0 or 1).
  step(dir: number[]) {
    if (!this.canMove() || this.continuous) return;
    const step = Number($<HTMLSelectElement>('jog-step').value);
    this.send({ cmd: 'jog', delta: dir.map((v) => v * step), feed: this.feed() });
  }

  /// Moves along `dir` until `stop`.
  start(dir: number[]) {
    if (!this.canMove() || this.moving) return;
    this.moving = true;
    this.send({ cmd: 'jog_start', direction: dir, feed: this.feed() });
  }

  stop() {
    if (!this.moving) return;
    this.moving = false;
    try { this.send({ cmd: 'jog_stop' }); } catch { /* the server stops it when the socket drops */ }
  }

  /// The step select one size smaller (-1) or larger (+1), "hold to move" last.
  changeStep(by: number) {
    const sel = $<HTMLSelectElement>('jog-step');
    sel.selectedIndex = Math.max(0, Math.min(sel.options.length - 1, sel.selectedIndex + by));
  }
}

const KEYS: Record<string, number[]> = {
  ArrowLeft: [-1, 0, 0], ArrowRight: [1, 0, 0], ArrowUp: [0, 1, 0], ArrowDown: [0, -1, 0],
  PageUp: [0, 0, 1], PageDown: [0, 0, -1],
};

/// Keys jog while the page has focus outside text fields and the editor.
function typing(t: EventTarget | null): boolean {
  const e = t as HTMLElement | null;
  return !!e && (e.isContentEditable || ['INPUT', 'TEXTAREA', 'SELECT'].includes(e.tagName) || !!e.closest?.('#editor'));
}

export function keyboardJog(jog: Jogger) {
  let held: string | null = null;
  window.addEventListener('keydown', (e) => {
    if (typing(e.target) || e.ctrlKey || e.altKey || e.metaKey) return;
    if (e.key === '[' || e.key === ']') { jog.changeStep(e.key === '[' ? -1 : 1); e.preventDefault(); return; }
    const dir = KEYS[e.key];
    if (!dir) return;
    e.preventDefault();
    if (e.repeat) return;
    if (jog.continuous) { held = e.key; jog.start(dir); } else jog.step(dir);
  });
  window.addEventListener('keyup', (e) => {
    if (held === e.key) { held = null; jog.stop(); }
  });
  window.addEventListener('blur', () => { held = null; });
}

/// Gamepad: left stick X Y, right stick (or the triggers) Z, continuous while pushed.
export function gamepadJog(jog: Jogger) {
  if (!('getGamepads' in navigator)) return;
  let last = '0,0,0';
  let polling = false;
  const dead = (v: number) => (Math.abs(v) < 0.5 ? 0 : Math.sign(v));
  const poll = () => {
    const pads = navigator.getGamepads().filter((p): p is Gamepad => !!p);
    if (pads.length === 0) { polling = false; if (last !== '0,0,0') { last = '0,0,0'; jog.stop(); } return; }
    const p = pads[0];
    const trig = (i: number) => (p.buttons[i]?.value ?? 0);
    const z = dead(-(p.axes[3] ?? 0)) || dead(trig(7) - trig(6));
    const dir = [dead(p.axes[0] ?? 0), dead(-(p.axes[1] ?? 0)), z];
    const key = dir.join(',');
    if (key !== last) {
      last = key;
      jog.stop();
      if (key !== '0,0,0') jog.start(dir);
    }
    requestAnimationFrame(poll);
  };
  window.addEventListener('gamepadconnected', (e) => {
    $('gamepad-hint').textContent = ` · gamepad ${(e as GamepadEvent).gamepad.id.slice(0, 24)}: left stick X Y, right stick or triggers Z`;
    if (!polling) { polling = true; requestAnimationFrame(poll); }
  });
}
