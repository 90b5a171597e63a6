// One coarse mesh (samples/creature.obj, 320 triangles) four ways, side by side: as it is;
// Loop-subdivided by three-subdivide (CPU, a new mesh); refined by tessella's refineGeometry
// (CPU in wasm, a new mesh); drawn by TessellatedMesh (GPU: the pattern instanced, nets in a
// texture). Each label says its triangles, the time to make it and what a deforming frame
// would upload.
import * as THREE from 'three';
import { OBJLoader } from 'three/addons/loaders/OBJLoader.js';
import { mergeVertices } from 'three/addons/utils/BufferGeometryUtils.js';
import { LoopSubdivision } from 'three-subdivide';
import { ready } from 'tessella';
import { refineGeometry, TessellatedMesh } from 'tessella/three';
import { frame, ground, run, stage } from './common.js';

const LEVEL = 8;

run(async () => {
  await ready;
  const s = stage();
  const obj = await new OBJLoader().loadAsync('/samples/creature.obj');
  let coarse = null;
  obj.traverse((o) => {
    if (o.isMesh) coarse = o.geometry;
  });
  // OBJLoader gives a triangle soup; welded, the mesh shares its vertices (and smooth normals).
  coarse = mergeVertices(coarse.deleteAttribute('normal'));
  coarse.computeVertexNormals();
  const faces = coarse.index.count / 3;
  const material = () => new THREE.MeshStandardMaterial({ color: 0x3377cc, roughness: 0.45 });
  const timed = (fn) => {
    const t0 = performance.now();
    const out = fn();
    return [out, performance.now() - t0];
  };
  const [loop, loopMs] = timed(() => LoopSubdivision.modify(coarse, 3));
  const [refined, refineMs] = timed(() => refineGeometry(coarse, { scheme: 'pn', level: LEVEL }));
  const row = new THREE.Group();
  s.scene.add(row);
  // The TessellatedMesh takes its source's place (the source is hidden): placed last in the row.
  const source = new THREE.Mesh(coarse, material());
  row.add(source);
  const [tessellated, tessellateMs] = timed(() => new TessellatedMesh(source, material(), { scheme: 'pn', level: LEVEL }));
  const entries = [
    [new THREE.Mesh(coarse, material()), `coarse: ${faces} triangles`],
    [new THREE.Mesh(loop, material()), `three-subdivide (Loop, 3 steps): ${triangles(loop)} triangles, ${loopMs.toFixed(0)} ms on the CPU; a deforming frame uploads ${bytes(loop)} bytes`],
    [new THREE.Mesh(refined, material()), `refineGeometry (PN, level ${LEVEL}): ${triangles(refined)} triangles, ${refineMs.toFixed(0)} ms on the CPU; a deforming frame uploads ${bytes(refined, ['position', 'normal'])} bytes`],
    [tessellated, `TessellatedMesh (PN, level ${LEVEL}): ${faces * LEVEL * LEVEL} triangles in one instanced draw, ${tessellateMs.toFixed(0)} ms to set up; a deforming frame uploads ${tessellated.uploadedBytes} bytes`],
  ];
  const width = new THREE.Box3().setFromObject(source).getSize(new THREE.Vector3()).x * 1.25;
  entries.forEach(([mesh, text], i) => {
    // The TessellatedMesh follows its source's transform: the source is the one moved.
    const placed = mesh === tessellated ? source : mesh;
    placed.position.x = (i - 1.5) * width;
    placed.castShadow = true;
    if (mesh !== tessellated) row.add(mesh);
    label(text, i, entries.length);
  });
  source.castShadow = true;
  row.updateMatrixWorld(true);
  ground(s.scene, row);
  const { centre } = frame(s, row, new THREE.Vector3(0, 0.25, 1));
  // Backed off until the row spans the window's width: each label under its mesh.
  const across = Math.tan(THREE.MathUtils.degToRad(s.camera.fov / 2)) * s.camera.aspect;
  const distance = (2 * width) / across;
  s.camera.position.copy(centre).add(new THREE.Vector3(0, 0.25, 1).normalize().multiplyScalar(distance));
  s.controls.update();
  return s;
});

function triangles(geometry) {
  return (geometry.index?.count ?? geometry.getAttribute('position').count) / 3;
}

// Bytes of the attributes (all, or those named) and the index: what a new pose of this mesh
// sends to the GPU.
function bytes(geometry, names = Object.keys(geometry.attributes)) {
  return names.reduce((n, name) => n + geometry.getAttribute(name).array.byteLength, 0);
}

function label(text, i, n) {
  const div = document.createElement('div');
  div.style.cssText = `position:fixed;bottom:8px;left:${(100 * i) / n + 0.5}%;width:${100 / n - 1}%;font:12px/1.35 system-ui,sans-serif;background:#fffc;padding:4px 6px;border-radius:4px`;
  div.textContent = text;
  document.body.append(div);
}
