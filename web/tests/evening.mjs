// An evening at the machine, through the page's visible controls only, against the grbl
// emulator with a stock block (tilted and warped top), a touch plate on it and a tool length
// setter: connect, jog over the plate and probe Z with it; measure the tool on the setter;
// run a two-tool program whose M6s pause for the change (remeasured on the setter), with a
// hold and a resume; probe a 4 × 4 height map and run an engraving levelled with it. Every
// expectation is computed here from the emulator's numbers below, never from our code.
//
// The whole evening runs on grbl; the other flavours run the parts that differ by firmware:
// on grblHAL the XYZ corner probe, the manual change with re-measure and the park policy;
// on FluidNC the touch plate and the levelled engraving (OFICINA_FLAVOURS picks flavours).

import { startServer, startEmulator, launch, suite, assert, sleep, out, connectBoard, mdi } from './harness.mjs';
import path from 'node:path';
import { writeFileSync } from 'node:fs';

// The emulated shop (machine coordinates, mm).
const BLOCK = { x0: 10, y0: 10, x1: 290, y1: 190, top: -60 };
const TILT = [0.002, -0.001];
const WARP = { w: 0.1, lambda: 120 };
const PLATE = { x0: 150, y0: 50, x1: 190, y1: 90, thickness: 10 };
const SETTER = { x: 300, y: 100, top: -50 };
const TOOL_LENGTH = 15;
/// The block's top at machine X, Y: top + tilt·(x, y) + w·sin(2πx/λ)·sin(2πy/λ).
const surface = (x, y) => {
  const k = 2 * Math.PI / WARP.lambda;
  return BLOCK.top + TILT[0] * x + TILT[1] * y + WARP.w * Math.sin(k * x) * Math.sin(k * y);
};

/// The tool's diameter on grblHAL, whose evening probes the block's corner with its side.
const TOOL_DIAMETER = 6;
const SHOP = [
  '--probe-block', `${BLOCK.x0},${BLOCK.y0},${BLOCK.x1},${BLOCK.y1},${BLOCK.top}`,
  '--probe-plate', `${PLATE.x0},${PLATE.y0},${PLATE.x1},${PLATE.y1},${PLATE.thickness}`,
  '--probe-setter', `${SETTER.x},${SETTER.y},${SETTER.top}`,
  '--probe-tilt', TILT.join(','),
  '--probe-warp', `${WARP.w},${WARP.lambda}`,
  '--tool-length', String(TOOL_LENGTH),
  '--set', '110=6000', '--set', '111=6000', '--set', '112=3000',
  '--set', '120=500', '--set', '121=500', '--set', '122=500',
];
const FLAVOURS = (process.env.OFICINA_FLAVOURS || 'grbl,grblhal,fluidnc').split(',');

const { test, state, finish } = suite('evening');
const server = await startServer();
const browser = await launch();
const page = await browser.newPage({ viewport: { width: 1600, height: 1100 } });
state.page = page;
/// The flavour whose evening runs, and its board.
let flavour = 'grbl', board = null;
/// A screenshot's name: the grbl evening's as they were, the others' with their flavour.
const shotPath = (name) => path.join(out, flavour === 'grbl' ? `evening-${name}.png` : `evening-${flavour}-${name}.png`);

const dro = () => page.evaluate(() => Object.fromEntries(['x', 'y', 'z'].flatMap((a) =>
  [['m' + a, Number(document.getElementById('m' + a).textContent)], ['w' + a, Number(document.getElementById('w' + a).textContent)]])));
