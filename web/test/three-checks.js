// Checks three-mesh.test.js (WebGLRenderer) and three-webgpu.test.js (WebGPURenderer) both make
// of the torus-knot page (three/mesh.js, three/webgpu.js), through its `run(config)`.
import assert from 'node:assert/strict';
import { count, darker, iou, mask } from './harness.js';

/** The source deformed over `frames` frames: on the GPU, on the CPU, and the CPU's rest pose. */
export async function deformed(run, frames) {
  const gpu = await run({ scheme: 'pn', level: 8, frames, deform: true, castShadow: false });
  const cpu = await run({ scheme: 'pn', level: 8, frames, deform: true, plain: true, castShadow: false });
  const rest = await run({ scheme: 'pn', level: 8, plain: true, castShadow: false });
  return { gpu, cpu, rest };
}

/**
 * It follows the source: the last pose drawn on the GPU is the CPU's refinement of it, and not
 * the rest pose.
 */
export function assertFollows({ gpu, cpu, rest }) {
  const score = iou(mask(gpu.img), mask(cpu.img));
  const moved = iou(mask(gpu.img), mask(rest.img));
  console.log(`deformed: IoU ${score.toFixed(5)} with the CPU's last pose, ${moved.toFixed(5)} with the rest pose`);
  assert.ok(score >= 0.99, `IoU ${score}`);
  assert.ok(moved < 0.95, `IoU with the rest pose ${moved}: the surface did not follow`);
}

/**
 * Shadows cast on a plane from a directional light, then from a point light (whose shadow map
 * takes the distance material), like the CPU mesh's; and received from a ball. The shadow pass
 * draws the surface instanced too. `shot(cpu, gpu)` gets the directional light's pictures.
 */
export async function assertShadows(run, shot) {
  const lit = await run({ plane: true, castShadow: false });
  const shaded = await run({ plane: true, castShadow: true });
  const cpuShaded = await run({ plane: true, castShadow: true, plain: true });
  const cpuLit = await run({ plane: true, castShadow: false, plain: true });
  // Two passes, one instanced draw each: the shadow map's (the patched depth material) and the picture's.
  assert.deepEqual(shaded.log[0].instanced, [{ count: 3 * 64, instances: shaded.faces }, { count: 3 * 64, instances: shaded.faces }]);
  assert.equal(lit.log[0].instanced.length, 1);
  const cast = darker(shaded.img, lit.img);
  const cpuCast = darker(cpuShaded.img, cpuLit.img);
  console.log(`cast shadow: ${count(cast)} pixels darker (CPU mesh: ${count(cpuCast)}), IoU ${iou(cast, cpuCast).toFixed(4)}`);
  shot(cpuShaded.img, shaded.img);
  assert.ok(count(cast) > 2000, `only ${count(cast)} pixels darker with castShadow`);
  assert.ok(iou(cast, cpuCast) > 0.9, `shadow IoU ${iou(cast, cpuCast)}`);
  const pointLit = await run({ plane: true, castShadow: false, point: true });
  const pointShaded = await run({ plane: true, castShadow: true, point: true });
  const cpuPointShaded = await run({ plane: true, castShadow: true, point: true, plain: true });
  const pointCast = darker(pointShaded.img, pointLit.img);
  const cpuPointCast = darker(cpuPointShaded.img, pointLit.img);
  console.log(`point light: ${count(pointCast)} pixels darker (CPU mesh: ${count(cpuPointCast)}), IoU ${iou(pointCast, cpuPointCast).toFixed(4)}`);
  assert.ok(count(pointCast) > 2000, `only ${count(pointCast)} pixels darker under the point light`);
  assert.ok(iou(pointCast, cpuPointCast) > 0.9, `point shadow IoU ${iou(pointCast, cpuPointCast)}`);
  const open = await run({ occluder: true, occluderCasts: false });
  const covered = await run({ occluder: true, occluderCasts: true });
  // No plane: whatever gets darker is the tessellated surface, in the ball's shadow.
  const received = darker(covered.img, open.img);
  console.log(`received shadow: ${count(received)} pixels darker`);
  assert.ok(count(received) > 300, `only ${count(received)} pixels darker under the ball`);
  const inside = mask(open.img);
  for (let i = 0; i < received.length; i++) if (received[i]) assert.equal(inside[i], 1);
}
