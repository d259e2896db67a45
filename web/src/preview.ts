// The three.js preview: toolpaths coloured rapid / feed / plunge (or by depth), the views of
// seed 002 (iso, XY, ZY, depth) with orbit, zoom and pan, a timeline that draws the path up to
// a segment, and a coarse level of detail drawn while the view moves on big programs.

import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import type { Batch } from './worker';

const COLOURS: [number, number, number][] = [
  [0.82, 0.28, 0.28], // rapid
  [0.29, 0.66, 1.0], // feed
  [0.94, 0.82, 0.31], // plunge
];
/// Above this many segments, a decimated copy is drawn while the camera moves.
const LOD_THRESHOLD = 200_000;
/// The coarse copy keeps about this many segments.
const LOD_TARGET = 60_000;
/// Full detail comes back this long after the last camera move, ms.
const LOD_SETTLE_MS = 200;

export type View = 'iso' | 'xy' | 'zy' | 'depth';

interface Chunk {
  start: number; // index of its first segment in the program
  count: number;
  positions: Float32Array;
  kinds: Uint8Array;
  lines: Uint32Array;
  full: THREE.LineSegments;
  coarse: THREE.LineSegments | null;
}

export class Preview {
  readonly renderer: THREE.WebGLRenderer;
  readonly scene = new THREE.Scene();
  readonly camera: THREE.PerspectiveCamera;
  readonly controls: OrbitControls;
  private chunks: Chunk[] = [];
  private group = new THREE.Group();
  private marker: THREE.Mesh;
  private grid: THREE.GridHelper | null = null;
  private min = new THREE.Vector3(Infinity, Infinity, Infinity);
  private max = new THREE.Vector3(-Infinity, -Infinity, -Infinity);
  private dirty = true;
  private moving = false;
  private settleTimer = 0;
  private stride = 1;
  view: View = 'iso';
  total = 0;
  /// Segments drawn: the timeline's position (= total when not scrubbing).
  shown = 0;
  frames = 0;

