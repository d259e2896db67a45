// Tool changes on firmware without a changer: the policy the sender follows at M6 (pause,
// park, remeasure on the tool setter, ignore), kept in this browser and given to the
// connected board; and while a job waits at an M6, a banner naming the tool and the line,
// with the button that resumes once the tool is in.

import type { LiveMessage, Snapshot } from './api';
import { Section, WorkshopHooks, addSection, num, remember } from './workshop';
import { isMarlin } from './machine';

const FORM = `
<div class="form">
  <label>At M6 <select name="policy">
    <option value="pause">pause for a manual change</option>
    <option value="park">park, then pause</option>
    <option value="remeasure">pause, then measure on the tool setter</option>
    <option value="ignore">ignore (drop M6 and T)</option>
  </select></label>
  <label>Park X <input name="park_x" type="number" step="any"> (machine)</label>
  <label>Park Y <input name="park_y" type="number" step="any"></label>
  <label>Park Z <input name="park_z" type="number" step="any"></label>
  <label>Setter X <input name="tc_setter_x" type="number" step="any"> (machine)</label>
  <label>Setter Y <input name="tc_setter_y" type="number" step="any"></label>
  <label>Setter start Z <input name="tc_setter_z" type="number" step="any"></label>
</div>
<div id="toolchange-message" class="muted">Applies to grbl firmware; the virtual machine changes tools from its tool table.</div>`;

type Tool = { tool: number; line: number; prompt: string };

export function setupToolChange(hooks: WorkshopHooks): Section {
  const root = addSection('toolchange', 'Tool change', FORM);
  const message = root.querySelector<HTMLElement>('#toolchange-message')!;
  // The banner sits under the machine's state, where the operator looks.
  const banner = document.createElement('div');
  banner.id = 'toolchange-banner';
  banner.hidden = true;
  // Unmissable: the job waits for the operator's hands.
  banner.style.cssText = 'border:2px solid #e0a030;background:#3a2a08;color:#ffd680;padding:6px 8px;margin:6px 0;border-radius:4px';
  banner.innerHTML = '<b id="toolchange-tool"></b><p id="toolchange-prompt"></p><button id="toolchange-continue">Tool changed — continue</button>';
  const alarm = document.getElementById('alarm')!;
  alarm.parentElement!.insertBefore(banner, alarm.nextSibling);
  banner.querySelector<HTMLButtonElement>('#toolchange-continue')!.onclick = () => {
    try { hooks.send({ cmd: 'resume' }); } catch (e) { hooks.error((e as Error).message); }
  };

  let last: Snapshot | null = null;
  let sentFor = '';
  const policy = (): Record<string, unknown> => {
    const p = root.querySelector<HTMLSelectElement>('[name=policy]')!.value;
    const triple = (a: string, b: string, c: string, what: string) => {
      const v = [num(root, a, true), num(root, b, true), num(root, c, true)];
      if (v.every((x) => x === null)) return null;
      if (v.some((x) => x === null)) throw new Error(`${what}: give X, Y and Z (machine mm)`);
      return v;
    };
    const park = triple('park_x', 'park_y', 'park_z', 'Park position');
    const setter = triple('tc_setter_x', 'tc_setter_y', 'tc_setter_z', 'Tool setter');
    if (p === 'park' && !park) throw new Error('park: give the park position (machine X, Y, Z)');
    if (p === 'remeasure' && !setter) throw new Error('remeasure: give the tool setter (machine X, Y and the Z to start probing from)');
    return { cmd: 'tool_change', policy: p, park, setter };
  };
  /// The policy to the connected board (firmware only).
  const apply = () => {
    // Marlin interprets M6 itself (or refuses it): the sender has no policy to apply.
    if (!last || last.is_virtual || isMarlin(last.uri)) return;
    try {
      hooks.send(policy());
      message.textContent = `${root.querySelector<HTMLSelectElement>('[name=policy]')!.selectedOptions[0].text} (given to ${last.uri})`;
      message.classList.remove('error');
    } catch (e) {
      message.textContent = (e as Error).message;
      message.classList.add('error');
    }
  };
  remember(root, 'oficina.toolchange', apply);
  // Before every start: the board may have been reconnected since.
  document.getElementById('start')!.addEventListener('click', () => apply(), { capture: true });

  return {
    handle(m: LiveMessage) {
      if (m.type !== 'status' || !m.status) return;
      last = m.status;
      if (!last.is_virtual && sentFor !== last.uri) { sentFor = last.uri; apply(); }
      if (last.is_virtual) sentFor = '';
      const tc = (last as Snapshot & { tool_change?: Tool | null }).tool_change ?? null;
      banner.hidden = tc === null;
      document.body.dataset.toolChange = tc ? `T${tc.tool}@${tc.line}` : '';
      if (tc) {
        banner.querySelector('#toolchange-tool')!.textContent = `Tool change: put in T${tc.tool} (M6 at line ${tc.line})`;
        banner.querySelector('#toolchange-prompt')!.textContent = tc.prompt;
      }
    },
  };
}