const waitState = (s, timeout = 30000) => page.waitForFunction((s) => document.body.dataset.state === s, s, { timeout });
const openSection = async (id) => {
  if (!(await page.$eval(`#${id}`, (d) => d.open))) await page.click(`#${id} > summary`);
};
async function load(program) {
  await page.fill('#text', program);
  // This program's check, not one shown before it.
  await page.waitForFunction((p) => window.__oficina.stats.checkedText === p
    && / 0 errors/.test(' ' + document.getElementById('summary').textContent), program, { timeout: 30000 })
    .catch(async () => { throw new Error(`the program does not check: ${await page.textContent('#summary')} ${await page.textContent('#diagnostics')}`); });
}
/// The page's console, kept beside the screenshots for a failure's story.
const consoleTail = async () => {
  const text = await page.textContent('#console');
  writeFileSync(path.join(out, 'evening-console.txt'), text);
  return text.slice(-400).replace(/\n/g, ' | ');
};
/// The machine position sampled from the DRO every 30 ms while the job runs, from
/// `startSampling()` to `stopSampling()` (which resolves with the [x, y, z] samples).
const startSampling = () => page.evaluate(() => {
  const w = window;
  w.__samples = [];
  w.__sampler = setInterval(() => {
    if (document.body.dataset.state !== 'run') return;
    w.__samples.push(['mx', 'my', 'mz'].map((id) => Number(document.getElementById(id).textContent)));
  }, 30);
});
const stopSampling = () => page.evaluate(() => { clearInterval(window.__sampler); return window.__samples; });
/// Waits for a probing routine's answer in the Probe section; a failure is thrown in its words.
async function probed() {
  await page.waitForFunction(() => ['done', 'failed'].includes(document.body.dataset.probe), null, { timeout: 60000 });
  const text = await page.textContent('#probe-result');
  if ((await page.evaluate(() => document.body.dataset.probe)) === 'failed') throw new Error(`probing failed: ${text}`);
  await waitState('idle');
  await sleep(400);
  return text;
}

/// Connects the page to this flavour's board: jogs over the touch plate with the buttons
/// on grbl, goes there with a typed line on the others.
const connect = () => test(`${flavour}: connect to the board and ${flavour === 'grbl' ? 'jog' : 'go'} over the touch plate`, async () => {
  if (page.url() === 'about:blank') {
    await page.goto(server.url);
    await page.waitForFunction(() => document.getElementById('summary').textContent.includes('errors'), null, { timeout: 30000 });
  }
  await connectBoard(page, board.uri);
  await waitState('idle');
  if (flavour !== 'grbl') {
    await mdi(page, 'G0 X170 Y70');
    await mdi(page, 'G0 Z-30');
    await page.waitForFunction(() => document.body.dataset.state === 'idle' && Number(document.getElementById('mz').textContent) === -30, null, { timeout: 15000 });
    return;
  }
  await page.fill('#jog-feed', '5000');
  await page.selectOption('#jog-step', '10');
  // To machine X170 Y70 (the plate's middle), and 30 mm down.
  const target = { X: 170, Y: 70, Z: -30 };
  const buttons = { X: '1,0,0', Y: '0,1,0', Z: '0,0,-1' };
  for (const axis of ['X', 'Y', 'Z']) {
    for (let i = 0; i < Math.abs(target[axis]) / 10; i++) {
      await page.click(`#jog button[data-jog="${buttons[axis]}"]`);
      await page.waitForFunction(([id, v]) => Math.abs(Number(document.getElementById(id).textContent) - v) < 1e-3,
        ['m' + axis.toLowerCase(), Math.sign(target[axis]) * 10 * (i + 1)], { timeout: 15000 });
      await waitState('idle');
    }
  }
  const d = await dro();
  assert(Math.abs(d.mx - 170) < 1e-3 && Math.abs(d.my - 70) < 1e-3 && Math.abs(d.mz + 30) < 1e-3, `over the plate: ${JSON.stringify(d)}`);
});

