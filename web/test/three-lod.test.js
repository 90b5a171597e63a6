// TessellatedMesh's `lod` option in headless Chromium (WebGL2 on SwiftShader): per-edge levels
// from the camera drawn with the GPU tessellator's patterns (one instanced draw per part used)
// look like refineGeometry's CPU refinement with the same lod, camera and size; the surface is
// watertight (no background pixel inside a closed mesh's silhouette, even with levels that differ
// wildly from edge to edge); a nearer camera draws more triangles; a frame that moves the camera
// and deforms the source uploads at most 256 bytes per coarse triangle. The page
// (three/index.html?page=lod: three/lod.js) and the package come from the repository: build js/ first.
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { PNG } from 'pngjs';
import { count, differing, gapsInside, iou, mask, openRepoPage } from './harness.js';

const SHOT = process.env.TESSELLA_THREE_SHOT;

let three;
before(async () => {
  three = await openRepoPage('web/test/three/index.html?page=lod', { global: 'tessellaLod' });
});
after(() => three?.close());

async function run(config, shot) {
  const out = await three.run(config);
  if (SHOT && shot) writeFileSync(`${SHOT}-${shot}.png`, PNG.sync.write(out.img));
  return out;
}

test('the LOD picture is refineGeometry\'s with the same lod, camera and size, and has no holes', async () => {
  for (const [spacing, eye, pixels, scheme = 'pn'] of [
    ['fractional-odd', [0, 0.4, 3], 6],
    ['equal', [0.5, 0.3, 2.2], 5],
    ['fractional-even', [1.2, -0.2, 1.5], 4],
    ['fractional-odd', [0.3, 0.6, 2.4], 5, 'png1'],
  ]) {
    const cpu = await run({ scheme, spacing, eye, pixels, plain: true }, `${spacing}-${scheme}-cpu`);
    const gpu = await run({ scheme, spacing, eye, pixels }, `${spacing}-${scheme}-gpu`);
    const a = mask(cpu.img);
    const b = mask(gpu.img);
    const score = iou(a, b);
    const frame = gpu.log[0];
    const gaps = gapsInside(gpu.img, a);
    console.log(`${scheme} ${spacing} from ${eye}: IoU ${score.toFixed(5)} (${count(a)} / ${count(b)} pixels), ${frame.triangles} triangles drawn in ${frame.instanced.length} instanced draws (CPU ${cpu.cpuTriangles}), ${gaps} holes`);
    assert.ok(count(b) > 0.1 * b.length, `${spacing}: only ${count(b)} pixels drawn`);
    assert.ok(score >= 0.99, `${spacing}: IoU ${score}`);
    assert.equal(gaps, 0, `${spacing}: ${gaps} background pixels inside the silhouette`);
    // Every triangle the CPU's adaptive refinement makes, drawn by the parts' instanced draws.
    assert.equal(frame.lodTriangles, cpu.cpuTriangles);
    assert.equal(frame.triangles, cpu.cpuTriangles);
    assert.equal(frame.instanced.reduce((n, d) => n + (d.count / 3) * d.instances, 0), cpu.cpuTriangles);
    // Lit: the GPU's points and normals are the CPU's (shading within a few pixels).
    const cpuLit = await run({ scheme, spacing, eye, pixels, plain: true, material: 'standard' }, `${spacing}-${scheme}-cpulit`);
    const gpuLit = await run({ scheme, spacing, eye, pixels, material: 'standard' }, `${spacing}-${scheme}-lit`);
    const off = differing(cpuLit.img, gpuLit.img, 12);
    console.log(`  lit: ${off} pixels shaded differently`);
    assert.ok(off < 0.01 * count(a), `${spacing}: ${off} pixels shaded differently`);
  }
  assert.deepEqual(three.problems, []);
});

test('a map by the coarse uvs and vertex colours look as on refineGeometry\'s mesh', async () => {
  const config = { spacing: 'fractional-odd', eye: [0.6, 0.5, 2.2], pixels: 5, extras: true, material: 'standard' };
  const cpu = await run({ ...config, plain: true }, 'extras-cpu');
  const gpu = await run(config, 'extras-gpu');
  const a = mask(cpu.img);
  const score = iou(a, mask(gpu.img));
  const off = differing(cpu.img, gpu.img, 12);
  console.log(`map and colours: IoU ${score.toFixed(5)}, ${off} of ${count(a)} pixels shaded differently`);
  assert.ok(score >= 0.99, `IoU ${score}`);
  assert.ok(off < 0.01 * count(a), `${off} pixels shaded differently`);
  assert.deepEqual(three.problems, []);
});

