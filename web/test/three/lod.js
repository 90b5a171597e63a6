// The test page of TessellatedMesh's `lod` option (web/test/three-lod.test.js): a closed coarse
// mesh drawn by three's WebGLRenderer either as a TessellatedMesh whose per-edge levels come from
// the camera (children drawing the tessellator's parts, instanced), or as a plain Mesh of
// refineGeometry's CPU refinement with the same lod, camera and size; the WebGL calls counted.
// `renderer: 'webgpu'` (web/test/three-webgpu-lod.test.js, a page opened with WebGPU) draws the
// same scene with three's WebGPURenderer into a render target read back, its draws counted
// (GPURenderPassEncoder.drawIndexed).
import * as THREE from 'three';
import { ready } from 'tessella';
import { refineGeometry, TessellatedMesh } from 'tessella/three';
import { checkerTexture, glRenderer, gpuRenderer, readTarget, spy } from './common.js';

const WIDTH = 320;
const HEIGHT = 240;
const FOV = 45;
const { canvas, renderer } = glRenderer(WIDTH, HEIGHT);
renderer.shadowMap.enabled = true;

const gl = renderer.getContext();
const counts = { instanced: [], uploaded: 0 };
spy(gl, 'drawElementsInstanced', (a) => counts.instanced.push({ count: a[1], instances: a[4] }));
for (const name of ['texImage2D', 'texSubImage2D', 'bufferData', 'bufferSubData']) {
  spy(gl, name, (args) => {
    // bufferSubData(target, offset, data, srcOffset, length): the bytes given by length.
    if (name === 'bufferSubData' && args.length >= 5) {
      counts.uploaded += args[4] * args[2].BYTES_PER_ELEMENT;
      return;
    }
    for (const a of args) if (ArrayBuffer.isView(a)) counts.uploaded += a.byteLength;
  });
}

let gpu = null;
async function webgpu() {
  if (gpu !== null) return gpu;
  const { renderer: r, target, started } = await gpuRenderer(WIDTH, HEIGHT);
  await started;
  if (r.backend.isWebGPUBackend !== true) throw new Error('no WebGPU');
  spy(GPURenderPassEncoder.prototype, 'drawIndexed', ([count, instances = 1]) => counts.instanced.push({ count, instances }));
  gpu = { renderer: r, target };
  return gpu;
}

// The coarse mesh: an icosahedron subdivided once, its vertices pushed about a little so the
// PN patches bend differently along each edge, welded (indexed).
function coarse() {
  const ico = new THREE.IcosahedronGeometry(1, 1);
  const p = ico.getAttribute('position');
  // Weld: IcosahedronGeometry is a triangle soup.
  const key = (i) => [p.getX(i), p.getY(i), p.getZ(i)].map((x) => x.toFixed(5)).join(',');
  const ids = new Map();
  const positions = [];
  const indices = [];
  for (let i = 0; i < p.count; i++) {
    const k = key(i);
    if (!ids.has(k)) {
      ids.set(k, ids.size);
      const [x, y, z] = [p.getX(i), p.getY(i), p.getZ(i)];
      const s = 1 + 0.15 * Math.sin(3 * x + 2 * y) * Math.cos(2 * z);
      positions.push(s * x, s * y * 0.8, s * z);
    }
    indices.push(ids.get(k));
  }
  const out = new THREE.BufferGeometry();
  out.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
  out.setIndex(indices);
  out.computeVertexNormals();
  return out;
}

/**
 * Draws `frames` frames (the camera moving from `eye` towards `to` when given, the source
 * deforming when `deform`) and returns the last picture with per-frame counts. `plain`: a Mesh
 * of refineGeometry with the same lod, camera and size. `cameraOption`: the TessellatedMesh
 * gets the camera and size as options (else it takes those of the previous render). `levels`: per-edge levels given instead of the camera's.
 */
