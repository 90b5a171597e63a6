// tessella/three's TessellatedMesh with `lod` without a GPU: the levels a camera gives draw as
// many triangles as refine's adaptive refinement with the same lod, camera and size (through
// the mesh's transform), one child per part used; what a frame uploads; tolerance LOD without
// a camera; raycasts on the LOD surface; the errors. The pictures (equal to refineGeometry's,
// watertight) are tested in a browser: web/test/three-lod.test.js.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { IcosahedronGeometry, MeshStandardMaterial, OrthographicCamera, PerspectiveCamera, Raycaster, Scene, TorusKnotGeometry, Vector3 } from 'three';
import { ready, refine, TessellaError } from '../src/index.js';
import { TessellatedMesh } from '../src/three.js';

await ready;

function coarse(g) {
  const p = g.getAttribute('position');
  const indices = g.index !== null ? g.index.array : Uint32Array.from({ length: p.count }, (_, i) => i);
  return { positions: p.array, normals: g.getAttribute('normal').array, indices };
}

function drawn(mesh) {
  let n = 0;
  for (const c of mesh.lod.children) if (c.visible) n += (c.geometry.drawRange.count / 3) * c.geometry.instanceCount;
  return n;
}

test('the levels of a camera draw the triangles of refine with the same lod, camera and size, through the mesh\'s transform', () => {
  const g = new TorusKnotGeometry(0.8, 0.3, 24, 5);
  const scene = new Scene();
  for (const spacing of ['equal', 'fractional-odd', 'fractional-even']) {
    for (const [eye, fov, size, pixels] of [[[0, 1, 4], 45, [640, 480], 6], [[1.5, 0.2, 1.8], 60, [1280, 720], 3]]) {
      const camera = new PerspectiveCamera(fov, size[0] / size[1], 0.1, 100);
      // The mesh moved by 2 along x and scaled by 1.5: the camera, moved and scaled alike, sees
      // in the mesh's coordinates what refine's camera sees.
      camera.position.set(2 + 1.5 * eye[0], 1.5 * eye[1], 1.5 * eye[2]);
      camera.lookAt(2, 0, 0);
      const mesh = new TessellatedMesh(g, new MeshStandardMaterial(), { scheme: 'pn', lod: `screen:${pixels}`, spacing, camera, size });
      mesh.position.set(2, 0, 0);
      mesh.scale.setScalar(1.5);
      scene.add(mesh);
      scene.updateMatrixWorld();
      const cpu = refine(coarse(g), { scheme: 'pn', lod: `screen:${pixels}`, spacing, camera: [...eye, 0, 0, 0, fov], size });
      const want = cpu.indices.length / 3;
      assert.equal(mesh.lod.triangleCount, want, `${spacing} ${eye}`);
      assert.equal(drawn(mesh), want, `${spacing} ${eye}: the children draw them`);
      // One child per part drawn, each one instanced draw of its part.
      const visible = mesh.lod.children.filter((c) => c.visible);
      assert.equal(visible.length, mesh.surface.draws.length / 3);
      assert.ok(visible.every((c) => c.material === mesh.material && c.geometry.boundingSphere === mesh.geometry.boundingSphere));
      // The parts, built once: about 1.9 MB for the fractional spacings, 5.9 MB for equal.
      const [lo, hi] = spacing === 'equal' ? [5.8e6, 6e6] : [1.8e6, 2e6];
      assert.ok(mesh.lod.partBytes > lo && mesh.lod.partBytes < hi, `${spacing}: ${mesh.lod.partBytes} bytes of parts`);
      scene.remove(mesh);
      mesh.dispose();
    }
  }
});

