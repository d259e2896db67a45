// The profile editor: a machine profile's TOML (steps/unit, rates, accelerations, backlash,
// travel, kinematics), checked by the motion crate's own validation on the server, whose
// key and message are shown; a good one is put on the virtual machine.

import { withToken } from './api';

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;

interface Answer { ok: boolean; key?: string; error?: string; name?: string; uri?: string }

async function send(path: string, body: string): Promise<Answer> {
  const r = await fetch(withToken(path), { method: 'POST', body });
  return r.json().catch(() => ({ ok: false, error: `${r.status} ${r.statusText}` }));
}

function show(a: Answer, what: string) {
  const m = $('profile-message');
  m.className = a.ok ? 'muted' : 'error';
  m.textContent = a.ok ? `${a.name}: ${what}` : `${a.key ? a.key + ': ' : ''}${a.error}`;
}

export function setupProfileEditor(profiles: string[]) {
  const pick = $<HTMLSelectElement>('profile-pick');
  pick.innerHTML = profiles.map((p) => `<option>${p}</option>`).join('');
  const load = async () => {
    const r = await fetch(withToken('/api/profiles/' + encodeURIComponent(pick.value)));
    $<HTMLTextAreaElement>('profile-text').value = await r.text();
    $('profile-message').textContent = '';
  };
  pick.onchange = load;
  $('profile-check').onclick = async () => show(await send('/api/profiles/check', $<HTMLTextAreaElement>('profile-text').value), 'valid');
  $('profile-use').onclick = async () => show(await send('/api/profiles/use', $<HTMLTextAreaElement>('profile-text').value), 'on the virtual machine');
  load();
}

export interface ToolRow { number: number; pocket: number; diameter: number; length: number; comment: string }

/// The tool table: checked by the interpreter's own parser (line and column of an error),
/// saved in the job folder when good, shown as a table.
export async function setupToolEditor(onSaved: () => void) {
  const text = $<HTMLTextAreaElement>('tools-text');
  text.value = await (await fetch(withToken('/api/tools'))).text();
  const showRows = (rows: ToolRow[]) => {
    $('tools-table').innerHTML = '<tr><th>T</th><th>pocket</th><th>Ø mm</th><th>length mm</th><th></th></tr>' +
      rows.map((t) => `<tr><td>${t.number}</td><td>${t.pocket}</td><td>${t.diameter}</td><td>${t.length}</td><td style="text-align:left">${t.comment.replace(/[<&]/g, '')}</td></tr>`).join('');
  };
  $('tools-save').onclick = async () => {
    const r = await fetch(withToken('/api/tools'), { method: 'PUT', body: text.value });
    const a = await r.json().catch(() => ({ ok: false, error: `${r.status} ${r.statusText}` }));
    const m = $('tools-message');
    m.className = a.ok ? 'muted' : 'error';
    // The check and the next run use the saved table: the program is checked again.
    if (a.ok) { showRows(a.tools); m.textContent = `saved ${a.tools.length} tools`; onSaved(); }
    else m.textContent = a.line ? `line ${a.line}, column ${a.col}: ${a.error}` : a.error;
  };
}
