// tessella/three's TessellatedMesh following a SkinnedMesh in headless Chromium (WebGL2 on
// SwiftShader): the creature loaded by three's GLTFLoader and played by its AnimationMixer
// looks, at a given time, like refineGeometry of the vertices three itself skins
// (getVertexPosition) drawn as a plain Mesh; while it plays, each frame uploads the nets alone.
// Build js/ first (`cd js && npm ci && npm run build`).
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { PNG } from 'pngjs';
import { count, iou, mask, openRepoPage } from './harness.js';

const SHOT = process.env.TESSELLA_SKINNED_SHOT;

let three;
before(async () => {
  three = await openRepoPage('web/test/three/index.html?page=skinned', { global: 'tessellaSkinned' });
});
after(() => three?.close());
// The instanced path ('per-draw', pinned: the default, 'auto', bakes from the second frame under
// WebGLRenderer); the default has its own test below.
const run = (config) => three.run({ evaluation: 'per-draw', ...config });
const byDefault = (config) => three.run({ ...config, evaluation: undefined });

test('a SkinnedMesh played by AnimationMixer matches refineGeometry of the vertices three skins, at each time', async () => {
  const shots = [];
  for (const [clip, time] of [['wave', 0.5], ['hop', 0.3], ['breathe', 1.2]]) {
    const cpu = await run({ clip, times: [time], plain: true });
    const gpu = await run({ clip, times: [time] });
    const rest = await run({ clip, times: [0], plain: true });
    const a = mask(cpu.img);
    const b = mask(gpu.img);
    const score = iou(a, b);
    console.log(`${clip} at ${time} s: silhouette IoU ${score.toFixed(5)} (${count(a)} / ${count(b)} pixels), ${iou(b, mask(rest.img)).toFixed(4)} with the clip's start`);
    assert.ok(count(b) > 0.03 * b.length, `${clip}: only ${count(b)} pixels drawn`);
    assert.ok(score >= 0.99, `${clip} at ${time}: IoU ${score}`);
    assert.equal(gpu.log[0].instanced, 1, 'one instanced draw');
    shots.push(cpu.img, gpu.img);
  }
  if (SHOT) {
    // Each clip: left the CPU refinement of three's skinned vertices, right TessellatedMesh.
    const { width, height } = shots[0];
    const out = new PNG({ width: 2 * width, height: height * (shots.length / 2) });
    shots.forEach((img, i) => PNG.bitblt(img, out, 0, 0, width, height, (i % 2) * width, Math.floor(i / 2) * height));
    writeFileSync(SHOT, PNG.sync.write(out));
  }
  assert.deepEqual(three.problems, []);
});

test('while the clip plays, a frame uploads the nets alone: at most 256 bytes per coarse triangle', async () => {
  const times = [0.1, 0.2, 0.3, 0.4, 0.5];
  for (const level of [8, 16]) {
    const gpu = await run({ clip: 'wave', times, level });
    for (const [f, frame] of gpu.log.entries()) {
      if (f === 0) continue; // the first frame also uploads the pattern
      console.log(`level ${level}, frame ${f}: ${frame.uploaded} bytes (${(frame.uploaded / gpu.faces).toFixed(1)} per coarse triangle)`);
      assert.ok(frame.uploaded > 0, 'the moved nets are uploaded');
      assert.ok(frame.uploaded <= 256 * gpu.faces, `${frame.uploaded} bytes for ${gpu.faces} triangles`);
    }
  }
  assert.deepEqual(three.problems, []);
});

test("by default ('auto': per-frame under WebGLRenderer) the playing clip draws the pictures of 'per-draw'; after the first frames a frame uploads the nets alone, drawn not instanced", async () => {
  const times = [0.1, 0.2, 0.3, 0.4, 0.5];
  const auto = await byDefault({ clip: 'wave', times, level: 8 });
  const perDraw = await run({ clip: 'wave', times, level: 8 });
  assert.equal(auto.evaluation, 'per-frame');
  assert.equal(auto.fallback, null);
  // The first frame draws instanced (and bakes); the second uploads the welded topology once.
  assert.equal(auto.log[0].instanced, 1);
  for (const [f, frame] of auto.log.entries()) {
    if (f === 0) continue;
    assert.equal(frame.instanced, 0, `frame ${f} drawn instanced`);
    if (f === 1) continue;
    assert.ok(frame.uploaded > 0 && frame.uploaded <= 256 * auto.faces, `frame ${f}: ${frame.uploaded} bytes for ${auto.faces} triangles`);
  }
  const score = iou(mask(perDraw.img), mask(auto.img));
  console.log(`default against per-draw, wave at 0.5 s: IoU ${score.toFixed(5)}`);
  assert.ok(score >= 0.99, `IoU ${score}`);
  assert.deepEqual(three.problems, []);
});
