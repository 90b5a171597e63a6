// Runs tessella/three's benchmark page (js/bench/three/page.html) in headless Chromium (WebGL2 on
// SwiftShader here) and prints its table: frame time, GPU memory and bytes uploaded per frame of
// TessellatedMesh against a static refineGeometry Mesh and RefinedGeometry.update(), at levels
// 4, 8, 16 and 32 (static and deforming, per-draw and per-frame, a shadow-casting light), and an
// animated character (samples/animated-creature.glb playing its `wave` clip) refined offline by
// refineGltf against its SkinnedMesh tessellated, in the same frames. `--json FILE` also writes
// the rows; `--frames N`, `--levels 8,16`; `--no-animated` leaves the character out.
import { renameSync, writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { serve } from './serve.js';
import { CHROMIUM, NO_WEBGPU_FLAGS } from '../test/harness.js';

const args = process.argv.slice(2);
const option = (name) => {
  const at = args.indexOf(`--${name}`);
  return at >= 0 ? args[at + 1] : undefined;
};
const config = {};
if (option('frames') !== undefined) config.frames = Number(option('frames'));
if (option('levels') !== undefined) config.levels = option('levels').split(',').map(Number);
config.animated = !args.includes('--no-animated');
const json = option('json');

const root = fileURLToPath(new URL('../../', import.meta.url));
const server = await serve({ root, port: 0 });
const browser = await chromium.launch({ executablePath: CHROMIUM, args: NO_WEBGPU_FLAGS });
let failed = false;
try {
  const page = await browser.newPage();
  page.on('pageerror', (e) => console.error(`page error: ${e.message}`));
  await page.goto(`${server.url}js/bench/three/page.html`);
  await page.waitForFunction(() => window.benchThree !== undefined);
  await page.evaluate(() => window.benchThree.ready);
  const report = await page.evaluate((c) => window.benchThree.run(c), config);
  console.log(report.markdown);
  if (json) {
    writeFileSync(`${json}.tmp`, JSON.stringify(report.rows, null, 1) + '\n');
    renameSync(`${json}.tmp`, json);
  }
} catch (e) {
  console.error(`the benchmark failed: ${e instanceof Error ? e.message : String(e)}`);
  failed = true;
} finally {
  await browser.close();
  await server.close();
}
process.exit(failed ? 1 : 0);
