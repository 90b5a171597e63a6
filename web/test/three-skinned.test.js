// tessella/three's TessellatedMesh following a SkinnedMesh in headless Chromium (WebGL2 on
// SwiftShader): the creature loaded by three's GLTFLoader and played by its AnimationMixer
// looks, at a given time, like refineGeometry of the vertices three itself skins
// (getVertexPosition) drawn as a plain Mesh; while it plays, each frame uploads the nets alone
// (CPU posing), or the joint matrices and morph weights alone (GPU posing, the default, whose
// nets, pictures, fallbacks and rays are checked against CPU posing's).
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
    // The default posing: the nets built on the GPU, against three's own skinning.
    assert.equal(gpu.posedOn, 'gpu');
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

test('while the clip plays, a frame posed on the CPU uploads the nets alone: at most 256 bytes per coarse triangle', async () => {
  const times = [0.1, 0.2, 0.3, 0.4, 0.5];
  for (const level of [8, 16]) {
    const gpu = await run({ clip: 'wave', times, level, posing: 'cpu' });
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
  // Posed on the CPU (the nets uploaded); GPU posing's own tests are below.
  const auto = await byDefault({ clip: 'wave', times, level: 8, posing: 'cpu' });
  const perDraw = await run({ clip: 'wave', times, level: 8, posing: 'cpu' });
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

// GPU posing (posing: 'gpu'; 'auto', the default, takes it here): the nets built by a render
// pass from the joint matrices and morph weights draw the pictures CPU posing draws.
const differing = (a, b) => {
  let n = 0;
  for (let i = 0; i < a.data.length; i += 4) {
    if (Math.abs(a.data[i] - b.data[i]) > 2 || Math.abs(a.data[i + 1] - b.data[i + 1]) > 2 || Math.abs(a.data[i + 2] - b.data[i + 2]) > 2) n++;
  }
  return n;
};

async function samePicture(config, label) {
  const cpu = await three.run({ ...config, posing: 'cpu' });
  const gpu = await three.run({ ...config, posing: 'gpu' });
  assert.equal(cpu.posedOn, 'cpu');
  assert.equal(gpu.posedOn, 'gpu', `${label}: ${gpu.posingFallback}`);
  assert.equal(gpu.posingFallback, null);
  const a = mask(cpu.img);
  const b = mask(gpu.img);
  const score = iou(a, b);
  const diff = differing(cpu.img, gpu.img);
  console.log(`${label}: silhouette IoU ${score.toFixed(5)}, ${diff} pixels differ (of ${count(b)} drawn)`);
  assert.ok(count(b) > 0.03 * b.length, `${label}: only ${count(b)} pixels drawn`);
  assert.ok(score >= 0.99, `${label}: IoU ${score}`);
  assert.ok(diff <= 0.01 * count(b), `${label}: ${diff} pixels differ`);
  return { cpu, gpu };
}

test('GPU posing draws what CPU posing draws: clips at several times, four schemes, both evaluations', async () => {
  for (const [clip, times] of [['wave', [0.2, 0.5]], ['hop', [0.3, 0.6]], ['breathe', [0.4, 1.2]]]) {
    for (const time of times) await samePicture({ clip, times: [0.1, time], evaluation: 'per-draw' }, `${clip} at ${time} s, pn, per-draw`);
  }
  for (const scheme of ['phong', 'pn-aen', 'flat']) {
    await samePicture({ clip: 'hop', times: [0.3], scheme, evaluation: 'per-draw' }, `hop at 0.3 s, ${scheme}, per-draw`);
  }
  // The default evaluation ('per-frame' here) bakes the GPU's nets: several frames, the last compared.
  for (const scheme of ['pn', 'pn-aen']) {
    const { gpu } = await samePicture({ clip: 'wave', times: [0.1, 0.3, 0.5], scheme, evaluation: undefined }, `wave at 0.5 s, ${scheme}, default evaluation`);
    assert.equal(gpu.evaluation, 'per-frame');
  }
  assert.deepEqual(three.problems, []);
});

test('GPU posing with shadows, and a morph-only Mesh, draws what CPU posing draws', async () => {
  await samePicture({ clip: 'hop', times: [0.3], shadows: true, evaluation: undefined }, 'hop at 0.3 s with shadows, default evaluation');
  await samePicture({ clip: 'hop', times: [0.3], shadows: true, evaluation: 'per-draw' }, 'hop at 0.3 s with shadows, per-draw');
  for (const time of [0.2, 0.9]) await samePicture({ morphOnly: true, times: [0, time], evaluation: 'per-draw' }, `morph-only at ${time}`);
  assert.deepEqual(three.problems, []);
});

test("GPU posing's nets texture, read back, is the CPU's nets of the same pose", async () => {
  for (const [clip, scheme, morphOnly] of [['wave', 'pn', false], ['hop', 'pn-aen', false], ['breathe', 'phong', false], ['hop', 'flat', false], ['wave', 'pn', true]]) {
    const out = await three.run({ clip, times: [0.1, 0.45], scheme, posing: 'gpu', twin: true, morphOnly, evaluation: 'per-draw' });
    const { most, size, finite, holds, ratio } = out.nets;
    console.log(`${morphOnly ? 'morph-only' : clip} ${scheme}: nets differ by at most ${most.toExponential(2)} (${(most / size).toExponential(2)} of the size ${size.toFixed(3)}); bounding sphere ${ratio.toFixed(2)}x the CPU's`);
    assert.ok(finite);
    assert.ok(holds, 'the GPU-posed bounds hold the posed control points');
    assert.ok(ratio < 2, `${clip} ${scheme}: the bounding sphere is ${ratio}x the CPU's`);
    assert.ok(most <= 1e-4 * size, `${clip} ${scheme}: ${most}`);
  }
  // Reading the target back stalls the GPU, which Chromium warns of: this test's own doing.
  const stalls = three.problems.filter((p) => p.includes('GPU stall due to ReadPixels'));
  for (const p of stalls) three.problems.splice(three.problems.indexOf(p), 1);
  assert.deepEqual(three.problems, []);
});

test('GPU posing uploads the joint matrices and morph weights alone: at most 64 bytes a joint and 4 a weight (+16) a frame', async () => {
  const times = [0.1, 0.2, 0.3, 0.4];
  for (const evaluation of ['per-draw', undefined]) {
    const gpu = await three.run({ clip: 'wave', times, posing: 'gpu', evaluation });
    const most = 64 * gpu.bones + 4 * gpu.targets + 16;
    for (const [f, frame] of gpu.log.entries()) {
      if (f < 2) continue; // the first frames also upload the pattern, the pass's inputs and the welded topology
      console.log(`${evaluation ?? 'default'}, frame ${f}: ${frame.uploaded} bytes uploaded, ${frame.reported} reported (${gpu.bones} joints, ${gpu.targets} weights)`);
      assert.ok(frame.uploaded > 0 && frame.uploaded <= most, `${frame.uploaded} bytes, over ${most}`);
      assert.equal(frame.uploaded, frame.reported);
    }
  }
  assert.deepEqual(three.problems, []);
});

test('posing falls back to the CPU where the GPU cannot build the nets, and says why', async () => {
  const png1 = await three.run({ clip: 'wave', times: [0.3], scheme: 'png1', evaluation: 'per-draw' });
  assert.equal(png1.posedOn, 'cpu');
  assert.match(png1.posingFallback, /'png1' nets are built on the CPU/);
  const asked = await three.page.evaluate(() => window.tessellaSkinned.run({ clip: 'wave', scheme: 'png1', posing: 'gpu' }).then(() => 'no error', (e) => `${e.name}: ${e.message}`));
  assert.match(asked, /TessellaError: posing: 'gpu' cannot run: .*'png1' nets are built on the CPU/);
  const cpu = await three.run({ clip: 'wave', times: [0.3], posing: 'cpu', evaluation: 'per-draw' });
  assert.equal(cpu.posedOn, 'cpu');
  assert.equal(cpu.posingFallback, null);
  // The default poses on the GPU here; without float render targets, on the CPU, drawing the same.
  const auto = await three.run({ clip: 'wave', times: [0.3], evaluation: 'per-draw' });
  assert.equal(auto.posedOn, 'gpu');
  const noFloat = await three.run({ clip: 'wave', times: [0.3], evaluation: 'per-draw', noFloatTargets: true });
  assert.equal(noFloat.posedOn, 'cpu');
  assert.match(noFloat.posingFallback, /EXT_color_buffer_float/);
  assert.ok(iou(mask(noFloat.img), mask(auto.img)) >= 0.99);
  const refused = await three.page.evaluate(() => window.tessellaSkinned.run({ clip: 'wave', posing: 'gpu', noFloatTargets: true, evaluation: 'per-draw' }).then(() => 'no error', (e) => `${e.name}: ${e.message}`));
  assert.match(refused, /TessellaError: posing: 'gpu' cannot run: no float render targets \(EXT_color_buffer_float\)/);
});

test('a ray cast at a GPU-posed mesh hits where it is drawn (the pose, not the rest)', async () => {
  const gpu = await three.run({ clip: 'hop', times: [0.1, 0.3], posing: 'gpu', rayStep: 8, evaluation: 'per-draw' });
  const rest = await three.run({ clip: 'hop', times: [0], posing: 'cpu', evaluation: 'per-draw' });
  assert.equal(gpu.posedOn, 'gpu');
  const drawn = mask(gpu.img);
  const restMask = mask(rest.img);
  const at = ({ x, y }) => drawn[y * gpu.img.width + x];
  const wrong = gpu.rays.filter((r) => r.hit !== (at(r) === 1)).length;
  const moved = gpu.rays.filter((r) => at(r) !== restMask[r.y * gpu.img.width + r.x]).length;
  const hits = gpu.rays.filter((r) => r.hit).length;
  console.log(`${gpu.rays.length} rays: ${hits} hit, ${wrong} disagree with the picture; ${moved} pixels of the grid differ from the rest pose`);
  assert.ok(moved >= 10, 'the pose moved the creature');
  assert.ok(hits >= 50);
  assert.ok(wrong <= 2, `${wrong} rays disagree`);
});
