// The GMR paper's Figure 7 in three.js (WebGLRenderer): one coarse mesh drawn at levels 8, 16 and
// 32 four ways, in one run —
//   static refined: refineGeometry once, drawn as a plain Mesh (the baseline);
//   static tessellated: TessellatedMesh of the still mesh;
//   deforming refined: RefinedGeometry.update() every frame (CPU refinement, every refined vertex uploaded);
//   deforming tessellated: TessellatedMesh following the moved source (nets rebuilt and uploaded).
// A frame's time is from before the deformation to after a 1-pixel readPixels (which waits for
// the GPU); the median of `frames`. GPU memory: the bytes the WebGL calls allocate for the
// object (bufferData, texStorage2D, texImage2D), spied on the context; uploads: the bytes handed
// to WebGL in a frame after the first.
import * as THREE from 'three';
import { ready } from 'tessella';
import { RefinedGeometry, refineGeometry, TessellatedMesh } from 'tessella/three';

const canvas = document.createElement('canvas');
document.body.append(canvas);
const renderer = new THREE.WebGLRenderer({ canvas, antialias: false });
renderer.setPixelRatio(1);
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
  tally.allocated += viewBytes(a);
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

/** Measures every way at every level; returns rows and a markdown table. */
async function run({ levels = [8, 16, 32], frames = 7, size = 480, tubular = 40, radial = 6 } = {}) {
  await ready;
  renderer.setSize(size, size);
  const pixel = new Uint8Array(4);
  const rows = [];
  for (const level of levels) {
    for (const way of ['static refined', 'static tessellated', 'deforming refined', 'deforming tessellated']) {
      const scene = new THREE.Scene();
      scene.add(new THREE.HemisphereLight(0xffffff, 0x445566, 2));
      const camera = new THREE.PerspectiveCamera(40, 1, 0.1, 20);
      camera.position.set(0, 0, 4.2);
      const geometry = new THREE.TorusKnotGeometry(0.9, 0.3, tubular, radial);
      const rest = geometry.getAttribute('position').array.slice();
      const material = new THREE.MeshStandardMaterial({ color: 0x3377cc });
      const deforming = way.startsWith('deforming');
      const options = { scheme: 'pn', level };
      let step = () => {};
      let dispose = () => {};
      tally.allocated = 0;
      if (way.endsWith('refined') && !deforming) {
        scene.add(new THREE.Mesh(refineGeometry(geometry, options), material));
      } else if (way.endsWith('refined')) {
        const refined = new RefinedGeometry(geometry, options);
        scene.add(new THREE.Mesh(refined.geometry, material));
        step = (t) => {
          bend(geometry, rest, t);
          refined.update();
        };
        dispose = () => refined.dispose();
      } else {
        const source = new THREE.Mesh(geometry, material);
        scene.add(source);
        const mesh = new TessellatedMesh(source, material.clone(), options);
        if (deforming) step = (t) => bend(geometry, rest, t);
        dispose = () => mesh.dispose();
      }
      const times = [];
      let uploaded = 0;
      let allocated = 0;
      for (let f = 0; f <= frames; f++) {
        tally.uploaded = 0;
        const t0 = performance.now();
        step(0.3 * (f + 1));
        renderer.render(scene, camera);
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
        const ms = performance.now() - t0;
        if (f === 0) allocated = tally.allocated; // the first frame allocates everything
        else {
          times.push(ms);
          uploaded = Math.max(uploaded, tally.uploaded);
        }
      }
      const triangles = geometry.index.count / 3;
      rows.push({ level, way, triangles, drawn: triangles * level * level, ms: median(times), allocated, uploaded });
      dispose();
      renderer.renderLists.dispose();
      geometry.dispose();
    }
  }
  const base = new Map(rows.filter((r) => r.way === 'static refined').map((r) => [r.level, r]));
  const lines = [
    `${rows[0].triangles} coarse triangles (torus knot), PN, ${size}×${size}, median of ${frames} frames`,
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
