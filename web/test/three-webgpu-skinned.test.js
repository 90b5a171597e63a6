// tessella/three's TessellatedMesh following a SkinnedMesh under three's WebGPURenderer (its
// WebGPU backend: SwiftShader in headless Chromium): the creature loaded by three's GLTFLoader
// and played by its AnimationMixer looks, at a given time, like refineGeometry of the vertices
// three itself skins (getVertexPosition) drawn as a plain Mesh by the same renderer, and like
// the TessellatedMesh WebGLRenderer draws; the pose moves the silhouette (not the rest pose
// drawn at every time). The page is web/test/three/index.html?page=skinned (three/skinned.js,
// `renderer: 'webgpu'`); build js/ first (`cd js && npm ci && npm run build`).
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { PNG } from 'pngjs';
import { count, differing, iou, mask, openRepoPage } from './harness.js';

const SHOT = process.env.TESSELLA_SKINNED_SHOT;

let three;
before(async () => {
  three = await openRepoPage('web/test/three/index.html?page=skinned', { webgpu: true, global: 'tessellaSkinned' });
});
after(() => three?.close());
const run = (config) => three.run(config);

test('under WebGPURenderer a SkinnedMesh played by AnimationMixer matches refineGeometry of the vertices three skins, and the WebGL picture, at each time', async () => {
  const shots = [];
  for (const [clip, time] of [['wave', 0.5], ['hop', 0.3], ['breathe', 1.2], ['wave', 1.1]]) {
    const cpu = await run({ clip, times: [time], plain: true, renderer: 'webgpu' });
    const gpu = await run({ clip, times: [time], renderer: 'webgpu' });
    const gl = await run({ clip, times: [time] });
    const rest = await run({ clip, times: [0], plain: true, renderer: 'webgpu' });
    const [a, b, c, r] = [cpu, gpu, gl, rest].map((x) => mask(x.img));
    const score = iou(a, b);
    const withGl = iou(b, c);
    const moved = iou(b, r);
    const off = differing(cpu.img, gpu.img, 12);
    const offGl = differing(gl.img, gpu.img, 12);
    console.log(`${clip} at ${time} s: silhouette IoU ${score.toFixed(5)} with the CPU pose (${count(a)} / ${count(b)} pixels, ${off} shaded differently), ${withGl.toFixed(5)} with WebGLRenderer's TessellatedMesh (${offGl} shaded differently, ${differing(gl.img, gpu.img, 0)} pixels not the same bytes), ${moved.toFixed(4)} with the clip's start`);
    assert.ok(count(b) > 0.03 * b.length, `${clip}: only ${count(b)} pixels drawn`);
    assert.ok(score >= 0.99, `${clip} at ${time}: IoU ${score} with the CPU pose`);
    assert.ok(withGl >= 0.99, `${clip} at ${time}: IoU ${withGl} with the WebGL picture`);
    // The shading too: the GPU's normals are those of the CPU refinement of three's pose.
    assert.ok(off < 0.01 * count(a), `${clip} at ${time}: ${off} pixels shaded differently`);
    // The pose moves the silhouette by more than the 0.99 these pictures are held to.
    assert.ok(moved < 0.99, `${clip} at ${time}: the rest pose's silhouette (IoU ${moved})`);
    assert.equal(gpu.log[0].instanced, 1, 'one instanced draw');
    shots.push(cpu.img, gpu.img);
  }
  if (SHOT) {
    // Each row: left the CPU refinement of three's skinned vertices, right TessellatedMesh, both WebGPU.
    const { width, height } = shots[0];
    const out = new PNG({ width: 2 * width, height: height * (shots.length / 2) });
    shots.forEach((img, i) => PNG.bitblt(img, out, 0, 0, width, height, (i % 2) * width, Math.floor(i / 2) * height));
    writeFileSync(SHOT.replace(/\.png$/, '-webgpu.png'), PNG.sync.write(out));
  }
  assert.deepEqual(three.problems, []);
});

test('under WebGPURenderer, frames of a playing clip follow it: each frame the picture of its own time', async () => {
  // One TessellatedMesh drawn at several times in a row (its nets rebuilt each frame): the
  // last frame is the CPU pose of the last time, not of an earlier one.
  const times = [0, 0.15, 0.3];
  const playing = await run({ clip: 'hop', times, renderer: 'webgpu' });
  const last = await run({ clip: 'hop', times: [times.at(-1)], plain: true, renderer: 'webgpu' });
  const first = await run({ clip: 'hop', times: [times[0]], plain: true, renderer: 'webgpu' });
  const b = mask(playing.img);
  const score = iou(mask(last.img), b);
  const stale = iou(mask(first.img), b);
  console.log(`hop played at ${times.join(', ')} s: IoU ${score.toFixed(5)} with the CPU pose at ${times.at(-1)} s, ${stale.toFixed(5)} with the one at ${times[0]} s`);
  assert.ok(score >= 0.99, `IoU ${score}`);
  assert.ok(stale < 0.95, `the last frame looks like the first pose (IoU ${stale})`);
  // The default evaluation ('auto') stays per draw under WebGPURenderer: instanced every frame.
  for (const frame of playing.log) assert.equal(frame.instanced, 1);
  assert.equal(playing.evaluation, 'per-draw');
  assert.match(playing.fallback, /WebGPURenderer/);
  assert.deepEqual(three.problems, []);
});
