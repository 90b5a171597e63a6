// readAnimated: an animated glTF poses as three.js poses it, the bundled sample has its clips
// and rest pose and refines like any mesh, and bad input throws a TessellaError by name.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { Buffer } from 'node:buffer';
import { readFileSync } from 'node:fs';
import { AnimatedMesh, Deformer, InstancedSurface, ready, readAnimated, refine, Refiner, TessellaError } from '../src/index.js';
import { bytes } from './helpers.js';

await ready;

const fixtures = 'crates/tessella-io/tests/fixtures/three';

function diagonal(points) {
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (const p of points) {
    for (let k = 0; k < 3; k++) {
      lo[k] = Math.min(lo[k], p[k]);
      hi[k] = Math.max(hi[k], p[k]);
    }
  }
  return Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

/** Flat `got` (3 per vertex) within `tolerance` of the points `want`, coordinate by coordinate. */
function assertClose(got, want, tolerance, what) {
  assert.equal(got.length, want.length * 3, `${what}: vertex count`);
  let worst = 0;
  want.forEach((p, i) => {
    for (let k = 0; k < 3; k++) worst = Math.max(worst, Math.abs(got[i * 3 + k] - p[k]));
  });
  assert.ok(worst <= tolerance, `${what}: off by ${worst}, more than ${tolerance}`);
}

function points(flat) {
  const out = [];
  for (let i = 0; i < flat.length; i += 3) out.push([flat[i], flat[i + 1], flat[i + 2]]);
  return out;
}

function assertUnit(normals, what) {
  for (let i = 0; i < normals.length; i += 3) {
    const length = Math.hypot(normals[i], normals[i + 1], normals[i + 2]);
    assert.ok(Math.abs(length - 1) < 1e-4, `${what}: normal ${i / 3} has length ${length}`);
  }
}

test('a three.js export (.gltf, embedded buffer) poses as three.js posed it, within 1e-6 of the diagonal', () => {
  const expected = JSON.parse(readFileSync(new URL(`../../${fixtures}/skinned-poses.json`, import.meta.url), 'utf8'));
  const anim = readAnimated(bytes(`${fixtures}/skinned.gltf`), 'gltf');
  assert.ok(anim instanceof AnimatedMesh);
  assert.ok(anim.clips.includes(expected.clip), anim.clips.join(', '));
  assert.equal(anim.vertexCount, expected.vertex_count);
  assert.ok(anim.indices instanceof Uint32Array);
  assert.ok(anim.indices.length > 0 && anim.indices.length % 3 === 0);
  assert.ok(anim.indices.every((i) => i < anim.vertexCount));

  // No clip: the rest pose three.js binds the skin in.
  const rest = anim.pose(null);
  assert.ok(rest.positions instanceof Float32Array && rest.normals instanceof Float32Array);
  assertClose(rest.positions, expected.bind_positions, 1e-6 * diagonal(expected.bind_positions), 'bind pose');
  assert.deepEqual(anim.pose(undefined, 3).positions, rest.positions);

  expected.times.forEach((time, k) => {
    const want = expected.positions[k];
    const pose = anim.pose(expected.clip, time);
    assertClose(pose.positions, want, 1e-6 * diagonal(want), `${expected.clip} at ${time} s`);
    assert.equal(pose.normals.length, anim.vertexCount * 3);
    assertUnit(pose.normals, `${expected.clip} at ${time} s`);
    // The same clip by index.
    assert.deepEqual(anim.pose(anim.clips.indexOf(expected.clip), time).positions, pose.positions);
  });
  // The clip moves the mesh (the comparison is not of two rest poses).
  const mid = anim.pose(expected.clip, expected.times[2]).positions;
  assert.ok(mid.some((v, i) => Math.abs(v - rest.positions[i]) > 0.01));
  const last = Math.max(...expected.times.slice(0, -1));
  assert.ok(anim.duration(expected.clip) >= last);
  anim.free();
  assert.throws(() => anim.pose(null), (e) => e instanceof TessellaError && e.message.includes('freed'));
});

test('the bundled animated creature (.glb): clips, durations, rest pose, and a posed frame refines', () => {
  const anim = readAnimated(bytes('samples/animated-creature.glb'), 'glb');
  assert.deepEqual(anim.clips, ['wave', 'hop', 'breathe']);
  assert.deepEqual(anim.clips.map((c) => anim.duration(c)), [2.0, 0.8, 2.0]);
  assert.deepEqual([0, 1, 2].map((c) => anim.duration(c)), [2.0, 0.8, 2.0]);
  assert.equal(anim.indices.length, 960);

  // The bind pose is the rest pose: the creature of samples/creature.obj, vertex for vertex in
  // the file's order (readMesh orders vertices by first use; the obj's own lines are read here).
  const obj = readFileSync(new URL('../../samples/creature.obj', import.meta.url), 'utf8').split('\n');
  const vertices = obj.filter((l) => l.startsWith('v ')).map((l) => l.split(/\s+/).slice(1, 4).map(Number));
  const corners = obj.filter((l) => l.startsWith('f ')).flatMap((l) => l.split(/\s+/).slice(1, 4).map((c) => parseInt(c, 10) - 1));
  const creature = { positions: new Float32Array(vertices.flat()), indices: new Uint32Array(corners) };
  assert.equal(anim.vertexCount, vertices.length);
  assertClose(anim.pose(null).positions, vertices, 1e-5, 'rest pose');
  assert.deepEqual(anim.indices, creature.indices);

  // Every clip moves it and carries unit normals; past the end holds the last pose.
  for (const clip of anim.clips) {
    const d = anim.duration(clip);
    const pose = anim.pose(clip, d * 0.37);
    assert.ok(pose.positions.some((v, i) => Math.abs(v - creature.positions[i]) > 0.02), `${clip} moves`);
    assertUnit(pose.normals, clip);
    assert.deepEqual(anim.pose(clip, d + 5).positions, anim.pose(clip, d).positions);
  }

  // A posed frame refines as a mesh: the creature's 320 triangles at level 4 become 320 × 16.
  const frame = anim.pose('wave', 0.5);
  const level = 4;
  const out = refine({ positions: frame.positions, normals: frame.normals, indices: anim.indices }, { scheme: 'pn', level });
  const want = refine(creature, { scheme: 'pn', level });
  assert.equal(out.indices.length, 320 * level * level * 3);
  assert.equal(out.positions.length, want.positions.length);
  assert.equal(out.normals.length, want.positions.length);
  // And frame by frame through a Refiner, the same as the one-shot refine.
  const refiner = new Refiner(anim.indices, { scheme: 'pn', level });
  const live = refiner.refine(frame.positions, frame.normals);
  assert.deepEqual(live.positions, out.positions);
  assert.deepEqual(live.indices, out.indices);
  refiner.free();
  anim.free();
});

function throwsTessella(fn, text) {
  assert.throws(fn, (e) => {
    assert.ok(e instanceof TessellaError, `${e?.name}: ${e?.message}`);
    assert.ok(e.message.includes(text), `${JSON.stringify(e.message)} lacks ${JSON.stringify(text)}`);
    return true;
  });
}

// skinned.gltf, its JSON changed by `edit`.
function editedFixture(edit) {
  const json = JSON.parse(new TextDecoder().decode(bytes(`${fixtures}/skinned.gltf`)));
  edit(json);
  return new TextEncoder().encode(JSON.stringify(json));
}

test('a file without normals: each pose gets normals computed by the core', () => {
  const withNormals = readAnimated(bytes(`${fixtures}/skinned.gltf`), 'gltf');
  const anim = readAnimated(
    editedFixture((json) => {
      for (const p of json.meshes[0].primitives) delete p.attributes.NORMAL;
    }),
    'gltf',
  );
  for (const time of [0, 1]) {
    const want = withNormals.pose('bend', time);
    const pose = anim.pose('bend', time);
    assert.deepEqual(pose.positions, want.positions);
    assert.equal(pose.normals.length, anim.vertexCount * 3);
    assertUnit(pose.normals, `computed at ${time} s`);
  }
  assertUnit(anim.pose(null).normals, 'computed at rest');
});

test('bad files, clips and times throw a TessellaError naming the problem, and tessella keeps working', () => {
  const glb = bytes('samples/animated-creature.glb');
  const anim = readAnimated(glb, 'glb');
  throwsTessella(() => anim.pose('swim', 0.5), 'swim');
  throwsTessella(() => anim.pose(7, 0.5), '7');
  throwsTessella(() => anim.duration('swim'), 'swim');
  throwsTessella(() => anim.duration(), 'which clip');
  throwsTessella(() => anim.pose(-1, 0), 'an index');
  throwsTessella(() => anim.pose(1.5, 0), 'an index');
  throwsTessella(() => anim.pose('wave', NaN), 'finite');
  throwsTessella(() => anim.pose('wave', Infinity), 'finite');
  throwsTessella(() => anim.pose(null, NaN), 'finite');
  throwsTessella(() => anim.pose('wave'), 'time must be a number');
  throwsTessella(() => readAnimated(new Uint8Array([1, 2, 3, 4, 5, 6, 7, 8]), 'glb'), 'glb');
  throwsTessella(() => readAnimated(new TextEncoder().encode('{"asset": '), 'gltf'), 'gltf');
  throwsTessella(() => readAnimated(glb.subarray(0, glb.length / 2), 'glb'), 'glb');
  throwsTessella(() => readAnimated(bytes('samples/creature.obj'), 'obj'), 'only glTF');
  // Key times that do not increase: the glTF reader refuses them, naming the sampler.
  const stalled = editedFixture((json) => {
    const sampler = json.animations[0].samplers[json.animations[0].channels[0].sampler];
    const accessor = json.accessors[sampler.input];
    const view = json.bufferViews[accessor.bufferView];
    const buffer = json.buffers[view.buffer];
    const [head, data] = buffer.uri.split(',');
    const raw = Buffer.from(data, 'base64');
    const at = (view.byteOffset ?? 0) + (accessor.byteOffset ?? 0);
    raw.writeFloatLE(raw.readFloatLE(at), at + 4);
    buffer.uri = `${head},${raw.toString('base64')}`;
  });
  throwsTessella(() => readAnimated(stalled, 'gltf'), 'animation 0 sampler 0: its times');
  // One the reader refuses: a weights channel on a joint, which draws no mesh.
  const weightsOnJoint = editedFixture((json) => {
    json.animations[0].channels[0].target = { node: 1, path: 'weights' };
  });
  throwsTessella(() => readAnimated(weightsOnJoint, 'gltf'), 'weights of node 1, which has no mesh');
  throwsTessella(() => readAnimated(glb, 'fbx'), 'fbx');
  throwsTessella(() => readAnimated('not bytes', 'glb'), 'Uint8Array');
  throwsTessella(() => readAnimated(glb, 3), 'format');
  throwsTessella(() => new AnimatedMesh(), 'readAnimated');
  // Nothing broke: the same object and the package still work.
  assert.equal(anim.pose('hop', 0.2).positions.length, anim.vertexCount * 3);
  assert.equal(readAnimated(glb.buffer.slice(glb.byteOffset, glb.byteOffset + glb.byteLength), 'animated-creature.glb').clips.length, 3);
});

test('Deformer.posedBounds: the posed vertices box grown by the reach times the longest posed edge; bad indices throw', () => {
  // Two joints: joint 1 moves x by 2; vertex 0 is half on each, vertex 1 on joint 1, vertex 2
  // on joint 0; the morph target lifts every vertex by its weight. Posed at weight 0.5:
  // (1,0,.5), (3,0,.5), (0,1,.5); the longest edge (3,0)-(0,1) is sqrt(10).
  const d = new Deformer({
    positions: new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]),
    joints: [0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0],
    weights: new Float32Array([0.5, 0.5, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0]),
    jointCount: 2,
    positionDeltas: new Float32Array([0, 0, 1, 0, 0, 1, 0, 0, 1]),
    targets: 1,
  });
  const identity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
  const moved = [...identity];
  moved[12] = 2;
  const matrices = new Float32Array([...identity, ...moved]);
  const b = d.posedBounds(matrices, new Float32Array([0.5]), new Uint32Array([0, 1, 2]), 0.5);
  const g = 0.5 * Math.sqrt(10);
  const want = [-g, -g, 0.5 - g, 3 + g, 1 + g, 0.5 + g];
  assert.equal(b.length, 6);
  want.forEach((w, k) => assert.ok(Math.abs(b[k] - w) < 1e-6, `${[...b]}`));
  assert.throws(() => d.posedBounds(matrices, new Float32Array([0.5]), new Uint32Array([0, 1, 9]), 0.5), (e) => e instanceof TessellaError && /vertex 9/.test(e.message));
  d.free();
});

test("InstancedSurface.controlReach: the reach posedBounds takes, per scheme (the core's)", () => {
  const indices = new Uint32Array([0, 1, 2]);
  for (const [options, want] of [
    [{ scheme: 'pn' }, 0.5],
    [{ scheme: 'pn-aen' }, 0.5],
    [{ scheme: 'phong', alpha: -0.625 }, 0.625],
    [{ scheme: 'flat' }, 0],
    [{ scheme: 'png1' }, null],
  ]) {
    const s = new InstancedSurface(indices, { ...options, level: 4 });
    assert.equal(s.controlReach(), want, JSON.stringify(options));
    s.free();
  }
});
