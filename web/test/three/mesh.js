// The test page of TessellatedMesh (web/test/three-mesh.test.js): one scene drawn by
// three's WebGLRenderer, either as TessellatedMesh (the GPU evaluates the patches) or as a
// plain Mesh of refineGeometry's CPU refinement, with the WebGL calls counted: draws, and the
// bytes handed to texture and buffer uploads.
import * as THREE from 'three';
import { ready } from 'tessella';
import { refineGeometry, TessellatedMesh } from 'tessella/three';
import { checkerTexture, glRenderer, pose, spy, torusScene, vertexColours } from './common.js';

const WIDTH = 320;
const HEIGHT = 240;
const { canvas, renderer } = glRenderer(WIDTH, HEIGHT);
renderer.shadowMap.enabled = true;
renderer.shadowMap.type = THREE.PCFShadowMap;

const gl = renderer.getContext();
const counts = { instanced: [], draws: 0, uploaded: 0 };
spy(gl, 'drawElementsInstanced', (a) => counts.instanced.push({ count: a[1], instances: a[4] }));
spy(gl, 'drawArraysInstanced', (a) => counts.instanced.push({ count: a[2], instances: a[3] }));
spy(gl, 'drawElements', () => counts.draws++);
spy(gl, 'drawArrays', () => counts.draws++);
for (const name of ['texImage2D', 'texSubImage2D', 'texImage3D', 'texSubImage3D', 'bufferData', 'bufferSubData']) {
  spy(gl, name, (args) => {
    for (const a of args) {
      if (ArrayBuffer.isView(a)) counts.uploaded += a.byteLength;
      else if (a instanceof ArrayBuffer) counts.uploaded += a.byteLength;
    }
  });
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
  extras = false, point = false, evaluation = undefined, noFloatTargets = false,
} = {}) {
  await ready;
  // noFloatTargets: the renderer says it has no EXT_color_buffer_float (per-frame falls back).
  const has = renderer.extensions.has;
  if (noFloatTargets) renderer.extensions.has = (name) => name !== 'EXT_color_buffer_float' && has.call(renderer.extensions, name);
  const { scene, camera } = torusScene({ width: WIDTH, height: HEIGHT, point, plane, occluder, occluderCasts });
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
    vertexColours(geometry);
  }
  const map = checkerTexture();
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
    drawn = new TessellatedMesh(source, make(true), { ...options, evaluation });
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
  renderer.extensions.has = has;
  const png = canvas.toDataURL('image/png');
  const faces = geometry.index.count / 3;
  const mode = plain ? {} : { evaluation: drawn.evaluation, fallback: drawn.evaluationFallback, bakedBytes: drawn.bakedBytes };
  // The programs of the baked variant (the picture's and the shadow materials'; every run's so
  // far): whether their vertex shaders evaluate the patch.
  const baked = renderer.info.programs
    .filter((p) => p.cacheKey.includes(':baked|'))
    .map((p) => ({ evaluates: /tessella_evaluate\s*\(/.test(gl.getShaderSource(p.vertexShader)), nets: gl.getShaderSource(p.vertexShader).includes('tessellaNets') }));
  if (!plain) drawn.dispose();
  return { png, log, faces, ...mode, bakedPrograms: baked };
}

window.tessellaThree = { run, ready: ready.then(() => true) };
