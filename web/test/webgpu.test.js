// The page on the WebGPU engine (headless Chromium's SwiftShader adapter): screen-space LOD while
// the camera flies in (uploads O(coarse triangles) per frame, no crack), tags, displacement,
// animation, dragging a vertex, panels, GLB export, broken files. Needs dist/pkg (the engine);
// TESSELLA_WEB_NO_ENGINE=1 skips the suite with that reason.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync } from 'node:fs';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { DIST } from '../scripts/serve.js';
import { assertClean, capture, count, holes, iou, mask, message, open, start } from './harness.js';

const repo = fileURLToPath(new URL('../../', import.meta.url));
const skip = process.env.TESSELLA_WEB_NO_ENGINE === '1' ? 'TESSELLA_WEB_NO_ENGINE=1: the site was built without the engine' : false;

/**
 * An open, curved sheet (a height field) of triangles of very different sizes: screen-space LOD
 * gives its edges different levels, and seen from above nothing hides anything, so a background
 * pixel inside its outline is a crack.
 */
export function sheetObj(n = 8) {
  const lines = [];
  const xs = Array.from({ length: n + 1 }, (_, i) => -1 + 2 * (i / n) ** 1.6);
  for (const z of xs) for (const x of xs) lines.push(`v ${x} ${0.25 * Math.sin(2 * x) * Math.cos(2 * z)} ${z}`);
  const id = (i, j) => i * (n + 1) + j + 1;
  for (let i = 0; i < n; i++) {
    for (let j = 0; j < n; j++) {
      lines.push(`f ${id(i, j)} ${id(i + 1, j)} ${id(i + 1, j + 1)}`);
      lines.push(`f ${id(i, j)} ${id(i + 1, j + 1)} ${id(i, j + 1)}`);
    }
  }
  return Buffer.from(lines.join('\n') + '\n');
}

function differs(a, b) {
  return Buffer.compare(a.data, b.data) !== 0;
}

