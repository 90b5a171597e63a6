// The page in Chromium with WebGPU switched off (no --enable-unsafe-webgpu): the WebGL2
// fallback draws, says so, loads by URL and by file picker, refuses broken files with the
// reader's message while the previous mesh stays drawn, and refuses bad parameters.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { assertClean, capture, count, differing, holes, iou, mask, message, open, start } from './harness.js';

const noEngine = process.env.TESSELLA_WEB_NO_ENGINE === '1' ? 'TESSELLA_WEB_NO_ENGINE=1: the site was built without the engine, whose coarse side the fallback draws tags with' : false;

const repo = fileURLToPath(new URL('../../', import.meta.url));
const corpus = `${repo}tests/corpus/`;
const expected = JSON.parse(readFileSync(`${corpus}expected.json`, 'utf8'));

let env;
before(async () => {
  env = await start({ webgpu: false });
});
after(async () => {
  await env?.close();
});

test('without WebGPU the fallback draws the mesh given by URL and says which path it uses', async () => {
  const page = await open(env, '?mesh=samples/icosphere.obj&size=320x240&level=8');
  assert.equal(await page.evaluate(() => window.viewer.backend), 'webgl2');
  const banner = await page.locator('#banner').textContent();
  assert.match(banner, /WebGL2 fallback/);
  assert.match(await page.locator('#backend').textContent(), /WebGL2/);
  const img = await capture(page);
  assert.deepEqual([img.width, img.height], [320, 240]);
  const m = mask(img);
  // The icosphere fills a good part of the view and is one solid blob.
  assert.ok(count(m) > 0.15 * m.length, `only ${count(m)} of ${m.length} pixels are drawn`);
  assert.equal(holes(m, img.width, img.height), 0);
  const s = await page.evaluate(() => window.viewer.stats());
  assert.equal(s.backend, 'webgl2');
  assert.equal(s.refinedTriangles, s.coarseTriangles * 64);
  assertClean(assert, page);
  await page.close();
});

test('a file from the picker replaces the mesh; scheme, level and wireframe change the picture', async () => {
  const page = await open(env, '?mesh=samples/icosphere.obj&size=320x240&level=4&scheme=flat');
  const flat = mask(await capture(page));
  const coarse = (await page.evaluate(() => window.viewer.stats())).coarseTriangles;
  await page.evaluate(() => window.viewer.set({ scheme: 'pn' }));
  const pn = mask(await capture(page));
  // PN rounds the silhouette: more pixels covered, the shapes close but not equal.
  assert.ok(count(pn) > count(flat), `pn ${count(pn)} vs flat ${count(flat)}`);
  assert.ok(iou(pn, flat) > 0.9 && iou(pn, flat) < 0.995, `IoU ${iou(pn, flat)}`);
  await page.evaluate(() => window.viewer.set({ level: 7 }));
  assert.equal((await page.evaluate(() => window.viewer.stats())).refinedTriangles, coarse * 49);
  const plain = await capture(page);
  await page.evaluate(() => window.viewer.set({ wireframe: true }));
  const wire = await capture(page);
  // The wireframe darkens pixels inside the silhouette but leaves the silhouette alone.
  assert.ok(iou(mask(plain), mask(wire)) > 0.99);
  assert.ok(darkPixels(wire) > darkPixels(plain) + 500, `${darkPixels(wire)} vs ${darkPixels(plain)}`);

  await page.setInputFiles('#file', `${repo}samples/torus.obj`);
  await page.waitForFunction((n) => window.viewer.stats().coarseTriangles !== n, coarse);
  assert.equal(await page.evaluate(() => window.viewer.get().mesh), 'torus.obj');
  const torus = mask(await capture(page));
  // A torus has a hole in the middle at pitch 20: background inside its outline.
  assert.ok(holes(torus, 320, 240) > 100);
  assertClean(assert, page);
  await page.close();
});

test('every broken file of the corpus gives its message and the previous mesh stays drawn', async () => {
  const page = await open(env, '?mesh=samples/creature.obj&size=200x160&level=4');
  const before = await capture(page);
  for (const [name, text] of Object.entries(expected.bad)) {
    await page.setInputFiles('#file', `${corpus}bad/${name}`);
    await page.waitForFunction(() => !document.getElementById('message').hidden);
    const shown = await message(page);
    assert.ok(shown.includes(text), `${name}: the page says ${JSON.stringify(shown)}, expected ${JSON.stringify(text)}`);
    assert.match(shown, /previous mesh stays/);
    await page.evaluate(() => (document.getElementById('message').hidden = true));
  }
  const afterwards = await capture(page);
  assert.ok(Buffer.compare(before.data, afterwards.data) === 0, 'the picture changed after refused files');
  assert.equal(await page.evaluate(() => window.viewer.get().mesh), 'samples/creature.obj');
  assert.deepEqual(page.problems, []);
  await page.close();
});

