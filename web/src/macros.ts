// Macros: named G-code snippets kept in the job folder (macros.json), edited here, each a
// button that runs it through typed lines on the machine.

import { getJson, withToken } from './api';

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;

interface Macro { name: string; text: string; }

export function setupMacros(send: (cmd: Record<string, unknown>) => void, canRun: () => boolean) {
  let saved: Macro[] = [];
  const list = $('macro-list');
  const message = (text: string, error = false) => {
    $('macro-message').textContent = text;
    $('macro-message').className = error ? 'error' : 'muted';
  };
  const buttons = () => {
    const box = $('macro-buttons');
    box.innerHTML = saved.length ? '' : '<span class="muted">none yet</span>';
    for (const m of saved) {
      const b = document.createElement('button');
      b.textContent = m.name;
      b.title = m.text;
      b.className = 'macro';
      b.disabled = !canRun();
      b.onclick = () => send({ cmd: 'run_macro', name: m.name });
      box.appendChild(b);
    }
  };
  const addRow = (m: Macro) => {
    const row = document.createElement('div');
    row.className = 'macro-row';
    row.innerHTML = '<div class="row"><input class="macro-name" placeholder="name" maxlength="40"><button class="macro-delete" title="delete">✕</button></div><textarea class="macro-text" rows="3" spellcheck="false" placeholder="G0 X[x+1]"></textarea>';
    row.querySelector<HTMLInputElement>('.macro-name')!.value = m.name;
    row.querySelector<HTMLTextAreaElement>('.macro-text')!.value = m.text;
    row.querySelector<HTMLButtonElement>('.macro-delete')!.onclick = () => row.remove();
    list.appendChild(row);
  };
  const show = (macros: Macro[]) => {
    saved = macros;
    list.innerHTML = '';
    macros.forEach(addRow);
    buttons();
  };
  $('macro-add').onclick = () => addRow({ name: '', text: '' });
  $('macro-save').onclick = async () => {
    const macros = Array.from(list.querySelectorAll('.macro-row')).map((r) => ({
      name: r.querySelector<HTMLInputElement>('.macro-name')!.value.trim(),
      text: r.querySelector<HTMLTextAreaElement>('.macro-text')!.value,
    }));
    const r = await fetch(withToken('/api/macros'), { method: 'PUT', headers: { 'content-type': 'application/json' }, body: JSON.stringify(macros) });
    const body = await r.json().catch(() => ({ ok: false, error: `${r.status} ${r.statusText}` }));
    if (!body.ok) return message(body.error, true);
    show(body.macros);
    message(`saved ${body.macros.length} macros`);
  };
  getJson<{ macros: Macro[] }>('/api/macros').then((b) => show(b.macros)).catch((e) => message(String(e.message || e), true));
  // Only the buttons' state follows the machine: rebuilt, a button could lose a click.
  const refresh = () => {
    for (const b of Array.from($('macro-buttons').querySelectorAll<HTMLButtonElement>('button'))) b.disabled = !canRun();
  };
  return { refresh };
}
