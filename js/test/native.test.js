// The wasm build gives the native CPU's exact bits: flat, Phong, PN and PNG1 on every sample
// mesh at levels 1 to 16. The native side runs in this test (cargo, on this machine) and writes
// digests of its output; the meshes reach both sides as the same OBJ bytes.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { ready, readMesh, refine, variant } from '../src/index.js';
import { bytes, digest, repo } from './helpers.js';

await ready;

function nativeDigests() {
  const dir = mkdtempSync(join(tmpdir(), 'tessella-native-'));
  try {
    const out = join(dir, 'digests.json');
    execFileSync('cargo', ['run', '--quiet', '-p', 'tessella-wasm', '--example', 'native', '--', 'digests', out], {
      cwd: repo,
      stdio: ['ignore', 'inherit', 'inherit'],
    });
    return JSON.parse(readFileSync(out, 'utf8'));
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
}

test(`wasm (${variant}) refine equals the native CPU bit for bit`, () => {
  const entries = nativeDigests();
  assert.equal(entries.length, 6 * 4 * 16, 'every sample, scheme and level');
  const meshes = new Map();
  for (const e of entries) {
    if (!meshes.has(e.mesh)) meshes.set(e.mesh, readMesh(bytes(`samples/${e.mesh}`), e.mesh));
    const out = refine(meshes.get(e.mesh), { scheme: e.scheme, level: e.level });
    const where = `${e.mesh} ${e.scheme} level ${e.level}`;
    assert.equal(out.positions.length, e.vertices * 3, where);
    assert.equal(out.indices.length, e.triangles * 3, where);
    assert.equal(digest(out.positions), e.positions, `${where}: positions`);
    assert.equal(digest(out.normals), e.normals, `${where}: normals`);
    assert.equal(digest(out.indices), e.indices, `${where}: indices`);
  }
});

test('Float64Array positions and Uint16Array indices give the same bits as Float32Array and Uint32Array', () => {
  const m = readMesh(bytes('samples/torus.obj'), 'obj');
  const a = refine(m, { scheme: 'png1', level: 5 });
  const b = refine(
    { positions: Float64Array.from(m.positions), indices: Uint16Array.from(m.indices), normals: Float64Array.from(m.normals) },
    { scheme: 'png1', level: 5 },
  );
  assert.equal(digest(b.positions), digest(a.positions));
  assert.equal(digest(b.normals), digest(a.normals));
  assert.deepEqual(b.indices, a.indices);
});
