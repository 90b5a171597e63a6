// tessella/three's TessellatedMesh following a SkinnedMesh under three's WebGPURenderer (its
// WebGPU backend: SwiftShader in headless Chromium): the creature loaded by three's GLTFLoader
// and played by its AnimationMixer looks, at a given time, like refineGeometry of the vertices
// three itself skins (getVertexPosition) drawn as a plain Mesh by the same renderer, and like
// the TessellatedMesh WebGLRenderer draws; the pose moves the silhouette (not the rest pose
// drawn at every time). The page is web/test/three/index.html?page=skinned (three/skinned.js,
// `renderer: 'webgpu'`); GPU posing (the nets built by compute, three-gpu-nets-nodes.js) against
// CPU posing is page=webgpu's `skinned` (three/webgpu.js). Build js/ first (`cd js && npm ci &&
// npm run build`).
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { PNG } from 'pngjs';
import { count, differing, iou, mask, openRepoPage } from './harness.js';

const SHOT = process.env.TESSELLA_SKINNED_SHOT;

let three;
let gpu;
before(async () => {
  three = await openRepoPage('web/test/three/index.html?page=skinned', { webgpu: true, global: 'tessellaSkinned' });
  gpu = await openRepoPage('web/test/three/index.html?page=webgpu', { webgpu: true, global: 'tessellaThree' });
});
after(async () => {
  await three?.close();
  await gpu?.close();
});
const run = (config) => three.run(config);

// The creature drawn by page=webgpu's `skinned` (GPU or CPU posing), its picture decoded.
async function creature(config) {
  const out = await gpu.page.evaluate((c) => window.tessellaThree.skinned(c), config);
  if (out.rgba !== undefined) out.img = { width: out.width, height: out.height, data: Buffer.from(out.rgba, 'base64') };
  return out;
}

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

test('under WebGPURenderer GPU posing (the nets built by compute) draws the CPU posing\'s picture at each time, PN and PN-AEN, uploading only the joint matrices and morph weights', async () => {
  for (const scheme of ['pn', 'pn-aen']) {
    for (const [clip, time] of [['wave', 0.5], ['hop', 0.3], ['breathe', 1.2]]) {
      const onGpu = await creature({ clip, times: [time], scheme, posing: 'gpu' });
      const onCpu = await creature({ clip, times: [time], scheme, posing: 'cpu' });
      const rest = await creature({ clip, times: [0], scheme, posing: 'cpu' });
      assert.equal(onGpu.thrown, undefined, onGpu.thrown);
      assert.equal(onGpu.posedOn, 'gpu');
      assert.equal(onGpu.posingFallback, null);
      assert.equal(onGpu.netsTexture, 'storage', 'the nodes read the storage texture the compute writes');
      assert.equal(onCpu.posedOn, 'cpu');
      const [a, b, r] = [onCpu, onGpu, rest].map((x) => mask(x.img));
      const score = iou(a, b);
      const off = differing(onCpu.img, onGpu.img, 12);
      const moved = iou(b, r);
      const [g] = onGpu.log;
      const [c] = onCpu.log;
      console.log(`${scheme} ${clip} at ${time} s: IoU ${score.toFixed(5)} GPU against CPU posing (${count(a)} / ${count(b)} pixels, ${off} shaded differently, ${differing(onCpu.img, onGpu.img, 0)} not the same bytes), ${moved.toFixed(4)} with the clip's start; uploaded ${g.uploadedBytes} bytes (CPU posing ${c.uploadedBytes}), ${g.computes} compute calls`);
      assert.ok(count(b) > 0.03 * b.length, `${scheme} ${clip}: only ${count(b)} pixels drawn`);
      assert.ok(score >= 0.99, `${scheme} ${clip} at ${time}: IoU ${score}`);
      assert.ok(off < 0.005 * count(a), `${scheme} ${clip} at ${time}: ${off} pixels shaded differently`);
      assert.ok(moved < 0.99, `${scheme} ${clip} at ${time}: the rest pose's silhouette (IoU ${moved})`);
      // A frame uploads the 7 joint matrices and the one morph weight: (7 * 16 + 1) * 4 bytes;
      // CPU posing the whole nets texture.
      assert.equal(g.uploadedBytes, (7 * 16 + 1) * 4);
      assert.ok(c.uploadedBytes > 10 * g.uploadedBytes, `CPU posing uploads ${c.uploadedBytes}`);
      assert.equal(g.computes, 1, 'one compute call a frame (pose, then the nets)');
      assert.equal(c.computes, 0);
      assert.ok(onGpu.storageLeft === 0 && onCpu.storageLeft === 0, `storage buffers left after dispose: ${onGpu.storageLeft} (GPU posing), ${onCpu.storageLeft} (CPU)`);
    }
  }
  // A GPU-posed mesh and a static one (the CPU's DataTexture) sharing a material (its nodes,
  // its pipeline): each draws, with no validation error.
  const alone = await creature({ clip: 'hop', times: [0.3], scheme: 'pn', posing: 'cpu' });
  const twins = await creature({ clip: 'hop', times: [0.3], scheme: 'pn', posing: 'gpu', twin: true });
  const twinsCpu = await creature({ clip: 'hop', times: [0.3], scheme: 'pn', posing: 'cpu', twin: true });
  assert.equal(twins.posedOn, 'gpu');
  assert.equal(twins.netsTexture, 'storage');
  assert.equal(twins.twinNets, 'data');
  const [one, two, twoCpu] = [alone, twins, twinsCpu].map((x) => mask(x.img));
  console.log(`with a static mesh sharing the material: ${count(two)} pixels drawn (${count(one)} without it), IoU ${iou(two, twoCpu).toFixed(5)} with CPU posing`);
  assert.ok(count(two) > count(one) + 500, 'the static mesh is drawn');
  assert.ok(iou(two, twoCpu) >= 0.99);
  assert.ok(differing(twins.img, twinsCpu.img, 12) < 0.005 * count(two));
  assert.deepEqual(gpu.problems, []);
});

