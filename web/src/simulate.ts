// "Simulate stock": the editor's program replayed on a box of stock by the server
// (`oficina simulate`), the shaded stock shown over the 3D view with the report beside it.

type Source = (path: string) => Promise<{ url: string; body: string | null }>;

interface SimReport {
  stock_size: [number, number, number];
  pixel: number;
  grid_width: number;
  grid_height: number;
  resolution_note: string;
  removed_mm3: number;
  lowest_z: number;
  highest_z: number;
  program_lowest_z: number | null;
  machine_seconds: { Ok?: number; Err?: string };
  rapids_into_material: [number, number][];
  below_bottom: [number, number][];
  counts: [number, number, number];
  tools: { number: number; spec: string; from: string }[];
  notes: string[];
}

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;

function describe(r: SimReport): string {
  const [w, h, t] = r.stock_size;
  const lines = [
    `stock ${w.toFixed(1)} × ${h.toFixed(1)} × ${t.toFixed(1)} mm · grid ${r.grid_width} × ${r.grid_height}, ${r.resolution_note}`,
    `removed ${r.removed_mm3.toFixed(0)} mm³ · surface Z ${r.lowest_z.toFixed(3)} … ${r.highest_z.toFixed(3)}` +
      (r.program_lowest_z != null ? ` (program's lowest Z ${r.program_lowest_z.toFixed(3)})` : ''),
    `tools: ${r.tools.map((t) => `T${t.number} ${t.spec}`).join(', ')}`,
  ];
  if (r.machine_seconds.Ok != null) lines.push(`machine time ${(r.machine_seconds.Ok / 60).toFixed(1)} min (planner)`);
  if (r.counts[0]) lines.push(`RAPID INTO MATERIAL ×${r.counts[0]}: ` + r.rapids_into_material.slice(0, 8).map(([l, d]) => `line ${l} (${d.toFixed(2)} mm)`).join(', '));
  if (r.counts[1]) lines.push(`BELOW THE STOCK BOTTOM ×${r.counts[1]}: ` + r.below_bottom.slice(0, 8).map(([l, z]) => `line ${l} (Z${z.toFixed(2)})`).join(', '));
  for (const n of r.notes) lines.push(`note: ${n}`);
  return lines.join('\n');
}

export function setupSimulate(source: Source) {
  const status = $('stock-status');
  $('stock-close').onclick = () => { $('stock-view').hidden = true; };
  $<HTMLButtonElement>('simulate').onclick = async () => {
    const button = $<HTMLButtonElement>('simulate');
    button.disabled = true;
    status.textContent = 'simulating…';
    try {
      const src = await source('/api/simulate');
      const q = new URLSearchParams({
        stock: $<HTMLInputElement>('stock-size').value || 'auto',
        tool: $<HTMLInputElement>('stock-tool').value || 'flat:3',
      });
      const url = src.url + (src.url.includes('?') ? '&' : '?') + q.toString();
      const r = await fetch(url, { method: 'POST', body: src.body });
      if (!r.ok) throw new Error(await r.text());
      const { report, png } = (await r.json()) as { report: SimReport; png: string };
      $<HTMLImageElement>('stock-render').src = png;
      $('stock-report').textContent = describe(report);
      $('stock-view').hidden = false;
      document.body.dataset.stock = 'shown';
      status.textContent = `${report.removed_mm3.toFixed(0)} mm³ removed`;
    } catch (e) {
      status.textContent = `simulate: ${(e as Error).message}`;
      document.body.dataset.stock = 'failed';
    } finally {
      button.disabled = false;
    }
  };
}
