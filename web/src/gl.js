// The WebGL2 fallback's renderer: a refined mesh (from the npm package's CPU refinement) in
// vertex buffers, shaded as tessella-view's shade.wgsl does (Blinn-Phong with the same light,
// colours and constants, linear colour written as sRGB), with its wireframe: coarse edges bold
// and dark, the pattern's edges thin. One draw per panel, each in its own viewport.

const VERTEX = `#version 300 es
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 tri;    // corner of the refined triangle (wireframe draws)
layout(location = 3) in vec3 coarse; // barycentric coordinates in the coarse triangle
uniform mat4 viewProj;
out vec3 vWorld;
out vec3 vNormal;
out vec3 vTri;
out vec3 vCoarse;
void main() {
  vWorld = position;
  vNormal = normal;
  vTri = tri;
  vCoarse = coarse;
  gl_Position = viewProj * vec4(position, 1.0);
}`;

const FRAGMENT = `#version 300 es
precision highp float;
in vec3 vWorld;
in vec3 vNormal;
in vec3 vTri;
in vec3 vCoarse;
uniform vec3 eye;
uniform vec3 lightDir;
uniform vec3 baseColor;
uniform int wireframe;
out vec4 outColor;
vec3 toSrgb(vec3 c) {
  return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
void main() {
  vec3 coarseWidth = fwidth(vCoarse);
  vec3 triWidth = fwidth(vTri);
  vec3 view = normalize(eye - vWorld);
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;
  vec3 halfVector = normalize(lightDir + view);
  float diffuse = max(dot(n, lightDir), 0.0);
  float specular = diffuse > 0.0 ? pow(max(dot(n, halfVector), 0.0), 48.0) : 0.0;
  vec3 color = baseColor * (0.12 + 0.88 * diffuse) + vec3(0.35 * specular);
  if (wireframe != 0) {
    vec3 triD = vTri / max(triWidth, vec3(1e-6));
    vec3 coarseD = vCoarse / max(coarseWidth, vec3(1e-6));
    float triPx = 1.0 / max(max(triWidth.x, triWidth.y), max(triWidth.z, 1e-6));
    float coarsePx = 1.0 / max(max(coarseWidth.x, coarseWidth.y), max(coarseWidth.z, 1e-6));
    float fine = 1.0 - smoothstep(0.0, 0.9, min(triD.x, min(triD.y, triD.z)));
    float fineAlpha = 0.45 * smoothstep(3.0, 8.0, triPx);
    color = mix(color, color * 0.45, fine * fineAlpha);
    float halfWidth = clamp(0.06 * coarsePx, 0.35, 1.0);
    float dist = min(coarseD.x, min(coarseD.y, coarseD.z));
    float line = 1.0 - smoothstep(halfWidth - 0.5, halfWidth + 0.5, dist);
    color = mix(color, vec3(0.004, 0.006, 0.015), line);
  }
  outColor = vec4(toSrgb(color), 1.0);
}`;

/** The surface colour of `tessella render` (sRGB 120, 160, 215), linear. */
export const BASE_COLOR = [120, 160, 215].map((c) => {
  const x = c / 255;
  return x <= 0.04045 ? x / 12.92 : ((x + 0.055) / 1.055) ** 2.4;
});

function compile(gl, type, source) {
  const shader = gl.createShader(type);
  gl.shaderSource(shader, source);
  gl.compileShader(shader);
  if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) {
    throw new Error(`WebGL2 shader: ${gl.getShaderInfoLog(shader)}`);
  }
  return shader;
}

/**
 * Vertex data for one panel: indexed positions and normals, or (for the wireframe) one vertex
 * per triangle corner with that corner's barycentric coordinates in the refined and in the
 * coarse triangle (`faces`/`barycentric` from a soup refinement with `origin: true`).
 */
export function meshArrays(refined, wireframe) {
  const { positions, normals, indices } = refined;
  if (!wireframe) return { indexed: true, positions, normals, indices, count: indices.length };
  const n = indices.length;
  const p = new Float32Array(n * 3);
  const nr = new Float32Array(n * 3);
  const tri = new Float32Array(n * 3);
  const coarse = new Float32Array(n * 3);
  for (let i = 0; i < n; i++) {
    const v = indices[i];
    for (let k = 0; k < 3; k++) {
      p[i * 3 + k] = positions[v * 3 + k];
      nr[i * 3 + k] = normals[v * 3 + k];
      coarse[i * 3 + k] = refined.barycentric[v * 3 + k];
    }
    tri[i * 3 + (i % 3)] = 1;
  }
  return { indexed: false, positions: p, normals: nr, tri, coarse, count: n };
}