test('it casts a shadow like refineGeometry\'s mesh (the parts drawn into the shadow map too)', async () => {
  const config = { spacing: 'equal', eye: [0.4, 0.3, 3.2], pixels: 6, material: 'standard' };
  const lit = await run({ ...config, shadow: true, cast: false });
  const cpu = await run({ ...config, shadow: true, plain: true }, 'shadow-cpu');
  const gpu = await run({ ...config, shadow: true }, 'shadow-gpu');
  const off = differing(cpu.img, gpu.img, 12);
  const cast = differing(lit.img, gpu.img, 12);
  console.log(`shadow: ${cast} pixels darkened by it, ${off} differ from the CPU mesh's picture`);
  // Shadow map and picture: each draws the parts.
  assert.ok(gpu.log[0].instanced.length >= 2 * lit.log[0].instanced.length);
  assert.ok(cast > 2000, `only ${cast} pixels in the shadow`);
  assert.ok(off < 0.01 * cast, `${off} pixels differ`);
  assert.deepEqual(three.problems, []);
});

test('levels that differ wildly from edge to edge stay watertight', async () => {
  for (const spacing of ['fractional-odd', 'equal']) {
    const uniform = await run({ spacing, eye: [0.3, 0.5, 1.8], levels: [9] }, `${spacing}-uniform`);
    const wild = await run({ spacing, eye: [0.3, 0.5, 1.8], levels: [1, 17.3, 3.5, 40, 2.2, 8.9, 63] }, `${spacing}-wild`);
    const inside = mask(uniform.img);
    const gaps = gapsInside(wild.img, inside);
    const score = iou(inside, mask(wild.img));
    console.log(`${spacing}, per-edge levels 1 to 63: ${wild.log[0].triangles} triangles, ${gaps} holes, IoU ${score.toFixed(4)} with level 9 everywhere`);
    assert.equal(gaps, 0);
    assert.ok(score >= 0.97, `IoU ${score}`);
  }
  assert.deepEqual(three.problems, []);
});

test('a nearer camera draws more triangles; a frame that moves the camera and deforms the source uploads at most 256 bytes per coarse triangle', async () => {
  const far = await run({ eye: [0, 0, 6] });
  const near = await run({ eye: [0, 0, 2] });
  console.log(`triangles: ${far.log[0].triangles} from 6 away, ${near.log[0].triangles} from 2 away`);
  assert.ok(near.log[0].triangles > 2 * far.log[0].triangles);
  const frames = 5;
  const moving = await run({ eye: [0, 0, 4], to: [0.5, 0.3, 2], frames, deform: true });
  for (const [f, frame] of moving.log.entries()) {
    const per = frame.uploaded / moving.faces;
    console.log(`frame ${f}: ${frame.uploaded} bytes uploaded (${per.toFixed(1)} per coarse triangle: nets ${frame.netsBytes}, levels ${frame.lodBytes}), ${frame.triangles} triangles`);
    if (f === 0) continue; // the first frame also uploads the parts
    assert.ok(frame.lodBytes > 0 && frame.netsBytes > 0);
    assert.ok(frame.uploaded <= 256 * moving.faces, `frame ${f}: ${frame.uploaded} bytes for ${moving.faces} triangles`);
  }
  assert.ok(moving.log[frames - 1].triangles > moving.log[1].triangles);
  // The camera taken from the previous render (no camera option): the first frame draws the
  // levels of the mesh seen whole (not nothing), the second the camera's.
  const taken = await run({ eye: [0.5, 0.3, 2.5], cameraOption: false, frames: 2 });
  const given = await run({ eye: [0.5, 0.3, 2.5] });
  assert.ok(taken.log[0].triangles > moving.faces, `the first frame drew ${taken.log[0].triangles} triangles`);
  assert.equal(taken.log[1].triangles, given.log[0].triangles);
  assert.deepEqual(three.problems, []);
});