const plate = () => test(`${flavour}: probe Z with the plate: the stock top under it is work Z0`, async () => {
  await openSection('probe');
  await page.fill('#probe [name=thickness]', String(PLATE.thickness));
  await page.fill('#probe [name=travel]', '20');
  await page.fill('#probe [name=feed]', '200');
  await page.fill('#probe [name=slow_feed]', '25');
  await page.fill('#probe [name=retract]', '2');
  await page.selectOption('#probe [name=wcs]', '1');
  await page.click('#probe-z');
  const text = await probed();
  assert(text.includes('G54 offset set to'), `the result is shown: ${text}`);
  // grbl reports its work offset (WCO) every so many reports: the DRO follows within a few.
  await page.waitForFunction(() => Math.abs(Number(document.getElementById('wz').textContent) - Number(document.getElementById('mz').textContent)) > 1,
    null, { timeout: 5000 }).catch(() => {});
  const d = await dro();
  // The work Z the spindle would read with the tool tip on the stock's top here.
  const stockTop = surface(d.mx, d.my);
  const workAtTop = d.wz - (d.mz - (stockTop + TOOL_LENGTH));
  assert(Math.abs(workAtTop) < 0.01, `work Z at the stock top ${workAtTop.toFixed(4)} (DRO ${JSON.stringify(d)}, top ${stockTop.toFixed(4)})`);
  // The tool rests the retract above the plate: work Z = thickness + retract.
  assert(Math.abs(d.wz - (PLATE.thickness + 2)) < 0.01, `the DRO reads ${d.wz}, ${PLATE.thickness + 2} expected`);
  await page.screenshot({ path: shotPath('probe') });
});

const setter = () => test(`${flavour}: the tool length setter measures the tool; a missed touch is ALARM:5 in words`, async () => {
  await page.fill('#probe [name=setter_x]', String(SETTER.x));
  await page.fill('#probe [name=setter_y]', String(SETTER.y));
  await page.fill('#probe [name=safe_z]', '-5');
  await page.fill('#probe [name=reference]', '');
  // From safe Z −5 the tip is 15 mm lower, 30 mm above the pad: 40 mm of travel reaches it.
  await page.fill('#probe [name=travel]', '40');
  await page.fill('#probe [name=feed]', '600');
  await page.click('#probe-setter');
  const text = await probed();
  const expected = (SETTER.top + TOOL_LENGTH).toFixed(3);
  assert(text.includes(`(Z${expected})`), `the setter's touch at machine Z${expected}: ${text}`);
  // With that as the reference, the same tool's offset is 0.
  await page.fill('#probe [name=reference]', expected);
  await page.click('#probe-setter');
  const again = await probed();
  assert(/G43\.1 Z-?0\.000/.test(again), `the same tool has no length offset: ${again}`);
  // A probe with too short a travel fails with ALARM:5, explained in words.
  await page.fill('#probe [name=reference]', '');
  await page.fill('#probe [name=safe_z]', '20');
  await page.fill('#probe [name=travel]', '5');
  await page.click('#probe-setter');
  await page.waitForFunction(() => document.body.dataset.probe === 'failed', null, { timeout: 60000 });
  const failure = await page.textContent('#probe-result');
  assert(failure.startsWith('No contact') && failure.includes('ALARM:5'), `the failure in words: ${failure}`);
  await page.click('#unlock');
  await waitState('idle');
  await page.fill('#probe [name=safe_z]', '-5');
});

// Two tools; each cut long enough to hold in.
const passes = (y) => Array.from({ length: 3 }, (_, i) => `G1 X${i % 2 ? 120 : 160} Y${y + i} F600`).join('\n');
const twoTools = [
  'G21 G90', 'T1 M6', 'G0 Z5', 'G0 X120 Y120', 'G1 Z-0.5 F300', passes(120), 'G0 Z5',
  'T2 M6', 'G0 X120 Y140', 'G1 Z-0.5 F300', passes(140), 'G0 Z5', 'M2',
].join('\n') + '\n';
const lineOf = (text, s) => text.split('\n').findIndex((l) => l === s) + 1;

