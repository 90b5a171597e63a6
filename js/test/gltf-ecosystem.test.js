// Files as the glTF tools people use write them: gltfpack (-cc: meshopt compression and
// quantisation) and glTF-Transform's CLI (draco, meshopt, quantize, instance) on the bundled
// scene, each refined by the native CLI (which decodes meshopt) and checked with the Khronos
// validator; the Draco file is refused with the way out, which then works. refineGltf (wasm)
// gives the CLI's bytes where it can read the file, and refuses what it cannot decode.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, rmSync } from 'node:fs';
import { join } from 'node:path';
import { NodeIO } from '@gltf-transform/core';
import { ALL_EXTENSIONS } from '@gltf-transform/extensions';
import { ready, refineGltf, TessellaError } from '../src/index.js';
import { repo } from './helpers.js';
import { assertRefinedScene, assertValid, glbParts, gltfpack, gltfTransform, hasCli, NO_CLI, scratch, tessella } from './gltf-helpers.js';

await ready;

const LEVEL = 3;
const sample = join(repo, 'samples', 'scene.glb');
const dir = scratch();
test.after(() => rmSync(dir, { recursive: true, force: true }));

const read = (file) => new Uint8Array(readFileSync(file));

// Refines `file` with the native CLI and checks the result against the file; returns its path.
async function refineNative(file, where) {
  const out = file.replace(/\.glb$/, '-refined.glb');
  tessella('refine', file, '-o', out, '--level', String(LEVEL));
  const refined = read(out);
  await assertValid(assert, read(file), `${where} (input)`);
  await assertValid(assert, refined, where);
  assertRefinedScene(assert, glbParts(read(file)).json, glbParts(refined).json, LEVEL, where);
  return out;
}

const used = (file) => glbParts(read(file)).json.extensionsUsed ?? [];

test('gltfpack -cc (EXT_meshopt_compression, KHR_mesh_quantization): the CLI refines it and writes it decoded', async (t) => {
  if (!hasCli) return t.skip(NO_CLI);
  const packed = join(dir, 'gltfpack.glb');
  gltfpack('-i', sample, '-o', packed, '-cc');
  assert.ok(used(packed).includes('EXT_meshopt_compression') && used(packed).includes('KHR_mesh_quantization'), `${used(packed)}`);
  const out = await refineNative(packed, 'gltfpack -cc');
  assert.ok(!used(out).includes('EXT_meshopt_compression'), 'the refined file is written decoded');
});

test('glTF-Transform meshopt: the CLI refines it', async (t) => {
  if (!hasCli) return t.skip(NO_CLI);
  const file = join(dir, 'meshopt.glb');
  gltfTransform('meshopt', sample, file);
  assert.ok(used(file).includes('EXT_meshopt_compression'));
  await refineNative(file, 'gltf-transform meshopt');
});

test('refineGltf (wasm) refuses EXT_meshopt_compression by name, pointing to the native tool', () => {
  const file = join(dir, 'meshopt-wasm.glb');
  gltfTransform('meshopt', sample, file);
  assert.throws(() => refineGltf(read(file), { level: LEVEL }), (e) => {
    assert.ok(e instanceof TessellaError);
    assert.match(e.message, /EXT_meshopt_compression/);
    assert.match(e.message, /native/);
    return true;
  });
});

test('glTF-Transform quantize (KHR_mesh_quantization): the CLI refines it, wasm gives the same bytes', async (t) => {
  if (!hasCli) return t.skip(NO_CLI);
  const file = join(dir, 'quantize.glb');
  gltfTransform('quantize', sample, file);
  assert.ok(used(file).includes('KHR_mesh_quantization'));
  const out = await refineNative(file, 'gltf-transform quantize');
  assert.ok(Buffer.from(refineGltf(read(file), { level: LEVEL })).equals(readFileSync(out)));
});

test('glTF-Transform draco: refused by name with the way out (gltf-transform copy), which then refines', async (t) => {
  if (!hasCli) return t.skip(NO_CLI);
  const file = join(dir, 'draco.glb');
  gltfTransform('draco', sample, file);
  assert.ok(used(file).includes('KHR_draco_mesh_compression'));
  const wayOut = /KHR_draco_mesh_compression[\s\S]*@gltf-transform\/cli copy in\.glb plain\.glb/;
  assert.throws(() => tessella('refine', file, '-o', join(dir, 'draco-refined.glb'), '--level', String(LEVEL)), (e) => {
    assert.match(e.stderr, wayOut);
    return true;
  });
  assert.throws(() => refineGltf(read(file), { level: LEVEL }), (e) => e instanceof TessellaError && wayOut.test(e.message));
  // The way out: glTF-Transform decodes Draco on reading and writes plain geometry.
  const plain = join(dir, 'draco-plain.glb');
  gltfTransform('copy', file, plain);
  assert.ok(!used(plain).includes('KHR_draco_mesh_compression'));
  const out = await refineNative(plain, 'draco, then gltf-transform copy');
  assert.ok(Buffer.from(refineGltf(read(plain), { level: LEVEL })).equals(readFileSync(out)));
});

test('glTF-Transform instance (EXT_mesh_gpu_instancing): refined, the instancing and its attributes kept', async (t) => {
  if (!hasCli) return t.skip(NO_CLI);
  // The scene with its first mesh on six more sibling nodes, each moved, turned and scaled
  // (`instance` batches a mesh used by several nodes; it leaves animated scenes alone, so the
  // animation goes).
  const io = new NodeIO().registerExtensions(ALL_EXTENSIONS);
  const document = await io.readBinary(read(sample));
  const root = document.getRoot();
  for (const animation of root.listAnimations()) animation.dispose();
  const scene = root.getDefaultScene() ?? root.listScenes()[0];
  const mesh = root.listMeshes()[0];
  for (let i = 0; i < 6; i++) {
    const s = Math.sin(0.2 * i);
    scene.addChild(
      document
        .createNode(`copy ${i}`)
        .setMesh(mesh)
        .setTranslation([3 * i, 0, 5])
        .setRotation([0, s, 0, Math.sqrt(1 - s * s)])
        .setScale([1 + 0.1 * i, 1, 1]),
    );
  }
  const many = join(dir, 'many.glb');
  await io.write(many, document);
  const file = join(dir, 'instanced.glb');
  gltfTransform('instance', many, file);
  assert.ok(used(file).includes('EXT_mesh_gpu_instancing'), `${used(file)}`);

  const out = await refineNative(file, 'gltf-transform instance');
  assert.ok(used(out).includes('EXT_mesh_gpu_instancing'));
  // The same instances, attribute by attribute.
  const instances = async (path) => {
    const doc = await io.read(path);
    return doc
      .getRoot()
      .listNodes()
      .map((n) => n.getExtension('EXT_mesh_gpu_instancing'))
      .filter(Boolean)
      .map((b) => Object.fromEntries(b.listSemantics().map((s) => [s, Array.from(b.getAttribute(s).getArray())])));
  };
  const before = await instances(file);
  assert.equal(before.length, 1);
  assert.deepEqual(Object.keys(before[0]).sort(), ['ROTATION', 'SCALE', 'TRANSLATION']);
  assert.equal(before[0].TRANSLATION.length, 7 * 3);
  assert.deepEqual(await instances(out), before);
  assert.ok(Buffer.from(refineGltf(read(file), { level: LEVEL })).equals(readFileSync(out)));
});
