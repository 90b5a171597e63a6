// The test page of TessellatedMesh under WebGPURenderer (web/test/three-webgpu.test.js): one
// scene drawn by three's WebGPURenderer on its WebGPU backend, either as TessellatedMesh (the
// WGSL from the wasm evaluates the patches, called from TSL) or as a plain Mesh of
// refineGeometry's CPU refinement, with the GPU calls counted: draws (GPURenderPassEncoder) and
// the bytes handed to the queue's buffer and texture writes. Pictures are read back from a
// render target (no canvas snapshot needed): the renderer and the read-back are common.js's.
// `skinned` (web/test/three-webgpu-skinned.test.js) draws the animated creature with GPU or CPU
// posing and reads back the nets the compute wrote.
import * as THREE from 'three';
import { ClippingGroup, MeshBasicNodeMaterial, WebGPURenderer } from 'three/webgpu';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { attribute, instanceIndex, normalGeometry, texture, varying, vec4 } from 'three/tsl';
import { ready, TessellaError } from 'tessella';
import { refineGeometry, TessellatedMesh, tessellaFunctions } from 'tessella/three';
import { checkerTexture, gpuRenderer, pose, readTarget, spy, torusScene, vertexColours } from './common.js';

const WIDTH = 320;
const HEIGHT = 240;

const counts = { instanced: [], draws: 0, buffers: 0, textures: 0 };
spy(GPURenderPassEncoder.prototype, 'drawIndexed', ([count, instances = 1]) => {
  if (instances > 1) counts.instanced.push({ count, instances });
  else counts.draws++;
});
spy(GPURenderPassEncoder.prototype, 'draw', ([count, instances = 1]) => {
  if (instances > 1) counts.instanced.push({ count, instances });
  else counts.draws++;
});
// Bytes a write hands over: `size` (elements of a typed array, bytes of an ArrayBuffer) or the
// data past `dataOffset`.
spy(GPUQueue.prototype, 'writeBuffer', ([, , data, dataOffset = 0, size]) => {
  const unit = ArrayBuffer.isView(data) ? data.BYTES_PER_ELEMENT ?? 1 : 1;
  counts.buffers += size !== undefined ? size * unit : data.byteLength - dataOffset * unit;
});
spy(GPUQueue.prototype, 'writeTexture', ([, data, layout]) => {
  counts.textures += data.byteLength - (layout.offset ?? 0);
});

const { renderer, target, started } = await gpuRenderer(WIDTH, HEIGHT);
renderer.shadowMap.enabled = true;
renderer.shadowMap.type = THREE.PCFShadowMap;

/**
 * Draws the scene `frames` times (the source bent a little more each frame when `deform`) and
 * returns the last picture (RGBA bytes, base64, rows as read back) with per-frame counts.
 * `plain`: a Mesh of the CPU refinement of the last pose instead of the TessellatedMesh.
 */