const remeasure = () => test(`${flavour}: a two-tool program pauses at each M6 (remeasure), names the tool and line, and goes on`, async () => {
  await openSection('toolchange');
  await page.selectOption('#toolchange [name=policy]', 'remeasure');
  await page.fill('#toolchange [name=tc_setter_x]', String(SETTER.x));
  await page.fill('#toolchange [name=tc_setter_y]', String(SETTER.y));
  // The remeasure starts with the tip 5 mm over the pad.
  await page.fill('#toolchange [name=tc_setter_z]', String(SETTER.top + TOOL_LENGTH + 5));
  await page.dispatchEvent('#toolchange [name=tc_setter_z]', 'change');
  await load(twoTools);
  const notes = await page.$$eval('#diagnostics li', (l) => l.map((x) => `${x.className}: ${x.textContent}`));
  assert(notes.some((n) => n.includes('M6') && n.includes('remeasure')), `the check says what the sender does at M6: ${notes}`);
  await page.click('#start');
  for (const [tool, line] of [[1, lineOf(twoTools, 'T1 M6')], [2, lineOf(twoTools, 'T2 M6')]]) {
    await page.waitForFunction((t) => document.body.dataset.toolChange === t, `T${tool}@${line}`, { timeout: 60000 })
      .catch(async () => { throw new Error(`no banner for T${tool} at line ${line}: ${await page.evaluate(() => document.body.dataset.toolChange)}, state ${await page.evaluate(() => document.body.dataset.state)}; console: ${await consoleTail()}`); });
    const banner = await page.textContent('#toolchange-banner');
    assert(await page.isVisible('#toolchange-banner'), 'the banner is shown');
    assert(banner.includes(`T${tool}`) && banner.includes(`line ${line}`), `the banner names T${tool} and line ${line}: ${banner}`);
    if (tool === 2) await page.screenshot({ path: shotPath('toolchange') });
    await page.click('#toolchange-continue');
    await page.waitForFunction(() => document.body.dataset.toolChange === '', null, { timeout: 30000 })
      .catch(async () => { throw new Error(`T${tool} continue did not go on: state ${await page.evaluate(() => document.body.dataset.state)}; console: ${await consoleTail()}`); });
    if (tool === 1) {
      // A hold and a resume while the first tool cuts.
      await page.waitForFunction(() => document.body.dataset.state === 'run' && Number(document.getElementById('line').textContent) >= 6, null, { timeout: 60000 });
      await page.click('#hold');
      await waitState('hold');
      const held = await dro();
      await sleep(600);
      const still = await dro();
      assert(held.mx === still.mx && held.my === still.my, `nothing moves in a hold: ${JSON.stringify(held)} ${JSON.stringify(still)}`);
      await page.click('#resume');
      await waitState('run');
    }
  }
  await page.waitForFunction(() => document.body.dataset.jobDone === 'completed', null, { timeout: 120000 })
    .catch(async () => { throw new Error(`the job did not complete: ${await page.evaluate(() => document.body.dataset.jobDone)}; ${await consoleTail()}`); });
  const console_ = await page.textContent('#console');
  assert(console_.includes('tool T2 in place'), 'the console says the tool is in place');
});

// An engraving 0.1 mm deep over a 30 × 20 mm rectangle.
const ENGRAVE = { x0: 100, y0: 120, x1: 130, y1: 140, depth: 0.1 };
const engraving = [
  'G21 G90', 'G0 Z3', `G0 X${ENGRAVE.x0} Y${ENGRAVE.y0}`, `G1 Z-${ENGRAVE.depth} F200`,
  `G1 X${ENGRAVE.x1} F600`, `G1 Y${ENGRAVE.y1}`, `G1 X${ENGRAVE.x0}`, `G1 Y${ENGRAVE.y0 + 1}`, 'G0 Z3', 'M2',
].join('\n') + '\n';

