// tessella/gltf-transform: `document.transform(tessellate(options))` refines a glTF-Transform
// Document in place: valid when written, materials, textures, nodes, skins and animations kept
// (the same objects), level² times the triangles; compressed Documents (Draco, meshopt) too,
// since a Document holds decoded geometry.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { Logger, NodeIO, PropertyType } from '@gltf-transform/core';
import { ALL_EXTENSIONS, EXTMeshoptCompression, KHRDracoMeshCompression } from '@gltf-transform/extensions';
import draco3d from 'draco3dgltf';
import { MeshoptDecoder, MeshoptEncoder } from 'meshoptimizer';
import { refineGltf, TessellaError } from '../src/index.js';
import { tessellate } from '../src/gltf-transform.js';
import { bytes } from './helpers.js';
import { assertRefinedScene, assertValid, glbParts } from './gltf-helpers.js';

const io = new NodeIO().registerExtensions(ALL_EXTENSIONS);

// Per primitive: mode, triangles (or vertices), material, semantics, morph targets.
function shape(document) {
  return document
    .getRoot()
    .listMeshes()
    .flatMap((mesh) =>
      mesh.listPrimitives().map((p) => ({
        mode: p.getMode(),
        count: p.getIndices()?.getCount() ?? p.getAttribute('POSITION').getCount(),
        material: p.getMaterial(),
        semantics: p.listSemantics().sort(),
        targets: p.listTargets().map((t) => t.listSemantics().sort()),
      })),
    );
}

const KINDS = ['listNodes', 'listMeshes', 'listMaterials', 'listTextures', 'listAnimations', 'listSkins', 'listCameras', 'listScenes'];

function assertTessellated(before, document, objects, level, where) {
  for (const kind of KINDS) {
    const now = document.getRoot()[kind]();
    assert.equal(now.length, objects[kind].length, `${where}: ${kind}`);
    assert.ok(now.every((o, i) => o === objects[kind][i]), `${where}: ${kind} are the same objects`);
  }
  const after = shape(document);
  assert.equal(after.length, before.length);
  before.forEach((b, i) => {
    const a = after[i];
    assert.equal(a.material, b.material, `${where} primitive ${i}: material`);
    assert.deepEqual(a.targets, b.targets, `${where} primitive ${i}: morph targets`);
    assert.deepEqual(a.semantics.filter((s) => !(s === 'NORMAL' && !b.semantics.includes(s))), b.semantics, `${where} primitive ${i}: attributes`);
    if (b.mode === 4) assert.equal(a.count, level * level * b.count, `${where} primitive ${i}: triangles × ${level * level}`);
    else assert.equal(a.count, b.count, `${where} primitive ${i}: ${b.mode} kept`);
  });
  // No accessor is left without a user.
  for (const accessor of document.getRoot().listAccessors()) {
    assert.ok(accessor.listParents().some((p) => p.propertyType !== PropertyType.ROOT), `${where}: an accessor no one uses`);
  }
}

const objects = (document) => Object.fromEntries(KINDS.map((k) => [k, document.getRoot()[k]()]));

for (const [name, level] of [
  ['scene.glb', 3],
  ['animated-creature.glb', 2],
  ['scene-quantized.glb', 3],
]) {
  test(`tessellate({ level: ${level} }) on ${name} read by NodeIO: valid, everything kept, ×${level * level} triangles`, async () => {
    const input = bytes(`samples/${name}`);
    const document = await io.readBinary(input);
    const before = shape(document);
    const kept = objects(document);
    await document.transform(tessellate({ scheme: 'pn', level }));
    assertTessellated(before, document, kept, level, name);
    const written = await io.writeBinary(document);
    await assertValid(assert, written, name);
    // What refineGltf makes of the file, as glTF-Transform writes it.
    assertRefinedScene(assert, glbParts(input).json, glbParts(written).json, level, name);
    const direct = glbParts(refineGltf(input, { scheme: 'pn', level })).json;
    const viaTransform = glbParts(written).json;
    assert.deepEqual(
      viaTransform.meshes.map((m) => m.primitives.map((p) => viaTransform.accessors[p.attributes.POSITION].count)),
      direct.meshes.map((m) => m.primitives.map((p) => direct.accessors[p.attributes.POSITION].count)),
      `${name}: the same refined vertices as refineGltf`,
    );
  });
}

test('tessellate with maxEdge and Phong; a second transform refines again', async () => {
  const document = await io.readBinary(bytes('samples/scene.glb'));
  const before = shape(document);
  await document.transform(tessellate({ scheme: 'phong', alpha: 0.5, maxEdge: 10 }));
  assertTessellated(before, document, objects(document), 1, 'maxEdge 10 (level 1)');
  await document.transform(tessellate({ scheme: 'flat', level: 2 }));
  assertTessellated(before, document, objects(document), 2, 'then level 2');
  await assertValid(assert, await io.writeBinary(document), 'twice');
});

test('Draco and meshopt Documents are refined (decoded in the Document) and written compressed again', async () => {
  await MeshoptEncoder.ready;
  await MeshoptDecoder.ready;
  // Errors only: Draco's encoder says it skips the points and lines.
  const codecs = new NodeIO().setLogger(new Logger(Logger.Verbosity.ERROR)).registerExtensions(ALL_EXTENSIONS).registerDependencies({
    'draco3d.decoder': await draco3d.createDecoderModule(),
    'draco3d.encoder': await draco3d.createEncoderModule(),
    'meshopt.decoder': MeshoptDecoder,
    'meshopt.encoder': MeshoptEncoder,
  });
  for (const [Extension, name] of [
    [KHRDracoMeshCompression, 'KHR_draco_mesh_compression'],
    [EXTMeshoptCompression, 'EXT_meshopt_compression'],
  ]) {
    const plain = await codecs.readBinary(bytes('samples/scene.glb'));
    plain.createExtension(Extension).setRequired(true);
    const compressed = await codecs.writeBinary(plain);
    assert.ok(glbParts(compressed).json.extensionsRequired.includes(name));

    const document = await codecs.readBinary(compressed);
    const before = shape(document);
    await document.transform(tessellate({ level: 2 }));
    assertTessellated(before, document, objects(document), 2, name);
    const written = await codecs.writeBinary(document);
    assert.ok(glbParts(written).json.extensionsRequired.includes(name), `${name}: written compressed`);
    await assertValid(assert, written, name);
  }
});

test('tessellate refuses bad options with a TessellaError, and leaves the Document as it was', async () => {
  const document = await io.readBinary(bytes('samples/scene.glb'));
  const before = shape(document);
  await assert.rejects(document.transform(tessellate({ level: 3, maxEdge: 1 })), (e) => e instanceof TessellaError && /level and maxEdge both given/.test(e.message));
  await assert.rejects(document.transform(tessellate({ spacing: 'equal' })), (e) => e instanceof TessellaError && /spacing works on one mesh/.test(e.message));
  assert.deepEqual(shape(document), before);
  assert.throws(() => tessellate({ buffers: {} }), TessellaError);
});
