// Typed lines (MDI): G-code or `$` commands sent to the machine, the replies in the console;
// Up and Down browse the history, kept in this browser.

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;
const KEY = 'oficina.mdi-history';
const KEEP = 100;

function load(): string[] {
  try {
    const v = JSON.parse(localStorage.getItem(KEY) || '[]');
    return Array.isArray(v) ? v.filter((l) => typeof l === 'string').slice(-KEEP) : [];
  } catch { return []; }
}

export function setupMdi(send: (cmd: Record<string, unknown>) => void) {
  const input = $<HTMLInputElement>('mdi');
  const history = load();
  let at = history.length;
  const submit = () => {
    const line = input.value.trim();
    if (!line) return;
    send({ cmd: 'mdi', line });
    if (history[history.length - 1] !== line) history.push(line);
    while (history.length > KEEP) history.shift();
    try { localStorage.setItem(KEY, JSON.stringify(history)); } catch { /* private mode: this page only */ }
    at = history.length;
    input.value = '';
  };
  input.addEventListener('keydown', (e) => {
    if (e.key === 'Enter') { e.preventDefault(); submit(); }
    else if (e.key === 'ArrowUp' && at > 0) { e.preventDefault(); input.value = history[--at]; }
    else if (e.key === 'ArrowDown') { e.preventDefault(); at = Math.min(history.length, at + 1); input.value = history[at] ?? ''; }
  });
  $('mdi-send').onclick = submit;
}