const level = () => test(`${flavour}: a 4 × 4 height map and a levelled engraving follow the warped surface`, async () => {
  await load(engraving);
  await openSection('level');
  await page.fill('#level [name=nx]', '4');
  await page.fill('#level [name=ny]', '4');
  await page.fill('#level [name=margin]', '2');
  await page.fill('#level [name=clearance]', '3');
  await page.fill('#level [name=depth]', '-3');
  await page.fill('#level [name=level_feed]', '300');
  await page.click('#level-probe');
  await page.waitForFunction(() => ['mapped', 'failed'].includes(document.body.dataset.level), null, { timeout: 180000 })
    .catch(async () => { throw new Error(`no map: ${await page.textContent('#level-message')}; console: ${await consoleTail()}`); });
  const msg = await page.textContent('#level-message');
  assert((await page.evaluate(() => document.body.dataset.level)) === 'mapped', `the map: ${msg}`);
  await waitState('idle');
  // The map's heights against the surface: work Z = machine top + tool length − the work offset.
  const d = await dro();
  const wcoZ = d.mz - d.wz;
  const cells = await page.$$eval('#level-map tr', (rows) => rows.map((r) => Array.from(r.children).map((c) => c.textContent)));
  const xs = cells[0].slice(1).map(Number);
  const heights = cells.slice(1).flatMap((r) => r.slice(1).map((z, i) => ({ x: xs[i], y: Number(r[0]), z: Number(z) })));
  assert(heights.length === 16, `16 heights: ${heights.length}`);
  for (const h of heights) {
    const want = surface(h.x, h.y) + TOOL_LENGTH - wcoZ;
    assert(Math.abs(h.z - want) < 0.01, `height at X${h.x} Y${h.y}: ${h.z}, the surface says ${want.toFixed(4)}`);
  }
  // Start levelled; the DRO is sampled as it cuts.
  await page.check('#start-levelled');
  await startSampling();
  await page.click('#start');
  await page.waitForFunction(() => (document.getElementById('console').textContent || '').includes('levelled with level-map.json'), null, { timeout: 15000 });
  await page.waitForFunction(() => document.body.dataset.state === 'run', null, { timeout: 15000 });
  await page.screenshot({ path: shotPath('level') });
  await page.waitForFunction(() => document.body.dataset.jobDone === 'completed', null, { timeout: 120000 });
  const samples = await stopSampling();
  // Cutting samples: the tool below 1 mm over the surface, away from the plunge and lift points.
  const ends = [[ENGRAVE.x0, ENGRAVE.y0], [ENGRAVE.x0, ENGRAVE.y0 + 1]];
  let worst = 0, cuts = 0;
  for (const [mx, my, mz] of samples) {
    const depth = surface(mx, my) - (mz - TOOL_LENGTH);
    if (depth < -1) continue;
    if (ends.some(([x, y]) => Math.hypot(mx - x, my - y) < 0.05)) continue;
    cuts++;
    worst = Math.max(worst, Math.abs(depth - ENGRAVE.depth));
  }
  assert(cuts >= 20, `cutting seen at ${cuts} samples of ${samples.length}`);
  assert(worst <= 0.02, `depth below the true surface within 0.02 of ${ENGRAVE.depth}: worst ${worst.toFixed(4)} over ${cuts} samples`);
  // The map beside the finished job: the other sections folded away.
  for (const id of ['probe', 'toolchange']) {
    if (await page.$eval(`#${id}`, (d) => d.open)) await page.click(`#${id} > summary`);
  }
  await page.$eval('#level-map', (e) => e.scrollIntoView());
  await page.screenshot({ path: shotPath('level-done') });
  await page.uncheck('#start-levelled');
});

// Two tools inside the map, each cutting 0.1 mm deep: the levelled job stops at each M6 as a
// plain one does, and tool 2 is re-measured on the setter (the map stays valid).
const LEVEL_TOOLS_Y = [125, 135];
const levelledTools = [
  'G21 G90', 'T1 M6', 'G0 Z3', `G0 X102 Y${LEVEL_TOOLS_Y[0]}`, `G1 Z-${ENGRAVE.depth} F200`, 'G1 X128 F600', 'G0 Z3',
  'T2 M6', 'G0 Z3', `G0 X102 Y${LEVEL_TOOLS_Y[1]}`, `G1 Z-${ENGRAVE.depth} F200`, 'G1 X128 F600', 'G0 Z3', 'M2',
].join('\n') + '\n';

