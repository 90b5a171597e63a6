// tessella/three's TessellatedMesh in headless Chromium (WebGL2 on SwiftShader): drawn by the
// GPU from the nets texture it looks like the CPU refinement drawn as a plain Mesh, in one
// instanced draw; while the source deforms each frame uploads the nets alone; it casts and
// receives shadows (directional and point lights). The page (three/index.html?page=mesh: three/mesh.js) and the package come from the repository
// (js/src, js/dist, js/node_modules/three): build js/ first (`cd js && npm ci && npm run build`).
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { PNG } from 'pngjs';
import { count, darker, differing, iou, mask, openRepoPage } from './harness.js';
import { assertFollows, assertShadows, deformed } from './three-checks.js';

const SHOT = process.env.TESSELLA_THREE_SHOT;

let three;
before(async () => {
  three = await openRepoPage('web/test/three/index.html?page=mesh', { global: 'tessellaThree' });
});
after(() => three?.close());
// The tests of the draws' make-up (one instanced draw a pass, the nets alone uploaded) are those
// of 'per-draw' evaluation (pinned here: the default, 'auto', takes 'per-frame' under
// WebGLRenderer from the second frame); 'per-frame' and the default have their own below.
const run = (config) => three.run({ evaluation: 'per-draw', ...config });
const byDefault = (config) => three.run({ ...config, evaluation: undefined });
const perFrame = (config) => three.run({ evaluation: 'per-frame', ...config });

test('TessellatedMesh with MeshStandardMaterial looks like refineGeometry drawn as a Mesh, in one instanced draw', async () => {
  for (const [scheme, level, normals] of [['pn', 8], ['png1', 6], ['phong', 5], ['pn-aen', 4, 'real']]) {
    // No shadow casting here: one pass, so one draw. Real normals (Du x Dv) differ on the two
    // sides of an edge where the surface is only C0 (PN): each instance has its own edge
    // vertices, as in refine's soup, where the welded CPU mesh shares one.
    const soup = normals === 'real' ? true : undefined;
    const cpu = await run({ scheme, level, normals, soup, plain: true, castShadow: false });
    const gpu = await run({ scheme, level, normals, castShadow: false });
    const a = mask(cpu.img);
    const b = mask(gpu.img);
    assert.ok(count(b) > 0.08 * b.length, `${scheme}: only ${count(b)} pixels drawn`);
    const score = iou(a, b);
    console.log(`${scheme}${normals ? ` (${normals} normals)` : ''} level ${level}: silhouette IoU ${score.toFixed(5)} (${count(a)} / ${count(b)} pixels)`);
    assert.ok(score >= 0.99, `${scheme}: IoU ${score}`);
    // The shading too: the GPU's normals are the CPU's.
    const off = differing(cpu.img, gpu.img, 12);
    assert.ok(off < 0.01 * count(a), `${scheme}: ${off} pixels shaded differently`);
    const [frame] = gpu.log;
    // One draw call in all: instanced, the pattern's level² triangles once per coarse triangle.
    assert.equal(frame.calls, 1);
    assert.deepEqual(frame.instanced, [{ count: 3 * level * level, instances: gpu.faces }]);
    assert.equal(frame.draws, 0);
    assert.equal(cpu.log[0].instanced.length, 0);
  }
  assert.deepEqual(three.problems, []);
});

test('while the source deforms, a frame uploads the nets alone: at most 256 bytes per coarse triangle', async () => {
  const frames = 4;
  const runs = await deformed(run, frames);
  const { gpu } = runs;
  for (const [f, frame] of gpu.log.entries()) {
    console.log(`frame ${f}: ${frame.uploaded} bytes uploaded (${(frame.uploaded / gpu.faces).toFixed(1)} per coarse triangle), uploadedBytes ${frame.uploadedBytes}`);
    if (f === 0) continue; // the first frame also uploads the pattern
    assert.ok(frame.uploaded > 0, 'the moved nets are uploaded');
    assert.ok(frame.uploaded <= 256 * gpu.faces, `frame ${f}: ${frame.uploaded} bytes for ${gpu.faces} triangles`);
    assert.equal(frame.uploaded, frame.uploadedBytes);
    assert.equal(frame.calls, 1);
  }
  assertFollows(runs);
  assert.deepEqual(three.problems, []);
});

