// Workbench benchmark: time to the first drawn preview and to the whole preview, and the
// frame time while orbiting, on the program the server opens with (scripts/bench-web gives it
// a generated 1,000,000-segment program), in headless chromium (software rendering: no GPU).

import { chromium } from 'playwright-core';

const url = process.env.OFICINA_URL;
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking'],
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
const lod = await page.evaluate(() => window.__oficina.preview.orbitFrames(30, true));
const full = await page.evaluate(() => window.__oficina.preview.orbitFrames(10, false));
console.log(`program: ${s.segments.toLocaleString()} segments`);
console.log(`page load to first preview drawn: ${(tFirst / 1000).toFixed(2)} s (first batch ${(s.firstBatchMs / 1000).toFixed(2)} s after the preview request)`);
console.log(`page load to the whole preview:   ${(tAll / 1000).toFixed(2)} s`);
console.log(`  of which: page and program fetched ${(s.loadStartMs / 1000).toFixed(2)} s after navigation; text into the editor ${(s.editorMs / 1000).toFixed(2)} s; preview stream ${(s.previewMs / 1000).toFixed(2)} s`);
console.log(`timer lateness after loading:     ${lateness.toFixed(1)} ms`);
console.log(`orbit frame time, level of detail: median ${median(lod.slice(1)).toFixed(1)} ms (${(1000 / median(lod.slice(1))).toFixed(1)} frames/s)`);
console.log(`orbit frame time, full detail:     median ${median(full.slice(1)).toFixed(1)} ms (${(1000 / median(full.slice(1))).toFixed(1)} frames/s)`);
console.log('(headless chromium with --disable-gpu renders in software: a GPU draws far faster)');
if (process.env.OFICINA_BENCH_SHOT) await page.screenshot({ path: process.env.OFICINA_BENCH_SHOT });
await browser.close();
