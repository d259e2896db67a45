// 3D models (STL, OBJ) in the workbench: the model as the server places it (`oficina carve`'s
// scale, turn and size) drawn shaded in the 3D view under the toolpath, and the carving's
// answer (/api/model): its operations, simulated stock, gouge, leftover and times. The mesh
// is read and placed by the server only: the page draws the triangles it is given.

import * as THREE from 'three';
import { withToken } from './api';
import type { Preview } from './preview';

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;

/// The placement fields of the carve form (the server places the model with them).
export interface Placement { scale?: unknown; rotate?: unknown; size?: unknown }

interface Mesh { file: string; triangles: number; bounds: [number[], number[]]; work_offset: [number, number, number]; positions: string }

/// What /api/model answers beside the program.
export interface Carved {
  name: string; text: string; triangles: number;
  ops: { name: string; tool_number: number; tool: string; moves: number }[];
  report: { max_gouge: number; leftover_max: number; leftover_mean: number; scallop_max: number; scallop_mean: number };
  grid: [number, number, number]; planner_s: number | null; planner_error: string | null; feed_only_s: number; png: string;
}

let shown: THREE.Group | null = null;
/// A newer request wins over a slower older one.
let asked = 0;

/// Takes the model out of the 3D view (and forgets a request under way).
export function hideModel(preview: Preview) {
  asked++;
  remove(preview);
}

function remove(preview: Preview) {
  if (!shown) return;
  preview.scene.remove(shown);
  shown.traverse((o) => { if (o instanceof THREE.Mesh) { o.geometry.dispose(); (o.material as THREE.Material).dispose(); } });
  shown = null;
  delete $('viewport').dataset.model;
  preview.render();
}

/// Draws `file` as the server places it with `place`, framed; answers its description.
export async function showModel(preview: Preview, file: string, place: Placement): Promise<string> {
  const ask = ++asked;
  const r = await fetch(withToken('/api/model/mesh'), {
    method: 'POST', headers: { 'content-type': 'application/json' },
    body: JSON.stringify({ file, params: { scale: place.scale ?? 1, rotate: place.rotate ?? 0, size: place.size ?? null } }),
  });
  const text = await r.text();
  let v: Mesh & { error?: string };
  try { v = JSON.parse(text); } catch { throw new Error(text || `${r.status} ${r.statusText}`); }
  if (!r.ok) throw new Error(v.error ?? text);
  if (ask !== asked) return '';
  const bytes = Uint8Array.from(atob(v.positions), (c) => c.charCodeAt(0));
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(bytes.buffer), 3));
  geometry.computeVertexNormals();
  // Half see-through: the toolpath drawn over it stays visible where it runs on the surface.
  const material = new THREE.MeshPhongMaterial({ color: 0x9fb0c4, transparent: true, opacity: 0.6, side: THREE.DoubleSide, depthWrite: false });
  const group = new THREE.Group();
  group.add(new THREE.Mesh(geometry, material));
  group.add(new THREE.HemisphereLight(0xffffff, 0x303640, 0.9));
  const sun = new THREE.DirectionalLight(0xffffff, 1.2);
  sun.position.set(-1, -1, 2);
  group.add(sun);
  // The 3D view draws a program at the work offset: the model sits where its carving runs.
  const off = v.work_offset;
  group.position.set(off[0], off[1], off[2]);
  remove(preview);
  shown = group;
  preview.scene.add(group);
  preview.frameOn({ min: v.bounds[0].map((x, i) => x + off[i]), max: v.bounds[1].map((x, i) => x + off[i]) });
  $('viewport').dataset.model = String(v.triangles);
  const [lo, hi] = v.bounds;
  return `${v.file}: ${v.triangles.toLocaleString()} triangles, X ${lo[0].toFixed(2)}…${hi[0].toFixed(2)} Y ${lo[1].toFixed(2)}…${hi[1].toFixed(2)} Z ${lo[2].toFixed(2)}…${hi[2].toFixed(2)} mm`;
}

function hms(s: number): string {
  s = Math.max(0, Math.round(s));
  return `${Math.floor(s / 3600)}:${String(Math.floor(s / 60) % 60).padStart(2, '0')}:${String(s % 60).padStart(2, '0')}`;
}

/// The carving's report lines; the simulated stock shown under them.
export function carvedReport(c: Carved): string[] {
  const r = c.report;
  const img = $<HTMLImageElement>('model-stock');
  img.src = c.png;
  img.hidden = false;
  return [
    `${c.triangles.toLocaleString()} triangles carved in ${c.ops.length} operations:`,
    ...c.ops.map((o) => `  ${o.name}: T${o.tool_number} ${o.tool}, ${o.moves.toLocaleString()} moves`),
    `stock grid ${c.grid[0]} × ${c.grid[1]} at ${c.grid[2].toPrecision(4)} mm`,
    `max gouge ${r.max_gouge.toFixed(4)} mm · leftover vs model: max ${r.leftover_max.toFixed(3)}, mean ${r.leftover_mean.toFixed(4)} mm · scallop vs ideal: max ${r.scallop_max.toFixed(3)}, mean ${r.scallop_mean.toFixed(4)} mm`,
    c.planner_s != null ? `time: planner ${hms(c.planner_s)} · feed-only ${hms(c.feed_only_s)}` : `time: feed-only ${hms(c.feed_only_s)} (planner: ${c.planner_error})`,
  ];
}

/// Hides the previous carving's stock picture.
export function clearCarved() {
  const img = document.getElementById('model-stock') as HTMLImageElement | null;
  if (img) { img.hidden = true; img.removeAttribute('src'); }
}
