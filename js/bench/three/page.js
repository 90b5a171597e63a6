// The GMR paper's Figure 7 in three.js (WebGLRenderer): one coarse mesh drawn at levels 4, 8, 16
// and 32 six ways, in one run, with a shadow-casting directional light (so the shadow map's pass
// draws the surface too; the mesh casts and receives) —
//   static refined: refineGeometry once, drawn as a plain Mesh (the baseline);
//   static tessellated (per-draw): TessellatedMesh of the still mesh, every pass evaluating the patches;
//   static tessellated (per-frame): the same with the default evaluation ('auto', which under
//   WebGLRenderer is per-frame: checked), its vertices evaluated once into vertex buffers the
//   passes read;
//   deforming refined: RefinedGeometry.update() every frame (CPU refinement, every refined vertex uploaded);
//   deforming tessellated (per-draw, per-frame): TessellatedMesh following the moved source
//   (nets rebuilt and uploaded; per-frame: evaluated once a frame into the textures).
// With `animated: true` (as `npm run bench:three` runs it), three more ways of an animated
// character, the bundled skinned and morphing samples/animated-creature.glb playing its `wave`
// clip through three's AnimationMixer, advanced by the same fixed step every frame —
//   animated, refined offline: the glTF refined by the package's refineGltf (skin, morph targets
//   and clips kept), loaded by GLTFLoader and skinned by three (the animated rows' baseline);
//   animated, tessellated (CPU posing, GPU posing): the coarse glTF loaded by GLTFLoader, its
//   SkinnedMesh replaced by TessellatedMesh (`tessellate`, default evaluation: 'auto', checked
//   to be per-frame), posed in wasm with the nets uploaded (`posing: 'cpu'`), or by the default
//   (`'auto'`, checked to be on the GPU): the nets built by two render passes from the joint
//   matrices and morph weights, which alone are uploaded.
// Both are scaled into the torus knot's frame (same camera, same light), cast and receive.
// A frame's time is from before the deformation to after a 1-pixel readPixels (which waits for
// the GPU); the median of `frames`. GPU memory: the bytes the WebGL calls allocate for the
// object (bufferData, texStorage2D, texImage2D, texStorage3D, texImage3D) in its first two
// frames (the first allocates, compiles and, per-frame, bakes; the second draws the baked
// vertices, uploading the welded topology), spied on the context; uploads: the most bytes handed
// to WebGL in a measured frame.
// Every way is checked to draw something (pixels other than the clear colour after its first
// two frames); an animated way, to upload something (move) in every measured frame.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { ready, refineGltf } from 'tessella';
import { RefinedGeometry, refineGeometry, TessellatedMesh, tessellate } from 'tessella/three';

const canvas = document.createElement('canvas');
document.body.append(canvas);
const renderer = new THREE.WebGLRenderer({ canvas, antialias: false });
renderer.setPixelRatio(1);
renderer.shadowMap.enabled = true;
renderer.shadowMap.type = THREE.PCFShadowMap;
const gl = renderer.getContext();
const tally = { allocated: 0, uploaded: 0 };
const BYTES_PER_TEXEL = { [gl.RGBA32F]: 16, [gl.RGBA8]: 4 };
const wrap = (name, fn) => {
  const original = gl[name].bind(gl);
  gl[name] = (...args) => {
    fn(args);
    return original(...args);
  };
};
const viewBytes = (args) => args.reduce((n, a) => n + (ArrayBuffer.isView(a) ? a.byteLength : 0), 0);
wrap('bufferData', (a) => {
  const bytes = typeof a[1] === 'number' ? a[1] : viewBytes(a);
  tally.allocated += bytes;
  tally.uploaded += bytes;
});
wrap('bufferSubData', (a) => (tally.uploaded += viewBytes(a)));
wrap('texStorage2D', (a) => (tally.allocated += a[3] * a[4] * (BYTES_PER_TEXEL[a[2]] ?? 16)));
wrap('texImage2D', (a) => {
  // (target, level, internalformat, width, height, border, format, type, pixels): a render
  // target's texture is allocated with no pixels.
  const sized = a.length >= 9 && typeof a[3] === 'number' && BYTES_PER_TEXEL[a[2]] !== undefined;
  tally.allocated += sized ? a[3] * a[4] * BYTES_PER_TEXEL[a[2]] : viewBytes(a);
  tally.uploaded += viewBytes(a);
});
wrap('texSubImage2D', (a) => (tally.uploaded += viewBytes(a)));
// three's morph targets live in a 2D array texture (texStorage3D, then texSubImage3D).
wrap('texStorage3D', (a) => (tally.allocated += a[3] * a[4] * a[5] * (BYTES_PER_TEXEL[a[2]] ?? 16)));
wrap('texImage3D', (a) => {
  // (target, level, internalformat, width, height, depth, border, format, type, pixels)
  const sized = a.length >= 10 && typeof a[3] === 'number' && BYTES_PER_TEXEL[a[2]] !== undefined;
  tally.allocated += sized ? a[3] * a[4] * a[5] * BYTES_PER_TEXEL[a[2]] : viewBytes(a);
  tally.uploaded += viewBytes(a);
});
wrap('texSubImage3D', (a) => (tally.uploaded += viewBytes(a)));

