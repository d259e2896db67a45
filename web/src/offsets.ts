// The work offsets: zero an axis or all in the active system, choose G54…G59, go to the
// work zero, and the table of every system as the machine last reported it.

import type { Offsets } from './api';

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;
const SYSTEMS = ['G54', 'G55', 'G56', 'G57', 'G58', 'G59'];

export function setupOffsets(send: (cmd: Record<string, unknown>) => void) {
  for (const id of ['zero-x', 'zero-y', 'zero-z', 'zero']) {
    const b = $<HTMLButtonElement>(id);
    b.onclick = () => send({ cmd: 'zero', axes: b.dataset.axes!.split(',').map((v) => v === '1') });
  }
  $<HTMLSelectElement>('wcs').onchange = (e) => send({ cmd: 'select_system', system: Number((e.target as HTMLSelectElement).value) });
  $('goto-zero').onclick = () => send({ cmd: 'go_to_zero', z: $<HTMLInputElement>('goto-z').checked });
  $('read-offsets').onclick = () => send({ cmd: 'read_offsets' });
}

let shown = '';
export function showOffsets(o: Offsets) {
  const key = JSON.stringify(o);
  if (key === shown) return;
  shown = key;
  const wcs = $<HTMLSelectElement>('wcs');
  if (document.activeElement !== wcs) wcs.value = String(o.active);
  const f = (v: number) => v.toFixed(3);
  const row = (name: string, v: (string | number)[], cls = '') =>
    `<tr class="${cls}" data-row="${name}"><th>${name}</th>${v.map((x) => `<td>${typeof x === 'number' ? f(x) : x}</td>`).join('')}</tr>`;
  const rows = o.known ? SYSTEMS.map((s, i) => row(s, o.systems[i], i === o.active ? 'active' : '')) : [`<tr><td colspan="4" class="muted">not read yet</td></tr>`];
  if (o.g92.some((v) => v !== 0)) rows.push(row('G92', o.g92));
  if (o.tlo !== 0) rows.push(row('TLO', ['', '', o.tlo]));
  if (o.probe) rows.push(row('PRB', [...o.probe.pos], o.probe.touched ? '' : 'muted'));
  $('offsets').querySelector('tbody')!.innerHTML = rows.join('');
}
