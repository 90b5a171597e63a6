// TessellatedMesh following a SkinnedMesh that three's GLTFLoader made and its AnimationMixer
// plays (no GPU here: the nets texture is evaluated with the cubic Bernstein basis): at a given
// time its coarse vertices are the ones three skins (SkinnedMesh.getVertexPosition), and its
// surface is tessella's refinement of those vertices; a morphing Mesh's influences are
// followed too; a paused skeleton uploads nothing; rays hit the curved surface.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import {
  AnimationMixer,
  BufferAttribute,
  IcosahedronGeometry,
  Matrix3,
  Matrix4,
  Mesh,
  MeshStandardMaterial,
  Raycaster,
  Scene,
  Vector3,
} from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { ready, refine, TessellaError } from '../src/index.js';
import { TessellatedMesh } from '../src/three.js';
import { cubicPoint } from './helpers.js';

await ready;

async function creature() {
  const bytes = readFileSync(new URL('../../samples/animated-creature.glb', import.meta.url));
  const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  const gltf = await new Promise((resolve, reject) => new GLTFLoader().parse(buffer, '', resolve, reject));
  let skinned = null;
  gltf.scene.traverse((o) => {
    if (o.isSkinnedMesh) skinned = o;
  });
  return { gltf, skinned };
}

// The vertices three skins (getVertexPosition: morph targets, then skinning) and their
// normals moved by the blended matrix B = bindMatrixInverse · Σ w boneMatrix · bindMatrix:
// `inverse` by B's inverse transpose (what tessella does, and glTF's tools), otherwise by B's
// upper 3×3 (what three's skinning shader does; the two differ where the blend of rotations is
// not a rotation).
function threeSkins(mesh, inverse = true) {
  const g = mesh.geometry;
  const n = g.getAttribute('position').count;
  const positions = new Float32Array(3 * n);
  const normals = new Float32Array(3 * n);
  const v = new Vector3();
  const skinIndex = g.getAttribute('skinIndex');
  const skinWeight = g.getAttribute('skinWeight');
  const normal = g.getAttribute('normal');
  mesh.skeleton.update();
  const bone = new Matrix4();
  const blend = new Matrix4();
  for (let i = 0; i < n; i++) {
    mesh.getVertexPosition(i, v);
    v.toArray(positions, 3 * i);
    blend.set(0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0);
    for (let k = 0; k < 4; k++) {
      const w = skinWeight.getComponent(i, k);
      if (w === 0) continue;
      bone.fromArray(mesh.skeleton.boneMatrices, 16 * skinIndex.getComponent(i, k));
      for (let e = 0; e < 16; e++) blend.elements[e] += w * bone.elements[e];
    }
    const m = new Matrix4().multiplyMatrices(mesh.bindMatrixInverse, blend).multiply(mesh.bindMatrix);
    const nm = inverse ? new Matrix3().getNormalMatrix(m) : new Matrix3().setFromMatrix4(m);
    v.fromBufferAttribute(normal, i).applyMatrix3(nm).normalize();
    v.toArray(normals, 3 * i);
  }
  return { positions, normals, indices: g.index.array };
}

