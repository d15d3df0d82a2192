// The browser build in a real browser: Debian's chromium, headless, WebGPU on SwiftShader
// (never a downloaded browser). Serves target/web/ (scripts/web.sh build), opens the page
// on test scenes and compares what its canvas shows with `chiaro render` of the same
// scene, camera and size; a broken file must show an error; a dropped file must render.
//
// Run: node --test web/tests/ (CHIARO_BIN: the native CLI; CHROMIUM: the browser).

import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, existsSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, dirname, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { serveFolder } from './serve.mjs';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '../..');
const pageDir = join(process.env.CARGO_TARGET_DIR ? resolve(root, process.env.CARGO_TARGET_DIR) : join(root, 'target'), 'web');
const chiaro = process.env.CHIARO_BIN || join(root, 'target/release/chiaro');
const browserPath = process.env.CHROMIUM || '/usr/bin/chromium';
const work = mkdtempSync(join(tmpdir(), 'chiaro-web-test-'));
const WIDTH = 160;
const HEIGHT = 120;

// Two software rasterisers (lavapipe natively, SwiftShader in the browser) differ in
// rounding and in how much of an edge pixel a triangle covers. Measured on these scenes
// (docs/web.md), 160x120: mean |d| 0.005-0.84 of 255; pixels off by more than 16 of 255
// 0-2.2%, all on geometric edges; pixels outside their neighbourhood's range by more than
// 16: 0-0.21%. A real difference is far above: the boxes with the shadow distance cut to
// 5 m read mean 9.8 and 5.3% outside, with the exposure changed 7.4 and 22%.
const MAX_MEAN_DIFF = 1.5;
const MAX_SHARE_OUTSIDE = 0.005;

// The deferred path's settings, for the page (by URL) and the CLI (by file).
const DEFERRED = '[render]\npath = "deferred"\n';
const deferredFile = join(work, 'deferred.toml');
writeFileSync(deferredFile, DEFERRED);

// Broken files the server makes up: bad JSON, and a buffer that is not there.
const extraRoutes = {
  '/settings/deferred.toml': DEFERRED,
  '/broken/not-json.gltf': 'this is not { glTF',
  '/broken/missing-bin.gltf': JSON.stringify({
    asset: { version: '2.0' },
    buffers: [{ uri: 'nowhere.bin', byteLength: 36 }],
    bufferViews: [{ buffer: 0, byteLength: 36 }],
    accessors: [{ bufferView: 0, componentType: 5126, count: 3, type: 'VEC3', min: [0, 0, 0], max: [1, 1, 0] }],
    meshes: [{ primitives: [{ attributes: { POSITION: 0 } }] }],
    nodes: [{ mesh: 0 }],
    scenes: [{ nodes: [0] }],
  }),
};

let server;
let browser;
let base;

before(async () => {
  assert.ok(existsSync(join(pageDir, 'index.html')), `${pageDir}/index.html is missing: run scripts/web.sh build`);
  assert.ok(existsSync(chiaro), `${chiaro} is missing: build the CLI (cargo build --release)`);
  server = await serveFolder(pageDir, extraRoutes);
  base = `http://127.0.0.1:${server.address().port}`;
  browser = await chromium.launch({
    executablePath: browserPath,
    args: [
      '--headless=new', '--no-sandbox', '--enable-unsafe-webgpu', '--enable-features=Vulkan',
      '--use-vulkan=swiftshader', '--use-webgpu-adapter=swiftshader', '--use-angle=swiftshader',
      '--enable-unsafe-swiftshader', '--disable-background-networking', '--disable-component-update',
      '--disable-sync', '--no-first-run',
    ],
  });
});

after(async () => {
  await browser?.close();
  server?.close();
});

/** Opens the page with `query`, waits for its title to say done or error. */
async function openPage(query) {
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(`${base}/index.html?${query}`);
  await page.waitForFunction(
    () => document.title.startsWith('chiaro: done') || document.title.startsWith('chiaro: error'),
    null,
    { timeout: 300_000 },
  );
  return { page, errors };
}

/** `chiaro render` of `scene` (a path under tests/assets, or none for the demo) as PNG bytes. */
function nativeRender(scene, extra = []) {
  const output = join(work, `native-${Math.random().toString(36).slice(2)}.png`);
  const args = ['render', ...(scene ? [join(root, 'tests/assets', scene)] : []), '--width', `${WIDTH}`,
    '--height', `${HEIGHT}`, '--output', output, ...extra];
  execFileSync(chiaro, args, { stdio: ['ignore', 'ignore', 'inherit'] });
  return readFileSync(output);
}

