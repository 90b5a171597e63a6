// sceneCamera, the framing of tessella's pictures, against its defining properties: the pan
// moves the target along the view's axes by pan x the framed radius, reach grows the framed
// radius, and bad views are TessellaErrors.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { ready, sceneCamera, TessellaError } from '../src/index.js';

await ready;

// A box from (-1, 0, 1) to (3, 4, 3): centre (1, 2, 2), radius 3 (the farthest corner).
const corners = [];
for (const x of [-1, 3]) for (const y of [0, 4]) for (const z of [1, 3]) corners.push(x, y, z);
const near = (a, b, eps = 1e-4) => a.every((x, k) => Math.abs(x - b[k]) < eps);

test('the pan moves the target along the view axes by pan x the framed radius', () => {
  const view = { yaw: 40, pitch: 25, zoom: 1.5, width: 640, height: 480 };
  const still = sceneCamera(corners, view);
  assert.ok(near(still.target, [1, 2, 2]), String(still.target));
  const r = 3 * 1.2;
  const moved = sceneCamera(corners, { ...view, pan: [0.25, -0.5] });
  const expected = still.target.map((c, k) => c + (0.25 * still.right[k] - 0.5 * still.up[k]) * r);
  assert.ok(near(moved.target, expected), `${moved.target} vs ${expected}`);
  assert.ok(near(moved.forward, still.forward) && Math.abs(moved.distance - still.distance) < 1e-4);
});

test('reach grows the framed radius, and with it the distance', () => {
  const view = { yaw: 0, pitch: 0, width: 100, height: 100 };
  const [a, b] = [sceneCamera(corners, view), sceneCamera(corners, { ...view, reach: 1.2 })];
  // The distance is proportional to the radius: 3.6 against 4.8.
  assert.ok(Math.abs(b.distance / a.distance - 4.8 / 3.6) < 1e-5, `${a.distance} ${b.distance}`);
});

test('a bad view is a TessellaError that names what was wrong', () => {
  assert.throws(() => sceneCamera(corners, { height: 100 }), (e) => e instanceof TessellaError && /width must be a positive number/.test(e.message));
  assert.throws(() => sceneCamera(corners, { width: 100, height: 0 }), (e) => e instanceof TessellaError && /height/.test(e.message));
  assert.throws(() => sceneCamera(corners, { width: 1, height: 1, zoom: -1 }), (e) => e instanceof TessellaError && /zoom and aspect must be positive/.test(e.message));
  assert.throws(() => sceneCamera([0, 0], { width: 1, height: 1 }), (e) => e instanceof TessellaError && /multiple of 3/.test(e.message));
});