test('the menus list params.js\'s names with their labels, and choosing one sets the parameter', async () => {
  const { ANIMATIONS, LABELS, NORMALS, SCHEMES, SPACINGS } = await import('../src/params.js');
  const page = await open(env, '?mesh=samples/icosphere.obj&size=200x160&level=4');
  for (const [name, want] of [['scheme', SCHEMES], ['normals', NORMALS], ['spacing', SPACINGS], ['animate', ANIMATIONS]]) {
    const shown = await page.locator(`select[name=${name}] option`).evaluateAll((os) => os.map((o) => [o.value, o.textContent]));
    assert.deepEqual(shown, want.map((v) => [v, LABELS[v] ?? v]), name);
  }
  assert.equal(await page.inputValue('select[name=scheme]'), 'pn');
  await page.selectOption('select[name=scheme]', 'png1');
  await page.waitForFunction(() => window.viewer.get().scheme === 'png1');
  assert.equal(await message(page), '');
  await page.close();
  assert.deepEqual(page.problems, []);
});

test('NaN typed into a field, bad URL values and what needs WebGPU: a message, nothing changes', async () => {
  const page = await open(env, '?mesh=samples/icosphere.obj&size=200x160&level=4&zoom=abc');
  assert.match(await message(page), /zoom must be a positive number/);
  assert.equal(await page.evaluate(() => window.viewer.get().zoom), 1);
  const before = await capture(page);
  await page.fill('input[name=alpha]', 'NaN');
  await page.dispatchEvent('input[name=alpha]', 'change');
  assert.match(await message(page), /alpha must be a number/);
  assert.equal(await page.inputValue('input[name=alpha]'), '0.75');
  for (const [params, text] of [
    [{ level: Number.NaN }, /level must be/],
    [{ lod: 'screen:-3' }, /lod must be/],
    [{ displace: 'sine:0.05,10' }, /displace needs the WebGPU engine/],
    // The instanced pattern's largest level (without the engine: the npm package's memory cap).
    [{ level: 4000 }, noEngine ? /over the limit of/ : /level: 4000 is over 256/],
    [{ animate: 'twist', lod: 'screen:6' }, noEngine ? /animate needs the WebGPU engine/ : /animate needs a whole level on the grid/],
    [{ level: 240 }, /more than the WebGL2 fallback draws/], // 4.6 M triangles: the fallback's own cap
  ]) {
    const err = await page.evaluate((p) => window.viewer.set(p).then(() => null, (e) => e.message), params);
    assert.match(err ?? '', text);
    assert.match(await message(page), text);
  }
  assert.equal(await page.evaluate(() => window.viewer.get().level), 4);
  const afterwards = await capture(page);
  assert.ok(Buffer.compare(before.data, afterwards.data) === 0, 'a refused value changed the picture');
  assertClean(assert, page);
  await page.close();
});

test('the state is in the URL: a copied link opens the same view', async () => {
  const page = await open(env, '?mesh=samples/torus.obj&size=200x160&level=4');
  await page.evaluate(() => window.viewer.set({ scheme: 'phong', alpha: 0.5, yaw: -40, wireframe: true }));
  const link = page.url();
  assert.match(link, /scheme=phong/);
  assert.match(link, /alpha=0.5/);
  assert.match(link, /yaw=-40/);
  const first = await capture(page);
  const again = await env.browser.newPage();
  again.problems = [];
  await again.goto(link);
  await again.evaluate(() => window.viewer.ready);
  const second = await capture(again);
  assert.ok(Buffer.compare(first.data, second.data) === 0, 'the link gave another picture');
  assertClean(assert, page);
  await page.close();
  await again.close();
});

