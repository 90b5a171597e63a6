// TessellatedMesh's GPU posing under WebGLRenderer (WebGL2): a skinned or morphing source's
// control nets built on the GPU by two full-screen passes, which the draws (per draw, the
// 'per-frame' bake) then read instead of the DataTexture the CPU fills. The first poses the
// coarse vertices, as the CPU's Deformer does (morph targets, then linear blend skinning with
// the weights divided by their sum; the normal by the blended matrix's cofactors, normalised),
// into a small RGBA32F render target, two texels a vertex (position, normal; each texel's
// fragment poses its vertex). The second renders into an RGBA32F render target of the nets
// texture's size and layout, one fragment per texel: it finds its face and its texel in the
// face's net, fetches the face's posed corners (and PN-AEN's across normals) and writes its
// texel, computing only the part of the net that texel holds. The builders, the skinned normal
// and the texel packing are the GLSL the wasm generates from the core's Rust
// (InstancedSurface.netsPassGlsl(), gpu_nets.rs); this file only fetches and poses. Per frame only the joint matrices and the
// morph weights are uploaded; the rest vertices, influences, morph deltas and face indices
// once.
import {
  BufferAttribute,
  BufferGeometry,
  Camera,
  GLSL3,
  Mesh,
  NoBlending,
  RawShaderMaterial,
  Vector4,
} from 'three';
import { BAKED_SHIFT as SHIFT, BAKED_WIDTH as WIDTH, bakeMissing, floatTarget, floatTexture, FULL_SCREEN_VERTEX } from './three-bake.js';

// The first pass: a fragment a texel of the posed target, two texels a coarse vertex (its posed
// position, then its normal). `glsl`: the wasm's net pass functions (tessella_skin_normal is
// the one it calls). The rest texture holds `perVertex` texels a vertex: position, normal (then
// joints, weights when skinned); the deltas texture two a vertex and target (position, normal
// displacement), target-major.
const poseFragment = ({ glsl, perVertex, skinned, targets }) => `precision highp float;
precision highp int;
precision highp sampler2D;
${glsl}
uniform highp sampler2D tessellaRest;
uniform highp sampler2D tessellaJoints;
uniform highp sampler2D tessellaDeltas;
uniform highp sampler2D tessellaWeights;
uniform int tessellaVertexCount;
layout(location = 0) out vec4 tessellaPosed;

ivec2 tessella_at(int i) {
  return ivec2(i & ${WIDTH - 1}, i >> ${SHIFT});
}

mat4 tessella_joint(int j) {
  int t = 4 * j;
  return mat4(
    texelFetch(tessellaJoints, tessella_at(t), 0),
    texelFetch(tessellaJoints, tessella_at(t + 1), 0),
    texelFetch(tessellaJoints, tessella_at(t + 2), 0),
    texelFetch(tessellaJoints, tessella_at(t + 3), 0));
}

// Vertex v posed: morphed (the rest plus each weighted displacement), then moved by its
// blended joint matrix (the mesh's one matrix without a skeleton), its normal by that
// matrix's cofactors (tessella_skin_normal: the core's formula, normalised).
void tessella_pose(int v, out vec3 p, out vec3 n) {
  int r = ${perVertex} * v;
  p = texelFetch(tessellaRest, tessella_at(r), 0).xyz;
  n = texelFetch(tessellaRest, tessella_at(r + 1), 0).xyz;
  for (int t = 0; t < ${targets}; t++) {
    vec4 ws = texelFetch(tessellaWeights, ivec2(t >> 2, 0), 0);
    int c = t & 3;
    float w = c == 0 ? ws.x : c == 1 ? ws.y : c == 2 ? ws.z : ws.w;
    if (w == 0.0) continue;
    int d = 2 * (t * tessellaVertexCount + v);
    p += w * texelFetch(tessellaDeltas, tessella_at(d), 0).xyz;
    n += w * texelFetch(tessellaDeltas, tessella_at(d + 1), 0).xyz;
  }
${skinned ? `  vec4 joints = texelFetch(tessellaRest, tessella_at(r + 2), 0);
  vec4 weights = texelFetch(tessellaRest, tessella_at(r + 3), 0);
  mat4 m = mat4(0.0);
  float sum = 0.0;
  for (int i = 0; i < 4; i++) {
    if (weights[i] > 0.0) {
      m += weights[i] * tessella_joint(int(joints[i]));
      sum += weights[i];
    }
  }
  m = m * (1.0 / sum);` : '  mat4 m = tessella_joint(0);'}
  p = (m * vec4(p, 1.0)).xyz;
  n = tessella_skin_normal(mat3(m), n);
}

void main() {
  ivec2 texel = ivec2(gl_FragCoord.xy);
  int i = (texel.y << ${SHIFT}) + texel.x;
  int v = i >> 1;
  if (v >= tessellaVertexCount) {
    tessellaPosed = vec4(0.0);
    return;
  }
  vec3 p;
  vec3 n;
  tessella_pose(v, p, n);
  tessellaPosed = vec4((i & 1) == 0 ? p : n, 0.0);
}
`;