async function run({
  scheme = 'pn', spacing = 'fractional-odd', pixels = 6, eye = [0, 0.4, 3], to = null, plain = false, frames = 1,
  material = 'basic', cameraOption = true, deform = false, levels = null, extras = false,
  shadow = false, cast = true, renderer: which = 'webgl',
} = {}) {
  await ready;
  const g = which === 'webgpu' ? await webgpu() : null;
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(FOV, WIDTH / HEIGHT, 0.05, 50);
  const place = (f) => {
    const t = frames > 1 && to !== null ? f / (frames - 1) : 0;
    const e = to === null ? eye : eye.map((x, i) => x + t * (to[i] - x));
    camera.position.set(...e);
    camera.lookAt(0, 0, 0);
    camera.updateMatrixWorld();
    return e;
  };
  scene.add(new THREE.AmbientLight(0xffffff, 0.5));
  const light = new THREE.DirectionalLight(0xffffff, 2);
  light.position.set(1, 2, 3);
  scene.add(light);
  // shadow: the surface casts onto a plane behind it (the light's shadow map draws the parts
  // with the patched depth material).
  if (shadow) {
    light.castShadow = true;
    light.shadow.mapSize.set(512, 512);
    Object.assign(light.shadow.camera, { left: -3, right: 3, top: 3, bottom: -3, near: 0.5, far: 12 });
    const ground = new THREE.Mesh(new THREE.PlaneGeometry(12, 12), new THREE.MeshStandardMaterial({ color: 0xdddddd }));
    ground.position.z = -1.6;
    ground.receiveShadow = true;
    scene.add(ground);
  }
  const geometry = coarse();
  const rest = geometry.getAttribute('position').array.slice();
  const bend = (f) => {
    const p = geometry.getAttribute('position');
    for (let i = 0; i < p.count; i++) p.setY(i, rest[3 * i + 1] * (1 + 0.1 * f) + 0.05 * f * rest[3 * i] * rest[3 * i]);
    p.needsUpdate = true;
    geometry.computeVertexNormals();
  };
  const make0 = () => (material === 'basic' ? new THREE.MeshBasicMaterial({ color: 0x2255aa }) : new THREE.MeshStandardMaterial({ color: 0x3377cc, roughness: 0.5 }));
  // extras: a checker map by the coarse uvs (spherical) and vertex colours.
  let map = null;
  if (extras) {
    const p = geometry.getAttribute('position');
    const uvs = new Float32Array(2 * p.count);
    const colours = new Float32Array(3 * p.count);
    for (let i = 0; i < p.count; i++) {
      const [x, y, z] = [p.getX(i), p.getY(i), p.getZ(i)];
      uvs.set([0.5 + Math.atan2(z, x) / (2 * Math.PI), 0.5 + 0.4 * y], 2 * i);
      colours.set([1, 0.5 + 0.5 * Math.sin(3 * x), 0.5 + 0.5 * z], 3 * i);
    }
    geometry.setAttribute('uv', new THREE.BufferAttribute(uvs, 2));
    geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
    map = checkerTexture();
  }
  const make = () => {
    const m = make0();
    if (extras) {
      m.map = map;
      m.vertexColors = true;
    }
    return m;
  };
  const lod = `screen:${pixels}`;
  const log = [];
  let drawn;
  if (plain) {
    const e = place(frames - 1);
    if (deform) bend(frames - 1);
    // Given levels: one level everywhere, as refine's `level` with the spacing.
    const options = levels !== null ? { scheme, spacing, level: levels[0] } : { scheme, spacing, lod, camera: [...e, 0, 0, 0, FOV], size: [WIDTH, HEIGHT] };
    drawn = new THREE.Mesh(refineGeometry(geometry, options), make());
    drawn.castShadow = shadow && cast;
    scene.add(drawn);
  } else {
    drawn = new TessellatedMesh(geometry, make(), { scheme, spacing, lod, ...(cameraOption ? { camera, size: [WIDTH, HEIGHT] } : {}) });
    drawn.castShadow = shadow && cast;
    scene.add(drawn);
    if (levels !== null) {
      drawn.update();
      const n = drawn.surface.edgeCount;
      drawn.lod.setLevels(Float32Array.from({ length: n }, (_, e) => levels[e % levels.length]));
    }
  }
  for (let f = 0; f < frames; f++) {
    if (!plain) {
      place(f);
      if (deform) bend(f);
    }
    counts.instanced = [];
    counts.uploaded = 0;
    if (g !== null) {
      g.renderer.setRenderTarget(g.target);
      g.renderer.render(scene, camera);
      g.renderer.setRenderTarget(null);
    } else {
      renderer.render(scene, camera);
    }
    log.push({
      instanced: counts.instanced.slice(),
      uploaded: counts.uploaded,
      triangles: g !== null ? g.renderer.info.render.triangles : renderer.info.render.triangles,
      calls: g !== null ? g.renderer.info.render.calls : renderer.info.render.calls,
      netsBytes: plain ? 0 : drawn.uploadedBytes,
      lodBytes: plain ? 0 : drawn.lod.uploadedBytes,
      lodTriangles: plain ? 0 : drawn.lod.triangleCount,
    });
  }
  const picture = g !== null ? await readTarget(g.renderer, g.target) : { png: canvas.toDataURL('image/png') };
  const faces = geometry.index.count / 3;
  const cpuTriangles = plain ? drawn.geometry.index.count / 3 : 0;
  scene.remove(drawn);
  if (!plain) drawn.dispose();
  return { ...picture, log, faces, cpuTriangles };
}

window.tessellaLod = { run, ready: ready.then(() => true) };