async function run({
  scheme = 'pn', level = 8, normals = undefined, soup = undefined, plain = false, frames = 1, deform = false,
  plane = false, castShadow = true, occluder = false, occluderCasts = true, point = false, custom = false, map = false, colours = false,
  material = 'MeshStandardMaterial', fogClip = false, twin = false,
} = {}) {
  await ready;
  await started;
  const { scene, camera } = torusScene({ width: WIDTH, height: HEIGHT, point, plane, occluder, occluderCasts });
  const geometry = new THREE.TorusKnotGeometry(0.8, 0.3, 40, 6);
  const rest = geometry.getAttribute('position').array.slice();
  // colours: vertex colours (as mesh.js's extras).
  if (colours) vertexColours(geometry);
  // custom: a user's node material showing the normal as a colour: the CPU mesh's normal
  // attribute, or on TessellatedMesh the documented TSL function's.
  const make0 = () => {
    if (custom) return new MeshBasicNodeMaterial();
    if (material === 'MeshNormalMaterial') return new THREE.MeshNormalMaterial();
    return material === 'MeshStandardMaterial' ? new THREE.MeshStandardMaterial({ color: 0x3377cc, roughness: 0.5 }) : new THREE[material]({ color: 0x3377cc });
  };
  // fogClip: fog and a clipping plane (WebGPURenderer clips by ClippingGroup).
  if (fogClip) scene.fog = new THREE.Fog(0xffffff, 4, 8);
  // map: a checker texture, read by the coarse uvs (as mesh.js).
  const checkers = checkerTexture();
  const make = () => {
    const m = make0();
    if (map) m.map = checkers;
    m.vertexColors = colours;
    return m;
  };
  const source = new THREE.Mesh(geometry, make());
  source.castShadow = castShadow;
  source.receiveShadow = true;
  source.rotation.y = 0.3;
  const parent = fogClip ? new ClippingGroup() : scene;
  if (fogClip) {
    parent.clippingPlanes = [new THREE.Plane(new THREE.Vector3(-1, 0, 0), 0.6)];
    scene.add(parent);
  }
  parent.add(source);
  const options = { scheme, level, normals };
  let drawn;
  if (plain) {
    if (deform) pose(geometry, rest, frames - 1);
    drawn = new THREE.Mesh(refineGeometry(geometry, { ...options, soup }), source.material);
    if (custom) drawn.material.colorNode = varying(normalGeometry).mul(0.5).add(0.5);
    drawn.castShadow = castShadow;
    drawn.receiveShadow = true;
    drawn.rotation.copy(source.rotation);
    parent.remove(source);
    parent.add(drawn);
  } else {
    drawn = new TessellatedMesh(source, make(), options);
    if (custom) {
      const { normal } = tessellaFunctions(drawn.surface.wgsl());
      const n = normal({ nets: texture(drawn.netsTexture), face: instanceIndex, l: attribute('tessellaBarycentric', 'vec3') });
      drawn.material.colorNode = varying(n).mul(0.5).add(0.5);
    }
  }
  // twin: a second mesh of the same scheme (the same WGSL, its own nets) beside the first, its
  // material of the same kind but for its own colorNode (so its own program).
  let second = null;
  if (twin) {
    const red = () => Object.assign(make(), { colorNode: vec4(0.8, 0.2, 0.2, 1) });
    const other = new THREE.Mesh(new THREE.TorusKnotGeometry(0.8, 0.3, 40, 6), red());
    other.scale.setScalar(0.4);
    other.position.set(1.6, 0.4, 0);
    parent.add(other);
    if (plain) {
      second = new THREE.Mesh(refineGeometry(other.geometry, options), other.material);
      second.position.copy(other.position);
      second.scale.copy(other.scale);
      parent.remove(other);
      parent.add(second);
    } else {
      second = new TessellatedMesh(other, red(), options);
    }
  }
  const log = [];
  renderer.setRenderTarget(target);
  for (let f = 0; f < frames; f++) {
    if (!plain && deform) pose(geometry, rest, f);
    counts.instanced = [];
    counts.draws = 0;
    counts.buffers = 0;
    counts.textures = 0;
    renderer.render(scene, camera);
    log.push({
      instanced: counts.instanced.slice(),
      draws: counts.draws,
      buffers: counts.buffers,
      textures: counts.textures,
      uploadedBytes: plain ? 0 : drawn.uploadedBytes,
    });
  }
  const picture = await readTarget(renderer, target);
  renderer.setRenderTarget(null);
  const faces = geometry.index.count / 3;
  if (!plain) drawn.dispose();
  if (!plain && second !== null) second.dispose();
  return { ...picture, log, faces };
}

/** The error TessellatedMesh throws under a WebGPURenderer forced onto its WebGL2 backend. */
async function fallback() {
  await ready;
  const r = new WebGPURenderer({ canvas: document.createElement('canvas'), forceWebGL: true });
  await r.init();
  const scene = new THREE.Scene();
  scene.add(new TessellatedMesh(new THREE.TorusKnotGeometry(0.8, 0.3, 8, 3), new THREE.MeshStandardMaterial(), { level: 2 }));
  try {
    r.render(scene, new THREE.PerspectiveCamera());
    return { thrown: null };
  } catch (e) {
    return { thrown: e instanceof TessellaError ? e.message : `not a TessellaError: ${e}` };
  } finally {
    r.dispose();
  }
}

// The skinned pictures' size (as skinned.js's), and their render target.
const CREATURE = 320;
const creatureTarget = new THREE.RenderTarget(CREATURE, CREATURE, { colorSpace: THREE.SRGBColorSpace });
let creatureBytes = null;

// A fresh copy of the bundled animated creature (GLTFLoader): its scene, clips and SkinnedMesh.
async function creature() {
  creatureBytes ??= await (await fetch('/samples/animated-creature.glb')).arrayBuffer();
  const gltf = await new Promise((resolve, reject) => new GLTFLoader().parse(creatureBytes.slice(0), '', resolve, reject));
  let mesh = null;
  gltf.scene.traverse((o) => {
    if (o.isSkinnedMesh) mesh = o;
  });
  return { ...gltf, mesh };
}

/**
 * The creature played by its AnimationMixer (`clip` at each of `times`, seconds) as a
 * TessellatedMesh with `posing` ('gpu', 'cpu' or 'auto'), drawn by this WebGPURenderer; returns
 * the last picture, the mesh's posedOn, posingFallback and uploadedBytes per frame, the GPU
 * dispatches and the draw calls. `nets`: also the last frame's nets as drawn (the texture the
 * nodes read, read back from the GPU) and as the CPU builds them for the same pose (a
 * TessellatedMesh with posing 'cpu' made then, its DataTexture), compared: the largest
 * difference and the largest value. `scheme`, `level`, `normals`, `normalsFromSource`: the
 * mesh's options; `rigid`: a morphing Mesh of the creature's geometry instead of the SkinnedMesh;
 * `twin`: a static TessellatedMesh beside it sharing its material. `storageLeft`: the storage
 * buffers the renderer still holds once the meshes are disposed, against before them.
 */
