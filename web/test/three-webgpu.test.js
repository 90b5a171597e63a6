// tessella/three's TessellatedMesh under three's WebGPURenderer (three/webgpu, node materials)
// in headless Chromium (WebGPU on SwiftShader): the WGSL from the wasm, called from TSL as the
// material's positionNode, draws what the CPU refinement drawn as a plain Mesh looks like, in
// one instanced draw; while the source deforms each frame uploads the nets texture (and three's
// uniforms) alone; it casts and receives shadows. The page (three/index.html?page=webgpu: three/webgpu.js) and the package
// come from the repository (js/src, js/dist, js/node_modules/three): build js/ first
// (`cd js && npm ci && npm run build`).
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { PNG } from 'pngjs';
import { count, differing, iou, mask, openRepoPage } from './harness.js';
import { assertFollows, assertShadows, deformed } from './three-checks.js';

const SHOT = process.env.TESSELLA_THREE_SHOT;

let three;
before(async () => {
  three = await openRepoPage('web/test/three/index.html?page=webgpu', { webgpu: true, global: 'tessellaThree' });
  // On the WebGPU backend, not three's WebGL2 fallback.
  assert.equal(three.ready, true);
});
after(() => three?.close());
const run = (config) => three.run(config);

function save(path, left, right) {
  const out = new PNG({ width: 2 * left.width, height: left.height });
  for (const [img, x0] of [[left, 0], [right, left.width]]) {
    for (let y = 0; y < img.height; y++) {
      // Read back top row first under WebGPU; a PNG's first row is its top.
      img.data.copy(out.data, 4 * (y * out.width + x0), 4 * y * img.width, 4 * (y + 1) * img.width);
    }
  }
  writeFileSync(path, PNG.sync.write(out));
}

test('under WebGPURenderer, TessellatedMesh with MeshStandardMaterial looks like refineGeometry drawn as a Mesh, in one instanced draw', async () => {
  for (const [scheme, level, normals] of [['pn', 8], ['png1', 6], ['phong', 5], ['pn-aen', 4, 'real']]) {
    // Real normals differ on the two sides of a C0 edge: the CPU side draws refine's soup (see
    // three-mesh.test.js).
    const soup = normals === 'real' ? true : undefined;
    const cpu = await run({ scheme, level, normals, soup, plain: true, castShadow: false });
    const gpu = await run({ scheme, level, normals, castShadow: false });
    const a = mask(cpu.img);
    const b = mask(gpu.img);
    assert.ok(count(b) > 0.08 * b.length, `${scheme}: only ${count(b)} pixels drawn`);
    const score = iou(a, b);
    const off = differing(cpu.img, gpu.img, 12);
    console.log(`${scheme}${normals ? ` (${normals} normals)` : ''} level ${level}: silhouette IoU ${score.toFixed(5)} (${count(a)} / ${count(b)} pixels), ${off} pixels shaded differently`);
    if (SHOT) save(SHOT.replace(/\.png$/, `-${scheme}.png`), cpu.img, gpu.img);
    assert.ok(score >= 0.99, `${scheme}: IoU ${score}`);
    // The shading too: the GPU's normals are the CPU's.
    assert.ok(off < 0.01 * count(a), `${scheme}: ${off} pixels shaded differently`);
    // One draw in all: instanced, the pattern's level² triangles once per coarse triangle.
    const [frame] = gpu.log;
    assert.deepEqual(frame.instanced, [{ count: 3 * level * level, instances: gpu.faces }]);
    assert.equal(frame.draws, 0);
    assert.deepEqual(cpu.log[0].instanced, []);
    assert.equal(cpu.log[0].draws, 1);
  }
  assert.deepEqual(three.problems, []);
});

test('under WebGPURenderer, while the source deforms, a frame uploads the nets texture and uniforms: at most 256 bytes per coarse triangle', async () => {
  const frames = 4;
  const runs = await deformed(run, frames);
  const { gpu, cpu } = runs;
  for (const [f, frame] of gpu.log.entries()) {
    const all = frame.buffers + frame.textures;
    console.log(`frame ${f}: ${all} bytes written (${(all / gpu.faces).toFixed(1)} per coarse triangle): nets texture ${frame.textures}, buffers ${frame.buffers}; uploadedBytes ${frame.uploadedBytes}`);
    if (f === 0) continue; // the first frame also uploads the pattern
    assert.equal(frame.textures, frame.uploadedBytes, 'the texture writes are the nets');
    assert.ok(frame.textures > 0, 'the moved nets are uploaded');
    assert.ok(all <= 256 * gpu.faces, `frame ${f}: ${all} bytes for ${gpu.faces} triangles`);
    assert.deepEqual(frame.instanced, [{ count: 3 * 64, instances: gpu.faces }]);
  }
  // The CPU mesh of the same frames rewrites every refined vertex.
  console.log(`refineGeometry's mesh, for comparison, holds ${cpu.faces} coarse triangles' ${cpu.faces * 64} refined ones`);
  assertFollows(runs);
  assert.deepEqual(three.problems, []);
});

test('under WebGPURenderer it casts shadows (directional and point lights) and receives them, like the CPU mesh', async () => {
  await assertShadows(run, (cpuShaded, shaded) => {
    if (SHOT) save(SHOT.replace(/\.png$/, '-shadow.png'), cpuShaded, shaded);
  });
  assert.deepEqual(three.problems, []);
});

