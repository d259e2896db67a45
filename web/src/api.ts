// Talking to the Oficina server: JSON and binary over HTTP, live status over a WebSocket.
// A token given in the page's address (?token=…) is passed on with every request.

const token = new URLSearchParams(location.search).get('token');

export function withToken(path: string): string {
  if (!token) return path;
  return path + (path.includes('?') ? '&' : '?') + 'token=' + encodeURIComponent(token);
}

async function fail(r: Response): Promise<never> {
  throw new Error((await r.text()) || `${r.status} ${r.statusText}`);
}

export async function getJson<T>(path: string): Promise<T> {
  const r = await fetch(withToken(path));
  if (!r.ok) return fail(r);
  return r.json();
}

export async function postJson<T>(path: string, body: BodyInit): Promise<T> {
  const r = await fetch(withToken(path), { method: 'POST', body });
  if (!r.ok) return fail(r);
  return r.json();
}

export async function putFile(name: string, body: BodyInit): Promise<void> {
  const r = await fetch(withToken('/api/files/' + encodeURIComponent(name)), { method: 'PUT', body });
  if (!r.ok) return fail(r);
}

export interface Diag { line: number; col: number; len: number; severity: 'error' | 'warning' | 'note'; message: string; help: string | null; }
export interface Box3 { min: [number, number, number]; max: [number, number, number]; }
export interface CheckReport {
  diagnostics: Diag[]; errors: number; warnings: number; operations: number;
  /// The reading the check used: the machine's (grbl on firmware).
  dialect?: string;
  feed_extents: Box3 | null; rapid_extents: Box3 | null;
  feed_length: number; rapid_length: number; feed_moves: number; rapid_moves: number; arcs: number;
  tools: number[]; feed_rate_seconds: number;
  /// Each used tool as the saved tool table gives it (null: not in the table).
  tool_table: [number, { diameter: number; length: number } | null][];
  time: { Ok?: { seconds: number; segments: number }; Err?: string };
  machine: string;
}
export interface JobView { name: string; lines: number; from_line: number | null; speed: number | null; completed: boolean | null; }
export interface Snapshot {
  uri: string; machine: string; firmware: string; state: string;
  alarm: string | null; alarm_meaning: string | null;
  machine_pos: [number, number, number]; work_pos: [number, number, number];
  feed: number; line: number; elapsed: number; total: number; remaining: number | null;
  feed_override: number; job: JobView | null;
  /// The built-in virtual machine (no firmware `$` commands; its profile can change).
  is_virtual: boolean;
  offsets: Offsets;
}
export interface Offsets {
  systems: [number, number, number][]; active: number; g92: [number, number, number]; tlo: number;
  probe: { pos: [number, number, number]; touched: boolean } | null; known: boolean;
}
export type LiveMessage =
  | { type: 'hello'; client: number; controller: boolean }
  | { type: 'console'; lines: string[] }
  | { type: 'status'; status: Snapshot | null }
  | { type: 'control'; controller: number | null }
  | { type: 'progress'; stage: string; fraction: number }
  | { type: 'event'; event: { type: string; [k: string]: unknown } }
  | { type: 'ok'; cmd: string }
  | { type: 'error'; message: string };

/// The live channel; reconnects by itself (the job on the server never depends on it).
export class Live {
  private ws: WebSocket | null = null;
  constructor(private onMessage: (m: LiveMessage) => void, private onOpen: () => void) {
    this.open();
  }
  private open() {
    const proto = location.protocol === 'https:' ? 'wss:' : 'ws:';
    const ws = new WebSocket(withToken(`${proto}//${location.host}/ws`));
    ws.onmessage = (e) => this.onMessage(JSON.parse(e.data));
    ws.onopen = () => this.onOpen();
    ws.onclose = () => { this.ws = null; setTimeout(() => this.open(), 1000); };
    this.ws = ws;
  }
  send(cmd: Record<string, unknown>) {
    if (this.ws && this.ws.readyState === WebSocket.OPEN) this.ws.send(JSON.stringify(cmd));
    else throw new Error('not connected to the server');
  }
}
