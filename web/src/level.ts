// Auto-levelling: a grid probed over the loaded program's feed moves on the connected
// firmware, the height map shown (kept in the job folder as level-map.json), and "start
// levelled", which makes Start stream the program levelled with that map.

import type { LiveMessage } from './api';
import { Section, WorkshopHooks, addSection, explain, num, remember } from './workshop';

const HTML = `
<div class="form">
  <label>Points X <input name="nx" type="number" value="4" min="2" max="100" step="1"></label>
  <label>Points Y <input name="ny" type="number" value="4" min="2" max="100" step="1"></label>
  <label>Margin <input name="margin" type="number" value="2" min="0" max="1000" step="any"> mm</label>
  <label>Clearance <input name="clearance" type="number" value="3" min="-1000" max="1000" step="any"> mm (work Z)</label>
  <label>Deepest <input name="depth" type="number" value="-3" min="-1000" max="1000" step="any"> mm (work Z)</label>
  <label>Probe feed <input name="level_feed" type="number" value="200" min="1" max="100000" step="any"> mm/min</label>
</div>
<div class="row"><button id="level-probe">Probe grid</button><button id="level-load">Load saved map</button></div>
<label class="row"><input id="start-levelled" name="start_levelled" type="checkbox"> start levelled (Start streams the program with the map)</label>
<div id="level-message" class="muted">The map is saved in the job folder as level-map.json.</div>
<table id="level-map"></table>`;

/// level-map.json as the library writes it: `z` one row per Y, from the smallest Y.
interface MapJson { origin: [number, number]; spacing: [number, number]; nx: number; ny: number; z: number[][]; }

export function setupLevel(hooks: WorkshopHooks): Section {
  const root = addSection('level', 'Level', HTML);
  remember(root, 'oficina.level');
  const message = root.querySelector<HTMLElement>('#level-message')!;
  const say = (text: string, bad = false) => { message.textContent = text; message.classList.toggle('error', bad); };
  const levelled = root.querySelector<HTMLInputElement>('#start-levelled')!;
  root.querySelector<HTMLButtonElement>('#level-probe')!.onclick = async () => {
    // Busy from the click on: a map shown before is not this one.
    document.body.dataset.level = 'busy';
    try {
      const file = await hooks.prepareStart();
      const cmd = {
        cmd: 'probe_map', file, nx: num(root, 'nx'), ny: num(root, 'ny'), margin: num(root, 'margin'),
        clearance: num(root, 'clearance'), depth: num(root, 'depth'), feed: num(root, 'level_feed'),
      };
      say(`probing a ${cmd.nx} × ${cmd.ny} grid over ${file}…`);
      document.body.dataset.level = 'busy';
      hooks.send(cmd);
    } catch (e) { say((e as Error).message, true); document.body.dataset.level = 'failed'; }
  };
  root.querySelector<HTMLButtonElement>('#level-load')!.onclick = () => {
    try { hooks.send({ cmd: 'load_map' }); } catch (e) { say((e as Error).message, true); }
  };
  // Start, when levelled: the levelled program goes instead (the machine panel's own start
  // listener does not run).
  document.getElementById('start')!.addEventListener('click', async (e) => {
    if (!levelled.checked) return;
    e.stopImmediatePropagation();
    try {
      const file = await hooks.prepareStart();
      const from = (document.getElementById('from-line') as HTMLInputElement).value;
      hooks.send({ cmd: 'start_levelled', file, from_line: from ? Number(from) : null });
    } catch (err) { hooks.error((err as Error).message); }
  }, { capture: true });

  const table = root.querySelector<HTMLTableElement>('#level-map')!;
  const draw = (m: MapJson) => {
    const all = m.z.flat();
    const lo = Math.min(...all), hi = Math.max(...all);
    const colour = (z: number) => {
      const t = hi > lo ? (z - lo) / (hi - lo) : 0.5;
      return `hsl(${(1 - t) * 240}, 70%, 45%)`;
    };
    let html = `<tr><th>Y \\ X</th>${Array.from({ length: m.nx }, (_, i) => `<th>${(m.origin[0] + i * m.spacing[0]).toFixed(1)}</th>`).join('')}</tr>`;
    for (let j = m.ny - 1; j >= 0; j--) {
      html += `<tr><th>${(m.origin[1] + j * m.spacing[1]).toFixed(1)}</th>`;
      for (let i = 0; i < m.nx; i++) {
        const z = m.z[j][i];
        html += `<td style="background:${colour(z)};color:#fff">${z.toFixed(3)}</td>`;
      }
      html += '</tr>';
    }
    table.innerHTML = html;
    say(`height map ${m.nx} × ${m.ny}: Z ${lo.toFixed(3)} … ${hi.toFixed(3)} (${(hi - lo).toFixed(3)} mm), saved as level-map.json`);
  };

  return {
    handle(m: LiveMessage) {
      const any = m as unknown as { type: string; map?: MapJson; error?: string };
      if (m.type === 'status' && m.status) {
        const off = m.status.is_virtual || m.status.state !== 'idle';
        for (const b of Array.from(root.querySelectorAll<HTMLButtonElement>('button'))) b.disabled = off;
        levelled.disabled = m.status.is_virtual;
        if (m.status.is_virtual) levelled.checked = false;
      }
      if (any.type === 'height_map' && any.map) { draw(any.map); document.body.dataset.level = 'mapped'; }
      if (any.type === 'probing' && any.error?.startsWith('height map')) { say(explain(any.error), true); document.body.dataset.level = 'failed'; }
      if (m.type === 'error' && document.body.dataset.level === 'busy') { say(explain(m.message), true); document.body.dataset.level = 'failed'; }
    },
  };
}
