// The three.js preview: toolpaths coloured rapid / feed / plunge (or by depth), the views of
// seed 002 (iso, XY, ZY, depth) with orbit, zoom and pan, a timeline that draws the path up to
// a segment, and a coarse level of detail drawn while the view moves on big programs.

import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import type { Batch } from './worker';

const COLOURS: [number, number, number][] = [
  [209, 71, 71], // rapid
  [74, 168, 255], // feed
  [240, 209, 79], // plunge
];
/// A thread colour as drawn on the dark background: black and other threads nearly as dark
/// as the background (a lettered name's usual colour) are lifted well above the dim grey of
/// jumps, keeping their hue; other threads are drawn as they are.
function visible(rgb: number[]): number[] {
  const lum = 0.299 * rgb[0] + 0.587 * rgb[1] + 0.114 * rgb[2];
  const lift = lum < 60 ? 150 - lum : 0;
  return rgb.map((c) => Math.min(255, Math.round(c + lift)));
}

/// Jumps of an embroidery plan: the hoop moves with the needle up, no thread laid.
const JUMP: [number, number, number] = [96, 96, 110];
/// Above this many segments, a decimated copy is drawn while the camera moves.
const LOD_THRESHOLD = 200_000;
/// The coarse copy keeps about this many segments (a 1,000,000-segment raster keeps every
/// 50th point: 20 per 1,000-point row, the shape still plain while it turns).
const LOD_TARGET = 20_000;
/// Full detail comes back this long after the last camera move, ms.
const LOD_SETTLE_MS = 200;
/// While the camera moves on a big program, the frame is drawn at this fraction of the
/// resolution (a quarter of the pixels): fill is most of a software renderer's frame.
const MOVING_PIXEL_RATIO = 0.5;

export type View = 'iso' | 'xy' | 'zy' | 'depth';

/// One merged line geometry that grows as segments arrive: positions (2 points of xyz per
/// segment) and colours (normalised bytes per point) as attributes, one draw call, the new
/// part uploaded alone.
class Layer {
  positions = new Float32Array(0);
  colours = new Uint8Array(0);
  count = 0;
  readonly object: THREE.LineSegments;

  constructor() {
    this.object = new THREE.LineSegments(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ vertexColors: true }));
    // The bounds change as segments stream in: never culled (the view frames the path).
    this.object.frustumCulled = false;
    this.reserve(0);
  }

  /// Room for `segments` in all; a bigger buffer (doubling) replaces the attributes.
  reserve(segments: number) {
    if (segments <= this.positions.length / 6 && this.positions.length > 0) return;
    const cap = Math.max(1024, segments, (this.positions.length / 6) * 2);
    const p = new Float32Array(cap * 6), c = new Uint8Array(cap * 6);
    p.set(this.positions.subarray(0, this.count * 6));
    c.set(this.colours.subarray(0, this.count * 6));
    this.positions = p;
    this.colours = c;
    const g = this.object.geometry;
    g.setAttribute('position', new THREE.BufferAttribute(p, 3));
    g.setAttribute('color', new THREE.BufferAttribute(c, 3, true));
    g.setDrawRange(0, this.count * 2);
  }

  append(p: Float32Array, c: Uint8Array) {
    const n = p.length / 6;
    this.reserve(this.count + n);
    this.positions.set(p, this.count * 6);
    this.colours.set(c, this.count * 6);
    const g = this.object.geometry;
    for (const [name, len] of [['position', 6], ['color', 6]] as const) {
      const a = g.getAttribute(name) as THREE.BufferAttribute;
      a.addUpdateRange(this.count * len, n * len);
      a.needsUpdate = true;
    }
    this.count += n;
    g.setDrawRange(0, this.count * 2);
  }

  /// Colours replaced as a whole (the depth view).
  recolour(c: Uint8Array) {
    this.colours.set(c);
    const a = this.object.geometry.getAttribute('color') as THREE.BufferAttribute;
    a.clearUpdateRanges();
    a.needsUpdate = true;
  }

  show(segments: number) {
    this.object.geometry.setDrawRange(0, Math.min(segments, this.count) * 2);
  }

  clear() {
    this.count = 0;
    this.object.geometry.dispose();
    this.object.geometry = new THREE.BufferGeometry();
    this.positions = new Float32Array(0);
    this.colours = new Uint8Array(0);
    this.reserve(0);
  }
}

