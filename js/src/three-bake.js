// TessellatedMesh's 'per-frame' evaluation under WebGLRenderer (WebGL2): the refined mesh's
// welded vertices (welded(): refine's topology with each vertex's coarse triangle and
// barycentric point); when the nets change (and once at the start), one full-screen pass
// evaluates every vertex with the same generated GLSL the per-draw vertex shader calls
// (`tessella_evaluate`, InstancedSurface.glsl()), writing its position and unit normal into two
// RGBA32F render targets (texel v = vertex v, 2048 texels a row), copied on the GPU into two
// vertex buffers (readPixels into a PIXEL_PACK_BUFFER) that become the welded geometry's
// `position` and `normal`: every draw pass (the picture, shadow depth and distance maps) reads
// them as a refined Mesh reads its own, with a program of its own that evaluates nothing
// (three.js's 'baked' shader variant).
import {
  BufferAttribute,
  BufferGeometry,
  Camera,
  DataTexture,
  FloatType,
  GLBufferAttribute,
  GLSL3,
  Mesh,
  NearestFilter,
  NoBlending,
  RawShaderMaterial,
  RGBAFormat,
  Vector4,
  WebGLRenderTarget,
} from 'three';

/** Texels a row of the baked textures (WebGL2 guarantees textures 2048 wide). */
export const BAKED_WIDTH = 2048;
/** log2(BAKED_WIDTH): a texel index's row is `i >> BAKED_SHIFT`. */
export const BAKED_SHIFT = 11;

// One triangle over the whole target, from gl_VertexID alone: renderBufferDirect binds the
// buffers of attributes three has uploaded (as projectObject and the shadow pass have it do for
// the objects they draw), which a geometry drawn only here never is; its position attribute
// only gives the draw's count.
export const FULL_SCREEN_VERTEX = `precision highp float;
void main() {
  gl_Position = vec4(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0, 0.0, 1.0);
}
`;

// Texel v of the target: vertex v, at its origin (texel v of tessellaOrigins: the barycentric
// point and the coarse triangle).
const fragment = (glsl) => `precision highp float;
precision highp int;
precision highp sampler2D;
${glsl}
uniform highp sampler2D tessellaOrigins;
uniform int tessellaVertexCount;
layout(location = 0) out vec4 tessellaBakedPosition;
layout(location = 1) out vec4 tessellaBakedNormal;
void main() {
  ivec2 texel = ivec2(gl_FragCoord.xy);
  if ((texel.y << ${BAKED_SHIFT}) + texel.x >= tessellaVertexCount) discard;
  vec4 origin = texelFetch(tessellaOrigins, texel, 0);
  vec3 p;
  vec3 n;
  tessella_evaluate(int(origin.w), origin.xyz, p, n);
  tessellaBakedPosition = vec4(p, 1.0);
  tessellaBakedNormal = vec4(n, 0.0);
}
`;

const viewport = new Vector4();

/** Why `renderer` cannot bake at all (then the mesh evaluates per draw), or null. */
export function bakeMissing(renderer) {
  if (renderer == null || renderer.isWebGLRenderer !== true) return 'WebGPURenderer evaluates per draw (its nodes)';
  if (renderer.extensions == null || !renderer.extensions.has('EXT_color_buffer_float')) return 'no float render targets (EXT_color_buffer_float)';
  return null;
}

/**
 * The refined mesh's topology for 'per-frame' (`out`: refine's output with `origin`): one
 * vertex per refined vertex (shared by the coarse triangles that share it, as in the refined
 * Mesh), drawn by one indexed draw, not instanced; attributes `tessellaBarycentric` and
 * `tessellaFace` (each vertex's coarse triangle and point in it); `faces` for the corner
 * attributes.
 */
export function welded(out) {
  const count = out.faces.length;
  const faces = Uint32Array.from(out.faces, (f) => (f === 0xffffffff ? 0 : f));
  const l = out.barycentric.slice();
  for (let v = 0; v < count; v++) if (out.faces[v] === 0xffffffff) l.set([1, 0, 0], 3 * v);
  const index = count <= 0xffff ? Uint16Array.from(out.indices) : out.indices;
  return { count, faces, barycentric: l, face: Float32Array.from(faces), index };
}

/**
 * One TessellatedMesh's baked vertices: `bake(renderer)` (evaluates every vertex into the render targets),
 * `missing(renderer)` (why it cannot run there, or null), `bytes` (GPU memory of the targets).
 */
export class BakedSurface {
  #target = null;
  #origins;
  #material;
  #geometry;
  #mesh;
  #camera = new Camera();
  /** The vertex buffers the targets are copied into (positions, normals), their context and frame. */
  #buffers = null;
  #gl = null;