test('it casts shadows (on a plane, from a directional and a point light) and receives them (from a ball), like the CPU mesh', async () => {
  await assertShadows(run, (cpuShaded, shaded) => {
    if (!SHOT) return;
    // Left: the CPU refinement as a plain Mesh; right: TessellatedMesh.
    const out = new PNG({ width: 2 * shaded.width, height: shaded.height });
    PNG.bitblt(cpuShaded, out, 0, 0, shaded.width, shaded.height, 0, 0);
    PNG.bitblt(shaded, out, 0, 0, shaded.width, shaded.height, shaded.width, 0);
    writeFileSync(SHOT, PNG.sync.write(out));
  });
  assert.deepEqual(three.problems, []);
});

test("three's other materials draw it too (Lambert, Phong, Physical, Normal), and fog, clipping, maps and vertex colours work", async () => {
  const configs = ['MeshLambertMaterial', 'MeshPhongMaterial', 'MeshPhysicalMaterial', 'MeshNormalMaterial'].map((material) => ({ material }));
  configs.push({ material: 'standard', extras: true }, { material: 'MeshLambertMaterial', extras: true });
  for (const config of configs) {
    const cpu = await run({ ...config, plain: true });
    const gpu = await run(config);
    const score = iou(mask(cpu.img), mask(gpu.img));
    const off = differing(cpu.img, gpu.img, 12);
    console.log(`${config.material}${config.extras ? ' with fog, clipping, a map, vertex colours' : ''}: IoU ${score.toFixed(5)}, ${off} pixels of other colours`);
    assert.ok(score >= 0.99, `IoU ${score}`);
    assert.ok(off < 0.01 * count(mask(cpu.img)), `${off} pixels of other colours`);
  }
  // The extras change the picture: clipped away, fogged, textured.
  const plain = await run({});
  const extras = await run({ extras: true });
  assert.ok(count(mask(extras.img)) < 0.9 * count(mask(plain.img)), 'the clipping plane cut nothing');
  assert.deepEqual(three.problems, []);
});

test("a user's own ShaderMaterial draws it: calling tessella_evaluate itself, or reading position and normal", async () => {
  for (const material of ['ShaderMaterial', 'ShaderMaterialAttributes']) {
    const cpu = await run({ material: 'ShaderMaterialAttributes', plain: true, castShadow: false });
    const gpu = await run({ material, castShadow: false });
    const score = iou(mask(cpu.img), mask(gpu.img));
    const off = differing(cpu.img, gpu.img, 12);
    console.log(`${material}: IoU ${score.toFixed(5)}, ${off} pixels of other colours`);
    assert.ok(score >= 0.99, `${material}: IoU ${score}`);
    assert.ok(off < 0.01 * count(mask(cpu.img)), `${material}: ${off} pixels of other colours`);
    assert.equal(gpu.log[0].instanced.length, 1);
  }
  assert.deepEqual(three.problems, []);
});

