// A Refiner's frames equal one-shot refine of the same positions, bit for bit, written into
// the same output arrays each frame; a refused frame keeps the last good one.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { ready, readMesh, refine, Refiner, TessellaError } from '../src/index.js';
import { bytes, sameBits } from './helpers.js';

await ready;

// The mesh twisted about its y axis by `t` radians per unit of height (positions only).
function twisted(positions, t) {
  const out = new Float32Array(positions.length);
  for (let i = 0; i < positions.length; i += 3) {
    const [x, y, z] = positions.subarray(i, i + 3);
    const a = t * y;
    out[i] = Math.cos(a) * x - Math.sin(a) * z;
    out[i + 1] = y;
    out[i + 2] = Math.sin(a) * x + Math.cos(a) * z;
  }
  return out;
}

for (const scheme of ['phong', 'pn', 'png1']) {
  test(`${scheme}: frames equal one-shot refine, in the same arrays`, () => {
    const m = readMesh(bytes('samples/creature.obj'), 'obj');
    const twists = [0, 0.4, -0.7];
    // One-shot results first: a one-shot refine may grow the wasm memory, which detaches the
    // refiner's views (as documented).
    const wants = twists.map((t) => refine({ positions: twisted(m.positions, t), indices: m.indices }, { scheme, level: 6 }));
    const refiner = new Refiner(m.indices, { scheme, level: 6 });
    let first = null;
    twists.forEach((t, k) => {
      const out = refiner.refine(twisted(m.positions, t));
      assert.ok(sameBits(out.positions, wants[k].positions), `positions at twist ${t}`);
      assert.ok(sameBits(out.normals, wants[k].normals), `normals at twist ${t}`);
      assert.deepEqual(out.indices, wants[k].indices);
      // The same views every frame: frames allocate nothing that grows the memory.
      first ??= out;
      assert.equal(out.positions, first.positions);
      assert.equal(out.normals, first.normals);
    });
    // Given normals are used, not recomputed.
    const normals = new Float32Array(m.normals.length).fill(0);
    for (let i = 1; i < normals.length; i += 3) normals[i] = 1;
    const want = refine({ positions: m.positions, indices: m.indices, normals }, { scheme, level: 6 });
    const out = refiner.refine(m.positions, normals);
    assert.ok(sameBits(out.normals, want.normals));
    // A bad frame is refused and the output keeps the last good frame.
    const keep = out.positions.slice();
    const bad = m.positions.slice();
    bad[7] = NaN;
    assert.throws(() => refiner.refine(bad), (e) => e instanceof TessellaError && e.message.includes('non-finite'));
    assert.throws(() => refiner.refine(m.positions.subarray(3)), (e) => e instanceof TessellaError && e.message.includes('vertices'));
    assert.ok(sameBits(refiner.output.positions, keep));
    refiner.free();
    assert.throws(() => refiner.refine(m.positions), TessellaError);
  });
}

test('a refiner with uvs carries them like refine does', () => {
  const positions = new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0.5]);
  const indices = new Uint32Array([0, 1, 2, 2, 1, 3]);
  const uvs = new Float32Array([0, 0, 1, 0, 0, 1, 1, 1]);
  const want = refine({ positions, indices, uvs }, { scheme: 'pn', level: 3 });
  const refiner = new Refiner(indices, { scheme: 'pn', level: 3, uvs });
  const out = refiner.refine(positions);
  assert.ok(sameBits(out.uvs, want.uvs));
  assert.ok(sameBits(out.positions, want.positions));
});
