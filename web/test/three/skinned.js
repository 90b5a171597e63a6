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

// The GPU-posed mesh's nets (read back from its render target) against a CPU-posed twin's
// (the DataTexture InstancedSurface.update filled) for the same pose: the largest difference
// and the rest pose's size.
function netsDifference(gpu, cpu, size) {
  cpu.update();
  const target = gpu.gpuNetsTarget;
  const got = new Float32Array(target.width * target.height * 4);
  renderer.readRenderTargetPixels(target, 0, 0, target.width, target.height, got);
  const want = cpu.netsTexture.image.data;
  let most = 0;
  for (let i = 0; i < want.length; i++) most = Math.max(most, Math.abs(got[i] - want[i]));
  // The bounds GPU posing grows from the joints hold the CPU's (its control points' box).
  const holds = gpu.geometry.boundingBox.containsBox(cpu.geometry.boundingBox);
  const ratio = gpu.geometry.boundingSphere.radius / cpu.geometry.boundingSphere.radius;
  return { most, size, floats: want.length, finite: got.every(Number.isFinite), holds, ratio };
}

// A grid of rays through pixel centres (`step` pixels apart) cast at `mesh`: whether each hit.
function rays(mesh, camera, step) {
  const raycaster = new THREE.Raycaster();
  const out = [];
  for (let y = step / 2; y < HEIGHT; y += step) {
    for (let x = step / 2; x < WIDTH; x += step) {
      raycaster.setFromCamera(new THREE.Vector2(((x + 0.5) / WIDTH) * 2 - 1, 1 - ((y + 0.5) / HEIGHT) * 2), camera);
      out.push({ x, y, hit: raycaster.intersectObject(mesh, false).length > 0 });
    }
  }
  return out;
}

/**
 * Plays `clip` and draws the frames at `times` (seconds); returns the last picture and, per
 * frame, the bytes uploaded (WebGL) and the instanced draws. `plain`: draw the last pose as a
 * Mesh of refineGeometry over three's skinned vertices instead. `renderer`: 'webgl' or
 * 'webgpu' (the picture then read back from a render target, rows top first as a PNG's).
 * `evaluation`, `posing`: TessellatedMesh's options (left out: the defaults). `shadows`: the
 * light casts shadows onto a floor. `morphOnly`: a plain Mesh of the creature's geometry whose
 * morph influences follow `times` (no skeleton) instead of the SkinnedMesh. `twin`: also a
 * CPU-posed TessellatedMesh of the source, hidden, whose nets `netsDifference` compares.
 * `rayStep`: cast a grid of rays at the drawn mesh after the last frame. `noFloatTargets`: the
 * renderer claims no EXT_color_buffer_float during the run.
 */
async function run({ clip = 'wave', times = [0.5], scheme = 'pn', level = 8, plain = false, renderer: which = 'webgl', evaluation = undefined, posing = undefined, shadows = false, morphOnly = false, twin = false, rayStep = 0, noFloatTargets = false } = {}) {
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
  let source = skinned;
  if (morphOnly) {
    // The creature's geometry as a plain morphing Mesh in the SkinnedMesh's place.
    if (!(skinned.geometry.morphAttributes.position?.length > 0)) throw new Error('the creature has no morph targets');
    source = new THREE.Mesh(skinned.geometry, skinned.material);
    source.updateMorphTargets();
    skinned.parent.add(source);
    source.position.copy(skinned.position);
    source.quaternion.copy(skinned.quaternion);
    source.scale.copy(skinned.scale);
    skinned.visible = false;
  }
  renderer.shadowMap.enabled = shadows;
  if (shadows) {
    light.castShadow = true;
    light.shadow.mapSize.set(512, 512);
  }
  const mixer = new THREE.AnimationMixer(scene);
  mixer.clipAction(THREE.AnimationClip.findByName(gltf.animations, clip)).play();
  // Framed on the rest pose's box.
  scene.updateMatrixWorld(true);
  const box = new THREE.Box3().setFromObject(skinned, true);
  const centre = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3()).length();
  camera.position.copy(centre).add(new THREE.Vector3(0.3, 0.25, 1).normalize().multiplyScalar(1.6 * size));
  camera.lookAt(centre);
  if (shadows) {
    // A floor under the rest pose, catching the creature's shadow.
    const floor = new THREE.Mesh(new THREE.PlaneGeometry(4 * size, 4 * size), new THREE.MeshStandardMaterial({ color: 0xdddddd }));
    floor.rotation.x = -Math.PI / 2;
    floor.position.set(centre.x, box.min.y - 0.02 * size, centre.z);
    floor.receiveShadow = true;
    scene.add(floor);
    const s = light.shadow.camera;
    [s.left, s.right, s.top, s.bottom] = [-size, size, size, -size];
    light.target.position.copy(centre);
    light.position.copy(centre).add(new THREE.Vector3(1, 3, 2).normalize().multiplyScalar(2 * size));
    scene.add(light.target);
  }
  const material = new THREE.MeshStandardMaterial({ color: 0x3377cc, roughness: 0.5 });
  if (shadows) source.castShadow = true;
  const drawn = plain ? null : new TessellatedMesh(source, material, { scheme, level, evaluation, posing });
  // The twin is hidden; netsDifference updates it (on the CPU) from the skeleton as drawn.
  const cpuTwin = twin ? new TessellatedMesh(source, material.clone(), { scheme, level, evaluation: 'per-draw', posing: 'cpu' }) : null;
  if (cpuTwin !== null) cpuTwin.visible = false;
  const has = renderer.extensions.has;
  if (noFloatTargets) renderer.extensions.has = (name) => name !== 'EXT_color_buffer_float' && has.call(renderer.extensions, name);
  const log = [];
  try {
    for (const t of times) {
      mixer.setTime(t);
      if (morphOnly) source.morphTargetInfluences.forEach((_, k, a) => (a[k] = 0.5 + 0.5 * Math.sin(3 * t + k)));
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
        log.push({ uploaded: counts.uploaded, instanced: counts.instanced, calls: renderer.info.render.calls, reported: drawn?.uploadedBytes });
      }
    }
  } finally {
    // Put back, also when a run throws (posing: 'gpu' refused).
    renderer.extensions.has = has;
  }
  const faces = skinned.geometry.index.count / 3;
  const picture = g !== null ? await readTarget(g.renderer, g.target) : { png: canvas.toDataURL('image/png') };
  const mode = drawn === null ? {} : { evaluation: drawn.evaluation, fallback: drawn.evaluationFallback, posedOn: drawn.posedOn, posingFallback: drawn.posingFallback };
  const checks = {};
  if (cpuTwin !== null) checks.nets = netsDifference(drawn, cpuTwin, size);
  if (rayStep > 0) checks.rays = rays(drawn, camera, rayStep);
  const skeleton = { bones: skinned.skeleton.bones.length, targets: skinned.geometry.morphAttributes.position?.length ?? 0 };
  drawn?.dispose();
  cpuTwin?.dispose();
  renderer.shadowMap.enabled = false;
  return { ...picture, log, faces, ...mode, ...checks, ...skeleton };
}

window.tessellaSkinned = { run, ready: ready.then(() => true) };
