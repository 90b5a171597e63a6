// A glTF file's animation clips in the page (WebGPU engine, headless Chromium's SwiftShader):
// `?clip=wave&time=0.5` opens paused there with the clip menu, slider and stats showing it; a
// frame uploads the control nets alone (counted here from the file's triangle count, not from
// the engine); two times give two pictures; play and pause; the WebGL2 fallback refuses clips.
// Needs dist/pkg (the engine); TESSELLA_WEB_NO_ENGINE=1 skips the suite with that reason.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { DIST } from '../scripts/serve.js';
import { assertClean, capture, count, mask, message, open, start } from './harness.js';

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

describe('animation clips on the WebGL2 fallback', () => {
  let env;
  before(async () => {
    env = await start({ webgpu: false });
  });
  after(async () => env?.close());

  test('a clip needs the WebGPU engine, said by name', async () => {
    const page = await open(env, `?mesh=${SAMPLE}&size=160x160&clip=wave`);
    assert.equal(await page.evaluate(() => window.viewer.backend), 'webgl2');
    assert.match(await message(page), /clip needs the WebGPU engine/);
    await page.close();
  });
});
