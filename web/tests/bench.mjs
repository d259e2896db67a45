// Workbench benchmark: time to the first drawn preview and to the whole preview, and the
// frame time while orbiting, on the program the server opens with (scripts/bench-web gives it
// a generated 1,000,000-segment program), in headless chromium (software rendering: no GPU).

import { chromium } from 'playwright-core';

const url = process.env.OFICINA_URL;
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--enable-precise-memory-info'],
});
const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
const t0 = Date.now();
await page.goto(url);
await page.waitForFunction(() => window.__oficina && window.__oficina.stats.firstBatchMs > 0, null, { timeout: 600000 });
const tFirst = Date.now() - t0;
await page.waitForFunction(() => window.__oficina.stats.previewDone > 0, null, { timeout: 600000 });
const tAll = Date.now() - t0;
const s = await page.evaluate(() => window.__oficina.stats);
// The page stays responsive while the preview streams: a timer's lateness says how much.
const lateness = await page.evaluate(() => new Promise((res) => {
  const t = performance.now();
  setTimeout(() => res(performance.now() - t - 10), 10);
}));
const median = (a) => a.slice().sort((x, y) => x - y)[Math.floor(a.length / 2)];
const mb = (b) => (b == null ? 'n/a' : `${(b / 1e6).toFixed(0)} MB`);
// The page's JS heap with the whole preview held (the worker's own heap is not counted).
const ourHeap = await page.evaluate(() => (performance.memory ? performance.memory.usedJSHeapSize : null));
const lod = await page.evaluate(() => window.__oficina.preview.orbitFrames(30, true));
const full = await page.evaluate(() => window.__oficina.preview.orbitFrames(10, false));
const cost = await page.evaluate(() => (window.__oficina.preview.frameCost ? window.__oficina.preview.frameCost(5) : null));
console.log(`program: ${s.segments.toLocaleString()} segments`);
console.log(`page load to first preview drawn: ${(tFirst / 1000).toFixed(2)} s (first batch ${(s.firstBatchMs / 1000).toFixed(2)} s after the preview request)`);
console.log(`page load to the whole preview:   ${(tAll / 1000).toFixed(2)} s`);
console.log(`  of which: page and program fetched ${(s.loadStartMs / 1000).toFixed(2)} s after navigation; text into the editor ${(s.editorMs / 1000).toFixed(2)} s; preview stream ${(s.previewMs / 1000).toFixed(2)} s`);
console.log(`timer lateness after loading:     ${lateness.toFixed(1)} ms`);
console.log(`orbit frame time, level of detail: median ${median(lod.slice(1)).toFixed(1)} ms (${(1000 / median(lod.slice(1))).toFixed(1)} frames/s)`);
console.log(`orbit frame time, full detail:     median ${median(full.slice(1)).toFixed(1)} ms (${(1000 / median(full.slice(1))).toFixed(1)} frames/s)`);
console.log(`JS heap of the page with the preview held: ${mb(ourHeap)}`);
if (cost) {
  const c = (k) => `${cost[k].toFixed(1)} ms`;
  console.log(`where a frame's time goes (median of 5, 1280 x 800 page): nothing drawn ${c('empty@1')} (${c('empty@0.5')} at half resolution);`);
  console.log(`  coarse copy ${c('coarse@1')} (${c('coarse@0.5')} at half); full path ${c('full@1')} (${c('full@0.5')} at half)`);
}
console.log('(headless chromium with --disable-gpu renders in software: a GPU draws far faster)');
if (process.env.OFICINA_BENCH_SHOT) await page.screenshot({ path: process.env.OFICINA_BENCH_SHOT });
await page.close();

// The peer: CNCjs's approach (gcode-toolpath + gcode-parser, one three.js line) on the same
// program in the same chromium, in a page of its own (its heap measured alone).
if (process.env.OFICINA_PEER_BUNDLE && process.env.OFICINA_PROGRAM) {
  const peer = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  await peer.goto(new URL('/api/info', url).href);
  await peer.addScriptTag({ path: process.env.OFICINA_PEER_BUNDLE });
  const r = await peer.evaluate(async ([name, w, h]) => {
    const t0 = performance.now();
    const text = await (await fetch('/api/files/' + encodeURIComponent(name))).text();
    const fetchMs = performance.now() - t0;
    const p = window.__peerCncjs(text, w, h);
    const orbit = p.orbit(10);
    return { fetchMs, ...p, orbit };
  }, [process.env.OFICINA_PROGRAM, 1280 - 560, 800 - 80]).catch((e) => ({ error: String(e.message || e) }));
  console.log('');
  if (r.error) {
    console.log(`CNCjs approach: failed: ${r.error}`);
  } else {
    const total = r.fetchMs + r.totalMs;
    const o = median(r.orbit.slice(1));
    console.log('                          Oficina (streamed, worker)   CNCjs approach (gcode-toolpath, one THREE.Line)');
    console.log(`time to first preview     ${(tFirst / 1000).toFixed(2).padStart(6)} s                     ${(total / 1000).toFixed(2).padStart(6)} s (fetch ${(r.fetchMs / 1000).toFixed(2)}, parse ${(r.parseMs / 1000).toFixed(2)}, geometry ${(r.buildMs / 1000).toFixed(2)}, first frame ${(r.firstFrameMs / 1000).toFixed(2)})`);
    console.log(`whole preview             ${(tAll / 1000).toFixed(2).padStart(6)} s                     ${(total / 1000).toFixed(2).padStart(6)} s (all at once)`);
    console.log(`page thread blocked       no (worker)                  ${((r.parseMs + r.buildMs + r.firstFrameMs) / 1000).toFixed(2)} s in one task`);
    console.log(`orbit, moving             ${(1000 / median(lod.slice(1))).toFixed(1).padStart(6)} frames/s (LOD)          ${(1000 / o).toFixed(1).padStart(6)} frames/s (no LOD)`);
    console.log(`orbit, full detail        ${(1000 / median(full.slice(1))).toFixed(1).padStart(6)} frames/s                ${(1000 / o).toFixed(1).padStart(6)} frames/s`);
    console.log(`JS heap after preview     ${mb(ourHeap).padStart(8)}                     ${mb(r.heap).padStart(8)}`);
    console.log(`points drawn              ${s.segments.toLocaleString()} segments           ${r.segments.toLocaleString()} vertices (${r.lines.toLocaleString()} lines parsed)`);
  }
  await peer.close();
} else {
  console.log('(CNCjs comparison skipped: OFICINA_PEER_BUNDLE and OFICINA_PROGRAM not set)');
}
await browser.close();
