// Every bad input throws a TessellaError (an Error) with a message that says what was wrong,
// never a wasm trap, and the module keeps working afterwards.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { maxTextureWidth, ready, readMesh, refine, Refiner, schemes, TessellaError, writeMesh } from '../src/index.js';
import { bytes } from './helpers.js';

await ready;

const expected = JSON.parse(readFileSync(new URL('../../tests/corpus/expected.json', import.meta.url), 'utf8'));
const triangle = { positions: new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]), indices: new Uint32Array([0, 1, 2]) };

// A refinement whose answer is known without tessella: flat level 2 of one triangle has the
// corners and the three edge midpoints.
function stillWorks() {
  const out = refine(triangle, { scheme: 'flat', level: 2 });
  assert.equal(out.positions.length, 6 * 3);
  assert.equal(out.indices.length, 4 * 3);
  const points = new Set();
  for (let i = 0; i < out.positions.length; i += 3) points.add([...out.positions.subarray(i, i + 3)].join(','));
  for (const p of ['0,0,0', '1,0,0', '0,1,0', '0.5,0,0', '0,0.5,0', '0.5,0.5,0']) assert.ok(points.has(p), p);
}

function throwsTessella(fn, text) {
  assert.throws(fn, (e) => {
    assert.ok(e instanceof TessellaError, `${e?.name}: ${e?.message}`);
    assert.ok(e instanceof Error);
    assert.ok(e.message.includes(text), `${JSON.stringify(e.message)} lacks ${JSON.stringify(text)}`);
    return true;
  });
  stillWorks();
}

test('every bad file of tests/corpus throws a TessellaError with its expected message', () => {
  const bad = Object.entries(expected.bad);
  assert.ok(bad.length >= 40);
  for (const [name, text] of bad) throwsTessella(() => readMesh(bytes(`tests/corpus/bad/${name}`), name), text);
});

test('every good file of tests/corpus loads with its counts (a .gltf with its external buffer)', () => {
  const buffers = { 'buffer%20data.bin': bytes('tests/corpus/good/buffer data.bin') };
  for (const [name, counts] of Object.entries(expected.good)) {
    const m = readMesh(bytes(`tests/corpus/good/${name}`), name, { buffers });
    assert.equal(m.positions.length, counts.vertices * 3, name);
    assert.equal(m.indices.length, counts.triangles * 3, name);
  }
});

test('bad meshes and options throw TessellaError with the reason', () => {
  const nan = triangle.positions.slice();
  nan[4] = NaN;
  throwsTessella(() => refine({ ...triangle, positions: nan }), 'vertex 1 has a non-finite coordinate');
  throwsTessella(() => refine({ ...triangle, indices: new Uint32Array([0, 1, 3]) }), 'uses vertex 3, but the mesh has only 3 vertices');
  throwsTessella(() => refine({ ...triangle, indices: new Int32Array([0, -1, 2]) }), 'indices[1] is -1');
  throwsTessella(() => refine({ ...triangle, indices: new Float32Array([0, 1, 2]) }), 'integer typed array');
  throwsTessella(() => refine({ ...triangle, indices: new Uint32Array([0, 1]) }), 'not a multiple of 3');
  throwsTessella(() => refine({ ...triangle, positions: new Float32Array(8) }), 'positions has 8 numbers');
  throwsTessella(() => refine({ ...triangle, indices: new Uint32Array([0, 1, 1]) }), 'uses vertex 1 twice');
  throwsTessella(() => refine({ ...triangle, normals: new Float32Array(9) }), 'zero-length normal');
  throwsTessella(() => refine(triangle, { level: 0 }), 'level: must be a finite number above 0');
  throwsTessella(() => refine(triangle, { level: NaN }), 'got NaN');
  throwsTessella(() => refine(triangle, { scheme: 'loop' }), 'unknown scheme "loop"');
  throwsTessella(() => refine(triangle, { alpha: Infinity }), 'alpha: must be finite');
  throwsTessella(() => refine(triangle, { levle: 3 }), 'levle: unknown option');
  throwsTessella(() => refine(triangle, { level: 1e6 }), 'over the limit');
  throwsTessella(() => refine(triangle, { lod: 'screen:4' }), 'needs a camera');
  throwsTessella(() => refine(null), 'the mesh must be');
  throwsTessella(() => writeMesh(triangle, 'fbx'), 'unknown mesh format');
  throwsTessella(() => writeMesh({ ...triangle, indices: new Uint32Array([0, 1, 9]) }, 'glb'), '9');
  throwsTessella(() => new Refiner(new Uint32Array([0, 1]), {}), 'not a multiple of 3');
  throwsTessella(() => new Refiner(triangle.indices, { scheme: 'nope' }), 'unknown scheme');
  assert.ok(schemes().includes('png1'));
  // The layouts' width, read by three.js from the wasm: WebGL2's guaranteed MAX_TEXTURE_SIZE.
  assert.equal(maxTextureWidth(), 2048);
});