function bend(geometry, rest, t) {
  const p = geometry.getAttribute('position');
  for (let i = 0; i < p.count; i++) {
    const [x, y, z] = [rest[3 * i], rest[3 * i + 1], rest[3 * i + 2]];
    p.setXYZ(i, x, y + 0.15 * Math.sin(t) * x * x, z);
  }
  p.needsUpdate = true;
  geometry.computeVertexNormals();
}

function median(xs) {
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.floor(s.length / 2)];
}

const WAYS = [
  'static refined',
  'static tessellated (per-draw)',
  'static tessellated (per-frame)',
  'deforming refined',
  'deforming tessellated (per-draw)',
  'deforming tessellated (per-frame)',
];
const ANIMATED = ['animated, refined offline', 'animated, tessellated (CPU posing)', 'animated, tessellated (GPU posing)'];
const CREATURE = '/samples/animated-creature.glb';
const CLIP = 'wave';
/** The mixer's step each frame (seconds): a 30 fps animation. */
const STEP = 1 / 30;

// The light, its shadow map allocated once (before any tally) and shared by every scene.
const light = new THREE.DirectionalLight(0xffffff, 2);
light.position.set(1.5, 4, 3);
light.castShadow = true;
light.shadow.mapSize.set(1024, 1024);
Object.assign(light.shadow.camera, { left: -2, right: 2, top: 2, bottom: -2, near: 0.5, far: 12 });

/** One way's scene at one level: `step(t)` moves it (and refines, for RefinedGeometry). */
function setUp(way, level, tubular, radial) {
  const scene = new THREE.Scene();
  scene.add(new THREE.HemisphereLight(0xffffff, 0x445566, 1.2));
  const geometry = new THREE.TorusKnotGeometry(0.9, 0.3, tubular, radial);
  const rest = geometry.getAttribute('position').array.slice();
  const material = new THREE.MeshStandardMaterial({ color: 0x3377cc });
  const deforming = way.startsWith('deforming');
  const options = { scheme: 'pn', level };
  const shadows = (mesh) => {
    mesh.castShadow = true;
    mesh.receiveShadow = true;
    return mesh;
  };
  let step = () => {};
  let dispose = () => {};
  let check = () => {};
  if (way.endsWith('refined') && !deforming) {
    scene.add(shadows(new THREE.Mesh(refineGeometry(geometry, options), material)));
  } else if (way.endsWith('refined')) {
    const refined = new RefinedGeometry(geometry, options);
    scene.add(shadows(new THREE.Mesh(refined.geometry, material)));
    step = (t) => {
      bend(geometry, rest, t);
      refined.update();
    };
    dispose = () => refined.dispose();
  } else {
    const source = shadows(new THREE.Mesh(geometry, material));
    scene.add(source);
    // per-frame: the default evaluation ('auto'), checked after the first frames.
    const evaluation = way.includes('per-frame') ? 'per-frame' : 'per-draw';
    const mesh = new TessellatedMesh(source, material.clone(), { ...options, evaluation: evaluation === 'per-frame' ? undefined : evaluation });
    check = () => {
      if (mesh.evaluation !== evaluation) throw new Error(`${way}: evaluates ${mesh.evaluation} (${mesh.evaluationFallback})`);
    };
    if (deforming) step = (t) => bend(geometry, rest, t);
    dispose = () => mesh.dispose();
  }
  const triangles = geometry.index.count / 3;
  return { scene, triangles, drawn: triangles * level * level, step, check, dispose: () => { dispose(); geometry.dispose(); } };
}

/** A GLB's bytes (Uint8Array or ArrayBuffer) read by three's GLTFLoader. */
function parseGlb(bytes) {
  const buffer = bytes instanceof ArrayBuffer ? bytes : bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  return new Promise((resolve, reject) => new GLTFLoader().parse(buffer, '', resolve, reject));
}

const skinnedMeshes = (root) => {
  const found = [];
  root.traverse((o) => {
    if (o.isSkinnedMesh === true) found.push(o);
  });
  return found;
};

const trianglesOf = (meshes) => meshes.reduce((n, m) => n + m.geometry.index.count / 3, 0);

/**
 * The coarse creature's framing, the same for every animated way: its rest pose's box (as three
 * skins it) scaled to the torus knot's height (2.4) and centred on the origin.
 */
