// The scalar wasm (for engines without SIMD) gives the SIMD build's bits, and the probe that
// chooses between them differs from a valid module only by its SIMD instruction.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { ready, readMesh, refine, variant } from '../src/index.js';
import * as scalar from '../dist/scalar/tessella.js';
import { bytes, sameBits } from './helpers.js';

await ready;
await scalar.default({ module_or_path: readFileSync(new URL('../dist/scalar/tessella_bg.wasm', import.meta.url)) });

test('Node 20 loads the SIMD build', () => {
  assert.equal(variant, 'simd');
});

test('the scalar build gives the same bits as the SIMD build', () => {
  const m = readMesh(bytes('samples/icosphere.obj'), 'obj');
  for (const scheme of ['flat', 'phong', 'pn', 'png1']) {
    const a = refine(m, { scheme, level: 9 });
    const r = scalar.refine(Float32Array.from(m.positions), m.indices, m.normals, undefined, JSON.stringify({ scheme, level: 9 }));
    assert.ok(sameBits(r.takePositions(), a.positions), scheme);
    assert.ok(sameBits(r.takeNormals(), a.normals), scheme);
    r.free();
  }
});

test('the SIMD probe is a valid module but for its v128 instruction', () => {
  const src = readFileSync(new URL('../src/index.js', import.meta.url), 'utf8');
  const probe = new Uint8Array(JSON.parse(`[${src.match(/SIMD_PROBE = new Uint8Array\(\[([^\]]+)\]/)[1]}]`));
  assert.ok(WebAssembly.validate(probe));
  // i8x16.splat (0xfd 0x0f) replaced by two nops: i32.const 0; nop; nop; drop.
  const at = probe.indexOf(253);
  const scalarProbe = probe.slice();
  scalarProbe[at] = 1;
  scalarProbe[at + 1] = 1;
  assert.ok(WebAssembly.validate(scalarProbe));
});