/// Where each streamed batch landed in the full and the coarse layers (for the timeline).
interface BatchPlace { start: number; count: number; coarseStart: number; coarseCount: number }

export class Preview {
  readonly renderer: THREE.WebGLRenderer;
  readonly scene = new THREE.Scene();
  readonly camera: THREE.PerspectiveCamera;
  readonly controls: OrbitControls;
  private full = new Layer();
  private coarse = new Layer();
  private kinds = new Uint8Array(0);
  /// Colours given per segment (thread colours of stitches) instead of by kind: kept
  /// through the depth view.
  private given = false;
  private lines = new Uint32Array(0);
  private batches: BatchPlace[] = [];
  private group = new THREE.Group();
  private marker: THREE.Mesh;
  private grid: THREE.GridHelper | null = null;
  private min = new THREE.Vector3(Infinity, Infinity, Infinity);
  private max = new THREE.Vector3(-Infinity, -Infinity, -Infinity);
  private dirty = true;
  private moving = false;
  /// Segments are still arriving: a big program is drawn coarse until the last one (a full
  /// frame of a million segments takes the page's thread for ~0.4 s in software GL).
  private streaming = false;
  private settleTimer = 0;
  private stride = 1;
  view: View = 'iso';
  total = 0;
  /// Segments drawn: the timeline's position (= total when not scrubbing).
  shown = 0;
  frames = 0;
  /// Time spent in the last frame's render call and GPU wait, ms (for the benchmark).
  lastFrameMs = 0;

