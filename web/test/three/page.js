// The test page of TessellatedMesh (web/test/three-mesh.test.js): one scene drawn by
// three's WebGLRenderer, either as TessellatedMesh (the GPU evaluates the patches) or as a
// plain Mesh of refineGeometry's CPU refinement, with the WebGL calls counted: draws, and the
// bytes handed to texture and buffer uploads.
import * as THREE from 'three';
import { ready } from 'tessella';
import { refineGeometry, TessellatedMesh } from 'tessella/three';

const WIDTH = 320;
const HEIGHT = 240;
const canvas = document.createElement('canvas');
document.body.append(canvas);
const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true });
renderer.setPixelRatio(1);
renderer.setSize(WIDTH, HEIGHT);
renderer.setClearColor(0xffffff, 1);
renderer.shadowMap.enabled = true;
renderer.shadowMap.type = THREE.PCFShadowMap;

const gl = renderer.getContext();
const counts = { instanced: [], draws: 0, uploaded: 0 };
function spy(name, record) {
  const original = gl[name].bind(gl);
  gl[name] = (...args) => {
    record(args);
    return original(...args);
  };
}
spy('drawElementsInstanced', (a) => counts.instanced.push({ count: a[1], instances: a[4] }));
spy('drawArraysInstanced', (a) => counts.instanced.push({ count: a[2], instances: a[3] }));
spy('drawElements', () => counts.draws++);
spy('drawArrays', () => counts.draws++);
for (const name of ['texImage2D', 'texSubImage2D', 'texImage3D', 'texSubImage3D', 'bufferData', 'bufferSubData']) {
  spy(name, (args) => {
    for (const a of args) {
      if (ArrayBuffer.isView(a)) counts.uploaded += a.byteLength;
      else if (a instanceof ArrayBuffer) counts.uploaded += a.byteLength;
    }
  });
}

// The source's pose at a frame: frame 0 is the rest pose; later frames bend it.
function pose(geometry, rest, frame) {
  const p = geometry.getAttribute('position');
  for (let i = 0; i < p.count; i++) {
    const [x, y, z] = [rest[3 * i], rest[3 * i + 1], rest[3 * i + 2]];
    const b = 0.25 * frame;
    p.setXYZ(i, x, y + b * x * x - 0.2 * b, z * (1 + 0.15 * frame));
  }
  p.needsUpdate = true;
  geometry.computeVertexNormals();
}

// A user's own ShaderMaterial, coloured by its normal: the tessellated one calls the documented
// GLSL function itself; the other reads three's position and normal (which, patched, are the
// curved surface's).
function shaderMaterial(callsTessella) {
  const main = callsTessella
    ? `vec3 p;
  vec3 n;
  tessella_evaluate(gl_InstanceID, tessellaBarycentric, p, n);`
    : `vec3 p = position;
  vec3 n = normal;`;
  return new THREE.ShaderMaterial({
    vertexShader: `varying vec3 vNormal;
void main() {
  ${main}
  vNormal = normalize(normalMatrix * n);
  gl_Position = projectionMatrix * modelViewMatrix * vec4(p, 1.0);
}`,
    fragmentShader: `varying vec3 vNormal;
void main() {
  gl_FragColor = vec4(0.5 + 0.5 * normalize(vNormal), 1.0);
}`,
  });
}

/**
 * Draws the scene `frames` times (the source bent a little more each frame when `deform`) and
 * returns the last picture (PNG data URL) with per-frame counts. `plain`: a Mesh of the CPU
 * refinement of the last pose instead of the TessellatedMesh.
 */
