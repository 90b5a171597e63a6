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