  constructor(private host: HTMLElement) {
    this.renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(1);
    host.appendChild(this.renderer.domElement);
    this.scene.background = new THREE.Color(0x1b1e24);
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.1, 100000);
    this.camera.up.set(0, 0, 1);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', () => this.cameraMoved());
    this.group.add(this.full.object, this.coarse.object);
    this.coarse.object.visible = false;
    this.scene.add(this.group);
    this.marker = new THREE.Mesh(
      new THREE.SphereGeometry(1, 12, 8),
      new THREE.MeshBasicMaterial({ color: 0xf0b45a }),
    );
    this.marker.visible = false;
    this.scene.add(this.marker);
    this.scene.add(new THREE.AxesHelper(10));
    new ResizeObserver(() => this.resize()).observe(host);
    this.resize();
    const loop = () => {
      if (this.dirty) this.render();
      requestAnimationFrame(loop);
    };
    requestAnimationFrame(loop);
  }

  private resize() {
    const w = Math.max(1, this.host.clientWidth), h = Math.max(1, this.host.clientHeight);
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.dirty = true;
  }

  private cameraMoved() {
    this.dirty = true;
    if (this.total < LOD_THRESHOLD) return;
    this.moving = true;
    clearTimeout(this.settleTimer);
    this.settleTimer = window.setTimeout(() => { this.moving = false; this.dirty = true; }, LOD_SETTLE_MS);
  }

  render() {
    const coarse = (this.moving || this.streaming) && this.total >= LOD_THRESHOLD;
    this.full.object.visible = !coarse;
    this.coarse.object.visible = coarse;
    const ratio = coarse ? MOVING_PIXEL_RATIO : 1;
    if (this.renderer.getPixelRatio() !== ratio) {
      // Same size on the page, fewer pixels drawn while moving.
      this.renderer.setPixelRatio(ratio);
      this.renderer.setSize(Math.max(1, this.host.clientWidth), Math.max(1, this.host.clientHeight));
    }
    this.renderer.render(this.scene, this.camera);
    this.frames++;
    this.dirty = false;
  }

  clear() {
    this.full.clear();
    this.coarse.clear();
    this.kinds = new Uint8Array(0);
    this.lines = new Uint32Array(0);
    this.batches = [];
    this.total = 0;
    this.shown = 0;
    this.given = false;
    this.min.set(Infinity, Infinity, Infinity);
    this.max.set(-Infinity, -Infinity, -Infinity);
    this.marker.visible = false;
    this.dirty = true;
  }

  /// Expected number of segments (guessed from the text's size): sets the level-of-detail
  /// stride before the segments arrive, so the coarse copy is built as they come, and
  /// reserves the merged buffers once.
  expect(segmentsGuess: number) {
    this.stride = segmentsGuess >= LOD_THRESHOLD ? Math.max(2, Math.round(segmentsGuess / LOD_TARGET)) : 1;
    this.streaming = true;
    const n = Math.ceil(segmentsGuess * 1.1);
    this.full.reserve(n);
    if (this.stride > 1) this.coarse.reserve(Math.ceil(n / this.stride));
    this.kinds = grow(this.kinds, n, 0);
    this.lines = grow(this.lines, n, 0);
  }

  /// A batch of segments; `colours` (RGB bytes per point) instead of the kinds' colours.
  add(b: Batch, colours?: Uint8Array) {
    const n = b.kinds.length;
    if (colours) this.given = true;
    const p = b.positions;
    for (let i = 0; i < p.length; i += 3) {
      this.min.x = Math.min(this.min.x, p[i]); this.max.x = Math.max(this.max.x, p[i]);
      this.min.y = Math.min(this.min.y, p[i + 1]); this.max.y = Math.max(this.max.y, p[i + 1]);
      this.min.z = Math.min(this.min.z, p[i + 2]); this.max.z = Math.max(this.max.z, p[i + 2]);
    }
    this.full.append(p, colours ?? this.colours(b.kinds, p));
    this.kinds = grow(this.kinds, this.total + n, this.total);
    this.lines = grow(this.lines, this.total + n, this.total);
    this.kinds.set(b.kinds, this.total);
    this.lines.set(b.lines, this.total);
    const place = { start: this.total, count: n, coarseStart: this.coarse.count, coarseCount: 0 };
    if (this.stride > 1) {
      // Every stride-th point of the path joined in order: the shape stays, the count drops.
      const m = Math.floor(n / this.stride);
      const cp = new Float32Array(m * 6), ck = new Uint8Array(m), cc = new Uint8Array(m * 6);
      for (let j = 0; j < m; j++) {
        const a = j * this.stride, e = Math.min(n - 1, a + this.stride - 1);
        cp.set(p.subarray(a * 6, a * 6 + 3), j * 6);
        cp.set(p.subarray(e * 6 + 3, e * 6 + 6), j * 6 + 3);
        ck[j] = b.kinds[a];
        if (colours) cc.set(colours.subarray(a * 6, a * 6 + 6), j * 6);
      }
      this.coarse.append(cp, colours ? cc : this.colours(ck, cp));
      place.coarseCount = m;
    }
    this.batches.push(place);
    this.total += n;
    this.shown = this.total;
    if (this.batches.length === 1) this.fit();
    this.dirty = true;
  }

  private colours(kinds: Uint8Array, p: Float32Array): Uint8Array {
    const out = new Uint8Array(kinds.length * 6);
    const depth = this.view === 'depth';
    const z0 = this.min.z, z1 = this.max.z, span = Math.max(1e-9, z1 - z0);
    for (let i = 0; i < kinds.length; i++) {
      for (let v = 0; v < 2; v++) {
        let c = COLOURS[kinds[i]] ?? COLOURS[1];
        if (depth) {
          // Deep is dark, high is light: the picture reads as a depth map.
          const t = (p[i * 6 + v * 3 + 2] - z0) / span;
          c = kinds[i] === 0 ? [64, 64, 71] : [38 + 217 * t, 38 + 191 * t, 77 + 153 * t];
        }
        out.set(c, i * 6 + v * 3);
      }
    }
    return out;
  }

  finished() {
    this.streaming = false;
    this.fit();
    const size = new THREE.Vector3().subVectors(this.max, this.min);
    const span = Math.max(size.x, size.y, 1);
    if (this.grid) this.scene.remove(this.grid);
    this.grid = new THREE.GridHelper(Math.ceil(span * 1.4 / 10) * 10, 20, 0x3a3f4a, 0x2a2e36);
    this.grid.rotation.x = Math.PI / 2;
    this.grid.position.set((this.min.x + this.max.x) / 2, (this.min.y + this.max.y) / 2, this.min.z);
    this.scene.add(this.grid);
    if (this.view === 'depth') this.recolour();
    this.dirty = true;
  }

  /// An embroidery plan in sewing order: each stitch a segment from the previous point (the
  /// origin before the first) in its thread's colour, each jump a dim one; trims and stops
  /// move nothing. Returns the sewn stitches drawn. Kinds: 1 stitch, 0 jump (the legend's
  /// feed and rapid); a segment's "line" is its entry's number in the plan (from 1).
  stitches(blocks: { thread: string; points: number[] }[]): number {
    let n = 0;
    for (const b of blocks) n += b.points.length / 3;
    this.clear();
    this.program = null;
    this.expect(n);
    const pos = new Float32Array(n * 6), cols = new Uint8Array(n * 6), kinds = new Uint8Array(n), lines = new Uint32Array(n);
    let k = 0, entry = 0, sewn = 0, px = 0, py = 0;
    for (const b of blocks) {
      const rgb = visible([1, 3, 5].map((i) => parseInt(b.thread.slice(i, i + 2), 16) || 0));
      const p = b.points;
      for (let i = 0; i < p.length; i += 3) {
        entry++;
        const [x, y, kind] = [p[i], p[i + 1], p[i + 2]];
        if (kind === 0 || kind === 1) {
          pos.set([px, py, 0, x, y, 0], k * 6);
          const c = kind === 0 ? rgb : JUMP;
          cols.set(c, k * 6);
          cols.set(c, k * 6 + 3);
          kinds[k] = kind === 0 ? 1 : 0;
          lines[k] = entry;
          if (kind === 0) sewn++;
          k++;
        }
        [px, py] = [x, y];
      }
    }
    if (k > 0) this.add({ type: 'batch', positions: pos.slice(0, k * 6), kinds: kinds.slice(0, k), lines: lines.slice(0, k) }, cols.slice(0, k * 6));
    this.finished();
    return sewn;
  }

  bounds() {
    return { min: this.min.toArray(), max: this.max.toArray() };
  }

  /// The program's own extents (the check's: where it cuts, not where the tool stood
  /// before it), which the view frames; null: the drawn segments' bounds.
  private program: { min: number[]; max: number[] } | null = null;

  frameOn(box: { min: number[]; max: number[] } | null) {
    this.program = box;
    this.fit();
  }

  /// What the view frames: the program's extents, else the segments drawn.
  framed(): { min: number[]; max: number[] } {
    return this.program ?? this.bounds();
  }

  /// Segments of each kind drawn: what the legend's colours count.
  kindCounts() {
    const n = [0, 0, 0];
    for (const k of this.kinds.subarray(0, this.total)) n[k] = (n[k] ?? 0) + 1;
    return { rapid: n[0], feed: n[1], plunge: n[2] };
  }

  setView(v: View) {
    const recolour = (v === 'depth') !== (this.view === 'depth');
    this.view = v;
    if (recolour) this.recolour();
    this.fit();
  }

  private recolour() {
    if (this.given) return;
    const n = this.total;
    this.full.recolour(this.colours(this.kinds.subarray(0, n), this.full.positions.subarray(0, n * 6)));
    // The coarse copy keeps the first kind of each run of `stride` segments.
    const m = this.coarse.count;
    if (m > 0) {
      const ck = new Uint8Array(m);
      for (const b of this.batches) {
        for (let j = 0; j < b.coarseCount; j++) ck[b.coarseStart + j] = this.kinds[b.start + j * this.stride];
      }
      this.coarse.recolour(this.colours(ck, this.coarse.positions.subarray(0, m * 6)));
    }
    this.dirty = true;
  }

  /// Camera framing the whole path from the current view's direction.
  fit() {
    const f = this.framed();
    if (!isFinite(f.min[0])) return;
    const [lo, hi] = [new THREE.Vector3().fromArray(f.min), new THREE.Vector3().fromArray(f.max)];
    const centre = new THREE.Vector3().addVectors(lo, hi).multiplyScalar(0.5);
    const size = new THREE.Vector3().subVectors(hi, lo);
    // The tool marker in proportion to what is framed.
    this.marker.scale.setScalar(Math.max(size.x, size.y, 1) / 120);
    const r = Math.max(size.length() / 2, 1);
    // The narrower of the two angles of view holds the sphere (a tall viewport is narrower
    // across than the vertical field of view).
    const half = Math.atan(Math.tan((this.camera.fov * Math.PI) / 360) * Math.min(1, this.camera.aspect));
    const d = r / Math.sin(half) * 1.05;
    const dir = {
      iso: new THREE.Vector3(1, -1, 0.9),
      xy: new THREE.Vector3(0, -0.0001, 1),
      depth: new THREE.Vector3(0, -0.0001, 1),
      zy: new THREE.Vector3(1, 0, 0.0001),
    }[this.view].normalize();
    this.camera.position.copy(centre).addScaledVector(dir, d);
    this.camera.near = d / 1000;
    this.camera.far = d * 20;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(centre);
    this.controls.update();
    this.dirty = true;
  }

  /// Draw the path up to segment `s` and put the tool there; returns the segment's line.
  scrubTo(s: number): number {
    this.shown = Math.max(0, Math.min(s, this.total));
    this.full.show(this.shown);
    // The coarse copy up to the same point: its batch's share of the decimated segments.
    let coarse = 0;
    for (const b of this.batches) {
      if (b.start >= this.shown) break;
      coarse = b.coarseStart + Math.min(b.coarseCount, Math.floor((this.shown - b.start) / this.stride));
    }
    this.coarse.show(coarse);
    const k = this.shown;
    if (k > 0) {
      const p = this.full.positions;
      this.placeMarker(p[(k - 1) * 6 + 3], p[(k - 1) * 6 + 4], p[(k - 1) * 6 + 5]);
    }
    this.dirty = true;
    return k > 0 ? this.lines[k - 1] : 0;
  }

  /// The last segment of `line` (or the last one before it), for following a running job.
  segmentOfLine(line: number): number {
    if (this.total === 0 || this.lines[0] > line) return 0;
    // Lines rise through a program (loops aside): binary search.
    let lo = 0, hi = this.total - 1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (this.lines[mid] <= line) lo = mid; else hi = mid - 1;
    }
    return lo + 1;
  }

  placeMarker(x: number, y: number, z: number) {
    this.marker.position.set(x, y, z);
    this.marker.visible = true;
    this.dirty = true;
  }

  /// Where a frame's time goes (for the benchmark): median ms of `n` frames drawn with
  /// nothing, the coarse copy and the full path, each at full and at the moving resolution.
  frameCost(n = 5): Record<string, number> {
    const gl = this.renderer.getContext();
    const time = (full: boolean, coarse: boolean, ratio: number) => {
      this.renderer.setPixelRatio(ratio);
      this.renderer.setSize(Math.max(1, this.host.clientWidth), Math.max(1, this.host.clientHeight));
      this.full.object.visible = full;
      this.coarse.object.visible = coarse;
      const t: number[] = [];
      for (let i = 0; i < n; i++) {
        const t0 = performance.now();
        this.renderer.render(this.scene, this.camera);
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
        t.push(performance.now() - t0);
      }
      return t.sort((a, b) => a - b)[n >> 1];
    };
    const out: Record<string, number> = {};
    for (const r of [1, MOVING_PIXEL_RATIO]) {
      out[`empty@${r}`] = time(false, false, r);
      out[`coarse@${r}`] = time(false, true, r);
      out[`full@${r}`] = time(true, false, r);
    }
    this.moving = false;
    this.render();
    return out;
  }

  /// Orbit the camera by `frames` steps, rendering each: for the frame-time benchmark
  /// (`lod` false keeps full detail while moving).
  orbitFrames(frames: number, lod = true): Promise<number[]> {
    return new Promise((resolve) => {
      const times: number[] = [];
      if (!lod) { clearTimeout(this.settleTimer); this.moving = false; }
      let last = performance.now();
      const step = () => {
        const offset = new THREE.Vector3().subVectors(this.camera.position, this.controls.target);
        offset.applyAxisAngle(new THREE.Vector3(0, 0, 1), 0.02);
        this.camera.position.copy(this.controls.target).add(offset);
        this.camera.lookAt(this.controls.target);
        if (lod) this.cameraMoved();
        const t = performance.now();
        this.render();
        // Reading a pixel waits for the GPU (or the software rasteriser) to finish the frame.
        const gl = this.renderer.getContext();
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
        const now = performance.now();
        this.lastFrameMs = now - t;
        times.push(now - last);
        last = now;
        if (times.length < frames) requestAnimationFrame(step); else resolve(times);
      };
      requestAnimationFrame(step);
    });
  }
}

/// `a` with room for `n` entries (doubling), its first `keep` kept.
function grow<T extends Uint8Array | Uint32Array>(a: T, n: number, keep: number): T {
  if (n <= a.length) return a;
  const b = new (a.constructor as { new(n: number): T })(Math.max(n, a.length * 2));
  b.set(a.subarray(0, keep));
  return b;
}
