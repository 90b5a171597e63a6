// refineGltf: whole glTF scenes refined in wasm and written back as GLB. The Khronos validator
// finds no error, everything the scene held is kept, every triangle primitive has level² times
// its triangles, and the bytes are the native CLI's (`tessella refine in.glb -o out.glb`).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, rmSync } from 'node:fs';
import { join } from 'node:path';
import { ready, refineGltf, refineGltfWithReport, TessellaError } from '../src/index.js';
import { bytes, repo } from './helpers.js';
import { assertRefinedScene, assertValid, glbParts, hasCli, isTriangles, makeGlb, NO_CLI, primitives, scratch, tessella, triangleCount } from './gltf-helpers.js';

await ready;

const SAMPLES = ['scene.glb', 'scene-quantized.glb', 'animated-creature.glb'];
const LEVEL = 3;

for (const name of SAMPLES) {
  test(`refineGltf ${name} level ${LEVEL}: valid, everything kept, ${LEVEL * LEVEL}× the triangles`, async () => {
    const input = bytes(`samples/${name}`);
    const out = refineGltf(input, { level: LEVEL });
    assert.ok(out instanceof Uint8Array);
    await assertValid(assert, out, name);
    assertRefinedScene(assert, glbParts(input).json, glbParts(out).json, LEVEL, name);
  });
}