/** Per-pixel difference of two PNGs, decoded by the browser: mean |d| over channels (of
 * 255), the largest, and the share of pixels whose largest channel differs by more than 16. */
async function difference(page, pngA, pngB) {
  return page.evaluate(async ([a, b]) => {
    async function pixels(base64) {
      const blob = await (await fetch(`data:image/png;base64,${base64}`)).blob();
      const bitmap = await createImageBitmap(blob, { colorSpaceConversion: 'none', premultiplyAlpha: 'none' });
      const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
      const context = canvas.getContext('2d');
      context.drawImage(bitmap, 0, 0);
      return { width: bitmap.width, height: bitmap.height, data: context.getImageData(0, 0, bitmap.width, bitmap.height).data };
    }
    const [x, y] = await Promise.all([pixels(a), pixels(b)]);
    if (x.width !== y.width || x.height !== y.height) {
      return { sizes: [`${x.width}x${x.height}`, `${y.width}x${y.height}`] };
    }
    let sum = 0;
    let max = 0;
    let off = 0;
    for (let i = 0; i < x.data.length; i += 4) {
      let pixelMax = 0;
      for (let c = 0; c < 3; c++) {
        const d = Math.abs(x.data[i + c] - y.data[i + c]);
        sum += d;
        pixelMax = Math.max(pixelMax, d);
      }
      max = Math.max(max, pixelMax);
      if (pixelMax > 16) off++;
    }
    // Outside the neighbourhood: a pixel of one image further than 16 from the range its 3x3
    // neighbourhood spans in the other, either way. An edge pixel that one rasteriser
    // covers a little more than the other stays within its neighbours' range; a shadow or
    // a light that differs does not.
    function outside(p, q) {
      let count = 0;
      for (let row = 0; row < p.height; row++) {
        for (let col = 0; col < p.width; col++) {
          const i = 4 * (row * p.width + col);
          let worst = 0;
          for (let c = 0; c < 3; c++) {
            let lo = 255;
            let hi = 0;
            for (let dy = -1; dy <= 1; dy++) {
              for (let dx = -1; dx <= 1; dx++) {
                const r = Math.min(Math.max(row + dy, 0), p.height - 1);
                const k = Math.min(Math.max(col + dx, 0), p.width - 1);
                const v = q.data[4 * (r * p.width + k) + c];
                lo = Math.min(lo, v);
                hi = Math.max(hi, v);
              }
            }
            const v = p.data[i + c];
            worst = Math.max(worst, v - hi, lo - v);
          }
          if (worst > 16) count++;
        }
      }
      return count;
    }
    const count = x.width * x.height;
    const shareOutside = Math.max(outside(x, y), outside(y, x)) / count;
    return { mean: sum / (3 * count), max, shareOff: off / count, shareOutside };
  }, [pngA.toString('base64'), pngB.toString('base64')]);
}

async function canvasPng(page) {
  return page.locator('#chiaro-canvas').screenshot();
}

function assertClose(name, diff) {
  console.log(`${name}: mean |d| ${diff.mean?.toFixed(3)} of 255, max ${diff.max}, ` +
    `${((diff.shareOff ?? 1) * 100).toFixed(3)}% of pixels off by more than 16, ` +
    `${((diff.shareOutside ?? 1) * 100).toFixed(3)}% outside their neighbourhood's range`);
  assert.equal(diff.sizes, undefined, `${name}: sizes differ ${diff.sizes}`);
  assert.ok(diff.mean <= MAX_MEAN_DIFF, `${name}: mean difference ${diff.mean} > ${MAX_MEAN_DIFF}`);
  assert.ok(diff.shareOutside <= MAX_SHARE_OUTSIDE,
    `${name}: ${diff.shareOutside} of pixels outside their neighbourhood > ${MAX_SHARE_OUTSIDE}`);
}

