// The test page of TessellatedMesh following a SkinnedMesh (web/test/three-skinned.test.js,
// and under WebGPURenderer web/test/three-webgpu-skinned.test.js): the bundled animated
// creature loaded by three's GLTFLoader and posed by its AnimationMixer, drawn by WebGLRenderer
// (or, `renderer: 'webgpu'`, WebGPURenderer on its WebGPU backend) either as a TessellatedMesh
// or as a plain Mesh of refineGeometry over the vertices three skins
// (SkinnedMesh.getVertexPosition), with the bytes uploaded (WebGL) and the instanced draws
// counted.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { ready } from 'tessella';
import { refineGeometry, TessellatedMesh } from 'tessella/three';
import { glRenderer, gpuRenderer, readTarget, spy } from './common.js';

const WIDTH = 320;
const HEIGHT = 320;
const { canvas, renderer } = glRenderer(WIDTH, HEIGHT);

const gl = renderer.getContext();
const counts = { uploaded: 0, instanced: 0 };
for (const name of ['texImage2D', 'texSubImage2D', 'bufferData', 'bufferSubData']) {
  spy(gl, name, (args) => {
    for (const a of args) if (ArrayBuffer.isView(a)) counts.uploaded += a.byteLength;
  });
}
spy(gl, 'drawElementsInstanced', () => counts.instanced++);

// WebGPURenderer, made on the first run that asks for it (the WebGL test's browser has no
// WebGPU); its instanced draws counted in the same `counts`.
let gpu = null;
async function webgpu() {
  if (gpu !== null) return gpu;
  const { renderer: r, target, started } = await gpuRenderer(WIDTH, HEIGHT);
  await started;
  if (r.backend.isWebGPUBackend !== true) throw new Error('WebGPURenderer fell back to WebGL2: the browser has no WebGPU');
  spy(GPURenderPassEncoder.prototype, 'drawIndexed', ([, instances = 1]) => {
    if (instances > 1) counts.instanced++;
  });
  gpu = { renderer: r, target };
  return gpu;
}

async function load() {
  const buffer = await (await fetch('/samples/animated-creature.glb')).arrayBuffer();
  return new Promise((resolve, reject) => new GLTFLoader().parse(buffer, '', resolve, reject));
}

// The skinned vertices and normals as three poses them: getVertexPosition, and each normal
// moved by the inverse transpose of its blended matrix (bindMatrixInverse · Σ w boneMatrix ·
// bindMatrix), as a plain BufferGeometry.
function skinnedGeometry(mesh) {
  const g = mesh.geometry;
  const n = g.getAttribute('position').count;
  const positions = new Float32Array(3 * n);
  const normals = new Float32Array(3 * n);
  const skinIndex = g.getAttribute('skinIndex');
  const skinWeight = g.getAttribute('skinWeight');
  const normal = g.getAttribute('normal');
  mesh.skeleton.update();
  const v = new THREE.Vector3();
  const bone = new THREE.Matrix4();
  const blend = new THREE.Matrix4();
  const nm = new THREE.Matrix3();
  for (let i = 0; i < n; i++) {
    mesh.getVertexPosition(i, v).toArray(positions, 3 * i);
    blend.elements.fill(0);
    for (let k = 0; k < 4; k++) {
      const w = skinWeight.getComponent(i, k);
      if (w === 0) continue;
      bone.fromArray(mesh.skeleton.boneMatrices, 16 * skinIndex.getComponent(i, k));
      for (let e = 0; e < 16; e++) blend.elements[e] += w * bone.elements[e];
    }
    blend.premultiply(mesh.bindMatrixInverse).multiply(mesh.bindMatrix);
    v.fromBufferAttribute(normal, i).applyMatrix3(nm.getNormalMatrix(blend)).normalize().toArray(normals, 3 * i);
  }
  const out = new THREE.BufferGeometry();
  out.setIndex(g.index);
  out.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  out.setAttribute('normal', new THREE.BufferAttribute(normals, 3));
  return out;
}

/**
 * Plays `clip` and draws the frames at `times` (seconds); returns the last picture and, per
 * frame, the bytes uploaded (WebGL) and the instanced draws. `plain`: draw the last pose as a
 * Mesh of refineGeometry over three's skinned vertices instead. `renderer`: 'webgl' or
 * 'webgpu' (the picture then read back from a render target, rows top first as a PNG's).
 * `evaluation`: TessellatedMesh's option (left out: the default).
 */
async function run({ clip = 'wave', times = [0.5], scheme = 'pn', level = 8, plain = false, renderer: which = 'webgl', evaluation = undefined } = {}) {
  await ready;
  const g = which === 'webgpu' ? await webgpu() : null;
  const gltf = await load();
  const scene = gltf.scene;
  const camera = new THREE.PerspectiveCamera(35, WIDTH / HEIGHT, 0.05, 50);
  scene.add(new THREE.AmbientLight(0xffffff, 0.5));
  const light = new THREE.DirectionalLight(0xffffff, 2);
  light.position.set(1, 3, 2);
  scene.add(light);
  let skinned = null;
  scene.traverse((o) => {
    if (o.isSkinnedMesh) skinned = o;
  });
  const mixer = new THREE.AnimationMixer(scene);
  mixer.clipAction(THREE.AnimationClip.findByName(gltf.animations, clip)).play();
  // Framed on the rest pose's box.
  scene.updateMatrixWorld(true);
  const box = new THREE.Box3().setFromObject(skinned, true);
  const centre = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3()).length();
  camera.position.copy(centre).add(new THREE.Vector3(0.3, 0.25, 1).normalize().multiplyScalar(1.6 * size));
  camera.lookAt(centre);
  const material = new THREE.MeshStandardMaterial({ color: 0x3377cc, roughness: 0.5 });
  const drawn = plain ? null : new TessellatedMesh(skinned, material, { scheme, level, evaluation });
  const log = [];
  for (const t of times) {
    mixer.setTime(t);
    if (plain) {
      scene.updateMatrixWorld(true);
      const posed = new THREE.Mesh(refineGeometry(skinnedGeometry(skinned), { scheme, level }), material);
      posed.matrixAutoUpdate = false;
      posed.matrix.copy(skinned.matrixWorld);
      skinned.visible = false;
      scene.add(posed);
    }
    counts.uploaded = 0;
    counts.instanced = 0;
    if (g !== null) {
      g.renderer.setRenderTarget(g.target);
      g.renderer.render(scene, camera);
      g.renderer.setRenderTarget(null);
      log.push({ instanced: counts.instanced, calls: g.renderer.info.render.drawCalls });
    } else {
      renderer.render(scene, camera);
      log.push({ uploaded: counts.uploaded, instanced: counts.instanced, calls: renderer.info.render.calls });
    }
  }
  const faces = skinned.geometry.index.count / 3;
  const picture = g !== null ? await readTarget(g.renderer, g.target) : { png: canvas.toDataURL('image/png') };
  const mode = drawn === null ? {} : { evaluation: drawn.evaluation, fallback: drawn.evaluationFallback };
  drawn?.dispose();
  return { ...picture, log, faces, ...mode };
}

window.tessellaSkinned = { run, ready: ready.then(() => true) };