async function creatureFrame(glb) {
  const gltf = await parseGlb(glb);
  gltf.scene.updateMatrixWorld(true);
  const box = new THREE.Box3();
  for (const m of skinnedMeshes(gltf.scene)) box.union(new THREE.Box3().setFromObject(m, true));
  const size = box.getSize(new THREE.Vector3());
  const scale = 2.4 / Math.max(size.x, size.y);
  const offset = box.getCenter(new THREE.Vector3()).multiplyScalar(-scale);
  const triangles = trianglesOf(skinnedMeshes(gltf.scene));
  for (const m of skinnedMeshes(gltf.scene)) m.geometry.dispose();
  return { scale, offset, triangles };
}

/**
 * An animated way's scene at one level: the creature (refined offline by refineGltf, or coarse
 * with its SkinnedMeshes tessellated) playing CLIP; `step()` advances the mixer by STEP.
 */
async function setUpAnimated(way, level, glb, frame) {
  const scene = new THREE.Scene();
  scene.add(new THREE.HemisphereLight(0xffffff, 0x445566, 1.2));
  const offline = way === 'animated, refined offline';
  const gltf = await parseGlb(offline ? refineGltf(glb, { scheme: 'pn', level }) : glb);
  const creature = gltf.scene;
  const holder = new THREE.Group();
  holder.scale.setScalar(frame.scale);
  holder.position.copy(frame.offset);
  holder.add(creature);
  scene.add(holder);
  const material = new THREE.MeshStandardMaterial({ color: 0x3377cc });
  const skinned = skinnedMeshes(creature);
  if (skinned.length === 0) throw new Error(`${way}: the glTF has no SkinnedMesh`);
  const geometries = [];
  creature.traverse((o) => {
    if (o.isMesh !== true) return;
    geometries.push(o.geometry);
    o.material = material;
    o.castShadow = true;
    o.receiveShadow = true;
  });
  const mixer = new THREE.AnimationMixer(creature);
  const clip = THREE.AnimationClip.findByName(gltf.animations, CLIP);
  if (clip === null) throw new Error(`${way}: the glTF has no clip '${CLIP}'`);
  mixer.clipAction(clip).play();
  let handle = null;
  let check = () => {};
  let drawn = trianglesOf(skinned);
  if (offline) {
    if (drawn !== frame.triangles * level * level) throw new Error(`${way}: ${drawn} triangles refined from ${frame.triangles} at level ${level}`);
  } else {
    // The default evaluation ('auto'), checked after the first frames to be per-frame; posing
    // 'cpu', or the default ('auto'), checked to be on the GPU.
    const posing = way.includes('GPU') ? 'gpu' : 'cpu';
    handle = tessellate(creature, { scheme: 'pn', level, posing: posing === 'gpu' ? undefined : 'cpu' });
    const left = handle.skipped.filter((s) => s.object.isSkinnedMesh === true);
    if (handle.meshes.length === 0 || left.length > 0) throw new Error(`${way}: tessellate left ${left.map((s) => s.reason).join('; ')}`);
    drawn = frame.triangles * level * level;
    check = () => {
      for (const m of handle.meshes) {
        if (m.evaluation !== 'per-frame') throw new Error(`${way}: evaluates ${m.evaluation} (${m.evaluationFallback})`);
        if (m.posedOn !== posing) throw new Error(`${way}: posed on the ${m.posedOn} (${m.posingFallback})`);
      }
    };
  }
  const dispose = () => {
    handle?.dispose();
    mixer.stopAllAction();
    mixer.uncacheRoot(creature);
    for (const m of skinned) m.skeleton.dispose();
    for (const g of geometries) g.dispose();
    material.dispose();
  };
  return { scene, triangles: frame.triangles, drawn, step: () => mixer.update(STEP), check, animated: true, dispose };
}

/** Pixels of the canvas (size × size) other than the clear colour (black): what the last frame drew. */
function drawnPixels(size) {
  const rgba = new Uint8Array(4 * size * size);
  gl.readPixels(0, 0, size, size, gl.RGBA, gl.UNSIGNED_BYTE, rgba);
  const mask = new Uint8Array(size * size);
  for (let i = 0; i < mask.length; i++) mask[i] = rgba[4 * i] > 8 || rgba[4 * i + 1] > 8 || rgba[4 * i + 2] > 8 ? 1 : 0;
  return mask;
}

function iou(a, b) {
  let both = 0;
  let either = 0;
  for (let i = 0; i < a.length; i++) {
    both += a[i] & b[i];
    either += a[i] | b[i];
  }
  return either === 0 ? 1 : both / either;
}

/**
 * Measures every way at every level; returns rows and a markdown table. The ways of a level are
 * measured in turn frame after frame (way 1's frame 1, way 2's frame 1, ..., way 1's frame 2,
 * ...), so that what else the machine does falls on all of them alike. `animated`: the two
 * animated creature's ways too (their own table, against the offline-refined creature).
 */