/** Bytes `meshArrays(...)` puts in GPU buffers. */
export function arrayBytes(arrays) {
  let bytes = arrays.positions.byteLength + arrays.normals.byteLength;
  if (arrays.indexed) bytes += arrays.indices.byteLength;
  else bytes += arrays.tri.byteLength + arrays.coarse.byteLength;
  return bytes;
}

export class GlRenderer {
  constructor(canvas) {
    const gl = canvas.getContext('webgl2', { antialias: true, preserveDrawingBuffer: true });
    if (!gl) throw new Error('this browser has neither WebGPU nor WebGL2: nothing can draw here');
    this.gl = gl;
    const program = gl.createProgram();
    gl.attachShader(program, compile(gl, gl.VERTEX_SHADER, VERTEX));
    gl.attachShader(program, compile(gl, gl.FRAGMENT_SHADER, FRAGMENT));
    gl.linkProgram(program);
    if (!gl.getProgramParameter(program, gl.LINK_STATUS)) {
      throw new Error(`WebGL2 program: ${gl.getProgramInfoLog(program)}`);
    }
    this.program = program;
    this.uniforms = Object.fromEntries(
      ['viewProj', 'eye', 'lightDir', 'baseColor', 'wireframe'].map((u) => [u, gl.getUniformLocation(program, u)]),
    );
    this.panels = [];
  }

  /** The GPU's name as WebGL reports it. */
  adapter() {
    const gl = this.gl;
    const info = gl.getExtension('WEBGL_debug_renderer_info');
    return String(info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER));
  }

  /** Replaces the panels' vertex data; returns the bytes uploaded. */
  upload(panelArrays) {
    const gl = this.gl;
    for (const panel of this.panels) {
      gl.deleteVertexArray(panel.vao);
      for (const b of panel.buffers) gl.deleteBuffer(b);
    }
    let bytes = 0;
    this.panels = panelArrays.map((arrays) => {
      const vao = gl.createVertexArray();
      gl.bindVertexArray(vao);
      const buffers = [];
      const attribute = (location, data) => {
        const b = gl.createBuffer();
        gl.bindBuffer(gl.ARRAY_BUFFER, b);
        gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
        gl.enableVertexAttribArray(location);
        gl.vertexAttribPointer(location, 3, gl.FLOAT, false, 0, 0);
        buffers.push(b);
      };
      attribute(0, arrays.positions);
      attribute(1, arrays.normals);
      if (arrays.indexed) {
        gl.vertexAttrib3f(2, 1, 1, 1);
        gl.vertexAttrib3f(3, 1, 1, 1);
        const b = gl.createBuffer();
        gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, b);
        gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, arrays.indices, gl.STATIC_DRAW);
        buffers.push(b);
      } else {
        attribute(2, arrays.tri);
        attribute(3, arrays.coarse);
      }
      gl.bindVertexArray(null);
      bytes += arrayBytes(arrays);
      return { vao, buffers, count: arrays.count, indexed: arrays.indexed };
    });
    const error = gl.getError();
    if (error === gl.OUT_OF_MEMORY) throw new Error('WebGL2 ran out of memory for the refined mesh');
    return bytes;
  }

  /**
   * Draws panel i into `viewports[i]` ({ x, y, width, height } in pixels, y from the top) with
   * `cameras[i]` ({ glViewProj, eye, lightDir }), on a white background.
   */
  draw(viewports, cameras, wireframe) {
    const gl = this.gl;
    const { width, height } = gl.canvas;
    gl.viewport(0, 0, width, height);
    gl.disable(gl.SCISSOR_TEST);
    gl.clearColor(1, 1, 1, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LESS);
    gl.disable(gl.CULL_FACE);
    gl.useProgram(this.program);
    gl.uniform3fv(this.uniforms.baseColor, BASE_COLOR);
    gl.uniform1i(this.uniforms.wireframe, wireframe ? 1 : 0);
    this.panels.forEach((panel, i) => {
      const v = viewports[i];
      const cam = cameras[i];
      gl.viewport(v.x, height - v.y - v.height, v.width, v.height);
      gl.uniformMatrix4fv(this.uniforms.viewProj, false, Float32Array.from(cam.glViewProj));
      gl.uniform3fv(this.uniforms.eye, cam.eye);
      gl.uniform3fv(this.uniforms.lightDir, cam.lightDir);
      gl.bindVertexArray(panel.vao);
      if (panel.indexed) gl.drawElements(gl.TRIANGLES, panel.count, gl.UNSIGNED_INT, 0);
      else gl.drawArrays(gl.TRIANGLES, 0, panel.count);
    });
    gl.bindVertexArray(null);
    const error = gl.getError();
    if (error !== gl.NO_ERROR) throw new Error(`WebGL2 draw failed (error 0x${error.toString(16)})`);
  }
}
