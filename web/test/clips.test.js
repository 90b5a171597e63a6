// A glTF file's animation clips in the page (WebGPU engine, headless Chromium's SwiftShader):
// `?clip=wave&time=0.5` opens paused there with the clip menu, slider and stats showing it; a
// frame uploads the control nets alone (counted here from the file's triangle count, not from
// the engine); two times give two pictures; play and pause. The WebGL2 fallback plays them too
// (the engine's poses, its nets in a texture): the same picture as the engine at the same time,
// one instanced draw and at most 256 bytes handed to WebGL per coarse triangle per frame.
// Needs dist/pkg (the engine); TESSELLA_WEB_NO_ENGINE=1 skips the suite with that reason.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { DIST } from '../scripts/serve.js';
import { assertClean, capture, count, differing as differingBy, iou, mask, message, open, start, watch } from './harness.js';

const skip = process.env.TESSELLA_WEB_NO_ENGINE === '1' ? 'TESSELLA_WEB_NO_ENGINE=1: the site was built without the engine' : false;
const SAMPLE = 'samples/animated-creature.glb';

/** The triangle count of a GLB's meshes, read from its JSON chunk and accessors. */
function glbTriangles(bytes) {
  const jsonLength = bytes.readUInt32LE(12);
  const gltf = JSON.parse(bytes.subarray(20, 20 + jsonLength).toString('utf8'));
  let triangles = 0;
  for (const node of gltf.nodes ?? []) {
    if (node.mesh === undefined) continue;
    for (const primitive of gltf.meshes[node.mesh].primitives) triangles += gltf.accessors[primitive.indices].count / 3;
  }
  return triangles;
}

function differing(a, b) {
  let n = 0;
  for (let i = 0; i < a.data.length; i += 4) {
    if (Math.abs(a.data[i] - b.data[i]) > 8 || Math.abs(a.data[i + 1] - b.data[i + 1]) > 8 || Math.abs(a.data[i + 2] - b.data[i + 2]) > 8) n++;
  }
  return n;
}

describe('animation clips in the page', { skip }, () => {
  let env;
  before(async () => {
    if (!existsSync(join(DIST, 'pkg', 'tessella_viewer.js'))) throw new Error('dist/pkg has no engine: npm run build (or TESSELLA_WEB_NO_ENGINE=1)');
    env = await start({ webgpu: true });
  });
  after(async () => env?.close());

  test('a clip and time in the URL open paused there; a frame uploads the nets alone', async () => {
    const page = await open(env, `?mesh=${SAMPLE}&size=320x320&clip=wave&time=0.5`);
    const state = await page.evaluate(() => window.viewer.get());
    assert.equal(state.clip, 'wave');
    assert.equal(state.time, 0.5);
    assert.equal(state.playing, false);
    // The controls: the menu lists the file's clips, the slider stands at 0.5, play offered.
    assert.equal(await page.locator('#clip-row').isHidden(), false);
    const options = await page.locator('#clip option').evaluateAll((os) => os.map((o) => o.value));
    assert.deepEqual(options, ['none', 'wave', 'hop', 'breathe']);
    assert.equal(await page.locator('#clip').inputValue(), 'wave');
    assert.equal(Number(await page.locator('#clip-time').inputValue()), 0.5);
    assert.equal(await page.locator('#play').textContent(), 'play');
    assert.match(new URL(page.url()).search, /clip=wave/);
    assert.match(new URL(page.url()).search, /time=0\.5/);
    // The first frame posed the clip: PN's ten points and six normal-net entries of 12 bytes
    // for each of the file's triangles.
    const bytes = await (await fetch(`${env.url}${SAMPLE}`)).arrayBuffer();
    const triangles = glbTriangles(Buffer.from(bytes));
    assert.equal(triangles, 320);
    const stats = await page.evaluate(() => window.viewer.stats());
    assert.deepEqual(stats.clips, ['wave', 'hop', 'breathe']);
    assert.equal(stats.coarseTriangles, triangles);
    assert.equal(stats.uploadedBytes, triangles * 16 * 12, JSON.stringify(stats));
    assert.ok(stats.duration > 0.5);
    assert.equal(stats.poseError, null);
    const at = await capture(page);
    assert.ok(count(mask(at)) > 0.05 * at.width * at.height, 'the creature is drawn');
    if (process.env.TESSELLA_CLIP_SHOT) writeFileSync(process.env.TESSELLA_CLIP_SHOT, await page.screenshot());
    // Paused: another frame poses nothing again.
    await capture(page);
    assert.equal((await page.evaluate(() => window.viewer.stats())).uploadedBytes, 0);
    // The slider moves the pose (and keeps it paused); the URL follows.
    await page.locator('#clip-time').fill('0');
    await page.waitForFunction(() => window.viewer.get().time === 0);
    const start = await capture(page);
    assert.ok(differing(at, start) > 100, 'wave at 0 and at 0.5 look alike');
    assert.equal((await page.evaluate(() => window.viewer.get())).playing, false);
    // Play: the time moves on by itself.
    await page.locator('#play').click();
    assert.equal(await page.locator('#play').textContent(), 'pause');
    await page.waitForFunction(() => {
      const t = Number(document.getElementById('clip-time').value);
      return t > 0.05;
    });
    await page.locator('#play').click();
    const paused = await page.evaluate(() => window.viewer.get());
    assert.equal(paused.playing, false);
    assert.ok(paused.time > 0, JSON.stringify(paused));
    // The rest pose again: the menu's first entry.
    await page.locator('#clip').selectOption('none');
    assert.equal((await page.evaluate(() => window.viewer.get())).clip, 'none');
    assert.equal(await message(page), '');
    assertClean(assert, page);
    await page.close();
  });

  test('a clip the file lacks, and a clip on a mesh without clips, are refused by name', async () => {
    const page = await open(env, `?mesh=${SAMPLE}&size=160x160&clip=dance`);
    assert.match(await message(page), /^clip: /);
    assert.equal((await page.evaluate(() => window.viewer.get())).clip, 'none');
    await page.evaluate(() => window.viewer.load('samples/icosphere.obj'));
    assert.equal(await page.locator('#clip-row').isHidden(), true);
    const refused = await page.evaluate(() => window.viewer.set({ clip: 'wave' }).then(() => 'accepted', (e) => e.message));
    assert.match(refused, /^clip: /);
    await page.close();
  });
});

