// The stitch editor's plan, as the server sends it (`plan_json`): colour blocks in sewing
// order, each a thread and flat [x, y, kind, …] entries (kind 0 stitch, 1 jump, 2 trim,
// 3 stop), mm, y up. Entries are numbered over the whole plan in sewing order, as the
// library's `sections` and `sew_at_speed` number them. The edits here are the page's own
// (move, insert, delete, colour stops); alteration, linking, speed codes and writing are the
// library's, through the server.

export const STITCH = 0, JUMP = 1, TRIM = 2, STOP = 3;
export interface Block { thread: string; name: string; points: number[] }
export interface Plan { name: string; blocks: Block[] }
/// A design of the editor: its plan, where its origin goes when designs are linked, and its
/// sections [start, end, speed code] as the server last gave them.
export interface Placed { plan: Plan; at: [number, number]; sections: [number, number, number | null][] }

export function count(p: Plan): number {
  return p.blocks.reduce((n, b) => n + b.points.length / 3, 0);
}

/// Block and position in it of entry `i`, or null past the end.
export function locate(p: Plan, i: number): [number, number] | null {
  for (let b = 0; b < p.blocks.length; b++) {
    const n = p.blocks[b].points.length / 3;
    if (i < n) return [b, i];
    i -= n;
  }
  return null;
}

/// Entry `i`: x, y, kind.
export function entry(p: Plan, i: number): [number, number, number] | null {
  const at = locate(p, i);
  if (!at) return null;
  const q = p.blocks[at[0]].points, k = at[1] * 3;
  return [q[k], q[k + 1], q[k + 2]];
}

export function bounds(p: Plan, at: [number, number] = [0, 0]): [number, number, number, number] | null {
  let b: [number, number, number, number] | null = null;
  for (const bl of p.blocks) {
    for (let k = 0; k < bl.points.length; k += 3) {
      const x = bl.points[k] + at[0], y = bl.points[k + 1] + at[1];
      b = b ? [Math.min(b[0], x), Math.min(b[1], y), Math.max(b[2], x), Math.max(b[3], y)] : [x, y, x, y];
    }
  }
  return b;
}

/// Moves the entries `sel` by (dx, dy) mm.
export function moveEntries(p: Plan, sel: Iterable<number>, dx: number, dy: number) {
  for (const i of sel) {
    const at = locate(p, i);
    if (!at) continue;
    const q = p.blocks[at[0]].points;
    q[at[1] * 3] += dx; q[at[1] * 3 + 1] += dy;
  }
}

/// A stitch halfway between entry `i` and the next one (in i's block), sewn; its index.
export function insertAfter(p: Plan, i: number): number | null {
  const a = entry(p, i), b = entry(p, i + 1), at = locate(p, i);
  if (!a || !at) return null;
  const [x, y] = b ? [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2] : [a[0], a[1]];
  p.blocks[at[0]].points.splice(at[1] * 3 + 3, 0, x, y, STITCH);
  return i + 1;
}

/// Removes the entries `sel`; an emptied block goes with them (its colour change too).
export function deleteEntries(p: Plan, sel: Set<number>) {
  let i = 0;
  for (const b of p.blocks) {
    const kept: number[] = [];
    for (let k = 0; k < b.points.length; k += 3, i++) if (!sel.has(i)) kept.push(b.points[k], b.points[k + 1], b.points[k + 2]);
    b.points = kept;
  }
  p.blocks = p.blocks.filter((b) => b.points.length > 0);
}

/// Threads a new colour stop takes: the first not already in the plan.
const PALETTE = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#17becf', '#e377c2', '#8c564b', '#bcbd22', '#7f7f7f'];

/// A colour change before entry `i` (not the first of its block): the block is split there
/// and the rest sews in a new thread.
export function addColourStop(p: Plan, i: number): string | null {
  const at = locate(p, i);
  if (!at || at[1] === 0) return null;
  const b = p.blocks[at[0]];
  const used = new Set(p.blocks.map((x) => x.thread.toLowerCase()));
  const thread = PALETTE.find((c) => !used.has(c)) ?? PALETTE[(at[0] + 1) % PALETTE.length];
  const rest = b.points.splice(at[1] * 3);
  p.blocks.splice(at[0] + 1, 0, { thread, name: '', points: rest });
  return thread;
}

/// Removes the colour change that starts the block holding entry `i` (its stitches join the
/// block before); false when it is the first block.
export function removeColourStop(p: Plan, i: number): boolean {
  const at = locate(p, i);
  if (!at || at[0] === 0) return false;
  const [b] = p.blocks.splice(at[0], 1);
  p.blocks[at[0] - 1].points.push(...b.points);
  return true;
}

/// The index of the first entry of block `b`.
export function blockStart(p: Plan, b: number): number {
  let n = 0;
  for (let k = 0; k < b; k++) n += p.blocks[k].points.length / 3;
  return n;
}
