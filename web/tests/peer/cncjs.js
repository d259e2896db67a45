// CNCjs's way to a preview, for the benchmark beside ours (scripts/bench-web): the whole
// program text parsed on the page's thread by `gcode-toolpath` (which parses with
// `gcode-parser`), every end point pushed as a THREE.Vector3 with a THREE.Color per point,
// then one THREE.Line (a line strip) with vertex colours, as CNCjs's GCodeVisualizer builds
// it (written here from its description; modern three.js has no THREE.Geometry, so the
// points go through BufferGeometry.setFromPoints as that Geometry was converted on upload).
// Arcs are sampled as CNCjs does, a point every few degrees; this program has none.

import * as THREE from 'three';
import Toolpath from 'gcode-toolpath';

const COLOURS = {
  G0: new THREE.Color(0x00ff00),
  G1: new THREE.Color(0x0000ff),
  G2: new THREE.Color(0x00bfff),
  G3: new THREE.Color(0x00bfff),
};
const OTHER = new THREE.Color(0xd3d3d3);

/// Parses `text`, builds the line and renders one frame into a canvas of `width` × `height`;
/// returns the times of each step (ms) and the JS heap after building (bytes, when chromium
/// reports it).
function firstPreview(text, width, height) {
  const t0 = performance.now();
  const vertices = [];
  const colours = [];
  const frames = [];
  const toolpath = new Toolpath({
    addLine: (modal, v1, v2) => {
      vertices.push(new THREE.Vector3(v2.x, v2.y, v2.z));
      colours.push(COLOURS[modal.motion] || OTHER);
    },
    addArcCurve: (modal, v1, v2, v0) => {
      const isCW = modal.motion === 'G2';
      const r = Math.hypot(v1.x - v0.x, v1.y - v0.y);
      let a1 = Math.atan2(v1.y - v0.y, v1.x - v0.x);
      let a2 = Math.atan2(v2.y - v0.y, v2.x - v0.x);
      if (isCW && a2 >= a1) a2 -= 2 * Math.PI;
      if (!isCW && a2 <= a1) a2 += 2 * Math.PI;
      const n = Math.max(2, Math.ceil(Math.abs(a2 - a1) / (Math.PI / 36)));
      for (let i = 1; i <= n; i++) {
        const a = a1 + ((a2 - a1) * i) / n;
        vertices.push(new THREE.Vector3(v0.x + r * Math.cos(a), v0.y + r * Math.sin(a), v1.z + ((v2.z - v1.z) * i) / n));
        colours.push(COLOURS[modal.motion] || OTHER);
      }
    },
  });
  toolpath.loadFromStringSync(text, (line, index) => {
    frames.push({ line, vertexIndex: vertices.length });
  });
  const tParsed = performance.now();
  const geometry = new THREE.BufferGeometry().setFromPoints(vertices);
  const c = new Float32Array(colours.length * 3);
  colours.forEach((col, i) => col.toArray(c, i * 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(c, 3));
  const line = new THREE.Line(geometry, new THREE.LineBasicMaterial({ vertexColors: true }));
  const tBuilt = performance.now();
  const heap = performance.memory ? performance.memory.usedJSHeapSize : null;

  const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(width, height);
  const scene = new THREE.Scene();
  scene.add(line);
  geometry.computeBoundingSphere();
  const s = geometry.boundingSphere;
  const camera = new THREE.PerspectiveCamera(45, width / height, s.radius / 100, s.radius * 20);
  camera.up.set(0, 0, 1);
  const orbit = (angle) => {
    const d = s.radius * 2.8;
    camera.position.set(s.center.x + d * Math.cos(angle), s.center.y + d * Math.sin(angle), s.center.z + d * 0.6);
    camera.lookAt(s.center);
  };
  const frame = () => {
    renderer.render(scene, camera);
    const gl = renderer.getContext();
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
  };
  orbit(0);
  frame();
  const tDrawn = performance.now();
  return {
    segments: vertices.length,
    lines: frames.length,
    parseMs: tParsed - t0,
    buildMs: tBuilt - tParsed,
    firstFrameMs: tDrawn - tBuilt,
    totalMs: tDrawn - t0,
    heap,
    /// Frame times while orbiting (full detail: CNCjs has no level of detail), ms.
    orbit: (n) => {
      const times = [];
      for (let i = 1; i <= n; i++) {
        const t = performance.now();
        orbit(0.02 * i);
        frame();
        times.push(performance.now() - t);
      }
      renderer.dispose();
      return times;
    },
  };
}

window.__peerCncjs = firstPreview;