// Counts what the page hands WebGL2: draw calls by name and the bytes of every typed array
// given to bufferData/bufferSubData/texImage2D/texSubImage2D (what crosses to the GPU).
const GL_COUNTER = () => {
  window.glCount = { draws: {}, bytes: 0 };
  const proto = WebGL2RenderingContext.prototype;
  for (const name of ['drawElements', 'drawArrays', 'drawElementsInstanced', 'drawArraysInstanced']) {
    const f = proto[name];
    proto[name] = function (...args) {
      window.glCount.draws[name] = (window.glCount.draws[name] ?? 0) + 1;
      return f.apply(this, args);
    };
  }
  for (const name of ['bufferData', 'bufferSubData', 'texImage2D', 'texSubImage2D']) {
    const f = proto[name];
    proto[name] = function (...args) {
      const data = args.find((a) => ArrayBuffer.isView(a));
      if (data) window.glCount.bytes += data.byteLength;
      return f.apply(this, args);
    };
  }
};

async function openCounted(env, query) {
  const page = await env.browser.newPage();
  page.problems = watch(page);
  await page.addInitScript(GL_COUNTER);
  await page.goto(env.url + query);
  await page.evaluate(async () => {
    while (window.viewer?.ready === undefined) await new Promise((r) => setTimeout(r, 20));
    await window.viewer.ready;
  });
  return page;
}

