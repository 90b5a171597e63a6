// The scalar wasm (for engines without SIMD) gives the SIMD build's bits, and the probe that
// chooses between them differs from a valid module only by its SIMD instruction.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { execFileSync } from 'node:child_process';
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

test('the SIMD probe validates, and differs from a valid scalar module only by its SIMD instruction', () => {
  const src = readFileSync(new URL('../src/index.js', import.meta.url), 'utf8');
  const probe = new Uint8Array(src.match(/SIMD_PROBE = new Uint8Array\(\[([^\]]+)\]/)[1].split(",").filter((s) => s.trim() !== "").map(Number));
  assert.ok(WebAssembly.validate(probe));
  // i8x16.splat (0xfd 0x0f) replaced by two nops: i32.const 0; nop; nop; drop.
  const at = probe.indexOf(253);
  const scalarProbe = probe.slice();
  scalarProbe[at] = 1;
  scalarProbe[at + 1] = 1;
  assert.ok(WebAssembly.validate(scalarProbe));
});

test('TESSELLA_WASM=scalar loads the scalar build through the same loader', () => {
  const script = "const m = await import('./src/index.js'); await m.ready; console.log(m.variant, m.refine({ positions: new Float32Array([0,0,0,1,0,0,0,1,0]), indices: new Uint32Array([0,1,2]) }, { level: 3 }).indices.length)";
  const out = execFileSync(process.execPath, ['--input-type=module', '-e', script], {
    cwd: new URL('..', import.meta.url),
    env: { ...process.env, TESSELLA_WASM: 'scalar' },
    encoding: 'utf8',
  });
  assert.equal(out.trim(), 'scalar 27');
});