test('a SkinnedMesh played by AnimationMixer: the surface refines the vertices three skins, at every time', async () => {
  const { gltf, skinned } = await creature();
  assert.ok(skinned !== null, 'the creature is a SkinnedMesh');
  assert.ok(gltf.animations.length >= 2);
  const scene = gltf.scene;
  const level = 4;
  const mesh = new TessellatedMesh(skinned, new MeshStandardMaterial(), { scheme: 'pn', level });
  assert.equal(skinned.visible, false, 'the source is hidden');
  assert.equal(mesh.parent, skinned.parent, 'and replaced in its parent');
  const mixer = new AnimationMixer(scene);
  const extent = new Vector3();
  let frames = 0;
  for (const clip of gltf.animations) {
    const action = mixer.clipAction(clip).play();
    for (const time of [0.1, 0.37, clip.duration * 0.8]) {
      mixer.setTime(time);
      const before = mesh.netsTexture.version;
      scene.updateMatrixWorld(true); // three does this before rendering: the mesh follows
      assert.equal(mesh.netsTexture.version, before + 1, `${clip.name} ${time}: the nets are rebuilt once`);
      const three = threeSkins(skinned);
      skinned.geometry.computeBoundingBox();
      const size = new Vector3().fromArray(three.positions, 0).length() + skinned.geometry.boundingBox.getSize(extent).length();
      // The surface: tessella's refinement of three's own skinned vertices and normals.
      const cpu = refine(three, { scheme: 'pn', level, soup: true, origin: true });
      let worst = 0;
      for (let v = 0; v < cpu.faces.length; v++) {
        const l = Array.from(cpu.barycentric.subarray(3 * v, 3 * v + 3));
        const p = cubicPoint(mesh, cpu.faces[v], l);
        for (let a = 0; a < 3; a++) worst = Math.max(worst, Math.abs(p[a] - cpu.positions[3 * v + a]));
      }
      assert.ok(worst < 1e-5 * size, `${clip.name} at ${time}: the surface is off by ${worst} (size ${size})`);
      // Against three's shader normals (the blended matrix itself): close, not equal.
      const shaderNormals = refine(threeSkins(skinned, false), { scheme: 'pn', level, soup: true });
      let apart = 0;
      for (let i = 0; i < shaderNormals.positions.length; i++) apart = Math.max(apart, Math.abs(shaderNormals.positions[i] - cpu.positions[i]));
      assert.ok(apart < 1e-3 * size, `${clip.name} at ${time}: three's normals move the surface by ${apart}`);
      frames++;
    }
    // Paused: the skeleton holds, nothing is rebuilt or uploaded.
    const version = mesh.netsTexture.version;
    scene.updateMatrixWorld(true);
    mesh.onBeforeRender(fakeWebGL2);
    assert.equal(mesh.netsTexture.version, version, `${clip.name}: paused, yet rebuilt`);
    action.stop();
  }
  assert.equal(frames, 3 * gltf.animations.length);
  mesh.dispose();
});

// What TessellatedMesh reads of a WebGLRenderer (WebGL2).
const fakeWebGL2 = {
  capabilities: { maxTextureSize: 4096, maxVertexTextures: 16 },
  getContext: () => ({ drawElementsInstanced() {}, vertexAttribDivisor() {}, texStorage2D() {}, RGBA32F: 0x8814 }),
};

test('a Mesh with morph targets: its influences move the surface; absolute targets too', () => {
  for (const relative of [true, false]) {
    const geometry = new IcosahedronGeometry(1, 1);
    const base = geometry.getAttribute('position');
    const target = new Float32Array(base.count * 3);
    for (let i = 0; i < base.count; i++) {
      // Stretch along y: a displacement (relative) or the moved position (absolute).
      target[3 * i + 1] = relative ? base.getY(i) : 2 * base.getY(i);
      if (!relative) {
        target[3 * i] = base.getX(i);
        target[3 * i + 2] = base.getZ(i);
      }
    }
    geometry.morphAttributes.position = [new BufferAttribute(target, 3)];
    geometry.morphTargetsRelative = relative;
    const source = new Mesh(geometry, new MeshStandardMaterial());
    source.updateMorphTargets();
    const mesh = new TessellatedMesh(source, undefined, { scheme: 'pn', level: 2 });
    const top = () => mesh.geometry.boundingBox.max.y;
    const rest = top();
    source.morphTargetInfluences[0] = 0.5;
    mesh.updateMatrixWorld();
    // Halfway to twice as tall: the top rises by about half the rest height.
    assert.ok(Math.abs(top() - 1.5 * rest) < 0.02 * rest, `${relative}: top ${top()} from ${rest}`);
    // The coarse corners: three's getVertexPosition (morphed, unskinned).
    const v = new Vector3();
    const f = 7;
    const corner = geometry.index === null ? 3 * f : geometry.index.getX(3 * f);
    source.getVertexPosition(corner, v);
    const p = cubicPoint(mesh, f, [1, 0, 0]);
    assert.ok(v.distanceTo(new Vector3(...p)) < 1e-6, `${relative}: corner ${p} vs ${v.toArray()}`);
    mesh.dispose();
  }
});

