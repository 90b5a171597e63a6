// Draws the README's before/after picture of a glTF scene with three.js: the coarse file and
// `tessella refine`'s scene output (nodes, materials, textures kept) side by side, each loaded by
// three's GLTFLoader and drawn by WebGLRenderer in headless Chromium (WebGL2 on SwiftShader),
// labelled with the CLI's triangle counts. The page is web/test/three/index.html?page=gltf
// (three/gltf.js), served from the repository with three from js/node_modules.
//
//   node scripts/scene-picture.js [--input samples/scene.glb] [--level 6]
//       [--out docs/images/scene-before-after.png] [--size 600x400]   (one panel's size)
//       [--eye X,Y,Z] [--target X,Y,Z] [--fov DEG]                     (the camera of both panels)
//
// The CLI is target/debug/tessella (`cargo build -p tessella-cli`; TESSELLA_CLI names another).
import { spawnSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, renameSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { PNG } from 'pngjs';
import { serve } from './serve.js';
import { CHROMIUM, NO_WEBGPU_FLAGS } from '../test/harness.js';

const args = process.argv.slice(2);
const option = (name, fallback) => {
  const at = args.indexOf(`--${name}`);
  return at >= 0 ? args[at + 1] : fallback;
};
const root = fileURLToPath(new URL('../../', import.meta.url));
const input = resolve(root, option('input', 'samples/scene.glb'));
const level = Number(option('level', '6'));
const out = resolve(root, option('out', 'docs/images/scene-before-after.png'));
const [width, height] = option('size', '600x400').split('x').map(Number);
const vector = (name, fallback) => option(name, fallback).split(',').map(Number);
const view = { eye: vector('eye', '-2.6,1.6,4.4'), target: vector('target', '-0.15,0.05,0'), fov: Number(option('fov', '35')) };
const cli = process.env.TESSELLA_CLI ?? join(root, 'target', 'debug', 'tessella');
if (!existsSync(cli)) throw new Error(`${cli} is missing: run \`cargo build -p tessella-cli\` first`);
const three = join(root, 'js', 'node_modules', 'three', 'build', 'three.module.js');
if (!existsSync(three)) throw new Error('js/node_modules/three is missing: run `cd js && npm ci` first');

const work = mkdtempSync(join(tmpdir(), 'tessella-picture-'));
const server = await serve({ root, port: 0 });
const browser = await chromium.launch({ executablePath: CHROMIUM, args: NO_WEBGPU_FLAGS });
let failed = false;
try {
  const refined = join(work, 'refined.glb');
  // "samples/scene.glb -> refined.glb: 898 triangles -> 16331 vertices, 32328 triangles (pn, level 6, ...)"
  const run = spawnSync(cli, ['refine', input, '-o', refined, '--level', String(level)], { encoding: 'utf8' });
  if (run.status !== 0) throw new Error(`tessella refine failed: ${run.stderr}`);
  const said = run.stdout + run.stderr; // the summary line goes to stderr
  const m = /: (\d+) triangles -> \d+ vertices, (\d+) triangles/.exec(said);
  if (!m) throw new Error(`no triangle counts in the CLI's output: ${said}`);
  const [coarseTriangles, refinedTriangles] = [Number(m[1]), Number(m[2])];
  const page = await browser.newPage();
  const problems = [];
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  page.on('console', (msg) => {
    if (msg.type() === 'error' || msg.type() === 'warning') problems.push(`console ${msg.type()}: ${msg.text()}`);
  });
  await page.goto(`${server.url}web/test/three/index.html?page=gltf`);
  await page.waitForFunction(() => window.tessellaGltf !== undefined);
  const thousands = (n) => n.toLocaleString('en-US');
  const panels = [
    { glb: readFileSync(input).toString('base64'), label: `coarse (${thousands(coarseTriangles)} triangles)` },
    { glb: readFileSync(refined).toString('base64'), label: `refined, level ${level} (${thousands(refinedTriangles)} triangles)` },
  ];
  const result = await page.evaluate((c) => window.tessellaGltf.picture(c), { panels, width, height, ...view });
  if (problems.length > 0) throw new Error(problems.join('\n'));
  const png = Buffer.from(result.png.split(',')[1], 'base64');
  // Not blank: each panel has drawn (not white) pixels.
  const img = PNG.sync.read(png);
  for (let k = 0; k < panels.length; k++) {
    let drawn = 0;
    for (let y = 0; y < height; y++) {
      for (let x = k * width; x < (k + 1) * width; x++) {
        const i = 4 * (y * img.width + x);
        if (img.data[i] < 240 || img.data[i + 1] < 240 || img.data[i + 2] < 240) drawn++;
      }
    }
    if (drawn < 0.05 * width * height) throw new Error(`panel ${k} is nearly blank (${drawn} pixels drawn)`);
    console.log(`${panels[k].label}: ${drawn} pixels drawn (${result.panels[k].triangles} triangles drawn, instances included)`);
  }
  writeFileSync(`${out}.tmp`, png);
  renameSync(`${out}.tmp`, out);
  console.log(`wrote ${out} (${img.width} x ${img.height})`);
} catch (e) {
  console.error(`the picture failed: ${e instanceof Error ? e.message : String(e)}`);
  failed = true;
} finally {
  await browser.close();
  await server.close();
  rmSync(work, { recursive: true, force: true });
}
process.exit(failed ? 1 : 0);