test("a user's node material calls the documented TSL function (tessellaFunctions' normal): the CPU mesh's normals", async () => {
  for (const [scheme, level] of [['pn', 6], ['png1', 4]]) {
    const cpu = await run({ scheme, level, plain: true, castShadow: false, custom: true });
    const gpu = await run({ scheme, level, castShadow: false, custom: true });
    const off = differing(cpu.img, gpu.img, 12);
    const score = iou(mask(cpu.img), mask(gpu.img));
    console.log(`${scheme} level ${level}, normals as colours: IoU ${score.toFixed(5)}, ${off} pixels of other colours`);
    if (SHOT) save(SHOT.replace(/\.png$/, `-custom-${scheme}.png`), cpu.img, gpu.img);
    assert.ok(score >= 0.99, `IoU ${score}`);
    assert.ok(off < 0.01 * count(mask(cpu.img)), `${off} pixels of other colours`);
    assert.deepEqual(gpu.log[0].instanced, [{ count: 3 * level * level, instances: gpu.faces }]);
  }
  assert.deepEqual(three.problems, []);
});

test('under WebGPURenderer a map reads the coarse uvs, and vertex colours the coarse colours, blended over each coarse triangle as on the CPU mesh', async () => {
  const plain = await run({ castShadow: false });
  for (const extra of [{ map: true }, { colours: true }, { map: true, colours: true }]) {
    const cpu = await run({ plain: true, castShadow: false, ...extra });
    const gpu = await run({ castShadow: false, ...extra });
    const score = iou(mask(cpu.img), mask(gpu.img));
    const off = differing(cpu.img, gpu.img, 12);
    // The extra changes the picture: not a texture read at one uv, not one colour.
    const changed = differing(plain.img, gpu.img, 12);
    const name = Object.keys(extra).join(' and ');
    console.log(`${name}: IoU ${score.toFixed(5)}, ${off} pixels of other colours than the CPU mesh's, ${changed} than without`);
    if (SHOT) save(SHOT.replace(/\.png$/, `-${Object.keys(extra).join('-')}.png`), cpu.img, gpu.img);
    assert.ok(score >= 0.99, `${name}: IoU ${score}`);
    assert.ok(off < 0.01 * count(mask(cpu.img)), `${name}: ${off} pixels of other colours`);
    assert.ok(changed > 0.3 * count(mask(cpu.img)), `${name}: ${changed} pixels changed`);
  }
  assert.deepEqual(three.problems, []);
});

test('under WebGPURenderer two TessellatedMeshes of one scheme and topology draw each its own nets and material (one instanced draw each)', async () => {
  const cpu = await run({ plain: true, castShadow: false, twin: true });
  const gpu = await run({ castShadow: false, twin: true });
  const one = await run({ castShadow: false });
  const score = iou(mask(cpu.img), mask(gpu.img));
  const off = differing(cpu.img, gpu.img, 12);
  console.log(`two meshes: IoU ${score.toFixed(5)}, ${off} pixels of other colours`);
  if (SHOT) save(SHOT.replace(/\.png$/, '-twin.png'), cpu.img, gpu.img);
  assert.ok(score >= 0.99, `IoU ${score}`);
  assert.ok(off < 0.01 * count(mask(cpu.img)), `${off} pixels of other colours`);
  assert.ok(count(mask(gpu.img)) > count(mask(one.img)) + 1000, 'the second mesh drew nothing');
  // three orders the draws (front to back): either order.
  const draws = gpu.log[0].instanced.slice().sort((a, b) => a.instances - b.instances);
  assert.deepEqual(draws, [{ count: 3 * 64, instances: gpu.faces }, { count: 3 * 64, instances: gpu.faces }]);
  assert.deepEqual(three.problems, []);
});

test("under WebGPURenderer three's other materials draw it too (Lambert, Phong, Physical, Normal), with fog and clipping", async () => {
  const configs = ['MeshLambertMaterial', 'MeshPhongMaterial', 'MeshPhysicalMaterial', 'MeshNormalMaterial'].map((material) => ({ material }));
  configs.push({ fogClip: true }, { material: 'MeshLambertMaterial', fogClip: true });
  for (const config of configs) {
    const cpu = await run({ ...config, plain: true, castShadow: false });
    const gpu = await run({ ...config, castShadow: false });
    const score = iou(mask(cpu.img), mask(gpu.img));
    const off = differing(cpu.img, gpu.img, 12);
    console.log(`${config.material ?? 'MeshStandardMaterial'}${config.fogClip ? ' with fog and a clipping plane' : ''}: IoU ${score.toFixed(5)}, ${off} pixels of other colours`);
    assert.ok(score >= 0.99, `IoU ${score}`);
    assert.ok(off < 0.01 * count(mask(cpu.img)), `${off} pixels of other colours`);
  }
  // Fog and clipping change the picture: clipped away.
  const plain = await run({ castShadow: false });
  const cut = await run({ castShadow: false, fogClip: true });
  assert.ok(count(mask(cut.img)) < 0.9 * count(mask(plain.img)), 'the clipping plane cut nothing');
  assert.deepEqual(three.problems, []);
});

test("under WebGPURenderer's WebGL2 fallback backend, a TessellaError says what is missing", async () => {
  const { thrown } = await three.page.evaluate(() => window.tessellaThree.fallback());
  assert.match(thrown ?? '', /needs its WebGPU backend/);
  assert.deepEqual(three.problems, []);
});