const levelTwoTools = () => test(`${flavour}: a levelled two-tool program stops at each M6, re-measures tool 2, and both cut at depth`, async () => {
  // The remeasure policy and the map of the steps before stay in force.
  await load(levelledTools);
  await page.check('#start-levelled');
  const before = (await page.textContent('#console')).length;
  await startSampling();
  await page.click('#start');
  for (const [tool, line] of [[1, lineOf(levelledTools, 'T1 M6')], [2, lineOf(levelledTools, 'T2 M6')]]) {
    await page.waitForFunction((t) => document.body.dataset.toolChange === t, `T${tool}@${line}`, { timeout: 60000 })
      .catch(async () => { throw new Error(`no banner for T${tool} at line ${line}: ${await page.textContent('#level-message')}; console: ${await consoleTail()}`); });
    await page.click('#toolchange-continue');
    await page.waitForFunction(() => document.body.dataset.toolChange === '', null, { timeout: 30000 });
  }
  await page.waitForFunction(() => document.body.dataset.jobDone === 'completed', null, { timeout: 120000 })
    .catch(async () => { throw new Error(`the levelled job did not complete: ${await consoleTail()}`); });
  const samples = await stopSampling();
  const log = (await page.textContent('#console')).slice(before);
  assert(log.includes('levelled with level-map.json'), `started levelled: ${log.slice(-300)}`);
  assert(log.includes('tool T2 in place'), 'the console says tool 2 is in place');
  const offsets = [...log.matchAll(/tool length offset G43\.1 Z(-?[\d.]+)/g)].map((m) => Number(m[1]));
  assert(offsets.length >= 1 && Math.abs(offsets[offsets.length - 1]) < 0.01,
    `tool 2 re-measured on the setter (the same length here: offset 0): ${offsets}`);
  // Each tool's cut under the true surface, away from its plunge and lift points.
  const worst = [0, 0], cuts = [0, 0];
  for (const [mx, my, mz] of samples) {
    const depth = surface(mx, my) - (mz - TOOL_LENGTH);
    if (depth < -1 || mx < 102.05 || mx > 127.95) continue;
    const t = LEVEL_TOOLS_Y.findIndex((y) => Math.abs(my - y) < 1e-3);
    if (t < 0) continue;
    cuts[t]++;
    worst[t] = Math.max(worst[t], Math.abs(depth - ENGRAVE.depth));
  }
  assert(cuts[0] >= 10 && cuts[1] >= 10, `both tools seen cutting: ${cuts}`);
  assert(worst[0] <= 0.02 && worst[1] <= 0.02, `each tool's depth within 0.02 of ${ENGRAVE.depth}: worst ${worst.map((w) => w.toFixed(4))}`);
  await page.uncheck('#start-levelled');
});

const corner = () => test(`${flavour}: the XYZ corner probe makes the block's front-left top corner X0 Y0 Z0`, async () => {
  await openSection('probe');
  // Over the block, 10 mm in from both sides; the tip 5 mm above the top.
  await mdi(page, 'G53 G0 Z-30');
  await mdi(page, `G53 G0 X${BLOCK.x0 + 10} Y${BLOCK.y0 + 10}`);
  await mdi(page, 'G53 G0 Z-40');
  await waitState('idle');
  await page.fill('#probe [name=thickness]', '0');
  await page.fill('#probe [name=tool_diameter]', String(TOOL_DIAMETER));
  await page.fill('#probe [name=reach]', '15');
  await page.fill('#probe [name=depth]', '3');
  await page.fill('#probe [name=side_x]', '0');
  await page.fill('#probe [name=side_y]', '0');
  await page.fill('#probe [name=travel]', '20');
  await page.fill('#probe [name=feed]', '1000');
  await page.fill('#probe [name=slow_feed]', '100');
  await page.fill('#probe [name=retract]', '2');
  await page.selectOption('#probe [name=wcs]', '1');
  await page.click('#probe-corner');
  const text = await probed();
  const nums = (s) => s.match(/X(-?[\d.]+) Y(-?[\d.]+) Z(-?[\d.]+)/).slice(1).map(Number);
  const contacts = text.split('; ')[0].split(', ').map(nums);
  const offset = nums(text.split('offset set to ')[1]);
  // The top touched under the start, the tip on the surface; the sides at the block's own.
  const top = surface(contacts[0][0], contacts[0][1]) + TOOL_LENGTH;
  assert(Math.abs(offset[0] - BLOCK.x0) < 0.01 && Math.abs(offset[1] - BLOCK.y0) < 0.01, `G54 X, Y at the block's sides ${BLOCK.x0}, ${BLOCK.y0}: ${text}`);
  assert(Math.abs(offset[2] - top) < 0.01, `G54 Z at the top (machine Z ${top.toFixed(4)} with the tip on it): ${text}`);
  await page.screenshot({ path: shotPath('corner') });
  // Back up to the work zero: the tool's centre over the corner, 5 mm above it.
  await mdi(page, 'G0 Z5');
  await mdi(page, 'G0 X0 Y0');
  await page.waitForFunction(() => document.body.dataset.state === 'idle' && ['wx', 'wy', 'wz'].every((id, i) => Math.abs(Number(document.getElementById(id).textContent) - [0, 0, 5][i]) < 1e-3), null, { timeout: 15000 });
});

