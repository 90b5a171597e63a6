// Throughput in one run, same machine, same mesh, same output triangle count:
//   native tessella on one thread (a release build of crates/tessella-wasm/examples/native.rs),
//   the package's SIMD wasm and scalar wasm (one-shot refine, and Refiner frames),
//   three-subdivide's Loop subdivision (iterations k = level 2^k, the same triangle count).
// Prints a Markdown table with ratios; usage:
//   node bench/bench.js [MESH.obj] [SCHEME] [ITERATIONS] [SECONDS]
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import os from 'node:os';
import { fileURLToPath } from 'node:url';
import { BufferAttribute, BufferGeometry } from 'three';
import { LoopSubdivision } from 'three-subdivide';
import { ready, readMesh, refine, Refiner } from '../src/index.js';
import * as scalar from '../dist/scalar/tessella.js';

const repo = fileURLToPath(new URL('../../', import.meta.url));
const [meshPath = 'samples/icosphere-4k.obj', scheme = 'pn', iterations = '3', seconds = '2'] = process.argv.slice(2);
const level = 2 ** Number(iterations);
const budget = Number(seconds);

await ready;
const scalarWasm = await scalar.default({ module_or_path: readFileSync(new URL('../dist/scalar/tessella_bg.wasm', import.meta.url)) });

function time(fn) {
  fn();
  const start = performance.now();
  let runs = 0;
  while (runs < 3 || performance.now() - start < budget * 1000) {
    fn();
    runs++;
  }
  return (performance.now() - start) / 1000 / runs;
}

const mesh = readMesh(readFileSync(`${repo}/${meshPath}`), meshPath);
const faces = mesh.indices.length / 3;
const options = { scheme, level };
const json = JSON.stringify(options);

console.error('building and running the native benchmark (release)...');
execFileSync('cargo', ['build', '--quiet', '--release', '-p', 'tessella-wasm', '--example', 'native'], { cwd: repo, stdio: 'inherit' });
const native = JSON.parse(
  execFileSync(`${repo}/target/release/examples/native`, ['bench', `${repo}/${meshPath}`, scheme, String(level), String(budget)], { encoding: 'utf8' }),
);

let triangles = 0;
const simdOneShot = time(() => (triangles = refine(mesh, options).indices.length / 3));
const scalarOneShot = time(() => {
  const r = scalar.refine(mesh.positions, mesh.indices, mesh.normals, undefined, json);
  r.takePositions();
  r.takeNormals();
  r.takeIndices();
  r.free();
});

const refiner = new Refiner(mesh.indices, options);
const simdFrame = time(() => refiner.refine(mesh.positions, mesh.normals));
const raw = new scalar.Refiner(mesh.indices, undefined, json);
const scalarFrame = time(() => {
  new Float32Array(scalarWasm.memory.buffer, raw.positionsInput(mesh.positions.length), mesh.positions.length).set(mesh.positions);
  new Float32Array(scalarWasm.memory.buffer, raw.normalsInput(mesh.normals.length), mesh.normals.length).set(mesh.normals);
  raw.frame(true);
});

const geometry = new BufferGeometry();
geometry.setAttribute('position', new BufferAttribute(mesh.positions, 3));
geometry.setAttribute('normal', new BufferAttribute(mesh.normals, 3));
geometry.setIndex(new BufferAttribute(mesh.indices, 1));
let loopTriangles = 0;
const loop = time(() => {
  const out = LoopSubdivision.modify(geometry, Number(iterations), { split: false });
  loopTriangles = out.getAttribute('position').count / 3;
});
if (loopTriangles !== triangles || native.triangles !== triangles) {
  throw new Error(`triangle counts differ: tessella ${triangles}, native ${native.triangles}, three-subdivide ${loopTriangles}`);
}

const mtri = (s) => (triangles / s / 1e6).toFixed(2);
const rows = [
  ['native, 1 thread: refine', native.oneShotSeconds],
  ['wasm simd128: refine', simdOneShot],
  ['wasm scalar: refine', scalarOneShot],
  ['native, 1 thread: frame (update + evaluate)', native.frameSeconds],
  ['wasm simd128: Refiner frame', simdFrame],
  ['wasm scalar: Refiner frame', scalarFrame],
  [`three-subdivide Loop, ${iterations} iterations`, loop],
];
console.log(`${meshPath}: ${faces} triangles, ${scheme} level ${level} = ${triangles} output triangles (${native.vertices} vertices)`);
console.log(`${os.cpus()[0].model}, ${os.cpus().length} cores, Node ${process.versions.node}, ${os.platform()} ${os.arch()}\n`);
console.log('| run | ms | M triangles/s | vs native (same kind) | vs three-subdivide |');
console.log('|---|---:|---:|---:|---:|');
for (const [name, s] of rows) {
  const base = name.includes('frame') ? native.frameSeconds : native.oneShotSeconds;
  const vsNative = name.startsWith('three') ? '' : `${(base / s).toFixed(2)}×`;
  console.log(`| ${name} | ${(s * 1000).toFixed(1)} | ${mtri(s)} | ${vsNative} | ${(loop / s).toFixed(0)}× |`);
}
