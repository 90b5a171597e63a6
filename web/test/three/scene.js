// The test page of `tessellate` (web/test/three-scene.test.js): the repository's
// samples/scene.glb loaded by three's GLTFLoader, with a half-size copy of each of its meshes
// (sharing the mesh's geometry and material, as `Object3D.clone()` does), its normal maps
// removed unless `normalMaps`, drawn by
// WebGLRenderer or WebGPURenderer (its WebGPU backend) in one of these ways:
// - `coarse`: as loaded;
// - `scene`: after `tessellate(scene, options)` (one patched material per source material);
// - `restored`: after `tessellate` then `untessellate` (the coarse scene again);
// - `separate`: each triangle mesh replaced by its own `new TessellatedMesh(mesh, undefined,
//   options)` (a clone of its material each: the path three-mesh.test.js checks);
// - `mixed`: each triangle mesh replaced by a TessellatedMesh, meshes that shared a source
//   material sharing one clone of it (as `tessellate` does), every other mesh 'per-frame' and
//   the others 'per-draw' (so one material draws both evaluations' programs in one frame);
// - `cpu`: each triangle mesh's geometry replaced by `refineGeometry` (a plain Mesh).
// `evaluation` goes to every TessellatedMesh (left out: the default); `frames` draws the scene
// that many times (the picture and instanced draws are the last frame's).
// `run` returns the picture and what the scene held (meshes, materials, what was skipped).
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { ready } from 'tessella';
import { cloneMaterial, refineGeometry, TessellatedMesh, tessellate, untessellate } from 'tessella/three';
import { glRenderer, gpuRenderer, readTarget, spy } from './common.js';

const WIDTH = 400;
const HEIGHT = 300;

const gl = glRenderer(WIDTH, HEIGHT);
const glCounts = { instanced: [] };
spy(gl.renderer.getContext(), 'drawElementsInstanced', (a) => glCounts.instanced.push({ count: a[1], instances: a[4] }));

// WebGPU, when the browser has it (the test starts Chromium with WebGPU on SwiftShader).
let gpu = null;
async function webgpu() {
  if (gpu !== null) return gpu;
  if (navigator.gpu === undefined || (await navigator.gpu.requestAdapter()) === null) return null;
  const { renderer, target, started } = await gpuRenderer(WIDTH, HEIGHT);
  await started;
  gpu = { renderer, target, instanced: [] };
  spy(GPURenderPassEncoder.prototype, 'drawIndexed', ([count, instances = 1]) => {
    if (instances > 1) gpu.instanced.push({ count, instances });
  });
  return gpu;
}

let glb = null;
async function load(normalMaps) {
  glb ??= await (await fetch('/samples/scene.glb')).arrayBuffer();
  const gltf = await new Promise((resolve, reject) => new GLTFLoader().parse(glb.slice(0), '', resolve, reject));
  const scene = gltf.scene;
  // The Checker material's normal map reads the second uv set (uv1) with the file's tangents,
  // which TessellatedMesh does not carry (see js/README.md): without it, every way draws the
  // same shading.
  if (!normalMaps) {
    scene.traverse((o) => {
      if (o.material?.normalMap) {
        o.material.normalMap = null;
        o.material.needsUpdate = true;
      }
    });
  }
  // A half-size copy of each triangle mesh below the file's: meshes that share a material (and
  // a geometry) with another, of other sizes (other nets textures, other row widths).
  const copies = new THREE.Group();
  copies.position.set(0, -1.75, 0);
  copies.scale.setScalar(0.5);
  const meshes = [];
  scene.traverse((o) => {
    if (o.isMesh) meshes.push(o);
  });
  for (const m of meshes) {
    const copy = m.clone();
    m.updateWorldMatrix(true, false);
    m.matrixWorld.decompose(copy.position, copy.quaternion, copy.scale);
    copies.add(copy);
  }
  scene.add(copies);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x8899aa, 1.2));
  const key = new THREE.DirectionalLight(0xffffff, 1.6);
  key.position.set(-3, 4, 5);
  scene.add(key);
  return scene;
}