test('a nearer camera draws more; a frame uploads the levels only when they change, at most 256 bytes per coarse triangle with the nets', () => {
  const g = new IcosahedronGeometry(1, 2);
  const camera = new PerspectiveCamera(45, 4 / 3, 0.1, 100);
  camera.position.set(0, 0, 8);
  const scene = new Scene();
  const mesh = new TessellatedMesh(g, undefined, { scheme: 'pn', lod: 'screen:4', spacing: 'fractional-odd', camera, size: [800, 600] });
  scene.add(mesh);
  scene.updateMatrixWorld();
  const faces = mesh.surface.faceCount;
  const far = mesh.lod.triangleCount;
  assert.ok(mesh.lod.uploadedBytes > 0 && mesh.lod.uploadedBytes <= 64 * faces, `${mesh.lod.uploadedBytes}`);
  scene.updateMatrixWorld();
  assert.equal(mesh.lod.uploadedBytes, 0, 'same camera, same nets: nothing new');
  camera.position.set(0, 0, 2.5);
  scene.updateMatrixWorld();
  assert.ok(mesh.lod.triangleCount > 4 * far, `${far} -> ${mesh.lod.triangleCount}`);
  // The source moves: new nets and new levels.
  const p = g.getAttribute('position');
  p.setX(0, p.getX(0) + 0.3);
  p.needsUpdate = true;
  scene.updateMatrixWorld();
  const bytes = mesh.uploadedBytes + mesh.lod.uploadedBytes;
  assert.ok(mesh.lod.uploadedBytes > 0);
  assert.ok(bytes <= 256 * faces, `${bytes} bytes for ${faces} triangles`);
  mesh.dispose();
});

test('tolerance LOD needs no camera and matches refine; given per-edge levels are drawn', () => {
  const g = new TorusKnotGeometry(0.8, 0.3, 24, 5);
  for (const spacing of ['equal', 'fractional-odd']) {
    const mesh = new TessellatedMesh(g, undefined, { scheme: 'pn', lod: 'tolerance:0.002', spacing });
    mesh.updateMatrixWorld();
    const cpu = refine(coarse(g), { scheme: 'pn', lod: 'tolerance:0.002', spacing });
    assert.equal(mesh.lod.triangleCount, cpu.indices.length / 3, spacing);
    assert.equal(drawn(mesh), cpu.indices.length / 3);
    // One level everywhere: refine's uniform level with that spacing.
    mesh.lod.setLevels(new Float32Array(mesh.surface.edgeCount).fill(5));
    mesh.updateMatrixWorld();
    assert.equal(drawn(mesh), refine(coarse(g), { scheme: 'pn', level: 5, spacing }).indices.length / 3);
    mesh.dispose();
  }
});

test('raycasts hit the LOD surface where refine puts it', () => {
  const g = new IcosahedronGeometry(1, 0);
  const camera = new PerspectiveCamera(45, 1, 0.1, 100);
  camera.position.set(0.1, 0.2, 3);
  camera.lookAt(0, 0, 0);
  const mesh = new TessellatedMesh(g, undefined, { scheme: 'pn', lod: 'screen:8', spacing: 'equal', camera, size: [512, 512] });
  mesh.updateMatrixWorld();
  const cpu = refine({ positions: g.getAttribute('position').array, normals: g.getAttribute('normal').array, indices: Uint32Array.from({ length: 60 }, (_, i) => i) }, { scheme: 'pn', lod: 'screen:8', spacing: 'equal', camera: [0.1, 0.2, 3, 0, 0, 0, 45], size: [512, 512] });
  const ray = new Raycaster(new Vector3(0.05, 0.1, 5), new Vector3(0, 0, -1));
  const hits = ray.intersectObject(mesh, false);
  assert.equal(hits[0].object, mesh);
  // The nearest refined triangle's plane along the ray: the hit is on the refined surface.
  let best = Infinity;
  const P = cpu.positions;
  for (let t = 0; t < cpu.indices.length; t += 3) {
    const [a, b, c] = [0, 1, 2].map((k) => new Vector3().fromArray(P, 3 * cpu.indices[t + k]));
    const hit = ray.ray.intersectTriangle(a, b, c, false, new Vector3());
    if (hit !== null) best = Math.min(best, hit.distanceTo(ray.ray.origin));
  }
  assert.ok(Math.abs(hits[0].distance - best) < 1e-5, `${hits[0].distance} vs ${best}`);
  mesh.dispose();
});

