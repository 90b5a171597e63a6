// tessella/three's example pages (js/examples) in headless Chromium (WebGL2 on SwiftShader):
// each loads, draws its scene (not a blank canvas), and reports no error. Build js/ first
// (`cd js && npm ci && npm run build`). TESSELLA_EXAMPLES_SHOTS=DIR saves each picture there.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync, writeFileSync } from 'node:fs';
import { PNG } from 'pngjs';
import { differing, startRepo, watch } from './harness.js';

const SHOTS = process.env.TESSELLA_EXAMPLES_SHOTS;
const PAGES = ['gltf', 'skinned', 'lod', 'compare'];

let env;
before(async () => {
  env = await startRepo({ needs: ['js/node_modules/three-subdivide/src/index.js'] });
});
after(() => env?.close());

for (const name of PAGES) {
  test(`the ${name} example draws its scene without an error`, async () => {
    const page = await env.browser.newPage({ viewport: { width: 800, height: 500 } });
    const problems = watch(page);
    await page.goto(`${env.url}js/examples/${name}.html`);
    await page.waitForFunction(() => window.example !== undefined);
    await page.evaluate(() => window.example.then(() => true));
    assert.deepEqual(problems, []);
    // Held still, the picture with and without the TessellatedMeshes: they draw the surfaces.
    await page.evaluate(() => window.example.then((e) => e.pause()));
    const shot = await page.screenshot();
    await page.evaluate(() => window.example.then((e) => e.showTessellated(false)));
    const without = PNG.sync.read(await page.screenshot());
    const img = PNG.sync.read(shot);
    // Pixels whose colour differs by more than 24 in a channel.
    const drawn = differing(img, without, 24);
    console.log(`${name}: the TessellatedMeshes draw ${drawn} pixels`);
    if (SHOTS) {
      mkdirSync(SHOTS, { recursive: true });
      writeFileSync(`${SHOTS}/${name}.png`, shot);
    }
    assert.ok(drawn > 0.01 * img.width * img.height, `${name}: only ${drawn} pixels drawn by TessellatedMeshes`);
    assert.deepEqual(problems, []);
    await page.close();
  });
}

test('the benchmark page (npm run bench:three) measures the nine ways; the tessellated ones upload less, per-draw holds less, the animated creatures agree', async () => {
  const page = await env.browser.newPage();
  const problems = [];
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  await page.goto(`${env.url}js/bench/three/page.html`);
  await page.waitForFunction(() => window.benchThree !== undefined);
  await page.evaluate(() => window.benchThree.ready);
  const { rows, agreement } = await page.evaluate(() => window.benchThree.run({ levels: [8], frames: 1, size: 128, animated: true }));
  const by = Object.fromEntries(rows.map((r) => [r.way, r]));
  assert.deepEqual(Object.keys(by).sort(), [
    'animated, refined offline', 'animated, tessellated (CPU posing)', 'animated, tessellated (GPU posing)',
    'deforming refined', 'deforming tessellated (per-draw)', 'deforming tessellated (per-frame)',
    'static refined', 'static tessellated (per-draw)', 'static tessellated (per-frame)',
  ]);
  // The creature refined offline and tessellated, playing the same clip: the same silhouette;
  // posed on the CPU the tessellated one uploads its nets (192 bytes a coarse triangle), on the
  // GPU its 7 joint matrices and a texel of morph weights (7 × 64 + 16), the offline one its bones.
  assert.ok(agreement[8] >= 0.98, `animated silhouettes IoU ${agreement[8]}`);
  const tessellated = by['animated, tessellated (CPU posing)'];
  assert.equal(tessellated.uploaded, tessellated.triangles * 192);
  assert.equal(by['animated, tessellated (GPU posing)'].uploaded, 7 * 64 + 16);
  assert.ok(by['animated, refined offline'].uploaded > 0);
  assert.equal(by['animated, refined offline'].drawn, tessellated.triangles * 64);
  for (const r of rows) assert.ok(r.ms > 0 && r.allocated > 0, JSON.stringify(r));
  // The nets (12 RGBA32F texels a triangle) against every refined vertex's position and normal.
  for (const mode of ['per-draw', 'per-frame']) {
    assert.equal(by[`deforming tessellated (${mode})`].uploaded, by[`deforming tessellated (${mode})`].triangles * 192);
    assert.equal(by[`static tessellated (${mode})`].uploaded, 0);
  }
  assert.ok(by['deforming refined'].uploaded >= 24 * (by['deforming refined'].drawn / 2), JSON.stringify(by['deforming refined']));
  assert.ok(by['static tessellated (per-draw)'].allocated < by['static refined'].allocated / 4);
  // per-frame holds the refined vertices (baked): more than the refined Mesh's position and normal.
  assert.ok(by['static tessellated (per-frame)'].allocated > by['static refined'].allocated / 2);
  assert.deepEqual(problems, []);
  await page.close();
});