// The second pass: a fragment a texel of the nets. It finds its face and its texel in the
// face's net, fetches the face's posed corners (and PN-AEN's across vertices' normals) from the
// first pass's target, calls the net builders and writes its texel.
const netFragment = ({ glsl, texels }) => `precision highp float;
precision highp int;
precision highp sampler2D;
${glsl}
uniform highp sampler2D tessellaTopology;
uniform highp sampler2D tessellaPosed;
uniform int tessellaFacesPerRow;
uniform int tessellaFaceCount;
layout(location = 0) out vec4 tessellaNet;

ivec2 tessella_at(int i) {
  return ivec2(i & ${WIDTH - 1}, i >> ${SHIFT});
}

int tessella_word(int w) {
  vec4 t = texelFetch(tessellaTopology, tessella_at(w >> 2), 0);
  int c = w & 3;
  return int(c == 0 ? t.x : c == 1 ? t.y : c == 2 ? t.z : t.w);
}

void main() {
  ivec2 texel = ivec2(gl_FragCoord.xy);
  int slot = texel.x / ${texels};
  int face = texel.y * tessellaFacesPerRow + slot;
  if (slot >= tessellaFacesPerRow || face >= tessellaFaceCount) {
    tessellaNet = vec4(0.0);
    return;
  }
  int at = face * TESSELLA_NETS_STRIDE;
  vec3 p[3];
  vec3 n[3];
  for (int c = 0; c < 3; c++) {
    int v = 2 * tessella_word(at + c);
    p[c] = texelFetch(tessellaPosed, tessella_at(v), 0).xyz;
    n[c] = texelFetch(tessellaPosed, tessella_at(v + 1), 0).xyz;
  }
  vec3 across[6];
  for (int a = 0; a < 6; a++) {
    if (TESSELLA_NETS_ACROSS) across[a] = texelFetch(tessellaPosed, tessella_at(2 * tessella_word(at + 3 + a) + 1), 0).xyz;
    else across[a] = n[a / 2];
  }
  tessellaNet = tessella_nets_texel_of(p, n, across, texel.x - slot * ${texels});
}
`;

const viewport = new Vector4();

/**
 * Why `renderer` cannot build the nets (then the CPU poses), or null: WebGLRenderer with float
 * render targets (EXT_color_buffer_float), as the 'per-frame' bake needs.
 */
export function gpuNetsMissing(renderer) {
  if (renderer == null || renderer.isWebGLRenderer !== true) return 'GPU posing builds the nets under WebGLRenderer (WebGL2); this renderer poses on the CPU';
  return bakeMissing(renderer);
}

// A float texture of `texels` RGBA texels, rows of WIDTH (one row if fewer), filled by `data`.
function texture(data, texels) {
  const width = Math.max(1, Math.min(texels, WIDTH));
  const height = Math.max(1, Math.ceil(texels / WIDTH));
  const full = new Float32Array(width * height * 4);
  full.set(data.subarray(0, Math.min(data.length, full.length)));
  const t = floatTexture(full, width, height);
  t.needsUpdate = true;
  return t;
}

/**
 * One TessellatedMesh's nets built on the GPU from its posed source. `surface`: the
 * InstancedSurface (a frame built: its layout, the pass's GLSL and topology); `rest`: the
 * source's rest data (SourcePose.rest: positions, normals, joints, weights, deltas, targets,
 * matrixCount). `render(renderer, matrices, weights)` poses and builds into `target`;
 * `uploadBytes` is what each frame uploads.
 */
export class GpuNets {
  #material;
  #poseMaterial;
  #posed;
  #geometry;
  #mesh;
  #camera = new Camera();
  #joints;
  #weights;
  #inputs;
  #skinned;
  #targets;