function camera() {
  const c = new THREE.PerspectiveCamera(38, WIDTH / HEIGHT, 0.05, 100);
  c.position.set(-2.6, 1.2, 5.6);
  c.lookAt(-0.1, -0.55, 0);
  return c;
}

function triangleMeshes(scene) {
  const out = [];
  scene.traverse((o) => {
    if (o.isMesh && !(o instanceof TessellatedMesh) && o.geometry.getAttribute('position') !== undefined) out.push(o);
  });
  return out;
}

// What a material looks like from outside: the properties tessella would patch, and its version.
function fingerprint(m) {
  return JSON.stringify({
    version: m.version,
    own: Object.keys(m).sort(),
    onBeforeCompile: m.onBeforeCompile === THREE.Material.prototype.onBeforeCompile,
    key: m.customProgramCacheKey(),
    positionNode: m.positionNode ?? null,
  });
}

async function draw(scene, which) {
  if (which === 'webgpu') {
    const g = await webgpu();
    g.instanced = [];
    g.renderer.setRenderTarget(g.target);
    g.renderer.render(scene, camera());
    // Rows come back top first; the test flips nothing (it compares WebGPU pictures with each other).
    const picture = await readTarget(g.renderer, g.target);
    g.renderer.setRenderTarget(null);
    return { ...picture, instanced: g.instanced.slice() };
  }
  glCounts.instanced = [];
  gl.renderer.render(scene, camera());
  return { png: gl.canvas.toDataURL('image/png'), instanced: glCounts.instanced.slice() };
}

