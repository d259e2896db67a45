// Preview segments streamed from the server's interpreter: read as they arrive, handed to the
// page in batches of typed arrays (transferred, not copied), so no file size freezes the page.
// Record: from xyz, to xyz as f32, then line << 2 | kind as u32, little-endian (28 bytes).

const RECORD = 28;

export interface Batch { type: 'batch'; positions: Float32Array; kinds: Uint8Array; lines: Uint32Array; }
export type WorkerOut = Batch | { type: 'done'; segments: number; ms: number } | { type: 'error'; message: string };

self.onmessage = async (e: MessageEvent) => {
  const { url, body } = e.data as { url: string; body: string | null };
  const t0 = performance.now();
  try {
    const r = await fetch(url, { method: 'POST', body });
    if (!r.ok || !r.body) throw new Error(await r.text());
    const reader = r.body.getReader();
    let carry = new Uint8Array(0);
    let segments = 0;
    for (;;) {
      const { done, value } = await reader.read();
      if (done) break;
      let bytes = value;
      if (carry.length) {
        const joined = new Uint8Array(carry.length + value.length);
        joined.set(carry);
        joined.set(value, carry.length);
        bytes = joined;
      }
      const n = Math.floor(bytes.length / RECORD);
      carry = bytes.slice(n * RECORD);
      if (n === 0) continue;
      const view = new DataView(bytes.buffer, bytes.byteOffset, n * RECORD);
      const positions = new Float32Array(n * 6);
      const kinds = new Uint8Array(n);
      const lines = new Uint32Array(n);
      for (let i = 0; i < n; i++) {
        const o = i * RECORD;
        for (let k = 0; k < 6; k++) positions[i * 6 + k] = view.getFloat32(o + 4 * k, true);
        const tag = view.getUint32(o + 24, true);
        kinds[i] = tag & 3;
        lines[i] = tag >>> 2;
      }
      segments += n;
      const msg: Batch = { type: 'batch', positions, kinds, lines };
      (self as unknown as Worker).postMessage(msg, [positions.buffer, kinds.buffer, lines.buffer]);
    }
    (self as unknown as Worker).postMessage({ type: 'done', segments, ms: performance.now() - t0 });
  } catch (err) {
    (self as unknown as Worker).postMessage({ type: 'error', message: String((err as Error).message || err) });
  }
};