async function run({ levels = [4, 8, 16, 32], frames = 7, size = 480, tubular = 40, radial = 6, animated = false } = {}) {
  await ready;
  renderer.setSize(size, size);
  const glb = animated ? new Uint8Array(await (await fetch(CREATURE)).arrayBuffer()) : null;
  const creature = animated ? await creatureFrame(glb) : null;
  const camera = new THREE.PerspectiveCamera(40, 1, 0.1, 20);
  camera.position.set(0, 0, 4.2);
  const pixel = new Uint8Array(4);
  const frame = ({ scene, step }, t) => {
    scene.add(light); // one light (an object has one parent): into the scene drawn
    const t0 = performance.now();
    step(t);
    renderer.render(scene, camera);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
    return performance.now() - t0;
  };
  // The shadow map, allocated here, is no way's.
  const empty = new THREE.Scene();
  empty.add(light);
  renderer.render(empty, camera);
  const rows = [];
  const agreement = new Map(); // level -> the least silhouette IoU of a tessellated animated way and the offline-refined one
  for (const level of levels) {
    const ways = [];
    for (const way of animated ? [...WAYS, ...ANIMATED] : WAYS) {
      // (refineGltf and GLTFLoader touch no WebGL: what is tallied is the first two frames'.)
      tally.allocated = 0;
      const set = ANIMATED.includes(way) ? await setUpAnimated(way, level, glb, creature) : setUp(way, level, tubular, radial);
      // The first frame allocates everything (and compiles, and bakes); the second draws the
      // baked vertices (per-frame), uploading the welded topology.
      frame(set, 0.3);
      frame(set, 0.3);
      set.check();
      const mask = drawnPixels(size);
      const pixels = mask.reduce((n, m) => n + m, 0);
      if (pixels < 0.005 * size * size) throw new Error(`${way} at level ${level}: ${pixels} pixels drawn`);
      ways.push({ way, set, allocated: tally.allocated, uploaded: 0, leastUploaded: Infinity, times: [], pixels, mask });
    }
    if (animated) {
      const [a, ...others] = ANIMATED.map((way) => ways.find((w) => w.way === way).mask);
      agreement.set(level, Math.min(...others.map((b) => iou(a, b))));
    }
    for (const w of ways) w.mask = null;
    for (let f = 1; f <= frames; f++) {
      for (const w of ways) {
        tally.uploaded = 0;
        w.times.push(frame(w.set, 0.3 * (f + 1)));
        w.uploaded = Math.max(w.uploaded, tally.uploaded);
        w.leastUploaded = Math.min(w.leastUploaded, tally.uploaded);
      }
    }
    for (const w of ways) {
      // An animated way moves every frame: something (bones or nets) is uploaded each time.
      if (w.set.animated && w.leastUploaded === 0) throw new Error(`${w.way} at level ${level}: a measured frame uploaded nothing (did not move)`);
      const { way, times, allocated, uploaded, pixels } = w;
      const { triangles, drawn } = w.set;
      rows.push({ level, way, triangles, drawn, ms: median(times), times, allocated, uploaded, pixels });
      w.set.dispose();
    }
    renderer.renderLists.dispose();
  }
  const table = (title, names, baseline) => {
    const base = new Map(rows.filter((r) => r.way === baseline).map((r) => [r.level, r]));
    const lines = [title, '', `| level | way | frame ms | × ${baseline} | GPU memory (bytes) | uploaded per frame (bytes) |`, '|---|---|---|---|---|---|'];
    for (const r of rows.filter((r) => names.includes(r.way))) {
      const b = base.get(r.level);
      lines.push(`| ${r.level} | ${r.way} | ${r.ms.toFixed(1)} | ${(r.ms / b.ms).toFixed(2)} | ${r.allocated} | ${r.uploaded} |`);
    }
    return lines;
  };
  const lines = table(
    `${rows[0].triangles} coarse triangles (torus knot), PN, ${size}×${size}, a shadow-casting directional light (1024² map), median of ${frames} frames`,
    WAYS,
    'static refined',
  );
  if (animated) {
    const a = rows.find((r) => r.way === ANIMATED[1]);
    const ious = levels.map((l) => `${l}: ${agreement.get(l).toFixed(3)}`).join(', ');
    lines.push('', ...table(
      `The animated creature (${CREATURE}, ${a.triangles} coarse triangles, skinned and morphing), its '${CLIP}' clip played by AnimationMixer (${(1 / STEP).toFixed(0)} fps steps), in the same frames; the least silhouette IoU of a tessellated one and the offline one after the first two frames, by level: ${ious}`,
      ANIMATED,
      ANIMATED[0],
    ));
  }
  return { rows, agreement: Object.fromEntries(agreement), markdown: lines.join('\n') };
}

window.benchThree = { run, ready: ready.then(() => true) };