async function skinned({ clip = 'wave', times = [0.5], scheme = 'pn', level = 8, normals = undefined, normalsFromSource = undefined, posing = 'gpu', nets = false, rigid = false, twin = false } = {}) {
  await ready;
  await started;
  const loaded = await creature();
  const { scene, animations } = loaded;
  let mesh = loaded.mesh;
  if (rigid) {
    // rigid: a plain morphing Mesh of the same geometry in the SkinnedMesh's place (the clips
    // bind to it by name; 'breathe' moves its morph weight).
    const plain = new THREE.Mesh(mesh.geometry, mesh.material);
    plain.name = mesh.name;
    plain.position.copy(mesh.position);
    plain.quaternion.copy(mesh.quaternion);
    plain.scale.copy(mesh.scale);
    mesh.parent.add(plain);
    mesh.removeFromParent();
    mesh = plain;
  }
  const camera = new THREE.PerspectiveCamera(35, 1, 0.05, 50);
  scene.add(new THREE.AmbientLight(0xffffff, 0.5));
  const light = new THREE.DirectionalLight(0xffffff, 2);
  light.position.set(1, 3, 2);
  scene.add(light);
  const mixer = new THREE.AnimationMixer(scene);
  mixer.clipAction(THREE.AnimationClip.findByName(animations, clip)).play();
  scene.updateMatrixWorld(true);
  const box = new THREE.Box3().setFromObject(mesh, true);
  const centre = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3()).length();
  camera.position.copy(centre).add(new THREE.Vector3(0.3, 0.25, 1).normalize().multiplyScalar(1.6 * size));
  camera.lookAt(centre);
  const material = new THREE.MeshStandardMaterial({ color: 0x3377cc, roughness: 0.5 });
  const options = { scheme, level, normals, normalsFromSource };
  // The renderer's storage buffers before the meshes: every one they make is freed by dispose.
  const storageBefore = renderer.info.memory.storageAttributes;
  let drawn;
  try {
    drawn = new TessellatedMesh(mesh, material, { ...options, posing });
  } catch (e) {
    return { thrown: e instanceof TessellaError ? e.message : `not a TessellaError: ${e}` };
  }
  // twin: a static TessellatedMesh (a torus knot beside the creature, its nets the CPU's
  // DataTexture) sharing the material, and so the nodes, with the GPU-posed one.
  let other = null;
  if (twin) {
    const knot = new THREE.TorusKnotGeometry(0.15 * size, 0.05 * size, 40, 6);
    knot.deleteAttribute('uv');
    const source = new THREE.Mesh(knot, material);
    source.position.copy(centre).add(new THREE.Vector3(0.3 * size, 0.2 * size, 0));
    scene.add(source);
    other = new TessellatedMesh(source, material, options);
  }
  const log = [];
  renderer.setRenderTarget(creatureTarget);
  try {
    for (const t of times) {
      mixer.setTime(t);
      const before = renderer.info.compute.calls;
      renderer.render(scene, camera);
      log.push({ uploadedBytes: drawn.uploadedBytes, computes: renderer.info.compute.calls - before, draws: renderer.info.render.drawCalls });
    }
  } catch (e) {
    drawn.dispose();
    other?.dispose();
    renderer.setRenderTarget(null);
    return { thrown: e instanceof TessellaError ? e.message : `not a TessellaError: ${e}` };
  }
  const picture = await readTarget(renderer, creatureTarget);
  renderer.setRenderTarget(null);
  const out = {
    ...picture,
    log,
    posedOn: drawn.posedOn,
    posingFallback: drawn.posingFallback,
    normalMode: drawn.surface.normalMode,
    netsTexture: drawn.netsTexture.isStorageTexture === true ? 'storage' : 'data',
    twinNets: other === null ? null : other.netsTexture.isStorageTexture === true ? 'storage' : 'data',
  };
  other?.dispose();
  if (nets) {
    const { width, height } = drawn.surface;
    const gpu = drawn.netsTexture.isStorageTexture === true ? await renderer.backend.copyTextureToBuffer(drawn.netsTexture, 0, 0, width, height, 0) : drawn.netsTexture.image.data;
    drawn.dispose();
    const cpu = new TessellatedMesh(mesh, material, { ...options, posing: 'cpu' });
    const want = cpu.netsTexture.image.data;
    let most = 0;
    let largest = 0;
    for (let i = 0; i < want.length; i++) {
      most = Math.max(most, Math.abs(gpu[i] - want[i]));
      largest = Math.max(largest, Math.abs(want[i]));
    }
    cpu.dispose();
    out.nets = { most: Number.isNaN(most) ? 'NaN' : most, largest, length: gpu.length, expected: want.length };
  } else {
    drawn.dispose();
  }
  out.storageLeft = renderer.info.memory.storageAttributes - storageBefore;
  return out;
}

window.tessellaThree = { run, fallback, skinned, ready: Promise.all([ready, started]).then(() => renderer.backend.isWebGPUBackend === true) };
