// A panic inside the wasm (a bug; none is known, so a test hook panics on purpose) is thrown
// as a TessellaError, not `RuntimeError: unreachable`, and the package then refuses to compute
// from the panicked instance's state. Its own file: node --test runs each file in its own process.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { __panicForTests, ready, refine, TessellaError } from '../src/index.js';

await ready;

test('a panic is a TessellaError and later calls say the instance is unusable', () => {
  assert.throws(__panicForTests, (e) => e instanceof TessellaError && /panicked[^]*a deliberate panic for the tests/.test(e.message));
  const triangle = { positions: new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]), indices: new Uint32Array([0, 1, 2]) };
  assert.throws(() => refine(triangle), (e) => e instanceof TessellaError && e.message.includes('after an internal panic'));
});
