// Chiaro's page against three.js (../shared/peers/threejs-bench) in the same headless
// chromium, on the same scenes and size, alternating one run of each per round. Both
// report each frame's time from its start to GPU completion (onSubmittedWorkDone).
// Benchmarks only: no test depends on it.
//
//   node web/bench/vs-threejs.mjs [--three DIR] [--assets DIR] [--width 640] [--height 360]
//        [--frames 10] [--warmup 3] [--rounds 3] [--msaa 4] [scene.gltf ...]
//
// Scenes are paths under --assets (default: the benchmark scene and the shadow samples).

import { resolve, dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { parseArgs } from 'node:util';
import { chromium } from 'playwright-core';
import { serveMounts } from '../tests/serve.mjs';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '../..');
const { values, positionals } = parseArgs({
  allowPositionals: true,
  options: {
    three: { type: 'string', default: join(root, '../shared/peers/threejs-bench') },
    assets: { type: 'string', default: join(root, '../shared/assets') },
    width: { type: 'string', default: '640' },
    height: { type: 'string', default: '360' },
    frames: { type: 'string', default: '10' },
    warmup: { type: 'string', default: '3' },
    rounds: { type: 'string', default: '3' },
    msaa: { type: 'string', default: '4' },
  },
});
const scenes = positionals.length ? positionals : [
  'chiaro-bench/shadow-bench.gltf',
  'ShadowsDirectional/glTF/shadows-directional.gltf',
  'ShadowsSpot/glTF/shadows-spot.gltf',
];

const server = await serveMounts({
  '/chiaro/': join(root, 'target/web'),
  '/three/': resolve(values.three),
  '/assets/': resolve(values.assets),
});
const base = `http://127.0.0.1:${server.address().port}`;
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--headless=new', '--no-sandbox', '--enable-unsafe-webgpu', '--enable-features=Vulkan',
    '--use-vulkan=swiftshader', '--use-webgpu-adapter=swiftshader', '--use-angle=swiftshader',
    '--enable-unsafe-swiftshader', '--disable-background-networking', '--disable-component-update',
    '--disable-sync', '--no-first-run'],
});

async function run(url, doneTitle, errorTitle, read) {
  const page = await browser.newPage();
  await page.goto(url);
  await page.waitForFunction(([d, e]) => document.title.startsWith(d) || document.title.startsWith(e),
    [doneTitle, errorTitle], { timeout: 600_000 });
  const title = await page.title();
  const result = title.startsWith(doneTitle) ? await page.evaluate(read) : { error: title };
  await page.close();
  return result;
}

const { width, height, frames, warmup, msaa } = values;
const settings = msaa === '4' ? '' : `&settings=${encodeURIComponent(`data:,[render]%0Amsaa=${msaa}`)}`;
const rows = [];
for (const scene of scenes) {
  const chiaro = [];
  const three = [];
  for (let round = 0; round < Number(values.rounds); round++) {
    const c = await run(`${base}/chiaro/index.html?scene=../assets/${scene}&width=${width}&height=${height}` +
      `&frames=${frames}&warmup=${warmup}&panel=0${settings}`, 'chiaro: done', 'chiaro: error', () => window.chiaro.stats);
    const t = await run(`${base}/three/index.html?scene=../assets/${scene}&width=${width}&height=${height}` +
      `&frames=${frames}&warmup=${warmup}&renderer=webgpu&shadows=scene&msaa=${msaa}`, 'bench: done', 'bench: error',
    () => window.benchResult);
    if (c.error || t.error) {
      console.log(`${scene} round ${round}: chiaro ${c.error ?? 'ok'}, three ${t.error ?? 'ok'}`);
      continue;
    }
    chiaro.push(c);
    three.push(t);
    console.log(`${scene} round ${round}: chiaro median ${c.frame_ms_median.toFixed(1)} ms ` +
      `(first frame ${c.first_frame_ms.toFixed(0)} ms, load to first frame ${c.load_to_first_frame_ms.toFixed(0)} ms), ` +
      `three.js median ${t.frame_ms_median.toFixed(1)} ms (first frame ${t.first_frame_ms.toFixed(0)} ms)`);
  }
  const median = (xs) => xs.slice().sort((a, b) => a - b)[Math.floor(xs.length / 2)];
  if (chiaro.length) {
    const c = median(chiaro.map((r) => r.frame_ms_median));
    const t = median(three.map((r) => r.frame_ms_median));
    rows.push({ scene, chiaro_ms: c, three_ms: t, ratio: t / c, rounds: chiaro.length, adapter: chiaro[0].adapter });
  }
}
console.log(`\n${width}x${height}, MSAA ${msaa}, ${frames} frames after ${warmup} warm-up, median of round medians`);
console.log('| scene | Chiaro ms | three.js ms | three.js / Chiaro |');
console.log('|---|---|---|---|');
for (const r of rows) {
  console.log(`| ${r.scene} | ${r.chiaro_ms.toFixed(1)} | ${r.three_ms.toFixed(1)} | ${r.ratio.toFixed(2)}x |`);
}
await browser.close();
server.close();
