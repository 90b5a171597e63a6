// The camera of `tessella render` (crates/tessella-view/src/camera.rs and render.rs's
// scene_uniforms), ported line for line for the WebGL2 fallback: the npm package does not
// export it. test/camera.test.js checks it against the Rust side's pictures (same
// silhouette as `tessella render`). Matrices are column-major Float64Array(16), as glam's.

/** Vertical field of view, degrees (camera.rs FOV_Y_DEGREES). */
export const FOV_Y_DEGREES = 30;

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const normalize = (a) => scale(a, 1 / Math.hypot(a[0], a[1], a[2]));

/** Centre (the bounding box's) and radius of a sphere around `positions` (3 per vertex). */
export function boundingSphere(positions) {
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < positions.length; i += 3) {
    for (let k = 0; k < 3; k++) {
      lo[k] = Math.min(lo[k], positions[i + k]);
      hi[k] = Math.max(hi[k], positions[i + k]);
    }
  }
  const center = scale(add(lo, hi), 0.5);
  let radius = 0;
  for (let i = 0; i < positions.length; i += 3) {
    radius = Math.max(radius, Math.hypot(positions[i] - center[0], positions[i + 1] - center[1], positions[i + 2] - center[2]));
  }
  return { center, radius: Math.max(radius, 1e-6) };
}

/** `a * b` for column-major 4x4 matrices. */
export function mul(a, b) {
  const out = new Float64Array(16);
  for (let c = 0; c < 4; c++) {
    for (let r = 0; r < 4; r++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
      out[c * 4 + r] = s;
    }
  }
  return out;
}

/** Right-handed view matrix looking from `eye` at `center`. */
function lookAtRh(eye, center, up) {
  const f = normalize(sub(center, eye));
  const s = normalize(cross(f, up));
  const u = cross(s, f);
  return Float64Array.from([s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0, -dot(s, eye), -dot(u, eye), dot(f, eye), 1]);
}

/** Right-handed perspective projection onto wgpu's depth range 0..=1. */
function perspectiveRh(fovY, aspect, near, far) {
  const h = 1 / Math.tan(fovY * 0.5);
  const w = h / aspect;
  const r = far / (near - far);
  return Float64Array.from([w, 0, 0, 0, 0, h, 0, 0, 0, 0, r, -1, 0, 0, r * near, 0]);
}

/**
 * Frames the sphere (`center`, `radius`): `yaw` turns about +Y, `pitch` raises the eye,
 * `zoom > 1` moves closer. Returns `{ viewProj, eye, lightDir, right, up, forward }`.
 */
export function framing(center, radius, yaw, pitch, zoom, aspect) {
  const fovY = (FOV_Y_DEGREES * Math.PI) / 180;
  const halfX = Math.atan(Math.tan(fovY * 0.5) * aspect);
  const half = Math.min(fovY * 0.5, halfX);
  const distance = radius / Math.sin(half) / zoom;
  const y = (yaw * Math.PI) / 180;
  const p = (pitch * Math.PI) / 180;
  const dir = [Math.cos(p) * Math.sin(y), Math.sin(p), Math.cos(p) * Math.cos(y)];
  const eye = add(center, scale(dir, distance));
  const up = Math.abs(dir[1]) > 0.999 ? [0, 0, 1] : [0, 1, 0];
  const view = lookAtRh(eye, center, up);
  const near = Math.max(distance - radius * 1.5, distance * 0.01);
  const far = distance + radius * 1.5;
  const proj = perspectiveRh(fovY, aspect, near, far);
  const forward = normalize(sub(center, eye));
  const right = normalize(cross(forward, up));
  const camUp = cross(right, forward);
  const lightDir = normalize(add(add(scale(right, -0.45), scale(camUp, 0.6)), scale(forward, -0.65)));
  return { viewProj: mul(proj, view), eye, lightDir, right, up: camUp, forward, distance };
}

/**
 * The camera `tessella render` draws `positions` (the coarse mesh) with: its bounding sphere
 * grown by a fifth (curved patches bulge past the coarse hull) plus `reach` (displacement).
 * `pan` shifts the target in the view plane, in units of the framed radius (the viewer's own
 * addition; [0, 0] is `tessella render`'s camera).
 */
export function sceneCamera(positions, { yaw, pitch, zoom, width, height, reach = 0, pan = [0, 0] }) {
  const { center, radius } = boundingSphere(positions);
  const r = radius * 1.2 + reach;
  const base = framing(center, r, yaw, pitch, zoom, width / height);
  if (pan[0] === 0 && pan[1] === 0) return base;
  const target = add(center, add(scale(base.right, pan[0] * r), scale(base.up, pan[1] * r)));
  return framing(target, r, yaw, pitch, zoom, width / height);
}

/** `viewProj` remapped from wgpu's clip depth 0..w to OpenGL's -w..w (same clipping planes). */
export function toGlClip(viewProj) {
  const remap = Float64Array.from([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2, 0, 0, 0, -1, 1]);
  return mul(remap, viewProj);
}

/** Projects a world point to pixel coordinates (origin top-left) and depth, or null behind the eye. */
export function project(viewProj, point, width, height) {
  const m = viewProj;
  const x = m[0] * point[0] + m[4] * point[1] + m[8] * point[2] + m[12];
  const y = m[1] * point[0] + m[5] * point[1] + m[9] * point[2] + m[13];
  const z = m[2] * point[0] + m[6] * point[1] + m[10] * point[2] + m[14];
  const w = m[3] * point[0] + m[7] * point[1] + m[11] * point[2] + m[15];
  if (!(w > 0)) return null;
  return [((x / w + 1) / 2) * width, ((1 - y / w) / 2) * height, z / w];
}
