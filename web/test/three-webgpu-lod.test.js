// TessellatedMesh's `lod` option under three's WebGPURenderer (WebGPU on SwiftShader): the parts
// drawn by the adaptive WGSL the wasm generates (AdaptiveSurface.wgsl(), from the same core
// pieces as the WebGL path's GLSL), called from TSL. Its picture is refineGeometry's CPU
// refinement with the same lod, camera and size (drawn by the same renderer) and WebGLRenderer's
// LOD picture; no holes; as many triangles as the CPU's; a nearer camera draws more; a map by
// the coarse uvs and vertex colours as under WebGL; and no WebGPU validation error or warning.
// The page (three/index.html?page=lod: three/lod.js, `renderer: 'webgpu'`) and the package come
// from the repository: build js/ first.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { PNG } from 'pngjs';
import { count, differing, gapsInside, iou, mask, openRepoPage } from './harness.js';

const SHOT = process.env.TESSELLA_THREE_SHOT;

let three;
before(async () => {
  three = await openRepoPage('web/test/three/index.html?page=lod', { webgpu: true, global: 'tessellaLod' });
});
after(() => three?.close());

async function run(config, shot) {
  const out = await three.run(config);
  if (SHOT && shot) {
    const png = new PNG({ width: out.img.width, height: out.img.height });
    out.img.data.copy(png.data);
    writeFileSync(`${SHOT}-${shot}.png`, PNG.sync.write(png));
  }
  return out;
}

test('under WebGPURenderer the LOD picture is refineGeometry\'s and WebGLRenderer\'s LOD picture, with no holes', async () => {
  for (const [spacing, eye, pixels, scheme = 'pn'] of [
    ['fractional-odd', [0, 0.4, 3], 6],
    ['equal', [0.5, 0.3, 2.2], 5],
    ['fractional-even', [1.2, -0.2, 1.5], 4],
    ['fractional-odd', [0.3, 0.6, 2.4], 5, 'png1'],
  ]) {
    const config = { scheme, spacing, eye, pixels, material: 'standard' };
    const cpu = await run({ ...config, plain: true, renderer: 'webgpu' }, `${spacing}-${scheme}-cpu`);
    const gpu = await run({ ...config, renderer: 'webgpu' }, `${spacing}-${scheme}-webgpu`);
    const gl = await run(config, `${spacing}-${scheme}-webgl`);
    const [a, b, c] = [cpu, gpu, gl].map((x) => mask(x.img));
    const frame = gpu.log[0];
    const gaps = gapsInside(gpu.img, a);
    const off = differing(cpu.img, gpu.img, 12);
    console.log(`${scheme} ${spacing} from ${eye}: IoU ${iou(a, b).toFixed(5)} vs CPU, ${iou(b, c).toFixed(5)} vs WebGL (${count(b)} pixels); ${frame.lodTriangles} triangles in ${frame.instanced.length} instanced draws (CPU ${cpu.cpuTriangles}); ${gaps} holes; ${off} pixels shaded differently from the CPU's`);
    assert.ok(count(b) > 0.1 * b.length, `${spacing}: only ${count(b)} pixels drawn`);
    assert.ok(iou(a, b) >= 0.99, `${spacing}: IoU ${iou(a, b)} vs CPU`);
    assert.ok(iou(b, c) >= 0.99, `${spacing}: IoU ${iou(b, c)} vs WebGL`);
    assert.equal(gaps, 0, `${spacing}: ${gaps} background pixels inside the silhouette`);
    // Every triangle of the CPU's adaptive refinement, drawn by the parts' instanced draws.
    assert.equal(frame.lodTriangles, cpu.cpuTriangles);
    assert.equal(frame.instanced.reduce((n, d) => n + (d.count / 3) * d.instances, 0), cpu.cpuTriangles);
    // Lit: the GPU's points and normals are the CPU's (shading within a few pixels).
    assert.ok(off < 0.01 * count(a), `${spacing}: ${off} pixels shaded differently`);
  }
  assert.deepEqual(three.problems, []);
});

test('under WebGPURenderer the levels follow the camera: nearer, more triangles, each frame the CPU\'s count', async () => {
  const far = await run({ eye: [0, 0.4, 4], renderer: 'webgpu' });
  const near = await run({ eye: [0, 0.4, 1.6], renderer: 'webgpu' });
  const cpuFar = await run({ eye: [0, 0.4, 4], plain: true, renderer: 'webgpu' });
  const cpuNear = await run({ eye: [0, 0.4, 1.6], plain: true, renderer: 'webgpu' });
  const drawn = (out) => out.log[0].instanced.reduce((n, d) => n + (d.count / 3) * d.instances, 0);
  console.log(`far ${drawn(far)} triangles (CPU ${cpuFar.cpuTriangles}), near ${drawn(near)} (CPU ${cpuNear.cpuTriangles})`);
  assert.equal(drawn(far), cpuFar.cpuTriangles);
  assert.equal(drawn(near), cpuNear.cpuTriangles);
  assert.ok(drawn(near) > 2 * drawn(far), `near ${drawn(near)}, far ${drawn(far)}`);
  // One mesh, the camera moving from far to near over frames (the levels of the last render).
  const moving = await run({ eye: [0, 0.4, 4], to: [0, 0.4, 1.6], frames: 3, cameraOption: false, renderer: 'webgpu' });
  const [first, , last] = moving.log;
  console.log(`moving: ${first.lodTriangles} then ${last.lodTriangles} triangles`);
  assert.ok(last.lodTriangles > first.lodTriangles);
  assert.deepEqual(three.problems, []);
});

test('under WebGPURenderer a map by the coarse uvs and vertex colours look as under WebGLRenderer and on refineGeometry\'s mesh', async () => {
  const config = { spacing: 'fractional-odd', eye: [0.6, 0.5, 2.2], pixels: 5, extras: true, material: 'standard' };
  const cpu = await run({ ...config, plain: true, renderer: 'webgpu' }, 'extras-cpu');
  const gpu = await run({ ...config, renderer: 'webgpu' }, 'extras-webgpu');
  const gl = await run(config, 'extras-webgl');
  const a = mask(cpu.img);
  const offCpu = differing(cpu.img, gpu.img, 24);
  const offGl = differing(gl.img, gpu.img, 24);
  console.log(`extras: ${offCpu} pixels differ from the CPU's, ${offGl} from WebGL's (of ${count(a)})`);
  assert.ok(iou(a, mask(gpu.img)) >= 0.99);
  assert.ok(offCpu < 0.02 * count(a), `${offCpu} pixels differ from the CPU's`);
  assert.ok(offGl < 0.02 * count(a), `${offGl} pixels differ from WebGL's`);
  assert.deepEqual(three.problems, []);
});