  /**
   * `uniforms`: the mesh's own uniform objects (shared, not copied): the nets
   * (`tessellaNets`, `tessellaFacesPerRow`) the bake reads.
   */
  constructor(glsl, uniforms, mesh) {
    this.vertices = mesh.count;
    this.rows = Math.max(1, Math.ceil(this.vertices / BAKED_WIDTH));
    const data = new Float32Array(BAKED_WIDTH * this.rows * 4);
    for (let v = 0; v < mesh.count; v++) {
      data.set(mesh.barycentric.subarray(3 * v, 3 * v + 3), 4 * v);
      data[4 * v + 3] = mesh.faces[v];
    }
    this.#origins = floatTexture(data, BAKED_WIDTH, this.rows);
    this.#origins.needsUpdate = true;
    this.#material = new RawShaderMaterial({
      glslVersion: GLSL3,
      vertexShader: FULL_SCREEN_VERTEX,
      fragmentShader: fragment(glsl),
      uniforms: {
        tessellaNets: uniforms.tessellaNets,
        tessellaFacesPerRow: uniforms.tessellaFacesPerRow,
        tessellaOrigins: { value: this.#origins },
        tessellaVertexCount: { value: this.vertices },
      },
      depthTest: false,
      depthWrite: false,
      blending: NoBlending,
    });
    this.#geometry = new BufferGeometry();
    this.#geometry.setAttribute('position', new BufferAttribute(new Float32Array(9), 3));
    this.#mesh = new Mesh(this.#geometry, this.#material);
    this.#mesh.frustumCulled = false;
    /**
     * GPU memory: the two targets, the origins and the two vertex buffers, 80 bytes a vertex
     * (rows of 2048 texels).
     */
    this.bytes = 5 * 16 * BAKED_WIDTH * this.rows;
    /** The geometry's `position` and `normal` once baked: the vertex buffers (GLBufferAttribute, xyz of 4 floats). */
    this.attributes = null;
  }

  /** The render target (two textures: positions, normals), once baked; else null. */
  get target() {
    return this.#target;
  }

  /** Why `renderer` cannot bake (then the mesh evaluates per draw), or null. */
  missing(renderer) {
    const why = bakeMissing(renderer);
    if (why !== null) return why;
    if (this.rows > renderer.capabilities.maxTextureSize) {
      return `${this.vertices} vertices need ${this.rows} rows of ${BAKED_WIDTH}, over the largest texture, ${renderer.capabilities.maxTextureSize}`;
    }
    return null;
  }

  /**
   * Evaluates every vertex into the targets, from within a render (a mesh's onBeforeShadow or
   * onBeforeRender): one draw of its own, after which the render target, the active cube face,
   * mipmap level and viewport (a shadow pass draws into parts of its map) are put back.
   */
  bake(renderer) {
    if (this.#target === null) {
      this.#target = floatTarget(BAKED_WIDTH, this.rows, 2);
    }
    const gl = renderer.getContext();
    const target = renderer.getRenderTarget();
    const face = renderer.getActiveCubeFace();
    const level = renderer.getActiveMipmapLevel();
    const v = gl.getParameter(gl.VIEWPORT);
    renderer.setRenderTarget(this.#target);
    renderer.renderBufferDirect(this.#camera, null, this.#geometry, this.#material, this.#mesh, null);
    // The targets copied into vertex buffers on the GPU (readPixels into a PIXEL_PACK_BUFFER), so
    // the draws read position and normal as attributes, as a refined Mesh's are.
    const bytes = 16 * BAKED_WIDTH * this.rows;
    if (this.#buffers === null) {
      this.#gl = gl;
      this.#buffers = [gl.createBuffer(), gl.createBuffer()];
      for (const b of this.#buffers) {
        gl.bindBuffer(gl.PIXEL_PACK_BUFFER, b);
        gl.bufferData(gl.PIXEL_PACK_BUFFER, bytes, gl.DYNAMIC_COPY);
      }
      this.attributes = this.#buffers.map((b) => new GLBufferAttribute(b, gl.FLOAT, 4, 4, this.vertices));
    }
    for (let k = 0; k < 2; k++) {
      gl.readBuffer(gl.COLOR_ATTACHMENT0 + k);
      gl.bindBuffer(gl.PIXEL_PACK_BUFFER, this.#buffers[k]);
      gl.readPixels(0, 0, BAKED_WIDTH, this.rows, gl.RGBA, gl.FLOAT, 0);
    }
    gl.bindBuffer(gl.PIXEL_PACK_BUFFER, null);
    gl.readBuffer(gl.COLOR_ATTACHMENT0);
    renderer.setRenderTarget(target, face, level);
    renderer.state.viewport(viewport.set(v[0], v[1], v[2], v[3]));
  }

  dispose() {
    if (this.#buffers !== null) for (const b of this.#buffers) this.#gl.deleteBuffer(b);
    this.#buffers = null;
    this.attributes = null;
    this.#target?.dispose();
    this.#target = null;
    this.#origins.dispose();
    this.#material.dispose();
    this.#geometry.dispose();
  }
}

/** An RGBA32F render target of `width` × `height` texels (`count` of them), sampled nearest, no mipmaps, no depth. */
export function floatTarget(width, height, count = 1) {
  return new WebGLRenderTarget(width, height, {
    count,
    type: FloatType,
    format: RGBAFormat,
    minFilter: NearestFilter,
    magFilter: NearestFilter,
    generateMipmaps: false,
    depthBuffer: false,
  });
}

/** An RGBA32F DataTexture of `width` × `height` texels holding `data`, sampled nearest, no mipmaps. */
export function floatTexture(data, width, height) {
  const t = new DataTexture(data, width, height, RGBAFormat, FloatType);
  t.minFilter = NearestFilter;
  t.magFilter = NearestFilter;
  t.generateMipmaps = false;
  return t;
}
