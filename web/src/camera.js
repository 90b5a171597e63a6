// What the page does with a camera: the camera itself is the npm package's `sceneCamera`, the
// framing `tessella render` and the WebGPU engine draw with (tessella_core::framing, one
// definition). Matrices are column-major, as glam's.

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
