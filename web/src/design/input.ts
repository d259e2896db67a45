// What the command line takes: a point typed absolute (`10,20`), relative to the last point
// (`@30,0`) or relative polar (`@30<45`: 30 mm at 45°), a number (a radius, a distance, an
// angle, a factor), or a word (a tool's name, `close`, `undo`…).

import type { Pt } from '../view2d';

export type Typed = { point: Pt } | { number: number } | { word: string } | { error: string };

const NUM = String.raw`[-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?`;
const XY = new RegExp(`^(@)?\\s*(${NUM})\\s*,\\s*(${NUM})$`, 'i');
const POLAR = new RegExp(`^@\\s*(${NUM})\\s*<\\s*(${NUM})$`, 'i');
const ONE = new RegExp(`^${NUM}$`, 'i');

/// Reads one entry; `last` is the last point given (relative entries need one).
export function readTyped(text: string, last: Pt | null): Typed {
  const s = text.trim();
  let m = s.match(POLAR);
  if (m) {
    if (!last) return { error: `${s}: a relative point needs a point before it` };
    const r = Number(m[1]), a = (Number(m[2]) * Math.PI) / 180;
    return { point: [last[0] + r * Math.cos(a), last[1] + r * Math.sin(a)] };
  }
  m = s.match(XY);
  if (m) {
    const x = Number(m[2]), y = Number(m[3]);
    if (!m[1]) return { point: [x, y] };
    if (!last) return { error: `${s}: a relative point needs a point before it` };
    return { point: [last[0] + x, last[1] + y] };
  }
  if (ONE.test(s)) return { number: Number(s) };
  if (/^[a-z]+$/i.test(s)) return { word: s.toLowerCase() };
  return { error: `'${s}': type x,y  @dx,dy  @length<angle  a number, or a command` };
}