test("'per-frame' evaluation draws the pictures of 'per-draw' and of the CPU refinement, shadows cast on a plane: the vertices baked once, then read", async () => {
  for (const [scheme, level, normals] of [['pn', 8], ['png1', 6], ['phong', 5], ['pn-aen', 4, 'real']]) {
    const soup = normals === 'real' ? true : undefined;
    // Three frames: the first bakes (and evaluates per draw, instanced), the second and third
    // read the baked vertices.
    const config = { scheme, level, normals, plane: true, frames: 3 };
    const cpu = await run({ ...config, soup, plain: true });
    const perDraw = await run({ ...config, evaluation: 'per-draw' });
    const baked = await perFrame(config);
    assert.equal(baked.evaluation, 'per-frame');
    assert.equal(baked.fallback, null);
    assert.ok(baked.bakedBytes > 0);
    assert.equal(perDraw.evaluation, 'per-draw');
    for (const [name, other] of [['per-draw', perDraw], ['CPU', cpu]]) {
      const score = iou(mask(other.img), mask(baked.img));
      const off = differing(other.img, baked.img, 12);
      console.log(`${scheme} level ${level}: per-frame against ${name}: IoU ${score.toFixed(5)}, ${off} pixels of other colours`);
      assert.ok(score >= 0.99, `${scheme} against ${name}: IoU ${score}`);
      assert.ok(off < 0.01 * count(mask(other.img)), `${scheme} against ${name}: ${off} pixels of other colours`);
    }
    // The first frame draws instanced (the shadow map's and the picture's draws) and bakes (one
    // more draw, not instanced); then those two draws of the surface are indexed, not
    // instanced; the second frame uploads the welded topology (its index), the third nothing.
    const [first, second, third] = baked.log;
    assert.equal(first.instanced.length, 2);
    assert.equal(second.instanced.length, 0);
    assert.equal(second.draws, first.draws - 1 + 2);
    assert.ok(second.uploaded > 0);
    assert.equal(third.instanced.length, 0);
    assert.equal(third.draws, second.draws);
    assert.equal(third.uploaded, 0);
    // The baked variant's programs (picture, shadow depth) evaluate nothing: no tessella_evaluate, no nets.
    assert.ok(baked.bakedPrograms.length >= 2);
    for (const p of baked.bakedPrograms) assert.deepEqual(p, { evaluates: false, nets: false });
    // The shadows are cast: darker than the picture without the casting.
    const lit = await perFrame({ ...config, castShadow: false });
    assert.ok(count(darker(baked.img, lit.img)) > 2000, `${scheme}: no shadow cast`);
  }
  assert.deepEqual(three.problems, []);
});

test("'per-frame' follows a deforming source (nets uploaded, vertices baked each frame) as 'per-draw' and the CPU do, with a shadow-casting light", async () => {
  const config = { scheme: 'pn', level: 8, frames: 4, deform: true, plane: true };
  const baked = await perFrame(config);
  const perDraw = await run({ ...config, evaluation: 'per-draw' });
  const cpu = await run({ ...config, plain: true });
  const rest = await run({ scheme: 'pn', level: 8, plane: true, plain: true });
  assert.equal(baked.evaluation, 'per-frame');
  for (const [f, frame] of baked.log.entries()) {
    if (f === 0) continue;
    assert.equal(frame.instanced.length, 0);
    // (The second frame also uploads the welded topology, drawn from then on.)
    if (f === 1) continue;
    // The nets alone reach WebGL (the bake and its copy stay on the GPU).
    assert.equal(frame.uploaded, frame.uploadedBytes);
    assert.ok(frame.uploaded > 0 && frame.uploaded <= 256 * baked.faces);
  }
  for (const [name, other] of [['per-draw', perDraw], ['CPU', cpu]]) {
    const score = iou(mask(other.img), mask(baked.img));
    const off = differing(other.img, baked.img, 12);
    console.log(`deformed, per-frame against ${name}: IoU ${score.toFixed(5)}, ${off} pixels of other colours`);
    assert.ok(score >= 0.99, `against ${name}: IoU ${score}`);
    assert.ok(off < 0.01 * count(mask(other.img)), `against ${name}: ${off} pixels of other colours`);
  }
  const moved = iou(mask(baked.img), mask(rest.img));
  assert.ok(moved < 0.97, `IoU with the rest pose ${moved}: the surface did not follow`);
  assert.deepEqual(three.problems, []);
});

