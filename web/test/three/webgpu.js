// The test page of TessellatedMesh under WebGPURenderer (web/test/three-webgpu.test.js): one
// scene drawn by three's WebGPURenderer on its WebGPU backend, either as TessellatedMesh (the
// WGSL from the wasm evaluates the patches, called from TSL) or as a plain Mesh of
// refineGeometry's CPU refinement, with the GPU calls counted: draws (GPURenderPassEncoder) and
// the bytes handed to the queue's buffer and texture writes. Pictures are read back from a
// render target (no canvas snapshot needed): the renderer and the read-back are common.js's.
import * as THREE from 'three';
import { ClippingGroup, MeshBasicNodeMaterial, WebGPURenderer } from 'three/webgpu';
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

window.tessellaThree = { run, fallback, ready: Promise.all([ready, started]).then(() => renderer.backend.isWebGPUBackend === true) };