for (const [name, scene, camera, deferred] of [
  ['the demo', null, null, false],
  ['the demo on the deferred path', null, null, true],
  ['ShadowsSpot (glTF with a .bin, spot shadow)', 'ShadowsSpot/glTF/shadows-spot.gltf', '0', false],
  ['the benchmark scene (65 lights, 7 shadowed)', 'chiaro-bench/shadow-bench.gltf', '0', false],
]) {
  test(`the page renders ${name} as chiaro render does`, async () => {
    const query = new URLSearchParams({ width: WIDTH, height: HEIGHT, frames: 2, panel: 0 });
    if (scene) query.set('scene', `scenes/${scene}`);
    if (camera) query.set('camera', camera);
    if (deferred) query.set('settings', 'settings/deferred.toml');
    const { page, errors } = await openPage(query.toString());
    assert.equal(await page.title(), 'chiaro: done', `page errors: ${errors.join('; ')}`);
    const stats = await page.evaluate(() => window.chiaro.stats);
    assert.equal(stats.frames, 2);
    assert.ok(stats.frame_ms_min > 0 && stats.frame_ms_min <= stats.frame_ms_median, JSON.stringify(stats));
    assert.ok(stats.frame_ms_median <= stats.frame_ms_max, JSON.stringify(stats));
    assert.match(stats.adapter, /^\S.* \(BrowserWebGpu, /, 'the adapter is named');
    const native = nativeRender(scene, [...(camera ? ['--camera', camera] : []),
      ...(deferred ? ['--settings', deferredFile] : [])]);
    assertClose(name, await difference(page, await canvasPng(page), native));
    await page.close();
  });
}

test('every shader compiles with the browser\'s own WGSL compiler', async () => {
  // Chromium compiles WGSL with Tint, not naga: stricter in places (uniformity analysis
  // among them). The page compiles each artifact and lists Tint's errors.
  const { page } = await openPage('check=shaders&width=64&height=64');
  assert.equal(await page.title(), 'chiaro: done');
  const check = await page.evaluate(() => window.chiaro.shader_check);
  assert.ok(check.modules >= 10, `only ${check.modules} shaders were compiled`);
  assert.deepEqual(check.errors, []);
  await page.close();
});

test('a broken file shows its error on the page and in the title', async () => {
  for (const [file, expected] of [
    ['broken/not-json.gltf', /broken\/not-json\.gltf/],
    ['broken/missing-bin.gltf', /nowhere\.bin/],
    ['broken/absent.gltf', /HTTP 404/],
  ]) {
    const { page } = await openPage(`scene=${file}&width=64&height=48&frames=1`);
    const title = await page.title();
    assert.ok(title.startsWith('chiaro: error: '), title);
    assert.match(title, expected);
    const shown = page.locator('#chiaro-error');
    assert.ok(await shown.isVisible(), `${file}: the error is not shown`);
    assert.match(await shown.textContent(), expected);
    await page.close();
  }
});

test('a file dropped on the canvas renders as chiaro render draws it', async () => {
  const { page, errors } = await openInteractive(`width=${WIDTH}&height=${HEIGHT}`);
  const before = await page.locator('#chiaro-scene-info').textContent();
  // A real drop event: a DataTransfer holding the file, as a browser makes it.
  const transfer = await page.evaluateHandle(async () => {
    const bytes = await (await fetch('scenes/InstancedBoxes/boxes-instanced.glb')).arrayBuffer();
    const transfer = new DataTransfer();
    transfer.items.add(new File([bytes], 'boxes-instanced.glb'));
    return transfer;
  });
  await page.dispatchEvent('#chiaro-canvas', 'drop', { dataTransfer: transfer });
  await page.waitForFunction((old) => {
    const info = document.getElementById('chiaro-scene-info').textContent;
    return info !== old && info.includes('boxes-instanced.glb');
  }, before, { timeout: 120_000 });
  // The page counts the frames it finished since a scene opened.
  await page.waitForFunction(
    () => (window.chiaro.scene_frames >= 1 && window.chiaro.idle === true) || document.title.startsWith('chiaro: error'),
    null, { timeout: 120_000 });
  assert.ok(!(await page.title()).startsWith('chiaro: error'), await page.title());
  assert.deepEqual(errors, []);
  const native = nativeRender('InstancedBoxes/boxes-instanced.glb', ['--camera', '0']);
  assertClose('dropped boxes-instanced.glb', await difference(page, await canvasPng(page), native));
  await page.close();
});

/** Opens the interactive page (no `frames`) and waits for its first frame. */
async function openInteractive(query) {
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(`${base}/index.html?${query}`);
  await page.waitForFunction(
    () => (window.chiaro?.scene_frames >= 1 && window.chiaro.idle === true) || document.title.startsWith('chiaro: error'),
    null,
    { timeout: 300_000 },
  );
  return { page, errors };
}

/** Does `action`, then waits until the page has finished a frame after it and has
 * nothing left to draw (`window.chiaro.idle`). */
async function afterFrame(page, action) {
  const count = await page.evaluate(() => window.chiaro.scene_frames);
  await action();
  await page.waitForFunction((n) => window.chiaro.scene_frames > n && window.chiaro.idle === true, count,
    { timeout: 120_000 });
}

test('the viewer orbits with the mouse, shows debug views (drawn and read back) and refuses bad settings', async () => {
  const { page, errors } = await openInteractive(`width=${WIDTH}&height=${HEIGHT}`);
  const start = await canvasPng(page);
  // Orbit: a drag across the canvas turns the camera about the scene.
  const box = await page.locator('#chiaro-canvas').boundingBox();
  await page.mouse.move(box.x + 40, box.y + 60);
  await afterFrame(page, async () => {
    await page.mouse.down();
    await page.mouse.move(box.x + 120, box.y + 60, { steps: 4 });
    await page.mouse.up();
  });
  const turned = await difference(page, start, await canvasPng(page));
  assert.ok(turned.mean > 5, `the drag changed the image by only ${turned.mean}`);
  // A debug view drawn by a pass: the forward path's cascade tint.
  await afterFrame(page, () => page.selectOption('#chiaro-debug', { label: 'cascades' }));
  const before = await canvasPng(page);
  await afterFrame(page, () => page.selectOption('#chiaro-debug', 'none'));
  const plain = await canvasPng(page);
  const tinted = await difference(page, before, plain);
  assert.ok(tinted.mean > 5, `the cascade view changed the image by only ${tinted.mean}`);
  // Debug views computed from read-backs replace the 3D view with images.
  for (const [label, count] of [['shadow atlases', 2], ['aov depth', 1], ['clusters', 1]]) {
    await afterFrame(page, () => page.selectOption('#chiaro-debug', { label }));
    const shown = await page.evaluate(() => [...document.querySelectorAll('#chiaro-debug-images canvas')].map((c) => {
      const data = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      const values = new Set();
      for (let i = 0; i < data.length; i += 4 * 7) values.add(data[i]);
      return { width: c.width, height: c.height, distinct: values.size };
    }));
    assert.equal(shown.length, count, `${label}: ${JSON.stringify(shown)}`);
    assert.ok(shown.every((image) => image.distinct > 4), `${label} shows a flat image: ${JSON.stringify(shown)}`);
    assert.ok(await page.locator('#chiaro-canvas').isHidden(), `${label}: the 3D view is still shown`);
  }
  await afterFrame(page, () => page.selectOption('#chiaro-debug', 'none'));
  assert.ok(await page.locator('#chiaro-canvas').isVisible(), 'the 3D view is back');
  // Settings: an invalid value is refused with its key, a valid one applies.
  await page.fill('#chiaro-settings', '[render]\nexposure_ev100 = "bright"\n');
  await page.click('#chiaro-apply');
  assert.match(await page.locator('#chiaro-settings-error').textContent(), /exposure_ev100/);
  await page.fill('#chiaro-settings', '[render]\nexposure_ev100 = 14.0\n');
  await afterFrame(page, () => page.click('#chiaro-apply'));
  assert.equal(await page.locator('#chiaro-settings-error').textContent(), '');
  const darker = await difference(page, await canvasPng(page), plain);
  assert.ok(darker.mean > 5, `the exposure changed the image by only ${darker.mean}`);
  assert.deepEqual(errors, []);
  await page.close();
});

test('a light\'s shadows switch off and to PCSS from the panel', async () => {
  // The demo's sun (light 0) casts the shadows of every object on the floor.
  const { page, errors } = await openInteractive(`width=${WIDTH}&height=${HEIGHT}`);
  const soft = await canvasPng(page);
  const select = page.locator('#chiaro-lights select').first();
  assert.equal(await select.inputValue(), 'soft');
  await afterFrame(page, () => select.selectOption('none'));
  const unshadowed = await difference(page, soft, await canvasPng(page));
  // The same page draws the same frame bit for bit: any change is the setting's.
  assert.ok(unshadowed.mean > 0.3, `switching the shadow off changed too little: ${JSON.stringify(unshadowed)}`);
  await afterFrame(page, () => select.selectOption('pcss'));
  // The sun's disc (0.53 degrees by default) widened to 5: penumbrae wide enough to see.
  const size = page.locator('#chiaro-lights input').first();
  assert.equal(await size.inputValue(), '0.53');
  await afterFrame(page, async () => {
    await size.fill('5');
    await size.press('Enter');
    await size.blur();
  });
  const pcss = await difference(page, soft, await canvasPng(page));
  assert.ok(pcss.mean > 0.05 && pcss.mean < unshadowed.mean, `pcss against soft: ${JSON.stringify(pcss)}`);
  // Back to soft: the first picture again, bit for bit (so the changes above are the
  // settings', not noise).
  await afterFrame(page, () => select.selectOption('soft'));
  const again = await difference(page, soft, await canvasPng(page));
  assert.equal(again.max, 0, `soft again differs: ${JSON.stringify(again)}`);
  assert.deepEqual(errors, []);
  await page.close();
});
