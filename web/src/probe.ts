// Probing: a Z touch plate, an XYZ outside corner and a tool length setter, run by the
// server's session on the connected firmware; what they measured or why they failed is shown.

import type { LiveMessage } from './api';
import { Section, WorkshopHooks, addSection, explain, num, remember } from './workshop';

const HTML = `
<div class="form probe-form">
  <label>Plate thickness <input name="thickness" type="number" value="10" min="0" max="1000" step="any"> mm</label>
  <label>Set <select name="wcs">${[1, 2, 3, 4, 5, 6].map((i) => `<option value="${i}">G${53 + i}</option>`).join('')}</select></label>
  <label>Fast feed <input name="feed" type="number" value="100" min="1" max="100000" step="any"> mm/min</label>
  <label>Slow feed <input name="slow_feed" type="number" value="25" min="1" max="100000" step="any"> mm/min</label>
  <label>Travel <input name="travel" type="number" value="20" min="0.1" max="1000" step="any"> mm</label>
  <label>Retract <input name="retract" type="number" value="2" min="0.1" max="500" step="any"> mm</label>
</div>
<div class="row"><button id="probe-z">Probe Z (plate)</button></div>
<div class="form probe-form">
  <label>Tool diameter <input name="tool_diameter" type="number" value="6" min="0" max="100" step="any"> mm</label>
  <label>Reach <input name="reach" type="number" value="15" min="0.1" max="1000" step="any"> mm</label>
  <label>Side depth <input name="depth" type="number" value="3" min="0.1" max="1000" step="any"> mm</label>
  <label>Side offset X <input name="side_x" type="number" value="0" min="-1000" max="1000" step="any"> mm</label>
  <label>Side offset Y <input name="side_y" type="number" value="0" min="-1000" max="1000" step="any"> mm</label>
</div>
<div class="row"><button id="probe-corner">Probe XYZ corner</button></div>
<div class="form probe-form">
  <label>Setter X <input name="setter_x" type="number" step="any" placeholder="here"> (machine)</label>
  <label>Setter Y <input name="setter_y" type="number" step="any" placeholder="here"> (machine)</label>
  <label>Safe Z <input name="safe_z" type="number" value="-5" step="any"> (machine)</label>
  <label>Reference Z <input name="reference" type="number" step="any" placeholder="none: this is the reference"> (machine)</label>
</div>
<div class="row"><button id="probe-setter">Measure on setter</button></div>
<div id="probe-result" class="muted">Probing runs on grbl firmware.</div>`;

export function setupProbe(hooks: WorkshopHooks): Section {
  const root = addSection('probe', 'Probe', HTML);
  remember(root, 'oficina.probe');
  const result = root.querySelector<HTMLElement>('#probe-result')!;
  const show = (text: string, bad = false) => {
    result.textContent = text;
    result.classList.toggle('error', bad);
    document.body.dataset.probe = bad ? 'failed' : text.startsWith('probing') ? 'busy' : 'done';
  };
  const approach = () => ({
    travel: num(root, 'travel'), feed: num(root, 'feed'), slow_feed: num(root, 'slow_feed'), retract: num(root, 'retract'),
  });
  const run = (make: () => Record<string, unknown>) => {
    try {
      const cmd = make();
      show('probing…');
      hooks.send(cmd);
    } catch (e) {
      show((e as Error).message, true);
    }
  };
  root.querySelector<HTMLButtonElement>('#probe-z')!.onclick = () => run(() => ({
    cmd: 'probe_z_plate', thickness: num(root, 'thickness'), wcs: Number(root.querySelector<HTMLSelectElement>('[name=wcs]')!.value), ...approach(),
  }));
  root.querySelector<HTMLButtonElement>('#probe-corner')!.onclick = () => run(() => ({
    cmd: 'probe_corner', thickness: num(root, 'thickness'), wcs: Number(root.querySelector<HTMLSelectElement>('[name=wcs]')!.value),
    tool_diameter: num(root, 'tool_diameter'), reach: num(root, 'reach'), depth: num(root, 'depth'),
    side_offset: [num(root, 'side_x'), num(root, 'side_y')], ...approach(),
  }));
  root.querySelector<HTMLButtonElement>('#probe-setter')!.onclick = () => run(() => {
    const x = num(root, 'setter_x', true), y = num(root, 'setter_y', true);
    if ((x === null) !== (y === null)) throw new Error('Setter X and Y: give both, or neither to probe where the tool is');
    return { cmd: 'probe_setter', at: x === null ? null : [x, y], safe_z: num(root, 'safe_z'), reference: num(root, 'reference', true), ...approach() };
  });
  return {
    handle(m: LiveMessage) {
      const any = m as unknown as { type: string; result?: Record<string, unknown>; error?: string };
      if (m.type === 'status' && m.status) {
        const virtual = m.status.is_virtual;
        for (const b of Array.from(root.querySelectorAll<HTMLButtonElement>('button'))) {
          b.disabled = virtual || m.status.state !== 'idle';
          b.title = virtual ? 'probing runs on grbl firmware: connect a board (the virtual machine has no probe input)' : '';
        }
      }
      if (m.type === 'error' && result.textContent === 'probing…') show(explain(m.message), true);
      if (any.type !== 'probing') return;
      if (any.error !== undefined) {
        if (!any.error.startsWith('height map')) show(explain(any.error), true);
        return;
      }
      const r = any.result!;
      const xyz = (p: number[]) => `X${p[0].toFixed(3)} Y${p[1].toFixed(3)} Z${p[2].toFixed(3)}`;
      if (r.kind === 'offset') {
        const contacts = (r.contacts as number[][]).map(xyz).join(', ');
        show(`${r.routine === 'corner' ? 'Corner' : 'Touch plate'}: contact at machine ${contacts}; ${r.wcs} offset set to ${xyz(r.offset as number[])}`);
      } else if (r.kind === 'setter') {
        const tlo = r.tool_offset as number | null;
        show(`Setter: contact at machine ${xyz(r.contact as number[])} (Z${(r.measured_z as number).toFixed(3)})` +
          (tlo === null ? ' — keep it as the reference Z for later tools' : `; tool length offset G43.1 Z${tlo.toFixed(3)} applied`));
      }
    },
  };
}
