// Shared by the tests: the repository's files, and the digest the native side computes too
// (crates/tessella-wasm/examples/native.rs).
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';

export const repo = fileURLToPath(new URL('../../', import.meta.url));

export function bytes(relative) {
  return new Uint8Array(readFileSync(new URL(`../../${relative}`, import.meta.url)));
}

/** FNV-1a and a multiplicative hash over the 32-bit words of a typed array, as hex. */
export function digest(array) {
  const words = new Uint32Array(array.buffer, array.byteOffset, array.byteLength / 4);
  let a = 0x811c9dc5;
  let b = 0x12345678;
  for (let i = 0; i < words.length; i++) {
    a = Math.imul(a ^ words[i], 16777619) >>> 0;
    const m = Math.imul(b ^ words[i], 0x9e3779b1) >>> 0;
    b = ((m << 13) | (m >>> 19)) >>> 0;
  }
  return a.toString(16).padStart(8, '0') + b.toString(16).padStart(8, '0');
}

/** The same bits (NaN payloads and signed zeros included). */
export function sameBits(a, b) {
  if (a.length !== b.length || a.constructor !== b.constructor) return false;
  const x = new Uint32Array(a.buffer, a.byteOffset, a.length);
  const y = new Uint32Array(b.buffer, b.byteOffset, b.length);
  for (let i = 0; i < x.length; i++) if (x[i] !== y[i]) return false;
  return true;
}

const CUBIC = [
  [3, 0, 0], [0, 3, 0], [0, 0, 3], [2, 1, 0], [1, 2, 0], [0, 2, 1], [0, 1, 2], [1, 0, 2], [2, 0, 1], [1, 1, 1],
];
const FACT = [1, 1, 2, 6];

/** Net entry `i` of face `f` from a TessellatedMesh's nets texture data, as the vertex shader reads it. */
export function netEntry(mesh, f, i) {
  const s = mesh.surface;
  const row = Math.floor(f / s.facesPerRow);
  const start = (row * s.width + (f % s.facesPerRow) * s.texelsPerFace) * 4;
  const d = mesh.netsTexture.image.data;
  return [d[start + 3 * i], d[start + 3 * i + 1], d[start + 3 * i + 2]];
}

/** The cubic Bernstein patch's point of face `f` at barycentric `l`, from the nets texture. */
export function cubicPoint(mesh, f, l) {
  const p = [0, 0, 0];
  CUBIC.forEach(([i, j, k], c) => {
    const w = (6 / (FACT[i] * FACT[j] * FACT[k])) * l[0] ** i * l[1] ** j * l[2] ** k;
    const q = netEntry(mesh, f, c);
    for (let a = 0; a < 3; a++) p[a] += w * q[a];
  });
  return p;
}
