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
// A frame's time is from before the deformation to after a 1-pixel readPixels (which waits for
// the GPU); the median of `frames`. GPU memory: the bytes the WebGL calls allocate for the
// object (bufferData, texStorage2D, texImage2D) in its first two frames (the first allocates,
// compiles and, per-frame, bakes; the second draws the baked vertices, uploading the welded
// topology), spied on the context; uploads: the most bytes handed to WebGL in a measured frame.
import * as THREE from 'three';
import { ready } from 'tessella';
import { RefinedGeometry, refineGeometry, TessellatedMesh } from 'tessella/three';

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
  return { scene, geometry, step, check, dispose: () => { dispose(); geometry.dispose(); } };
}

/**
 * Measures every way at every level; returns rows and a markdown table. The ways of a level are
 * measured in turn frame after frame (way 1's frame 1, way 2's frame 1, ..., way 1's frame 2,
 * ...), so that what else the machine does falls on all of them alike.
 */
async function run({ levels = [4, 8, 16, 32], frames = 7, size = 480, tubular = 40, radial = 6 } = {}) {
  await ready;
  renderer.setSize(size, size);
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
  for (const level of levels) {
    const ways = WAYS.map((way) => {
      tally.allocated = 0;
      const set = setUp(way, level, tubular, radial);
      // The first frame allocates everything (and compiles, and bakes); the second draws the
      // baked vertices (per-frame), uploading the welded topology.
      frame(set, 0.3);
      frame(set, 0.3);
      set.check();
      return { way, set, allocated: tally.allocated, uploaded: 0, times: [] };
    });
    for (let f = 1; f <= frames; f++) {
      for (const w of ways) {
        tally.uploaded = 0;
        w.times.push(frame(w.set, 0.3 * (f + 1)));
        w.uploaded = Math.max(w.uploaded, tally.uploaded);
      }
    }
    for (const w of ways) {
      const triangles = w.set.geometry.index.count / 3;
      const { way, times, allocated, uploaded } = w;
      rows.push({ level, way, triangles, drawn: triangles * level * level, ms: median(times), times, allocated, uploaded });
      w.set.dispose();
    }
    renderer.renderLists.dispose();
  }
  const base = new Map(rows.filter((r) => r.way === 'static refined').map((r) => [r.level, r]));
  const lines = [
    `${rows[0].triangles} coarse triangles (torus knot), PN, ${size}×${size}, a shadow-casting directional light (1024² map), median of ${frames} frames`,
    '',
    '| level | way | frame ms | × static refined | GPU memory (bytes) | uploaded per frame (bytes) |',
    '|---|---|---|---|---|---|',
  ];
  for (const r of rows) {
    const b = base.get(r.level);
    lines.push(`| ${r.level} | ${r.way} | ${r.ms.toFixed(1)} | ${(r.ms / b.ms).toFixed(2)} | ${r.allocated} | ${r.uploaded} |`);
  }
  return { rows, markdown: lines.join('\n') };
}

window.benchThree = { run, ready: ready.then(() => true) };