test('rays hit the curved surface, not the coarse one', () => {
  const scene = new Scene();
  // A coarse icosahedron: its faces are well inside the unit sphere; the PN surface bulges out.
  const geometry = new IcosahedronGeometry(1, 0);
  // Smooth normals (the sphere's): flat ones would make the PN surface the flat faces.
  geometry.setAttribute('normal', geometry.getAttribute('position').clone());
  const source = new Mesh(geometry, new MeshStandardMaterial());
  scene.add(source);
  const mesh = new TessellatedMesh(source, undefined, { scheme: 'pn', level: 8 });
  scene.updateMatrixWorld(true);
  const ray = new Raycaster(new Vector3(0.1, 0.05, 5), new Vector3(0, 0, -1));
  const [hit] = ray.intersectObject(mesh);
  const [coarse] = ray.intersectObject(new Mesh(source.geometry));
  assert.ok(hit !== undefined && hit.object === mesh);
  // The CPU refinement's surface along the ray: its closest triangle hit, independently.
  const cpu = refine(
    { positions: source.geometry.getAttribute('position').array, normals: source.geometry.getAttribute('normal').array, indices: Uint32Array.from({ length: 60 }, (_, i) => i) },
    { scheme: 'pn', level: 8 },
  );
  const g = new Mesh();
  g.geometry.setAttribute('position', new BufferAttribute(cpu.positions, 3));
  g.geometry.setIndex(new BufferAttribute(cpu.indices, 1));
  const [want] = ray.intersectObject(g);
  assert.ok(Math.abs(hit.distance - want.distance) < 1e-6, `${hit.distance} vs ${want.distance}`);
  assert.ok(hit.distance < coarse.distance - 0.01, `the curved surface (${hit.distance}) is nearer than the coarse one (${coarse.distance})`);
  mesh.dispose();
});

test('a SkinnedMesh without a skeleton is refused with a TessellaError', async () => {
  const { skinned } = await creature();
  skinned.skeleton = undefined;
  assert.throws(() => new TessellatedMesh(skinned, undefined, {}), (e) => e instanceof TessellaError && /skeleton/.test(e.message));
});

test("posing: the GPU is ruled out where it cannot build the nets, and 'gpu' then throws with the reason", async () => {
  const cases = [
    [{ scheme: 'png1', level: 4 }, /'png1' nets are built on the CPU/],
    [{ scheme: 'pn', level: 4, normalsFromSource: false }, /normals are computed from the posed positions/],
    [{ scheme: 'pn', lod: 'screen:8', spacing: 'equal' }, /lod reads the nets on the CPU/],
  ];
  for (const [options, reason] of cases) {
    const { skinned } = await creature();
    const mesh = new TessellatedMesh(skinned, undefined, options);
    assert.equal(mesh.posedOn, 'cpu');
    assert.match(mesh.posingFallback, reason);
    mesh.dispose();
    const again = await creature();
    assert.throws(
      () => new TessellatedMesh(again.skinned, undefined, { ...options, posing: 'gpu' }),
      (e) => e instanceof TessellaError && e.message.startsWith("posing: 'gpu' cannot run: ") && reason.test(e.message),
    );
  }
  // Allowed, it waits for the first render (no renderer here: the CPU poses); 'cpu' gives no reason.
  const { skinned } = await creature();
  for (const posing of [undefined, 'gpu', 'cpu']) {
    const mesh = new TessellatedMesh(skinned, undefined, { scheme: 'pn', level: 4, posing });
    assert.equal(mesh.posedOn, 'cpu');
    assert.equal(mesh.posingFallback, null);
    mesh.dispose();
  }
  // A source that neither skins nor morphs is not posed; an unknown posing is refused.
  const plain = new TessellatedMesh(new Mesh(new IcosahedronGeometry(1, 1)), undefined, { level: 2, posing: 'gpu' });
  assert.equal(plain.posedOn, null);
  plain.dispose();
  assert.throws(() => new TessellatedMesh(new IcosahedronGeometry(1, 1), undefined, { posing: 'webgl' }), (e) => e instanceof TessellaError && /posing: "webgl" is none of 'auto', 'gpu', 'cpu'/.test(e.message));
});