test('instanced: tags, animation and a dragged vertex change the picture; tags as the WebGPU engine draws them', { skip: noEngine }, async () => {
  const query = '?mesh=samples/icosphere.obj&size=320x240&scheme=st';
  const page = await open(env, query);
  const s = await page.evaluate(() => window.viewer.stats());
  assert.equal(s.instanced, true, JSON.stringify(s));
  assert.equal(s.refinedTriangles, s.coarseTriangles * 64);
  const before = await capture(page);
  // Tension 1 on the first 12 vertices flattens the scalar-tagged patches around them.
  const tags = JSON.stringify({ edges: [], vertices: Array.from({ length: 12 }, (_, i) => ({ index: i, tension: 1 })) });
  await page.evaluate((t) => window.viewer.set({ tags: t }), tags);
  const tagged = await capture(page);
  const changed = differing(before, tagged, 8);
  assert.ok(changed > 1000, `tags changed ${changed} pixels`);
  // The engine with the same tags: the same picture.
  const gpu = await start({ webgpu: true });
  try {
    const engine = await open(gpu, query);
    assert.equal(await engine.evaluate(() => window.viewer.backend), 'webgpu');
    await engine.evaluate((t) => window.viewer.set({ tags: t }), tags);
    const reference = await capture(engine);
    // Both pick the same coarse vertex and edge at a pixel (the same ray cast).
    for (const [x, y] of [[160, 120], [130, 90], [200, 150]]) {
      const mine = await page.evaluate(([x, y]) => window.viewer.pick(x, y), [x, y]);
      const theirs = await engine.evaluate(([x, y]) => window.viewer.pick(x, y), [x, y]);
      assert.deepEqual(mine, theirs, `pick(${x}, ${y})`);
    }
    const overlap = iou(mask(tagged), mask(reference));
    const off = differing(tagged, reference, 48);
    console.log(`tagged icosphere, fallback vs engine: IoU ${overlap.toFixed(4)}, ${off} pixels differ by > 48/255; the tags changed ${changed} pixels by > 8/255`);
    assert.ok(overlap >= 0.98, `IoU ${overlap}`);
    assert.ok(off < 0.02 * count(mask(reference)) && off < changed / 4, `${off} pixels differ from the engine's`);
    assertClean(assert, engine);
    await engine.close();
  } finally {
    await gpu.close();
  }
  // The pointer's tag edits go to the same tags.
  const hit = await page.evaluate(() => window.viewer.pick(160, 120));
  assert.ok(hit && Number.isInteger(hit.vertex) && hit.edge.length === 2, JSON.stringify(hit));
  const json = await page.evaluate((h) => {
    window.viewer.setEdgeSharpness(h.edge[0], h.edge[1], 1);
    window.viewer.setVertexTension(h.vertex, -1, 0);
    return window.viewer.tagsJson();
  }, hit);
  assert.ok(JSON.parse(json).vertices.some((v) => v.index === hit.vertex && v.tension === -1), json);
  assert.equal(JSON.parse(json).edges.length, 1, json);
  const edited = await capture(page);
  assert.ok(differing(tagged, edited, 0) > 0, 'the edited tags did not change the picture');
  // A dragged vertex moves the surface: pulled up out of the unit sphere, a spike on top.
  await page.evaluate((v) => window.viewer.moveVertex(v, 0, 1.8, 0), hit.vertex);
  const dragged = await capture(page);
  assert.ok(differing(edited, dragged, 8) > 50, 'the dragged vertex did not move the picture');
  // The GLB export is the surface drawn: level 8, 64 triangles a coarse one, the vertex dragged.
  const glb = Buffer.from(await page.evaluate(() => Array.from(window.viewer.exportGlb())));
  assert.equal(glb.subarray(0, 4).toString('latin1'), 'glTF');
  const gltf = JSON.parse(glb.subarray(20, 20 + glb.readUInt32LE(12)).toString('utf8'));
  const primitive = gltf.meshes[0].primitives[0];
  assert.equal(gltf.accessors[primitive.indices].count, s.coarseTriangles * 64 * 3);
  assert.ok(gltf.accessors[primitive.attributes.POSITION].max[1] >= 1.8 - 1e-4, JSON.stringify(gltf.accessors[primitive.attributes.POSITION]));
  // Animation: the twist moves the picture, every frame sending the nets alone (≤ 256 B a triangle).
  await page.evaluate(() => window.viewer.set({ tags: '', animate: 'twist' }));
  const frames = [];
  for (let i = 0; i < 3; i++) {
    await page.waitForTimeout(300);
    frames.push(await capture(page));
    const u = (await page.evaluate(() => window.viewer.stats())).uploadedBytes;
    assert.ok(u > 0 && u <= 256 * s.coarseTriangles, `${u} bytes in an animated frame`);
  }
  assert.ok(differing(frames[0], frames[2], 8) > 50, 'the twist did not move');
  assertClean(assert, page);
  await page.close();
});

/** Pixels much darker than the lit surface: wireframe lines (and the unlit rim). */
function darkPixels(img) {
  let n = 0;
  for (let i = 0; i < img.width * img.height; i++) if (img.data[4 * i] + img.data[4 * i + 1] + img.data[4 * i + 2] < 150) n++;
  return n;
}