  constructor(private host: HTMLElement) {
    this.renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(1);
    host.appendChild(this.renderer.domElement);
    this.scene.background = new THREE.Color(0x1b1e24);
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.1, 100000);
    this.camera.up.set(0, 0, 1);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', () => this.cameraMoved());
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
    const coarse = this.moving && this.total >= LOD_THRESHOLD;
    for (const c of this.chunks) {
      c.full.visible = !coarse;
      if (c.coarse) c.coarse.visible = coarse;
    }
    this.renderer.render(this.scene, this.camera);
    this.frames++;
    this.dirty = false;
  }

  clear() {
    for (const c of this.chunks) {
      c.full.geometry.dispose();
      c.coarse?.geometry.dispose();
    }
    this.group.clear();
    this.chunks = [];
    this.total = 0;
    this.shown = 0;
    this.min.set(Infinity, Infinity, Infinity);
    this.max.set(-Infinity, -Infinity, -Infinity);
    this.marker.visible = false;
    this.dirty = true;
  }

  /// Expected size of the whole program (bytes of text): sets the level-of-detail stride
  /// before the segments arrive, so the coarse copy is built as they come.
  expect(segmentsGuess: number) {
    this.stride = segmentsGuess >= LOD_THRESHOLD ? Math.max(2, Math.round(segmentsGuess / LOD_TARGET)) : 1;
  }

  add(b: Batch) {
    const n = b.kinds.length;
    const p = b.positions;
    for (let i = 0; i < p.length; i += 3) {
      this.min.x = Math.min(this.min.x, p[i]); this.max.x = Math.max(this.max.x, p[i]);
      this.min.y = Math.min(this.min.y, p[i + 1]); this.max.y = Math.max(this.max.y, p[i + 1]);
      this.min.z = Math.min(this.min.z, p[i + 2]); this.max.z = Math.max(this.max.z, p[i + 2]);
    }
    const full = this.lines(p, this.colours(b.kinds, p));
    let coarse: THREE.LineSegments | null = null;
    if (this.stride > 1) {
      // Every stride-th point of the path joined in order: the shape stays, the count drops.
      const m = Math.floor(n / this.stride);
      const cp = new Float32Array(m * 6), ck = new Uint8Array(m);
      for (let j = 0; j < m; j++) {
        const a = j * this.stride, e = Math.min(n - 1, a + this.stride - 1);
        cp.set(p.subarray(a * 6, a * 6 + 3), j * 6);
        cp.set(p.subarray(e * 6 + 3, e * 6 + 6), j * 6 + 3);
        ck[j] = b.kinds[a];
      }
      coarse = this.lines(cp, this.colours(ck, cp));
      coarse.visible = false;
      this.group.add(coarse);
    }
    this.group.add(full);
    const chunk = { start: this.total, count: n, positions: p, kinds: b.kinds, lines: b.lines, full, coarse };
    this.chunks.push(chunk);
    this.total += n;
    this.shown = this.total;
    if (this.chunks.length === 1) this.fit();
    this.dirty = true;
  }

  private lines(positions: Float32Array, colours: Float32Array): THREE.LineSegments {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    g.setAttribute('color', new THREE.BufferAttribute(colours, 3));
    return new THREE.LineSegments(g, new THREE.LineBasicMaterial({ vertexColors: true }));
  }

  private colours(kinds: Uint8Array, p: Float32Array): Float32Array {
    const out = new Float32Array(kinds.length * 6);
    const depth = this.view === 'depth';
    const z0 = this.min.z, z1 = this.max.z, span = Math.max(1e-9, z1 - z0);
    for (let i = 0; i < kinds.length; i++) {
      for (let v = 0; v < 2; v++) {
        let c = COLOURS[kinds[i]] ?? COLOURS[1];
        if (depth) {
          // Deep is dark, high is light: the picture reads as a depth map.
          const t = (p[i * 6 + v * 3 + 2] - z0) / span;
          c = kinds[i] === 0 ? [0.25, 0.25, 0.28] : [0.15 + 0.85 * t, 0.15 + 0.75 * t, 0.3 + 0.6 * t];
        }
        out.set(c, i * 6 + v * 3);
      }
    }
    return out;
  }

  finished() {
    this.fit();
    const size = new THREE.Vector3().subVectors(this.max, this.min);
    const span = Math.max(size.x, size.y, 1);
    this.marker.scale.setScalar(span / 120);
    if (this.grid) this.scene.remove(this.grid);
    this.grid = new THREE.GridHelper(Math.ceil(span * 1.4 / 10) * 10, 20, 0x3a3f4a, 0x2a2e36);
    this.grid.rotation.x = Math.PI / 2;
    this.grid.position.set((this.min.x + this.max.x) / 2, (this.min.y + this.max.y) / 2, this.min.z);
    this.scene.add(this.grid);
    if (this.view === 'depth') this.recolour();
    this.dirty = true;
  }

  bounds() {
    return { min: this.min.toArray(), max: this.max.toArray() };
  }

  /// Segments of each kind drawn: what the legend's colours count.
  kindCounts() {
    const n = [0, 0, 0];
    for (const c of this.chunks) for (const k of c.kinds) n[k] = (n[k] ?? 0) + 1;
    return { rapid: n[0], feed: n[1], plunge: n[2] };
  }

  setView(v: View) {
    const recolour = (v === 'depth') !== (this.view === 'depth');
    this.view = v;
    if (recolour) this.recolour();
    this.fit();
  }

  private recolour() {
    for (const c of this.chunks) {
      c.full.geometry.setAttribute('color', new THREE.BufferAttribute(this.colours(c.kinds, c.positions), 3));
    }
    this.dirty = true;
  }

  /// Camera framing the whole path from the current view's direction.
  fit() {
    if (!isFinite(this.min.x)) return;
    const centre = new THREE.Vector3().addVectors(this.min, this.max).multiplyScalar(0.5);
    const size = new THREE.Vector3().subVectors(this.max, this.min);
    const r = Math.max(size.length() / 2, 1);
    const d = r / Math.sin((this.camera.fov * Math.PI) / 360) * 1.05;
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
    let line = 0;
    for (const c of this.chunks) {
      const k = Math.max(0, Math.min(c.count, this.shown - c.start));
      c.full.geometry.setDrawRange(0, k * 2);
      c.coarse?.geometry.setDrawRange(0, Math.floor(k / this.stride) * 2);
      if (k > 0) {
        line = c.lines[k - 1];
        const p = c.positions;
        this.placeMarker(p[(k - 1) * 6 + 3], p[(k - 1) * 6 + 4], p[(k - 1) * 6 + 5]);
      }
    }
    this.dirty = true;
    return line;
  }

  /// The last segment of `line` (or the last one before it), for following a running job.
  segmentOfLine(line: number): number {
    let best = 0;
    for (const c of this.chunks) {
      if (c.count === 0 || c.lines[0] > line) break;
      // Lines rise through a program (loops aside): binary search within the chunk.
      let lo = 0, hi = c.count - 1;
      while (lo < hi) {
        const mid = (lo + hi + 1) >> 1;
        if (c.lines[mid] <= line) lo = mid; else hi = mid - 1;
      }
      best = c.start + lo + 1;
    }
    return best;
  }

  placeMarker(x: number, y: number, z: number) {
    this.marker.position.set(x, y, z);
    this.marker.visible = true;
    this.dirty = true;
  }

  /// Orbit the camera by `frames` steps, rendering each: for the frame-time benchmark
  /// (`lod` false keeps full detail while moving).
  orbitFrames(frames: number, lod = true): Promise<number[]> {
    return new Promise((resolve) => {
      const times: number[] = [];
      let last = performance.now();
      const step = () => {
        const offset = new THREE.Vector3().subVectors(this.camera.position, this.controls.target);
        offset.applyAxisAngle(new THREE.Vector3(0, 0, 1), 0.02);
        this.camera.position.copy(this.controls.target).add(offset);
        this.camera.lookAt(this.controls.target);
        if (lod) this.cameraMoved();
        this.render();
        // Reading a pixel waits for the GPU (or the software rasteriser) to finish the frame.
        const gl = this.renderer.getContext();
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
        const now = performance.now();
        times.push(now - last);
        last = now;
        if (times.length < frames) requestAnimationFrame(step); else resolve(times);
      };
      requestAnimationFrame(step);
    });
  }
}