  constructor(surface, rest) {
    const vertices = rest.positions.length / 3;
    const skinned = rest.joints !== undefined;
    const perVertex = skinned ? 4 : 2;
    const restData = new Float32Array(vertices * perVertex * 4);
    for (let v = 0; v < vertices; v++) {
      const r = 4 * perVertex * v;
      restData.set(rest.positions.subarray(3 * v, 3 * v + 3), r);
      restData.set(rest.normals.subarray(3 * v, 3 * v + 3), r + 4);
      if (skinned) {
        for (let i = 0; i < 4; i++) restData[r + 8 + i] = rest.joints[4 * v + i];
        restData.set(rest.weights.subarray(4 * v, 4 * v + 4), r + 12);
      }
    }
    const targets = rest.targets;
    const deltas = new Float32Array(Math.max(1, 2 * targets * vertices) * 4);
    for (let t = 0; t < targets; t++) {
      for (let v = 0; v < vertices; v++) {
        const d = 8 * (t * vertices + v);
        const s = 3 * (t * vertices + v);
        deltas.set(rest.positionDeltas.subarray(s, s + 3), d);
        if (rest.normalDeltas !== undefined) deltas.set(rest.normalDeltas.subarray(s, s + 3), d + 4);
      }
    }
    const words = surface.netsPassTopology();
    const topology = Float32Array.from(words);
    this.#inputs = [
      texture(topology, Math.ceil(topology.length / 4)),
      texture(restData, vertices * perVertex),
      texture(deltas, Math.max(1, 2 * targets * vertices)),
    ];
    this.#joints = texture(new Float32Array(16 * rest.matrixCount), 4 * rest.matrixCount);
    this.#weights = texture(new Float32Array(4 * Math.max(1, Math.ceil(targets / 4))), Math.max(1, Math.ceil(targets / 4)));
    this.#skinned = skinned;
    this.#targets = targets;
    /** The rows the input textures take (at most the largest texture's height). */
    this.rows = Math.max(...[...this.#inputs, this.#joints].map((t) => t.image.height));
    const glsl = surface.netsPassGlsl();
    const pass = (fragmentShader, uniforms) =>
      new RawShaderMaterial({ glslVersion: GLSL3, vertexShader: FULL_SCREEN_VERTEX, fragmentShader, uniforms, depthTest: false, depthWrite: false, blending: NoBlending });
    /** The posed coarse vertices, two texels a vertex (position, normal), rows of WIDTH. */
    this.#posed = floatTarget(Math.max(1, Math.min(2 * vertices, WIDTH)), Math.max(1, Math.ceil((2 * vertices) / WIDTH)));
    this.#poseMaterial = pass(poseFragment({ glsl, perVertex, skinned, targets }), {
      tessellaRest: { value: this.#inputs[1] },
      tessellaDeltas: { value: this.#inputs[2] },
      tessellaJoints: { value: this.#joints },
      tessellaWeights: { value: this.#weights },
      tessellaVertexCount: { value: vertices },
    });
    this.#material = pass(netFragment({ glsl, texels: surface.texelsPerFace }), {
      tessellaTopology: { value: this.#inputs[0] },
      tessellaPosed: { value: this.#posed.texture },
      tessellaFacesPerRow: { value: surface.facesPerRow },
      tessellaFaceCount: { value: surface.faceCount },
    });
    this.#geometry = new BufferGeometry();
    this.#geometry.setAttribute('position', new BufferAttribute(new Float32Array(9), 3));
    this.#mesh = new Mesh(this.#geometry, this.#material);
    this.#mesh.frustumCulled = false;
    /** The nets, in the layout of the nets DataTexture (RGBA32F, nearest). */
    this.target = floatTarget(surface.width, surface.height);
    /** Bytes a frame uploads: the joint matrices (a skeleton's) and the morph weights (when there are targets). */
    this.uploadBytes = (skinned ? this.#joints.image.data.byteLength : 0) + (targets > 0 ? this.#weights.image.data.byteLength : 0);
  }

  /** Why `renderer` cannot run this pass, or null. */
  missing(renderer) {
    const why = gpuNetsMissing(renderer);
    if (why !== null) return why;
    const size = renderer.capabilities.maxTextureSize;
    if (this.rows > size) return `the posing inputs need ${this.rows} rows of ${WIDTH} texels, over the largest texture, ${size}`;
    // The weights are one row of texels, four a texel.
    if (this.#targets > 4 * WIDTH) return `${this.#targets} morph targets, over the ${4 * WIDTH} the pass reads`;
    return null;
  }

  /**
   * Builds the nets of the pose `matrices` (16 floats a joint, bind space to posed mesh space,
   * SourcePose's) and morph `weights` into `target`, from within a render (onBeforeRender or
   * onBeforeShadow): two draws (the vertices posed, then the nets), after which the render
   * target, cube face, mipmap level and viewport are put back. Uploads the matrices (skinned;
   * a rigid source's one matrix once) and the weights.
   */
  render(renderer, matrices, weights, first) {
    if (this.#skinned || first) {
      this.#joints.image.data.set(matrices);
      this.#joints.needsUpdate = true;
    }
    if (this.#targets > 0) {
      this.#weights.image.data.set(weights);
      this.#weights.needsUpdate = true;
    }
    const gl = renderer.getContext();
    const target = renderer.getRenderTarget();
    const face = renderer.getActiveCubeFace();
    const level = renderer.getActiveMipmapLevel();
    const v = gl.getParameter(gl.VIEWPORT);
    renderer.setRenderTarget(this.#posed);
    renderer.renderBufferDirect(this.#camera, null, this.#geometry, this.#poseMaterial, this.#mesh, null);
    renderer.setRenderTarget(this.target);
    renderer.renderBufferDirect(this.#camera, null, this.#geometry, this.#material, this.#mesh, null);
    renderer.setRenderTarget(target, face, level);
    renderer.state.viewport(viewport.set(v[0], v[1], v[2], v[3]));
  }

  dispose() {
    for (const t of this.#inputs) t.dispose();
    this.#joints.dispose();
    this.#weights.dispose();
    this.#material.dispose();
    this.#poseMaterial.dispose();
    this.#posed.dispose();
    this.#geometry.dispose();
    this.target.dispose();
  }
}