describe('animation clips on the WebGL2 fallback', { skip }, () => {
  let env;
  let gpu;
  before(async () => {
    env = await start({ webgpu: false });
    gpu = await start({ webgpu: true });
  });
  after(async () => {
    await env?.close();
    await gpu?.close();
  });

  test('a paused clip is the WebGPU engine\'s picture at the same time; the pose moves with the time', async () => {
    const query = `?mesh=${SAMPLE}&size=320x320&clip=wave&time=0.5`;
    const page = await open(env, query);
    assert.equal(await page.evaluate(() => window.viewer.backend), 'webgl2');
    assert.equal(await message(page), '');
    const options = await page.locator('#clip option').evaluateAll((os) => os.map((o) => o.value));
    assert.deepEqual(options, ['none', 'wave', 'hop', 'breathe']);
    const state = await page.evaluate(() => window.viewer.get());
    assert.deepEqual([state.clip, state.time, state.playing], ['wave', 0.5, false]);
    const fallback = await capture(page);
    const engine = await open(gpu, query);
    assert.equal(await engine.evaluate(() => window.viewer.backend), 'webgpu');
    const reference = await capture(engine);
    const same = iou(mask(fallback), mask(reference));
    // The same counts: triangles drawn, and the static refined mesh they stand in for.
    const [mine, theirs] = [await page.evaluate(() => window.viewer.stats()), await engine.evaluate(() => window.viewer.stats())];
    for (const key of ['coarseTriangles', 'refinedTriangles', 'staticBytes', 'level', 'duration']) assert.equal(mine[key], theirs[key], key);
    assert.deepEqual(mine.clips, theirs.clips);
    assert.equal(mine.instanced, true);
    // The slider to 0: the fallback's picture moves away from the engine's at 0.5.
    await page.locator('#clip-time').fill('0');
    await page.waitForFunction(() => window.viewer.get().time === 0);
    const atZero = await capture(page);
    const moved = iou(mask(atZero), mask(reference));
    if (process.env.TESSELLA_CLIP_SHOT) {
      writeFileSync(process.env.TESSELLA_CLIP_SHOT, await page.screenshot());
    }
    console.log(`fallback vs engine, wave at 0.5 s: IoU ${same.toFixed(4)}; fallback at 0 s vs engine at 0.5 s: IoU ${moved.toFixed(4)}`);
    assert.ok(same >= 0.98, `fallback vs engine at 0.5 s: silhouette IoU ${same}`);
    const off = differingBy(fallback, reference, 48);
    assert.ok(off < 0.02 * count(mask(reference)), `${off} pixels differ from the engine's by more than 48/255`);
    assert.ok(moved < same - 0.02, `the pose at 0 s (IoU ${moved}) is no further from 0.5 s than the fallback is from the engine (${same})`);
    assertClean(assert, page);
    assertClean(assert, engine);
    await page.close();
    await engine.close();
  });

  test('playing, a frame uploads only the nets: one instanced draw, at most 256 bytes per coarse triangle', async () => {
    const page = await openCounted(env, `?mesh=${SAMPLE}&size=320x320&clip=wave&level=8`);
    const coarse = (await page.evaluate(() => window.viewer.stats())).coarseTriangles;
    assert.equal(coarse, 320);
    // Play for a while; count every frame's GL calls and bytes.
    const { frames, counted, perFrame, drawn } = await page.evaluate(async () => {
      const per = [];
      await new Promise((r) => requestAnimationFrame(r));
      window.glCount.bytes = 0;
      window.glCount.draws = {};
      for (let i = 0; i < 12; i++) {
        await new Promise((r) => requestAnimationFrame(r));
        per.push(window.viewer.stats().uploadedBytes);
      }
      return { frames: window.glCount.draws.drawElementsInstanced ?? 0, counted: window.glCount.bytes, perFrame: per, drawn: { ...window.glCount.draws } };
    });
    console.log(`fallback playing wave at level 8: ${JSON.stringify(perFrame)} bytes per frame (${coarse} coarse triangles), ${counted} bytes handed to WebGL in ${frames} frames`);
    assert.ok(frames >= 6, `only ${frames} frames drawn while playing: ${JSON.stringify(drawn)}`);
    // One instanced draw per frame and nothing else drawn.
    assert.deepEqual(Object.keys(drawn), ['drawElementsInstanced']);
    assert.ok(counted > 0, 'nothing uploaded while the clip plays');
    assert.ok(counted <= frames * 256 * coarse, `${counted / frames} bytes a frame, over 256 per coarse triangle`);
    // PN's nets: 16 entries of 3 floats in 12 RGBA32F texels, 320 nets in whole rows.
    for (const b of perFrame) assert.ok(b === 0 || b === coarse * 12 * 16, `stats say ${b} bytes in a frame`);
    assert.ok(perFrame.some((b) => b > 0));
    assertClean(assert, page);
    await page.close();
  });
});