test('refineGltf gives the native CLI\'s bytes', (t) => {
  if (!hasCli) return t.skip(NO_CLI);
  const dir = scratch();
  try {
    for (const name of SAMPLES) {
      const out = join(dir, `refined-${name}`);
      tessella('refine', join(repo, 'samples', name), '-o', out, '--level', String(LEVEL));
      const native = new Uint8Array(readFileSync(out));
      const wasm = refineGltf(bytes(`samples/${name}`), { level: LEVEL });
      assert.equal(wasm.length, native.length, `${name}: length`);
      assert.ok(Buffer.from(wasm).equals(Buffer.from(native)), `${name}: the same bytes`);
    }
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});

test('refineGltfWithReport: one entry per triangle primitive, its level and triangles', () => {
  const input = bytes('samples/scene.glb');
  const { json } = glbParts(input);
  const { glb, primitives: report } = refineGltfWithReport(input, { scheme: 'phong', level: 2 });
  const triangle = primitives(json).filter(([, , p]) => isTriangles(p));
  assert.deepEqual(report.map((r) => [r.mesh, r.primitive]), triangle.map(([m, i]) => [m, i]));
  report.forEach((r, k) => {
    assert.equal(r.level, 2);
    assert.equal(r.coarseTriangles, triangleCount(json, triangle[k][2]));
    assert.equal(r.triangles, 4 * r.coarseTriangles);
    assert.ok(r.vertices > 0 && Number.isInteger(r.degenerate) && Array.isArray(r.notes));
  });
  assert.ok(Buffer.from(glb).equals(Buffer.from(refineGltf(input, { scheme: 'phong', level: 2 }))));
});

test('maxEdge gives each primitive its own level; shorter edges, higher levels', () => {
  const input = bytes('samples/scene.glb');
  const coarse = refineGltfWithReport(input, { maxEdge: 0.2 }).primitives;
  const fine = refineGltfWithReport(input, { maxEdge: 0.05 }).primitives;
  coarse.forEach((r, k) => {
    assert.ok(fine[k].level >= r.level, `primitive ${k}: ${fine[k].level} < ${r.level}`);
    assert.equal(r.triangles, r.level * r.level * r.coarseTriangles);
  });
  assert.ok(fine.some((r, k) => r.level > coarse[k].level));
  assert.ok(new Set(fine.map((r) => r.level)).size > 1, 'parts of different sizes get different levels');
});

test('a .gltf with its external buffer (options.buffers) refines as the .glb does', () => {
  const input = bytes('samples/scene.glb');
  const { json, bin } = glbParts(input);
  json.buffers[0].uri = 'scene.bin';
  const text = new TextEncoder().encode(JSON.stringify(json));
  const fromGltf = refineGltf(text, { level: 2, buffers: { 'scene.bin': bin.slice() } });
  const fromGlb = refineGltf(input, { level: 2 });
  assert.deepEqual(glbParts(fromGltf).json.meshes, glbParts(fromGlb).json.meshes);
  assert.ok(Buffer.from(glbParts(fromGltf).bin).equals(Buffer.from(glbParts(fromGlb).bin)));
  assert.throws(() => refineGltf(text, { level: 2 }), (e) => e instanceof TessellaError && /scene\.bin/.test(e.message));
});

test('refineGltf errors: truncated bytes, an unknown required extension, level with maxEdge, ...', () => {
  const input = bytes('samples/scene.glb');
  const refused = (fn, pattern) =>
    assert.throws(fn, (e) => {
      assert.ok(e instanceof TessellaError && e instanceof Error, `${e}`);
      assert.match(e.message, pattern);
      return true;
    });
  refused(() => refineGltf(input.subarray(0, input.length - 100), { level: 3 }), /scene\.glb: malformed GLB/);
  refused(() => refineGltf(input.subarray(0, 40)), /malformed GLB/);
  refused(() => refineGltf(new Uint8Array(0)), /malformed glTF file/);

  const { json, bin } = glbParts(input);
  json.extensionsUsed = [...(json.extensionsUsed ?? []), 'EXT_not_a_real_extension'];
  json.extensionsRequired = [...(json.extensionsRequired ?? []), 'EXT_not_a_real_extension'];
  refused(() => refineGltf(makeGlb(json, bin), { level: 3 }), /requires the extension EXT_not_a_real_extension, which tessella does not know/);
  // Used but not required: ignored, as glTF says.
  json.extensionsRequired.pop();
  assert.ok(refineGltf(makeGlb(json, bin), { level: 1 }).length > 0);

  refused(() => refineGltf(input, { level: 3, maxEdge: 0.1 }), /level and maxEdge both given/);
  refused(() => refineGltf(input, { maxEdge: -1 }), /maxEdge: must be a length above 0/);
  refused(() => refineGltf(input, { maxEdge: NaN }), /maxEdge: must be a length above 0/);
  refused(() => refineGltf(input, { level: 2.5 }), /a fractional level works on one mesh/);
  refused(() => refineGltf(input, { lod: 'tolerance:0.01' }), /lod works on one mesh/);
  refused(() => refineGltf(input, { soup: true }), /soup works on one mesh/);
  refused(() => refineGltf(input, { level: 0 }), /level: must be a finite number above 0/);
  refused(() => refineGltf(input, { levle: 3 }), /levle: unknown option/);
  refused(() => refineGltf(input, { scheme: 'loop' }), /see schemes\(\)/);
  refused(() => refineGltf('scene.glb'), /refineGltf takes the file as a Uint8Array or ArrayBuffer/);
  refused(() => refineGltf(input, 3), /options must be an object/);
  // The module still works.
  assert.ok(refineGltf(input, { level: 1 }).length > 0);
});

test('refineGltf tangents: recomputed (default) or carried, the CLI\'s --tangents', async (t) => {
  const input = bytes('samples/scene.glb');
  const recomputed = refineGltf(input, { level: 2 });
  const carried = refineGltf(input, { level: 2, tangents: 'carried' });
  assert.ok(Buffer.from(refineGltf(input, { level: 2, tangents: 'recomputed' })).equals(Buffer.from(recomputed)));
  assert.ok(!Buffer.from(carried).equals(Buffer.from(recomputed)));
  await assertValid(assert, carried, 'scene.glb, tangents carried');
  assert.throws(() => refineGltf(input, { level: 2, tangents: 'guessed' }), (e) => {
    assert.ok(e instanceof TessellaError);
    assert.match(e.message, /tangents/);
    return true;
  });
  if (!hasCli) return t.skip(NO_CLI);
  const dir = scratch();
  try {
    const out = join(dir, 'carried.glb');
    tessella('refine', join(repo, 'samples', 'scene.glb'), '-o', out, '--level', '2', '--tangents', 'carried');
    assert.ok(Buffer.from(carried).equals(readFileSync(out)), 'the CLI\'s bytes');
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});