test('lod options and cameras it cannot draw with throw TessellaErrors that say what is wrong', () => {
  const g = new IcosahedronGeometry(1, 1);
  const cases = [
    [{ lod: 'screen:4' }, /spacing: lod draws the GPU tessellator's patterns/],
    [{ lod: 'screen:4', spacing: 'grid' }, /spacing: lod draws/],
    [{ lod: 'screen:4', spacing: 'equal', level: 3 }, /level: with lod/],
    [{ lod: 'screen:0', spacing: 'equal' }, /lod: bad levels: screen:0: pixels per edge must be a finite number above 0/],
    [{ lod: 'screen:4', spacing: 'equal', size: [640] }, /size: the image size/],
    [{ lod: 'screen:4', spacing: 'equal', camera: [0, 0, 5, 0, 0, 0, 45] }, /camera: the three.js Camera/],
  ];
  for (const [options, message] of cases) {
    assert.throws(() => new TessellatedMesh(g, undefined, options), (e) => e instanceof TessellaError && message.test(e.message), String(message));
  }
  const ortho = new OrthographicCamera(-1, 1, 1, -1, 0.1, 10);
  ortho.position.set(0, 0, 5);
  const mesh = new TessellatedMesh(g, undefined, { lod: 'screen:4', spacing: 'equal', camera: ortho, size: [64, 64] });
  assert.throws(() => mesh.updateMatrixWorld(), (e) => e instanceof TessellaError && /PerspectiveCamera/.test(e.message));
  // No camera yet (none given, no render): the levels of the mesh seen whole from three radii
  // away down -z (45°, 256 pixels), which raycasts hit too; levels of one's own: no CPU
  // refinement to hit.
  const ray = new Raycaster(new Vector3(0, 0, 5), new Vector3(0, 0, -1));
  const unseen = new TessellatedMesh(g, undefined, { lod: 'screen:4', spacing: 'equal' });
  unseen.updateMatrixWorld();
  const sphere = unseen.geometry.boundingSphere;
  const eye = sphere.center.clone().add(new Vector3(0, 0, 3 * sphere.radius));
  const first = refine(coarse(g), { lod: 'screen:4', spacing: 'equal', camera: [...eye.toArray(), ...sphere.center.toArray(), 45], size: [256, 256] });
  assert.equal(unseen.lod.triangleCount, first.indices.length / 3);
  assert.ok(unseen.lod.triangleCount > 0);
  assert.equal(ray.intersectObject(unseen).length > 0, true);
  unseen.lod.setLevels(new Float32Array(unseen.surface.edgeCount).fill(3));
  assert.throws(() => ray.intersectObject(unseen), (e) => e instanceof TessellaError && /setLevels/.test(e.message));
  // Distance LOD reads the eye only: an orthographic camera serves.
  const far = new TessellatedMesh(g, undefined, { lod: 'distance:1,10,8', spacing: 'equal', camera: ortho, size: [64, 64] });
  far.updateMatrixWorld();
  assert.ok(far.lod.triangleCount > 80);
});

test('with lod the coarse uvs reach the shader through the corners texture, three per face', () => {
  const g = new IcosahedronGeometry(1, 1);
  const uv = g.getAttribute('uv');
  const mesh = new TessellatedMesh(g, undefined, { lod: 'tolerance:0.01', spacing: 'fractional-odd' });
  const { body } = mesh.lod.patch('');
  assert.match(body, /vec2 uv = tessellaL\.x \* tessellaUv01\.xy \+ tessellaL\.y \* tessellaUv01\.zw \+ tessellaL\.z \* tessellaUv2;/);
  // Face f's texels: its corners' uvs (the soup's vertices 3f, 3f + 1, 3f + 2).
  const tex = mesh.lod.cornersTexture;
  const perRow = tex.image.width / 2;
  for (let f = 0; f < 80; f++) {
    const at = (Math.floor(f / perRow) * tex.image.width + (f % perRow) * 2) * 4;
    const got = Array.from(tex.image.data.subarray(at, at + 6));
    const want = [0, 1, 2].flatMap((k) => [uv.getX(3 * f + k), uv.getY(3 * f + k)]);
    assert.deepEqual(got, want.map(Math.fround), `face ${f}`);
  }
  mesh.dispose();
});