async function run({
  scheme = 'pn', level = 8, normals = undefined, soup = undefined, plain = false, frames = 1, deform = false, plane = false,
  castShadow = true, occluder = false, occluderCasts = true, material = 'standard',
  extras = false, point = false,
} = {}) {
  await ready;
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(40, WIDTH / HEIGHT, 0.1, 50);
  camera.position.set(0, 2.2, 5.2);
  camera.lookAt(0, -0.3, 0);
  scene.add(new THREE.AmbientLight(0xffffff, 0.4));
  // A directional light, or (point) a point light, whose shadows take the distance material.
  const light = point ? new THREE.PointLight(0xffffff, 40, 0, 2) : new THREE.DirectionalLight(0xffffff, 2.5);
  light.position.set(1.5, 5, 1);
  light.castShadow = true;
  light.shadow.mapSize.set(1024, 1024);
  if (point) Object.assign(light.shadow.camera, { near: 0.5, far: 12 });
  else Object.assign(light.shadow.camera, { left: -3, right: 3, top: 3, bottom: -3, near: 0.5, far: 12 });
  scene.add(light);
  if (plane) {
    const ground = new THREE.Mesh(new THREE.PlaneGeometry(10, 10), new THREE.MeshStandardMaterial({ color: 0xdddddd }));
    ground.rotation.x = -Math.PI / 2;
    ground.position.y = -1.4;
    ground.receiveShadow = true;
    scene.add(ground);
  }
  if (occluder) {
    const ball = new THREE.Mesh(new THREE.SphereGeometry(0.35, 24, 12), new THREE.MeshBasicMaterial({ color: 0x222222 }));
    ball.position.set(0.45, 2.2, 0.1);
    ball.castShadow = occluderCasts;
    scene.add(ball);
  }
  const geometry = new THREE.TorusKnotGeometry(0.8, 0.3, 40, 6);
  const rest = geometry.getAttribute('position').array.slice();
  const make0 = (tessellated) => {
    if (material === 'standard') return new THREE.MeshStandardMaterial({ color: 0x3377cc, roughness: 0.5 });
    if (material === 'MeshNormalMaterial') return new THREE.MeshNormalMaterial();
    if (material === 'ShaderMaterial') return shaderMaterial(tessellated);
    if (material === 'ShaderMaterialAttributes') return shaderMaterial(false);
    return new THREE[material]({ color: 0x3377cc });
  };
  // extras: fog, a clipping plane, a texture (by the coarse uvs) and vertex colours.
  if (extras) {
    scene.fog = new THREE.Fog(0xffffff, 4, 8);
    renderer.localClippingEnabled = true;
    const colours = new Float32Array(geometry.getAttribute('position').count * 3);
    for (let i = 0; i < colours.length; i += 3) colours.set([1, (i / colours.length) % 1, 0.5], i);
    geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
  }
  const checker = new Uint8Array(64 * 64 * 4);
  for (let i = 0; i < 64 * 64; i++) {
    const on = ((i % 64 >> 3) + (i >> 9)) % 2;
    checker.set(on ? [255, 255, 255, 255] : [60, 60, 60, 255], 4 * i);
  }
  const map = new THREE.DataTexture(checker, 64, 64);
  map.needsUpdate = true;
  const make = (tessellated = false) => {
    const m = make0(tessellated);
    if (extras) {
      m.map = map;
      m.vertexColors = true;
      m.clippingPlanes = [new THREE.Plane(new THREE.Vector3(-1, 0, 0), 0.6)];
      m.side = THREE.DoubleSide;
    }
    return m;
  };
  const source = new THREE.Mesh(geometry, make());
  source.castShadow = castShadow;
  source.receiveShadow = true;
  source.rotation.y = 0.3;
  scene.add(source);
  const options = { scheme, level, normals };
  let drawn;
  if (plain) {
    if (deform) pose(geometry, rest, frames - 1);
    drawn = new THREE.Mesh(refineGeometry(geometry, { ...options, soup }), source.material);
    drawn.castShadow = castShadow;
    drawn.receiveShadow = true;
    drawn.rotation.copy(source.rotation);
    scene.remove(source);
    scene.add(drawn);
  } else {
    drawn = new TessellatedMesh(source, make(true), options);
  }
  const log = [];
  for (let f = 0; f < frames; f++) {
    if (!plain && deform) pose(geometry, rest, f);
    counts.instanced = [];
    counts.draws = 0;
    counts.uploaded = 0;
    renderer.render(scene, camera);
    log.push({
      instanced: counts.instanced.slice(),
      draws: counts.draws,
      uploaded: counts.uploaded,
      calls: renderer.info.render.calls,
      uploadedBytes: plain ? 0 : drawn.uploadedBytes,
    });
  }
  const png = canvas.toDataURL('image/png');
  const faces = geometry.index.count / 3;
  if (!plain) drawn.dispose();
  return { png, log, faces };
}

window.tessellaThree = { run, ready: ready.then(() => true) };