test("'per-frame' falls back to evaluating per draw where WebGL has no float render targets, and still draws the surface", async () => {
  const config = { scheme: 'pn', level: 8, frames: 2, plane: true };
  const fallback = await perFrame({ ...config, noFloatTargets: true });
  const cpu = await run({ ...config, plain: true });
  assert.equal(fallback.evaluation, 'per-draw');
  assert.match(fallback.fallback, /EXT_color_buffer_float/);
  assert.equal(fallback.bakedBytes, 0);
  const score = iou(mask(cpu.img), mask(fallback.img));
  const off = differing(cpu.img, fallback.img, 12);
  console.log(`fallen back: IoU ${score.toFixed(5)} with the CPU's, ${off} pixels of other colours`);
  assert.ok(score >= 0.99, `IoU ${score}`);
  assert.ok(off < 0.01 * count(mask(cpu.img)), `${off} pixels of other colours`);
  // No bake: the second frame draws as the first.
  assert.equal(fallback.log[1].draws, fallback.log[0].draws);
  assert.deepEqual(three.problems, []);
});

test("the default evaluation ('auto') under WebGLRenderer is 'per-frame' from the second frame (the pictures of 'per-draw'); without float render targets, or for a ShaderMaterial, 'per-draw' instanced", async () => {
  const config = { scheme: 'pn', level: 8, plane: true, frames: 3 };
  const auto = await byDefault(config);
  const perDraw = await run(config);
  assert.equal(auto.evaluation, 'per-frame');
  assert.equal(auto.fallback, null);
  assert.ok(auto.bakedBytes > 0);
  // The first frame instanced (shadow map and picture) and the bake; then indexed draws.
  assert.equal(auto.log[0].instanced.length, 2);
  for (const frame of auto.log.slice(1)) assert.equal(frame.instanced.length, 0);
  assert.equal(auto.log[2].uploaded, 0);
  const score = iou(mask(perDraw.img), mask(auto.img));
  const off = differing(perDraw.img, auto.img, 12);
  console.log(`default against per-draw: IoU ${score.toFixed(5)}, ${off} pixels of other colours`);
  assert.ok(score >= 0.99, `IoU ${score}`);
  assert.ok(off < 0.01 * count(mask(perDraw.img)), `${off} pixels of other colours`);
  // Fog, a clipping plane, a map by the coarse uvs and vertex colours: the baked variant blends
  // the corners as the instanced one does.
  const extras = await byDefault({ scheme: 'pn', level: 8, frames: 3, extras: true, castShadow: false });
  const extrasPerDraw = await run({ scheme: 'pn', level: 8, frames: 3, extras: true, castShadow: false });
  assert.equal(extras.evaluation, 'per-frame');
  assert.equal(extras.log[2].instanced.length, 0);
  const extrasOff = differing(extrasPerDraw.img, extras.img, 12);
  console.log(`default with fog, clipping, a map and vertex colours against per-draw: IoU ${iou(mask(extrasPerDraw.img), mask(extras.img)).toFixed(5)}, ${extrasOff} pixels of other colours`);
  assert.ok(iou(mask(extrasPerDraw.img), mask(extras.img)) >= 0.99);
  assert.ok(extrasOff < 0.01 * count(mask(extrasPerDraw.img)), `${extrasOff} pixels of other colours`);
  // Without float render targets: per draw, instanced in every frame, the same picture.
  const fallback = await byDefault({ ...config, noFloatTargets: true });
  assert.equal(fallback.evaluation, 'per-draw');
  assert.match(fallback.fallback, /EXT_color_buffer_float/);
  for (const frame of fallback.log) assert.equal(frame.instanced.length, 2);
  assert.ok(iou(mask(perDraw.img), mask(fallback.img)) >= 0.99);
  // A ShaderMaterial (whose code may name gl_InstanceID) stays instanced unless asked.
  const shader = await byDefault({ ...config, material: 'ShaderMaterial' });
  assert.equal(shader.evaluation, 'per-draw');
  assert.match(shader.fallback, /ShaderMaterial/);
  for (const frame of shader.log) assert.equal(frame.instanced.length, 2);
  assert.deepEqual(three.problems, []);
});
