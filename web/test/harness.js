// The browser tests' harness: Debian's Chromium driven headless by playwright-core, the static
// server on a free 127.0.0.1 port, every page error and console error recorded (a test fails on
// any), the viewer's canvas captured as PNG and decoded, and picture measures (masks, IoU,
// holes inside a silhouette).
import { existsSync } from 'node:fs';
import { chromium } from 'playwright-core';
import { PNG } from 'pngjs';
import { serve, DIST } from '../scripts/serve.js';

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
  if (!existsSync(CHROMIUM)) throw new Error(`${CHROMIUM} is missing: apt-get install -y chromium (or set CHROMIUM)`);
  const server = await serve({ root: DIST, port: 0 });
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
  page.problems = [];
  page.on('pageerror', (e) => page.problems.push(`page error: ${e.message}`));
  page.on('console', (m) => {
    if (m.type() === 'error') page.problems.push(`console error: ${m.text()}`);
  });
  await page.goto(env.url + query);
  if (waitReady) await ready(page);
  return page;
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

/** Fails with every problem the page recorded. */
export function assertClean(assert, page) {
  assert.deepEqual(page.problems, [], 'the page reported errors');
}
