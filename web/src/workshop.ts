// The machine panel's workshop sections: probing, the tool-change prompt and policy, and
// auto-levelling. Each is its own module; this gives them the live channel and the page's
// helpers, and passes them every live message.

import type { LiveMessage } from './api';
import { setupProbe } from './probe';
import { setupToolChange } from './toolchange';
import { setupLevel } from './level';

export interface WorkshopHooks {
  send(cmd: Record<string, unknown>): void;
  /// Saves the program if needed and gives its file name.
  prepareStart(): Promise<string>;
  error(msg: string): void;
}

export interface Section { handle(m: LiveMessage): void; }

export function setupWorkshop(hooks: WorkshopHooks): Section {
  const sections = [setupProbe(hooks), setupToolChange(hooks), setupLevel(hooks)];
  return { handle: (m) => sections.forEach((s) => s.handle(m)) };
}

/// A `<details>` section added to the machine panel, before the console.
export function addSection(id: string, title: string, html: string): HTMLElement {
  const d = document.createElement('details');
  d.id = id;
  d.innerHTML = `<summary>${title}</summary>${html}`;
  const right = document.getElementById('right')!;
  const consoleHeading = Array.from(right.querySelectorAll('h4')).find((h) => h.textContent === 'Console');
  right.insertBefore(d, consoleHeading ?? null);
  return d;
}

/// A number field's value, refused clearly when it is not one (named by its label).
export function num(root: HTMLElement, name: string, optional = false): number | null {
  const input = root.querySelector<HTMLInputElement>(`[name="${name}"]`)!;
  const label = input.closest('label')?.firstChild?.textContent?.trim() || name;
  if (input.value.trim() === '') {
    if (optional) return null;
    throw new Error(`${label}: a number is needed`);
  }
  const v = Number(input.value);
  if (!Number.isFinite(v)) throw new Error(`${label}: '${input.value}' is not a number`);
  if (!input.checkValidity()) throw new Error(`${label}: ${input.validationMessage}`);
  return v;
}

/// Keeps a section's fields in localStorage under `key`.
export function remember(root: HTMLElement, key: string, onChange?: () => void) {
  const fields = Array.from(root.querySelectorAll<HTMLInputElement | HTMLSelectElement>('input[name], select[name]'));
  try {
    const saved = JSON.parse(localStorage.getItem(key) || '{}');
    for (const f of fields) {
      if (!(f.name in saved)) continue;
      if (f instanceof HTMLInputElement && f.type === 'checkbox') f.checked = !!saved[f.name];
      else f.value = String(saved[f.name]);
    }
  } catch { /* a bad entry is forgotten */ }
  for (const f of fields) {
    f.addEventListener('change', () => {
      const all: Record<string, unknown> = {};
      for (const g of fields) all[g.name] = g instanceof HTMLInputElement && g.type === 'checkbox' ? g.checked : g.value;
      localStorage.setItem(key, JSON.stringify(all));
      onChange?.();
    });
  }
}

/// A probing failure in words: grbl's alarms 4 and 5 said plainly first.
export function explain(message: string): string {
  if (/ALARM:5|no contact/i.test(message)) return `No contact: the probe travelled its whole distance without touching. ${message}`;
  if (/ALARM:4|already closed/i.test(message)) return `The probe was already touching before it moved (check the clip and the plate). ${message}`;
  return message;
}
