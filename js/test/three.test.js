// tessella/three: refineGeometry gives refine's arrays in a new indexed BufferGeometry and
// interpolates other float attributes; RefinedGeometry follows a deforming source in place.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { BufferAttribute, BufferGeometry, IcosahedronGeometry, TorusKnotGeometry } from 'three';
import { ready, refine } from '../src/index.js';
import { RefinedGeometry, refineGeometry } from '../src/three.js';
import { sameBits } from './helpers.js';

await ready;

function indexed(g) {
  return {
    positions: g.getAttribute('position').array,
    normals: g.getAttribute('normal').array,
    uvs: g.getAttribute('uv')?.array,
    indices: g.index.array,
  };
}

test('refineGeometry equals refine and carries uvs', () => {
  const source = new TorusKnotGeometry(1, 0.3, 24, 6);
  const out = refineGeometry(source, { scheme: 'pn', level: 4 });
  const want = refine(indexed(source), { scheme: 'pn', level: 4 });
  assert.ok(sameBits(out.getAttribute('position').array, want.positions));
  assert.ok(sameBits(out.getAttribute('normal').array, want.normals));
  assert.ok(sameBits(out.getAttribute('uv').array, want.uvs));
  assert.deepEqual(out.index.array, want.indices);
  assert.notEqual(out, source);
});

test('other float attributes are interpolated: a color linear in position stays linear under flat refinement', () => {
  const source = new IcosahedronGeometry(1, 1); // non-indexed
  const p = source.getAttribute('position').array;
  const color = (x, y, z) => [0.5 + 0.25 * x, 0.5 - 0.2 * y + 0.1 * z, 0.3 * z];
  const colors = new Float32Array(p.length);
  for (let i = 0; i < p.length; i += 3) colors.set(color(p[i], p[i + 1], p[i + 2]), i);
  source.setAttribute('color', new BufferAttribute(colors, 3));
  const out = refineGeometry(source, { scheme: 'flat', level: 5 });
  const q = out.getAttribute('position').array;
  const c = out.getAttribute('color').array;
  assert.equal(c.length, q.length);
  assert.ok(out.index !== null);
  for (let i = 0; i < q.length; i += 3) {
    const want = color(q[i], q[i + 1], q[i + 2]);
    for (let k = 0; k < 3; k++) assert.ok(Math.abs(c[i + k] - want[k]) < 1e-5, `vertex ${i / 3}`);
  }
});

test('RefinedGeometry updates its attributes in place from a deforming source', () => {
  const source = new TorusKnotGeometry(1, 0.3, 16, 5);
  const rest = source.getAttribute('position').array.slice();
  const live = new RefinedGeometry(source, { scheme: 'png1', level: 3, normalsFromSource: false });
  const positions = live.geometry.getAttribute('position').array;
  for (const s of [1.5, 0.5]) {
    const moved = rest.map((v, i) => (i % 3 === 1 ? v * s : v));
    source.getAttribute('position').array.set(moved);
    const version = live.geometry.getAttribute('position').version;
    const g = live.update();
    assert.equal(g, live.geometry);
    assert.equal(g.getAttribute('position').array, positions, 'the same array');
    assert.ok(g.getAttribute('position').version > version, 'marked for upload');
    const want = refine({ positions: moved, indices: source.index.array, uvs: source.getAttribute('uv').array }, { scheme: 'png1', level: 3 });
    assert.ok(sameBits(positions, want.positions));
    assert.ok(sameBits(g.getAttribute('normal').array, want.normals));
  }
  live.dispose();
});
