// The browser tests' harness: Debian's Chromium driven headless by playwright-core, the static
// server on a free 127.0.0.1 port, every page error and console error recorded (a test fails on
// any), the viewer's canvas captured as PNG and decoded, and picture measures (masks, IoU,
// holes inside a silhouette).
import { existsSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { PNG } from 'pngjs';
import { serve, DIST } from '../scripts/serve.js';

/** The repository's root: the three.js test pages are served from it (js/src, js/dist, js/node_modules). */
export const REPO = fileURLToPath(new URL('../../', import.meta.url));

export const CHROMIUM = process.env.CHROMIUM ?? '/usr/bin/chromium';

/** Flags that give headless Chromium a WebGPU adapter (SwiftShader) and a capturable canvas. */
export const WEBGPU_FLAGS = [
  '--enable-unsafe-webgpu',
  '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader',
  '--ignore-gpu-blocklist',
  '--enable-gpu',
  '--enable-features=Vulkan',
  '--use-vulkan=swiftshader',
];
/** The same without WebGPU: `requestAdapter()` gives null, WebGL2 still works (SwiftShader GL). */
export const NO_WEBGPU_FLAGS = WEBGPU_FLAGS.filter((f) => f !== '--enable-unsafe-webgpu');

/** Starts the server and a browser; `close()` stops both. */
export async function start({ webgpu = true } = {}) {
  if (!existsSync(`${DIST}/index.html`)) throw new Error(`${DIST} has no index.html: run \`npm run build\` first`);
  return launch(DIST, webgpu);
}

/** Serves `root` and starts Chromium (with WebGPU when `webgpu`); `close()` stops both. */
async function launch(root, webgpu) {
  if (!existsSync(CHROMIUM)) throw new Error(`${CHROMIUM} is missing: apt-get install -y chromium (or set CHROMIUM)`);
  const server = await serve({ root, port: 0 });
  let browser;
  try {
    browser = await chromium.launch({ executablePath: CHROMIUM, args: webgpu ? WEBGPU_FLAGS : NO_WEBGPU_FLAGS });
  } catch (e) {
    await server.close();
    throw e;
  }
  return {
    url: server.url,
    browser,
    async close() {
      await browser.close();
      await server.close();
    },
  };
}

/**
 * Opens the viewer at `query` (e.g. '?mesh=samples/icosphere.obj&size=320x240') and waits for
 * `viewer.ready`. `page.problems` collects uncaught page errors and console errors.
 */
export async function open(env, query = '', { waitReady = true } = {}) {
  const page = await env.browser.newPage();
  page.problems = watch(page);
  await page.goto(env.url + query);
  if (waitReady) await ready(page);
  return page;
}

/**
 * Records the page's uncaught errors and console errors (and console warnings when `warnings`)
 * in the array it returns.
 */
export function watch(page, { warnings = false } = {}) {
  const problems = [];
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  page.on('console', (m) => {
    if (m.type() === 'error' || (warnings && m.type() === 'warning')) problems.push(`console ${m.type()}: ${m.text()}`);
  });
  return problems;
}

/**
 * Serves the repository's root (not dist/) and starts a browser (WebGL2 only unless `webgpu`),
 * once the files the three.js pages load are there: the wasm, three (three.webgpu.js when
 * `webgpu`) and `needs` (paths from the root). `close()` stops both.
 */
export async function startRepo({ webgpu = false, needs = [] } = {}) {
  const three = webgpu ? 'js/node_modules/three/build/three.webgpu.js' : 'js/node_modules/three/build/three.module.js';
  for (const need of ['js/dist/simd/tessella_bg.wasm', three, ...needs]) {
    if (!existsSync(REPO + need)) throw new Error(`${need} is missing: run \`cd js && npm ci && npm run build\` first`);
  }
  return launch(REPO, webgpu);
}

/**
 * Opens the repository's test page at `path` (e.g. 'web/test/three/index.html?page=mesh') and waits for its
 * `window[global].ready`, whose value is `ready`. `problems` records page errors and console
 * errors and warnings. `run(config)` returns `window[global].run(config)` with its picture
 * decoded as `img` (`{ width, height, data }`): from a PNG data URL (`png`) or from RGBA bytes
 * in base64 (`rgba`, with `width` and `height`).
 */
export async function openRepoPage(path, { webgpu = false, global, needs = [] } = {}) {
  const env = await startRepo({ webgpu, needs });
  try {
    const page = await env.browser.newPage();
    const problems = watch(page, { warnings: true });
    await page.goto(`${env.url}/${path}`);
    await page.waitForFunction((g) => window[g] !== undefined, global);
    const value = await page.evaluate((g) => window[g].ready, global);
    return {
      page,
      problems,
      ready: value,
      async run(config) {
        const out = await page.evaluate(([g, c]) => window[g].run(c), [global, config]);
        out.img = out.png !== undefined
          ? PNG.sync.read(Buffer.from(out.png.split(',')[1], 'base64'))
          : { width: out.width, height: out.height, data: Buffer.from(out.rgba, 'base64') };
        return out;
      },
      close: env.close,
    };
  } catch (e) {
    await env.close();
    throw e;
  }
}

export async function ready(page) {
  await page.waitForFunction(() => window.viewer !== undefined && window.viewer.ready !== undefined);
  await page.evaluate(() => window.viewer.ready);
}

/** The viewer's canvas as `{ width, height, data }` (RGBA bytes) through `viewer.capture()`. */
export async function capture(page) {
  const bytes = await page.evaluate(async () => Array.from(await window.viewer.capture()));
  return PNG.sync.read(Buffer.from(bytes));
}

export function readPng(buffer) {
  return PNG.sync.read(buffer);
}

/** The text of the page's message line ('' when hidden). */
export async function message(page) {
  return page.evaluate(() => {
    const m = document.getElementById('message');
    return m.hidden ? '' : m.textContent;
  });
}

/** Pixels that are not the white background (any channel below 255 - `tolerance`). */
export function mask(img, tolerance = 12) {
  const m = new Uint8Array(img.width * img.height);
  for (let i = 0; i < m.length; i++) {
    const [r, g, b] = [img.data[4 * i], img.data[4 * i + 1], img.data[4 * i + 2]];
    m[i] = r < 255 - tolerance || g < 255 - tolerance || b < 255 - tolerance ? 1 : 0;
  }
  return m;
}

export function count(m) {
  let n = 0;
  for (const v of m) n += v;
  return n;
}

/** Intersection over union of two masks of one size. */
export function iou(a, b) {
  let inter = 0;
  let union = 0;
  for (let i = 0; i < a.length; i++) {
    inter += a[i] & b[i];
    union += a[i] | b[i];
  }
  return union === 0 ? 1 : inter / union;
}

/** Background pixels not reachable from the picture's border: holes (cracks) in a silhouette. */
export function holes(m, width, height) {
  const outside = new Uint8Array(m.length);
  const stack = [];
  const push = (x, y) => {
    const i = y * width + x;
    if (m[i] === 0 && outside[i] === 0) {
      outside[i] = 1;
      stack.push(i);
    }
  };
  for (let x = 0; x < width; x++) {
    push(x, 0);
    push(x, height - 1);
  }
  for (let y = 0; y < height; y++) {
    push(0, y);
    push(width - 1, y);
  }
  while (stack.length > 0) {
    const i = stack.pop();
    const x = i % width;
    const y = (i - x) / width;
    if (x > 0) push(x - 1, y);
    if (x < width - 1) push(x + 1, y);
    if (y > 0) push(x, y - 1);
    if (y < height - 1) push(x, y + 1);
  }
  let n = 0;
  for (let i = 0; i < m.length; i++) if (m[i] === 0 && outside[i] === 0) n++;
  return n;
}

/** Pixels whose colour differs by more than `threshold` in any channel. */
export function differing(a, b, threshold) {
  let n = 0;
  for (let i = 0; i < a.width * a.height; i++) {
    for (let k = 0; k < 3; k++) {
      if (Math.abs(a.data[4 * i + k] - b.data[4 * i + k]) > threshold) {
        n++;
        break;
      }
    }
  }
  return n;
}

/** Pixels at least `by` darker (sum of RGB) in `a` than in `b`, as a mask. */
export function darker(a, b, by = 30) {
  const m = new Uint8Array(a.width * a.height);
  for (let i = 0; i < m.length; i++) {
    const sa = a.data[4 * i] + a.data[4 * i + 1] + a.data[4 * i + 2];
    const sb = b.data[4 * i] + b.data[4 * i + 1] + b.data[4 * i + 2];
    m[i] = sa + by < sb ? 1 : 0;
  }
  return m;
}

/** Fails with every problem the page recorded. */
export function assertClean(assert, page) {
  assert.deepEqual(page.problems, [], 'the page reported errors');
}

/**
 * Background pixels of `img` whose 8 neighbours in `inside` (another picture's silhouette) are
 * all covered: holes in the surface where the other picture has none.
 */
export function gapsInside(img, inside) {
  const m = mask(img);
  const { width, height } = img;
  let n = 0;
  for (let y = 1; y < height - 1; y++) {
    for (let x = 1; x < width - 1; x++) {
      if (m[y * width + x]) continue;
      let all = true;
      for (let dy = -1; dy <= 1 && all; dy++) for (let dx = -1; dx <= 1; dx++) if (!inside[(y + dy) * width + x + dx]) all = false;
      if (all) n++;
    }
  }
  return n;
}