// A one-change program: the tool goes to the park position at its M6 and waits there.
const PARK = { x: 250, y: 180, z: -5 };
const oneChange = [
  'G21 G90', 'G0 Z5', 'G0 X20 Y20', 'G1 Z-0.5 F300', 'G1 X40 F600', 'G0 Z5',
  'T2 M6', 'G0 X20 Y30', 'G1 Z-0.5 F300', 'G1 X40 F600', 'G0 Z5', 'M2',
].join('\n') + '\n';

const park = () => test(`${flavour}: the park policy takes the tool to the park position at M6, and the job goes on from there`, async () => {
  await openSection('toolchange');
  await page.selectOption('#toolchange [name=policy]', 'park');
  await page.fill('#toolchange [name=park_x]', String(PARK.x));
  await page.fill('#toolchange [name=park_y]', String(PARK.y));
  await page.fill('#toolchange [name=park_z]', String(PARK.z));
  await page.dispatchEvent('#toolchange [name=park_z]', 'change');
  await load(oneChange);
  // The check's note follows the policy the board was given.
  await page.waitForFunction(() => Array.from(document.querySelectorAll('#diagnostics li')).some((l) => l.textContent.includes('M6') && l.textContent.includes('--tool-change park')), null, { timeout: 10000 })
    .catch(async () => { throw new Error(`the check names the park policy: ${await page.$$eval('#diagnostics li', (l) => l.map((x) => x.textContent))}`); });
  await page.click('#start');
  const line = lineOf(oneChange, 'T2 M6');
  await page.waitForFunction((t) => document.body.dataset.toolChange === t, `T2@${line}`, { timeout: 60000 })
    .catch(async () => { throw new Error(`no banner for T2: state ${await page.evaluate(() => document.body.dataset.state)}; ${await consoleTail()}`); });
  await page.waitForFunction((p) => ['mx', 'my', 'mz'].every((id, i) => Math.abs(Number(document.getElementById(id).textContent) - p[i]) < 1e-3), [PARK.x, PARK.y, PARK.z], { timeout: 30000 })
    .catch(async () => { throw new Error(`not at the park position: ${JSON.stringify(await dro())}`); });
  const banner = await page.textContent('#toolchange-banner');
  assert(banner.includes('T2') && banner.includes(`line ${line}`), `the banner names T2 and line ${line}: ${banner}`);
  await page.screenshot({ path: shotPath('park') });
  await page.click('#toolchange-continue');
  await page.waitForFunction(() => document.body.dataset.jobDone === 'completed', null, { timeout: 60000 })
    .catch(async () => { throw new Error(`the job did not complete: ${await consoleTail()}`); });
  const d = await dro();
  assert(Math.abs(d.wx - 40) < 1e-3 && Math.abs(d.wy - 30) < 1e-3 && Math.abs(d.wz - 5) < 1e-3, `the job went on after the park and ended at work X40 Y30 Z5: ${JSON.stringify(d)}`);
});

/// What each flavour's evening covers.
const PLAN = {
  grbl: [plate, setter, remeasure, level, levelTwoTools],
  grblhal: [corner, remeasure, park],
  fluidnc: [plate, level],
};
for (flavour of FLAVOURS) {
  board = await startEmulator(flavour, [...SHOP, ...(flavour === 'grblhal' ? ['--tool-diameter', String(TOOL_DIAMETER)] : [])]);
  await connect();
  for (const step of PLAN[flavour] ?? []) await step();
  board.stop();
}

await browser.close();
finish();