/** Draws the scene one `way` (see the top) with `renderer` ('webgl' or 'webgpu'). */
async function run({ way = 'coarse', renderer = 'webgl', scheme = 'pn', level = 6, normalMaps = false, evaluation = undefined, frames = 1 }) {
  await ready;
  const scene = await load(normalMaps);
  const options = { scheme, level, evaluation };
  const sources = triangleMeshes(scene);
  const info = {
    triangleMeshes: sources.length,
    sourceMaterials: new Set(sources.map((m) => m.material)).size,
    names: sources.map((m) => `${m.name}${m.visible ? '' : ' (hidden)'}`),
    faces: sources.map((m) => (m.geometry.index ? m.geometry.index.count : m.geometry.getAttribute('position').count) / 3),
    morphInfluences: sources.map((m) => Array.from(m.morphTargetInfluences ?? [])).flat(),
  };
  let handle = null;
  if (way === 'scene' || way === 'restored') {
    const prints = new Map(sources.map((m) => [m.material, fingerprint(m.material)]));
    handle = tessellate(scene, options);
    const disposed = new Set();
    for (const list of handle.materials.values()) for (const m of list) m.addEventListener('dispose', () => disposed.add(m));
    const patched = new Set(handle.meshes.map((m) => m.material));
    info.meshes = handle.meshes.length;
    info.patchedMaterials = patched.size;
    info.instances = handle.meshes.map((m) => m.geometry.instanceCount);
    info.handleMaterials = [...handle.materials.values()].reduce((n, l) => n + l.length, 0);
    info.patchedAreClones = [...patched].every((m) => !prints.has(m));
    // Every triangle mesh replaced: hidden, and a TessellatedMesh of it in its parent.
    // (A source with children, such as RingA holding RingB, is taken off every layer instead:
    // hidden, it would hide them.)
    const hidden = (s) => s.visible === false || s.layers.mask === 0;
    info.replaced = sources.filter((s) => hidden(s) && s.parent.children.some((c) => c instanceof TessellatedMesh && c.source === s)).length;
    info.hiddenByLayers = sources.filter((s) => s.visible && s.layers.mask === 0).map((s) => s.name);
    // Meshes that shared a source material share the patched one.
    info.sharedKept = sources.every((a) => sources.every((b) => {
      const ta = handle.meshes.find((m) => m.source === a);
      const tb = handle.meshes.find((m) => m.source === b);
      return (a.material === b.material) === (ta.material === tb.material);
    }));
    info.skipped = handle.skipped.map((s) => `${s.object.type}: ${s.reason}`);
    info.sourcesUntouched = sources.every((m) => prints.get(m.material) === fingerprint(m.material));
    if (way === 'restored') {
      const picture = await draw(scene, renderer);
      info.tessellatedInstanced = picture.instanced;
      info.removed = untessellate(scene);
      info.left = [];
      scene.traverse((o) => {
        if (o instanceof TessellatedMesh) info.left.push(o.name);
      });
      info.visibleAgain = sources.filter((m) => m.visible && m.layers.mask === 1).length;
      info.disposedMaterials = disposed.size;
      info.sourcesUntouchedAfter = sources.every((m) => prints.get(m.material) === fingerprint(m.material));
      info.handleMeshesAfter = handle.meshes.length;
    }
  } else if (way === 'separate') {
    for (const s of sources) new TessellatedMesh(s, undefined, options);
  } else if (way === 'mixed') {
    // One clone per source material (and kind of surface: a mesh the clone refuses gets its own).
    const clones = new Map();
    const seen = new Map();
    sources.forEach((s) => {
      const list = clones.get(s.material) ?? [];
      clones.set(s.material, list);
      // Alternately per draw and per frame among the meshes of one source material.
      const n = seen.get(s.material) ?? 0;
      seen.set(s.material, n + 1);
      const mode = { ...options, evaluation: n % 2 === 0 ? 'per-draw' : 'per-frame' };
      for (const m of list) {
        try {
          new TessellatedMesh(s, m, mode);
          return;
        } catch (e) {
          if (!/another kind/.test(e.message)) throw e;
        }
      }
      const m = cloneMaterial(s.material);
      list.push(m);
      new TessellatedMesh(s, m, mode);
    });
    info.mixedMaterials = [...clones.values()].reduce((n, l) => n + l.length, 0);
  } else if (way === 'cpu') {
    // Triangles without area (the file has two) draw nothing: left out, as TessellatedMesh
    // leaves them out (refine refuses them).
    const [p, q, r] = [new THREE.Vector3(), new THREE.Vector3(), new THREE.Vector3()];
    for (const s of sources) {
      const g = s.geometry.clone();
      const idx = Array.from(g.index.array);
      const position = g.getAttribute('position');
      const kept = [];
      for (let t = 0; t < idx.length; t += 3) {
        const [a, b, c] = idx.slice(t, t + 3);
        p.fromBufferAttribute(position, a);
        q.fromBufferAttribute(position, b).sub(p);
        r.fromBufferAttribute(position, c).sub(p);
        if (q.cross(r).lengthSq() !== 0) kept.push(a, b, c);
      }
      g.setIndex(kept);
      s.geometry = refineGeometry(g, options);
    }
  } else if (way !== 'coarse') {
    throw new Error(`no way ${way}`);
  }
  let picture;
  for (let f = 0; f < frames; f++) picture = await draw(scene, renderer);
  info.evaluations = [];
  const byMaterial = new Map();
  scene.traverse((o) => {
    if (!(o instanceof TessellatedMesh)) return;
    info.evaluations.push(o.evaluation);
    byMaterial.set(o.material, new Set([...(byMaterial.get(o.material) ?? []), o.evaluation]));
  });
  // Materials drawing meshes of both evaluations.
  info.bothEvaluations = [...byMaterial.values()].filter((e) => e.size === 2).length;
  // Free what this run made (the next run loads the file again).
  handle?.dispose();
  scene.traverse((o) => {
    if (o instanceof TessellatedMesh) o.dispose();
  });
  return { ...picture, ...info };
}

window.tessellaScene = { run, ready: ready.then(() => true) };