test('under WebGPURenderer the nets the compute writes are the CPU\'s nets for the same pose: each scheme the GPU builds, each normal mode, a skinned and a morphing source', async () => {
  const modes = new Set();
  for (const [scheme, clip, time, more] of [
    ['pn', 'wave', 0.5],
    ['pn-aen', 'hop', 0.3],
    ['phong', 'breathe', 1.2],
    ['flat', 'wave', 1.1],
    ['pn', 'hop', 0.7, { normals: 'linear' }],
    ['pn-aen', 'wave', 1.1, { normals: 'real' }],
    // A morphing Mesh (no skeleton): its one matrix, the morph weight.
    ['pn', 'breathe', 1.2, { rigid: true }],
  ]) {
    const out = await creature({ clip, times: [time], scheme, posing: 'gpu', nets: true, ...more });
    assert.equal(out.thrown, undefined, out.thrown);
    assert.equal(out.posedOn, 'gpu');
    modes.add(out.normalMode);
    const { most, largest, length, expected } = out.nets;
    console.log(`${scheme} (${out.normalMode} normals${more?.rigid ? ', a morphing Mesh' : ''}) ${clip} at ${time} s: the GPU's nets differ from the CPU's by at most ${most} (values up to ${largest.toFixed(3)})`);
    assert.equal(length, expected);
    assert.ok(largest > 0.1, 'the CPU nets are not empty');
    assert.ok(typeof most === 'number' && most <= 2e-5 * Math.max(1, largest), `${scheme} ${clip}: nets differ by ${most}`);
  }
  assert.deepEqual([...modes].sort(), ['linear', 'quadratic', 'real']);
  // And frames follow the clip: after playing on, the nets are the last time's.
  // A frame whose pose did not move (the last, at the same time) dispatches nothing.
  const played = await creature({ clip: 'hop', times: [0, 0.15, 0.3, 0.3], scheme: 'pn', posing: 'gpu', nets: true });
  assert.ok(played.nets.most <= 2e-5 * Math.max(1, played.nets.largest), `played: nets differ by ${played.nets.most}`);
  assert.deepEqual(played.log.map((f) => f.computes), [1, 1, 1, 0]);
  assert.deepEqual(gpu.problems, []);
});

test('under WebGPURenderer PNG1 and normals computed per frame fall back to CPU posing with the reason, and posing \'gpu\' refuses them', async () => {
  const auto = await creature({ clip: 'wave', times: [0.5], scheme: 'png1', posing: 'auto' });
  assert.equal(auto.thrown, undefined, auto.thrown);
  assert.equal(auto.posedOn, 'cpu');
  assert.match(auto.posingFallback, /png1/);
  assert.equal(auto.netsTexture, 'data');
  assert.equal(auto.log[0].computes, 0);
  const cpu = await creature({ clip: 'wave', times: [0.5], scheme: 'png1', posing: 'cpu' });
  assert.ok(iou(mask(auto.img), mask(cpu.img)) >= 0.999);
  const refused = await creature({ clip: 'wave', times: [0.5], scheme: 'png1', posing: 'gpu' });
  assert.match(refused.thrown ?? '', /posing: 'gpu' cannot run: .*png1/);
  // Normals computed from the posed positions each frame are the CPU's.
  const computed = await creature({ clip: 'wave', times: [0.5], scheme: 'pn', posing: 'auto', normalsFromSource: false });
  assert.equal(computed.posedOn, 'cpu');
  assert.match(computed.posingFallback, /normals/);
  const computedGpu = await creature({ clip: 'wave', times: [0.5], scheme: 'pn', posing: 'gpu', normalsFromSource: false });
  assert.match(computedGpu.thrown ?? '', /posing: 'gpu' cannot run: .*normals/);
  // The default ('auto') poses a PN surface on the GPU under WebGPURenderer.
  const byDefault = await creature({ clip: 'wave', times: [0.5], scheme: 'pn', posing: undefined });
  assert.equal(byDefault.posedOn, 'gpu');
  assert.deepEqual(gpu.problems, []);
});