describe('the WebGPU engine in the page', { skip }, () => {
  let env;
  before(async () => {
    if (!existsSync(join(DIST, 'pkg', 'tessella_viewer.js'))) throw new Error('dist/pkg has no engine: npm run build (or TESSELLA_WEB_NO_ENGINE=1)');
    env = await start({ webgpu: true });
  });
  after(async () => env?.close());

  test('WebGPU is used, says so, and draws', async () => {
    const page = await open(env, '?mesh=samples/creature.obj&size=320x240');
    assert.equal(await page.evaluate(() => window.viewer.backend), 'webgpu');
    assert.equal(await page.locator('#banner').isHidden(), true);
    const s = await page.evaluate(() => window.viewer.stats());
    assert.equal(s.backend, 'webgpu');
    // Named, even where the browser keeps the adapter's description to itself.
    assert.match(s.adapter, /^\S.* \(BrowserWebGpu/);
    assert.match(await page.locator('#adapter').textContent(), /: \S/);
    assert.ok(s.patternBytes > 0 && s.staticBytes > s.patternBytes, JSON.stringify(s));
    const m = mask(await capture(page));
    assert.ok(count(m) > 0.1 * m.length);
    assertClean(assert, page);
    await page.close();
  });

  test('flying in with lod=screen: levels follow the camera, < 128 uploaded bytes per coarse triangle, no crack', async () => {
    const page = await open(env, '?size=320x240&pitch=70&yaw=10', { waitReady: true });
    await page.setInputFiles('#file', { name: 'sheet.obj', mimeType: 'text/plain', buffer: sheetObj() });
    await page.waitForFunction(() => window.viewer.get().mesh === 'sheet.obj');
    await page.evaluate(() => window.viewer.set({ scheme: 'pn', lod: 'screen:6' }));
    const coarse = (await page.evaluate(() => window.viewer.stats())).coarseTriangles;
    const levels = [];
    for (const zoom of [0.8, 1, 1.3, 1.7, 2.2, 2.9]) {
      await page.evaluate((z) => window.viewer.set({ zoom: z }), zoom);
      const img = await capture(page);
      const s = await page.evaluate(() => window.viewer.stats());
      levels.push(s.level);
      assert.ok(s.uploadedBytes < 128 * coarse, `zoom ${zoom}: ${s.uploadedBytes} bytes for ${coarse} coarse triangles`);
      const m = mask(img);
      assert.ok(count(m) > 0.05 * m.length, `zoom ${zoom}: nearly blank`);
      assert.equal(holes(m, img.width, img.height), 0, `zoom ${zoom}: background pixels inside the sheet (a crack)`);
    }
    assert.ok(levels.at(-1) > levels[0], `levels did not follow the camera: ${levels}`);
    assertClean(assert, page);
    await page.close();
  });

  test('tags, displacement, animation, a dragged vertex and panels change the picture', async () => {
    const p2 = await open(env, '?mesh=samples/creature.obj&size=320x240&scheme=st');
    const before = await capture(p2);
    const hit = await p2.evaluate(() => window.viewer.pick(160, 120));
    assert.ok(hit && Number.isInteger(hit.vertex) && hit.edge.length === 2, JSON.stringify(hit));
    const json = await p2.evaluate((h) => {
      window.viewer.setEdgeSharpness(h.edge[0], h.edge[1], 1);
      window.viewer.setVertexTension(h.vertex, 0.8, 0.3);
      return window.viewer.tagsJson();
    }, hit);
    const tags = JSON.parse(json);
    assert.deepEqual(tags.edges.map((e) => [...e.vertices].sort((x, y) => x - y)), [[...hit.edge].sort((x, y) => x - y)]);
    assert.equal(tags.vertices[0].index, hit.vertex);
    const afterTags = await capture(p2);
    assert.ok(differs(before, afterTags), 'tags did not change the picture');

    await p2.evaluate(() => window.viewer.set({ tags: '', displace: 'sine:0.05,12' }));
    const bumpy = await capture(p2);
    assert.ok(differs(before, bumpy));
    assert.ok(iou(mask(before), mask(bumpy)) > 0.8);

    await p2.evaluate(() => window.viewer.set({ displace: 'none', animate: 'twist' }));
    const t1 = await capture(p2);
    await p2.waitForTimeout(400);
    const t2 = await capture(p2);
    assert.ok(differs(t1, t2), 'the twist did not move');
    await p2.evaluate(() => window.viewer.set({ animate: 'none' }));

    await p2.evaluate((v) => window.viewer.moveVertex(v, 0, 3, 0), hit.vertex);
    const moved = await capture(p2);
    assert.ok(count(mask(moved)) !== count(mask(before)), 'moving a vertex did not change the silhouette');

    await p2.evaluate(() => window.viewer.set({ panels: ['flat', 'phong', 'pn', 'png1'] }));
    const panels = await capture(p2);
    for (let k = 0; k < 4; k++) {
      let n = 0;
      for (let y = 0; y < 240; y++) for (let x = (k * 320) / 4 + 2; x < ((k + 1) * 320) / 4 - 2; x++) n += panels.data[4 * (y * 320 + x)] < 240 ? 1 : 0;
      assert.ok(n > 200, `panel ${k} is blank`);
    }
    assertClean(assert, p2);
    await p2.close();
  });

  test('GLB export reads back; a broken file keeps the previous mesh drawn', async () => {
    const page = await open(env, '?mesh=samples/icosphere.obj&size=200x160&level=4');
    const glb = await page.evaluate(() => Array.from(window.viewer.exportGlb().slice(0, 4)));
    assert.equal(Buffer.from(glb).toString('latin1'), 'glTF');
    const s = await page.evaluate(() => window.viewer.stats());
    const before = await capture(page);
    await page.setInputFiles('#file', join(repo, 'tests/corpus/bad/obj-nan-position.obj'));
    await page.waitForFunction(() => !document.getElementById('message').hidden);
    assert.match(await message(page), /previous mesh stays/);
    assert.ok(!differs(before, await capture(page)));
    assert.equal((await page.evaluate(() => window.viewer.stats())).coarseTriangles, s.coarseTriangles);
    // More than the device holds: refused with the reason, the previous surface still drawn.
    const err = await page.evaluate(() => window.viewer.set({ level: 4000 }).then(() => null, (e) => e.message));
    console.log(`# level 4000 on WebGPU: ${err}`);
    assert.match(err ?? '', /level 4000 is more than this device can draw/);
    assert.match(await message(page), /level 4000 is more than this device can draw/);
    assert.equal(await page.evaluate(() => window.viewer.get().level), 4);
    assert.ok(!differs(before, await capture(page)), 'a refused level changed the picture');
    assert.deepEqual(page.problems, []);
    await page.close();
  });
});
