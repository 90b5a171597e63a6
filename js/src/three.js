// tessella/three: refine three.js BufferGeometry. `three` is a peer dependency (the caller's
// own copy), never bundled.
import {
  Box3,
  BufferAttribute,
  BufferGeometry,
  DataTexture,
  FloatType,
  InstancedBufferAttribute,
  InstancedBufferGeometry,
  Matrix4,
  Mesh,
  MeshDepthMaterial,
  MeshDistanceMaterial,
  MeshStandardMaterial,
  NearestFilter,
  RGBAFormat,
  Sphere,
} from 'three';
import { AdaptiveSurface, Deformer, InstancedSurface, refine, Refiner, TessellaError } from './index.js';
import { LOD_MESH_OPTIONS, LodParts } from './three-lod.js';
import { missingNodes, setupNodes } from './three-nodes.js';
import { setupLodNodes } from './three-lod-nodes.js';
import { bakeMissing, BakedSurface, welded } from './three-bake.js';
import { GpuNets, gpuNetsMissing } from './three-gpu-nets.js';
import { GpuNetsNodes, gpuNetsNodesMissing } from './three-gpu-nets-nodes.js';

export { tessellaFunctions } from './three-nodes.js';
export { tessellate, TessellatedScene, untessellate } from './three-scene.js';

// Attributes tessella computes itself; every other float attribute is interpolated.
const OWN = new Set(['position', 'normal', 'uv']);

function sourceOf(geometry) {
  if (!(geometry instanceof BufferGeometry) && !(geometry && geometry.isBufferGeometry)) {
    throw new TessellaError('expected a three.js BufferGeometry');
  }
  const position = geometry.getAttribute('position');
  if (position === undefined) throw new TessellaError('the geometry has no position attribute');
  const count = position.count;
  const indices = geometry.index !== null ? geometry.index.array : Uint32Array.from({ length: count }, (_, i) => i);
  return { position, count, indices };
}

// An attribute's values as a tight Float32Array (interleaved or not), or null if it is not a
// float attribute.
function values(attribute) {
  const n = attribute.count * attribute.itemSize;
  if (attribute.isInterleavedBufferAttribute) {
    const out = new Float32Array(n);
    for (let i = 0; i < attribute.count; i++) {
      for (let k = 0; k < attribute.itemSize; k++) out[i * attribute.itemSize + k] = attribute.getComponent(i, k);
    }
    return out;
  }
  const a = attribute.array;
  // Normalized integers (glTF's quantized colours and uvs) stand for floats: denormalized.
  if (attribute.normalized === true && !(a instanceof Float32Array || a instanceof Float64Array)) return numbers(attribute, Float32Array);
  if (!(a instanceof Float32Array || a instanceof Float64Array)) return null;
  return a instanceof Float32Array && a.length === n ? a : Float32Array.from(a.subarray(0, n));
}

// A position, normal, uv or colour attribute's values as floats, whatever its storage
// (integer ones, as KHR_mesh_quantization allows, by value).
function floats(attribute) {
  return values(attribute) ?? numbers(attribute, Float32Array);
}

// Any attribute's values (integer or normalized ones too) as numbers, `itemSize` per vertex.
function numbers(attribute, Type) {
  const out = new Type(attribute.count * attribute.itemSize);
  for (let i = 0; i < attribute.count; i++) {
    for (let k = 0; k < attribute.itemSize; k++) out[i * attribute.itemSize + k] = attribute.getComponent(i, k);
  }
  return out;
}

// The morph targets' displacements of one attribute ('position' or 'normal'), all targets
// one after the other; absolute targets (morphTargetsRelative false) minus the base.
function deltas(geometry, name) {
  const targets = geometry.morphAttributes[name];
  const base = geometry.getAttribute(name);
  if (targets === undefined || targets.length === 0 || base === undefined) return null;
  const n = base.count * 3;
  const out = new Float32Array(targets.length * n);
  const rest = numbers(base, Float32Array);
  targets.forEach((target, t) => {
    if (target.count !== base.count || target.itemSize !== 3) {
      throw new TessellaError(`morph target ${t} of ${name} has ${target.count} entries of ${target.itemSize}; the geometry has ${base.count} of 3`);
    }
    const d = numbers(target, Float32Array);
    if (!geometry.morphTargetsRelative) for (let i = 0; i < n; i++) d[i] -= rest[i];
    out.set(d, t * n);
  });
  return out;
}

// What moves a skinned or morphing source's coarse vertices every frame: three's skeleton and
// morph influences, turned into the core's deform matrices and weights and posed in wasm.
class SourcePose {
  #mesh;
  #deformer;
  #indices;
  #matrices;
  #last;
  #weights;
  #m = new Matrix4();

  constructor(mesh) {
    const g = mesh.geometry;
    const position = g.getAttribute('position');
    const normal = g.getAttribute('normal');
    const skinned = mesh.isSkinnedMesh === true;
    const bones = skinned ? mesh.skeleton?.bones : undefined;
    if (skinned && (bones === undefined || bones.length === 0)) throw new TessellaError('the SkinnedMesh has no skeleton (bind one first)');
    const skinIndex = g.getAttribute('skinIndex');
    const skinWeight = g.getAttribute('skinWeight');
    if (skinned && (skinIndex === undefined || skinWeight === undefined || skinIndex.itemSize !== 4 || skinWeight.itemSize !== 4)) {
      throw new TessellaError('the SkinnedMesh\'s geometry needs skinIndex and skinWeight attributes of 4 components');
    }
    const dp = deltas(g, 'position');
    const targets = dp === null ? 0 : dp.length / (position.count * 3);
    const dn = targets > 0 && normal !== undefined && g.morphAttributes.normal?.length === targets ? deltas(g, 'normal') : null;
    this.#mesh = mesh;
    const rest = {
      positions: numbers(position, Float32Array),
      normals: normal === undefined ? undefined : numbers(normal, Float32Array),
      joints: skinned ? numbers(skinIndex, Uint32Array) : undefined,
      weights: skinned ? numbers(skinWeight, Float32Array) : undefined,
      jointCount: skinned ? bones.length : 0,
      positionDeltas: dp ?? undefined,
      normalDeltas: dn ?? undefined,
      targets,
    };
    this.#deformer = new Deformer(rest);
    /** The source's rest data (what the GPU posing pass uploads once), and the matrices a frame takes. */
    this.rest = { ...rest, matrixCount: this.#deformer.matrixCount };
    // The coarse triangles, for the bounds of a pose (`bounds`).
    this.#indices = Uint32Array.from(sourceOf(g).indices);
    this.#matrices = new Float32Array(this.#deformer.matrixCount * 16);
    this.#last = new Float32Array(this.#matrices.length + targets).fill(NaN);
    this.#weights = new Float32Array(targets);
    this.positions = new Float32Array(position.count * 3);
    this.normals = this.#deformer.hasNormals ? new Float32Array(position.count * 3) : undefined;
  }

  // The frame's joint matrices (bind space to posed mesh space, as three's
  // SkinnedMesh.applyBoneTransform composes them) and morph weights; whether they changed.
  #read() {
    const mesh = this.#mesh;
    if (mesh.isSkinnedMesh === true) {
      const { bones, boneInverses } = mesh.skeleton;
      const m = this.#m;
      bones.forEach((bone, i) => {
        m.multiplyMatrices(mesh.bindMatrixInverse, bone.matrixWorld).multiply(boneInverses[i]).multiply(mesh.bindMatrix);
        this.#matrices.set(m.elements, 16 * i);
      });
    } else {
      this.#matrices.set(this.#m.identity().elements);
    }
    const influences = mesh.morphTargetInfluences ?? [];
    for (let t = 0; t < this.#weights.length; t++) this.#weights[t] = influences[t] ?? 0;
    let changed = false;
    const last = this.#last;
    const k = this.#matrices.length;
    for (let i = 0; i < k; i++) if (last[i] !== this.#matrices[i]) changed = true;
    for (let t = 0; t < this.#weights.length; t++) if (last[k + t] !== this.#weights[t]) changed = true;
    return changed;
  }

  /** Whether the skeleton or the morph weights moved since the last `pose()`. */
  moved() {
    return this.#read();
  }

  /** Poses the coarse mesh into `positions` and `normals`. */
  pose() {
    this.#read();
    this.#deformer.pose(this.#matrices, this.#weights, this.positions, this.normals);
    this.#last.set(this.#matrices);
    this.#last.set(this.#weights, this.#matrices.length);
  }

  /** GPU posing: takes the current matrices and weights as the drawn ones (`drawnMatrices`, `drawnWeights`), posing nothing. */
  commit() {
    this.#read();
    this.#last.set(this.#matrices);
    this.#last.set(this.#weights, this.#matrices.length);
  }

  /** The joint matrices of the last `pose()` or `commit()` (16 floats each). */
  get drawnMatrices() {
    return this.#last.subarray(0, this.#matrices.length);
  }

  /** The morph weights of the last `pose()` or `commit()`. */
  get drawnWeights() {
    return this.#last.subarray(this.#matrices.length);
  }

  /** Poses `positions` and `normals` on the CPU with the drawn matrices and weights (a raycast of a GPU-posed mesh). */
  poseDrawn() {
    this.#deformer.pose(this.drawnMatrices, this.drawnWeights, this.positions, this.normals);
  }

  /**
   * Bounds that hold the drawn pose's curved surface (GPU posing, whose nets stay on the GPU):
   * the coarse vertices posed on the CPU with the drawn matrices and weights, positions only,
   * each triangle's box grown by `growth` times its longest edge (the scheme's control reach:
   * each patch lies in its control net's hull, within that of its triangle). Sets `box` and
   * `sphere` (three's Box3, Sphere).
   */
  bounds(box, sphere, growth) {
    const b = this.#deformer.posedBounds(this.drawnMatrices, this.drawnWeights, this.#indices, growth);
    box.min.set(b[0], b[1], b[2]);
    box.max.set(b[3], b[4], b[5]);
    box.getBoundingSphere(sphere);
  }

  free() {
    this.#deformer.free();
  }
}

// Interpolates a per-vertex attribute at each refined vertex: the barycentric blend of its
// coarse face's three corners.
function interpolate(data, itemSize, indices, faces, bary) {
  const out = new Float32Array(faces.length * itemSize);
  for (let v = 0; v < faces.length; v++) {
    const f = faces[v];
    if (f === 0xffffffff) continue;
    for (let c = 0; c < 3; c++) {
      const w = bary[v * 3 + c];
      const corner = indices[f * 3 + c] * itemSize;
      for (let k = 0; k < itemSize; k++) out[v * itemSize + k] += w * data[corner + k];
    }
  }
  return out;
}

/**
 * Refines a BufferGeometry (indexed or not) into a new indexed BufferGeometry: position,
 * normal (computed when the source has none) and uv from tessella, every other float
 * attribute (colors, extra uvs, ...) interpolated linearly over each coarse triangle.
 */
export function refineGeometry(geometry, options = {}) {
  const { position, indices } = sourceOf(geometry);
  const normal = geometry.getAttribute('normal');
  const uv = geometry.getAttribute('uv');
  const extra = Object.entries(geometry.attributes)
    .filter(([name]) => !OWN.has(name))
    .map(([name, a]) => [name, a, values(a)])
    .filter(([, , data]) => data !== null);
  const out = refine(
    {
      positions: floats(position),
      indices,
      normals: normal === undefined ? undefined : floats(normal),
      uvs: uv === undefined ? undefined : floats(uv),
    },
    { ...options, origin: extra.length > 0 },
  );
  const result = new BufferGeometry();
  result.setIndex(new BufferAttribute(out.indices, 1));
  result.setAttribute('position', new BufferAttribute(out.positions, 3));
  result.setAttribute('normal', new BufferAttribute(out.normals, 3));
  if (out.uvs !== undefined) result.setAttribute('uv', new BufferAttribute(out.uvs, 2));
  const coarse = Uint32Array.from(indices);
  for (const [name, a, data] of extra) {
    result.setAttribute(name, new BufferAttribute(interpolate(data, a.itemSize, coarse, out.faces, out.barycentric), a.itemSize));
  }
  result.computeBoundingSphere();
  return result;
}

/**
 * A refined geometry that follows a deforming source: `update()` reads the source's position
 * (and normal) attributes, refines them and writes the result into `geometry`'s attributes in
 * place (marking them for upload). The topology, uvs and options are those of the first frame.
 */
export class RefinedGeometry {
  #source;
  #refiner;
  #useNormals;

  constructor(geometry, options = {}) {
    const { indices } = sourceOf(geometry);
    const uv = geometry.getAttribute('uv');
    this.#source = geometry;
    this.#useNormals = options.normalsFromSource ?? geometry.getAttribute('normal') !== undefined;
    const { normalsFromSource, ...rest } = options;
    this.#refiner = new Refiner(indices, { ...rest, uvs: uv === undefined ? undefined : floats(uv) });
    const out = this.#step();
    this.geometry = new BufferGeometry();
    this.geometry.setIndex(new BufferAttribute(out.indices.slice(), 1));
    this.geometry.setAttribute('position', new BufferAttribute(out.positions.slice(), 3));
    this.geometry.setAttribute('normal', new BufferAttribute(out.normals.slice(), 3));
    if (out.uvs !== undefined) this.geometry.setAttribute('uv', new BufferAttribute(out.uvs.slice(), 2));
    this.geometry.computeBoundingSphere();
  }

  #step() {
    const g = this.#source;
    const normal = this.#useNormals ? g.getAttribute('normal') : undefined;
    return this.#refiner.refine(floats(g.getAttribute('position')), normal === undefined ? undefined : floats(normal));
  }

  /** Refines the source's current positions into `geometry` (no new arrays). */
  update() {
    const out = this.#step();
    const position = this.geometry.getAttribute('position');
    const normal = this.geometry.getAttribute('normal');
    position.array.set(out.positions);
    normal.array.set(out.normals);
    position.needsUpdate = true;
    normal.needsUpdate = true;
    this.geometry.computeBoundingSphere();
    return this.geometry;
  }

  /** Frees the wasm memory (the geometry stays). */
  dispose() {
    this.#refiner.free();
  }
}

// The options TessellatedMesh reads itself; the others go to InstancedSurface (the wasm side
// checks them: scheme, level, normals, alpha; lod, spacing and soup are refused there), or with
// `lod` to AdaptiveSurface (scheme, normals, alpha, spacing, lod; camera and size stay here).
const MESH_OPTIONS = ['normalsFromSource', 'group', 'evaluation', 'posing'];

// Where a skinned or morphing source is posed and its nets built (the `posing` option): 'auto'
// (the default) on the GPU where it can run (three-gpu-nets.js: WebGLRenderer with float render
// targets, a scheme whose nets the GPU builds, the source's own normals, no lod), else on the
// CPU; 'gpu' throws where it cannot run; 'cpu' always poses in wasm (SourcePose).
const POSINGS = ['auto', 'gpu', 'cpu'];

// The evaluation a TessellatedMesh takes without the `evaluation` option: 'auto', decided at the
// first render, when the renderer is known: 'per-frame' under WebGLRenderer where it can run
// (float render targets, the vertices within the largest texture; no lod, not a
// ShaderMaterial), which measured cheaper there (bench:three, js/README.md); 'per-draw' otherwise
// (WebGPURenderer's drawing stays the instanced one). Every mesh draws its first frame per draw,
// instanced; 'per-frame' swaps in the welded geometry from the frame after the first bake.
const EVALUATIONS = ['auto', 'per-frame', 'per-draw'];
const DEFAULT_EVALUATION = 'auto';

// Materials TessellatedMeshes draw with, and their patch: `key` (the kind of surface the patched
// shaders draw: basis, normals, uvs, colours, lod), `uniforms` (the `{ value }` objects the
// patched WebGL programs read: each mesh's own values are copied into them before it draws, see
// TessellatedMesh's #bind), `users` (the meshes drawing with it), `owned` (a clone tessella
// made, disposed with its last user) and `saved` (what patching changed on a caller's material,
// put back when its last user is disposed). Any number of TessellatedMeshes of one key share a
// material.
const patches = new WeakMap();

// The properties patching sets on a material (WebGLRenderer: the shader hook and its cache key;
// WebGPURenderer: the nodes).
const PATCHED = ['onBeforeCompile', 'customProgramCacheKey', 'positionNode', 'contextNode', 'colorNode'];

function savedProperties(material) {
  return PATCHED.map((name) => ({ name, own: Object.hasOwn(material, name), value: material[name] }));
}

// Puts back what patching changed (a property that still holds tessella's value), so the
// material draws plain meshes again.
function restoreProperties(material, saved, set) {
  for (const { name, own, value } of saved) {
    if (material[name] !== set[name]) continue;
    if (own) material[name] = value;
    else delete material[name];
  }
  material.needsUpdate = true;
}

// Why a posed source's nets cannot be built on the GPU whatever the renderer (then the CPU
// poses them), or null: lod reads the nets on the CPU (its levels from the camera); normals
// computed from the posed positions each frame (no source normals, normalsFromSource: false)
// are the CPU's; the scheme (PNG1, tags, ...) has no GPU builder.
function gpuPosingMissing(surface, lod, useNormals) {
  if (lod) return 'lod reads the nets on the CPU (its levels from the camera)';
  if (!useNormals) return 'the normals are computed from the posed positions each frame (no source normals, or normalsFromSource: false)';
  return surface.netsPassMissing();
}

/** What the renderer lacks for TessellatedMesh, or null. */
function missing(renderer) {
  if (renderer != null && renderer.isWebGPURenderer === true) return missingNodes(renderer);
  if (renderer == null || typeof renderer.getContext !== 'function' || renderer.capabilities == null) {
    return 'TessellatedMesh draws with three.js\'s WebGLRenderer (WebGL2) or WebGPURenderer; this renderer is neither';
  }
  const gl = renderer.getContext();
  const lacks = [];
  if (typeof gl.drawElementsInstanced !== 'function' || typeof gl.vertexAttribDivisor !== 'function') lacks.push('instanced drawing');
  if (typeof gl.texStorage2D !== 'function' || gl.RGBA32F === undefined) lacks.push('float (RGBA32F) textures');
  if (!(renderer.capabilities.maxVertexTextures > 0)) lacks.push('textures in the vertex shader');
  return lacks.length === 0 ? null : `TessellatedMesh cannot draw with this renderer: it lacks ${lacks.join(' and ')} (WebGL2 has them)`;
}

// The vertex shader's additions, one variant per evaluation (each its own program):
// - 'instanced' (per draw): the GLSL from the wasm (the generated evaluation and the nets reader),
//   the attributes, and at the top of main() the patch evaluated at the instance's coarse
//   triangle (`tessellaFaceIndex`), into locals named as three's attributes (position, normal,
//   uv, color) that hide them, so every chunk of three's shaders (lighting, shadows, fog,
//   clipping, maps) reads the curved surface;
// - 'baked' (per frame, three-bake.js): no evaluation at all: three's own `position` and
//   `normal` attributes are the baked vertex buffers; only the uvs and colours are blended from
//   the corners (a ShaderMaterial also gets the GLSL and `tessellaFaceIndex`, from the welded
//   vertex's `tessellaFace`, for its own code).
function vertexPatch(glsl, flags, { baked = false, shader = false } = {}) {
  let head;
  let body;
  if (!baked) {
    head = `${glsl}in vec3 tessellaBarycentric;\n`;
    body = [
      'int tessellaFaceIndex = gl_InstanceID;',
      'vec3 tessellaPosition;',
      'vec3 tessellaNormal;',
      'tessella_evaluate(tessellaFaceIndex, tessellaBarycentric, tessellaPosition, tessellaNormal);',
      'vec3 position = tessellaPosition;',
      'vec3 normal = tessellaNormal;',
    ];
  } else {
    head = shader ? `${glsl}in float tessellaFace;\n` : '';
    if (flags.uv || flags.color > 0) head += 'in vec3 tessellaBarycentric;\n';
    body = [
      ...(shader ? ['int tessellaFaceIndex = int(tessellaFace);'] : []),
      'vec3 tessellaPosition = position;',
      'vec3 tessellaNormal = normal;',
    ];
  }
  const l = 'tessellaBarycentric';
  if (flags.uv) {
    head += 'in vec4 tessellaUv01;\nin vec2 tessellaUv2;\n';
    body.push(`vec2 uv = ${l}.x * tessellaUv01.xy + ${l}.y * tessellaUv01.zw + ${l}.z * tessellaUv2;`);
  }
  if (flags.color > 0) {
    const t = flags.color === 4 ? 'vec4' : 'vec3';
    head += `in ${t} tessellaColor0;\nin ${t} tessellaColor1;\nin ${t} tessellaColor2;\n`;
    body.push(
      `${t} tessellaColor = ${l}.x * tessellaColor0 + ${l}.y * tessellaColor1 + ${l}.z * tessellaColor2;`,
      '#if defined( USE_COLOR_ALPHA )',
      flags.color === 4 ? 'vec4 color = tessellaColor;' : 'vec4 color = vec4(tessellaColor, 1.0);',
      '#elif defined( USE_COLOR )',
      flags.color === 4 ? 'vec3 color = tessellaColor.rgb;' : 'vec3 color = tessellaColor;',
      '#endif',
    );
  }
  return { head, body: body.join('\n') + '\n' };
}

// Both variants of vertexPatch for a material (a ShaderMaterial's baked one keeps the GLSL).
function vertexPatches(glsl, flags, material) {
  return {
    instanced: vertexPatch(glsl, flags),
    baked: vertexPatch(glsl, flags, { baked: true, shader: material.isShaderMaterial === true }),
  };
}

// Whether triangle (a, b, c) has area: three different vertices whose cross product is not
// exactly zero (in doubles, as the core's tessella_core::mesh::is_degenerate decides).
function hasArea(p, a, b, c) {
  if (a === b || b === c || a === c) return false;
  const [ux, uy, uz] = [p[3 * b] - p[3 * a], p[3 * b + 1] - p[3 * a + 1], p[3 * b + 2] - p[3 * a + 2]];
  const [vx, vy, vz] = [p[3 * c] - p[3 * a], p[3 * c + 1] - p[3 * a + 1], p[3 * c + 2] - p[3 * a + 2]];
  const [x, y, z] = [uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx];
  return x * x + y * y + z * z !== 0;
}

// The triangles of `indices` that have area in `positions` (the same array when all do).
function withoutCollapsed(indices, positions) {
  const kept = [];
  for (let t = 0; t + 2 < indices.length; t += 3) {
    const [a, b, c] = [indices[t], indices[t + 1], indices[t + 2]];
    if (Math.max(a, b, c) >= positions.length / 3 || hasArea(positions, a, b, c)) kept.push(a, b, c);
  }
  return kept.length === indices.length ? indices : Uint32Array.from(kept);
}

// The geometry group a TessellatedMesh draws (`options.group`, an index into geometry.groups):
// its index range and material index; null without the option.
function groupOf(geometry, group) {
  if (group === undefined || group === null) return null;
  const g = Number.isInteger(group) ? geometry.groups[group] : undefined;
  if (g === undefined) throw new TessellaError(`group: ${group} is not an index into the geometry's ${geometry.groups.length} groups`);
  const total = geometry.index !== null ? geometry.index.count : geometry.getAttribute('position')?.count ?? 0;
  const start = Math.min(g.start, total);
  const count = Math.min(g.count, total - start);
  if (start % 3 !== 0 || count % 3 !== 0) throw new TessellaError(`group ${group} starts at ${g.start} and counts ${g.count}: not whole triangles`);
  return { start, count, materialIndex: g.materialIndex ?? 0 };
}

/**
 * A copy of `material` to patch, leaving the original untouched: `clone()`, with the
 * original's own `onBeforeCompile` and `customProgramCacheKey` (which `copy` does not carry).
 */
export function cloneMaterial(material) {
  const copy = material.clone();
  if (Object.hasOwn(material, 'onBeforeCompile')) copy.onBeforeCompile = material.onBeforeCompile;
  if (Object.hasOwn(material, 'customProgramCacheKey')) copy.customProgramCacheKey = material.customProgramCacheKey;
  return copy;
}

// Patches a material's WebGL shaders with `variants[mode()]` (vertexPatches, or lod's one
// 'instanced'), the variant in its program cache key: a mesh's evaluation picks its program.
function patchMaterial(material, uniforms, key, variants, mode) {
  // A material's own onBeforeCompile and cache key still apply, after tessella's patch.
  const own = material.onBeforeCompile;
  const ownKey = material.customProgramCacheKey;
  material.onBeforeCompile = (shader, renderer) => {
    const { head, body } = variants[mode()];
    const at = shader.vertexShader.indexOf('void main() {');
    if (at < 0) throw new TessellaError('TessellatedMesh: the material\'s vertex shader has no `void main() {` to patch');
    Object.assign(shader.uniforms, uniforms);
    const main = at + 'void main() {'.length;
    shader.vertexShader = `${shader.vertexShader.slice(0, at)}${head}${shader.vertexShader.slice(at, main)}\n${body}${shader.vertexShader.slice(main)}`;
    own.call(material, shader, renderer);
  };
  material.customProgramCacheKey = () => `${key}:${mode()}|${ownKey.call(material)}`;
  material.needsUpdate = true;
}

/**
 * A curved surface drawn by the GPU in one instanced call: the refinement pattern stored once
 * and drawn once per coarse triangle, its vertex shader evaluating each triangle's patch from
 * control nets in a float texture, which `update()` rebuilds (on the CPU, in wasm) when the
 * source moves. `source` is a BufferGeometry, a Mesh or a SkinnedMesh; a Mesh is hidden and
 * this takes its place (its parent, transform, shadow flags). A SkinnedMesh's skeleton (posed by
 * three, e.g. an AnimationMixer) and a Mesh's morph target influences are followed every frame:
 * the coarse vertices are posed in wasm as three poses them (`SkinnedMesh.getVertexPosition`),
 * and only the nets are uploaded; or (`posing`, by default where it runs) two render passes build
 * the nets from the joint matrices and morph weights, which alone are uploaded (three-gpu-nets.js). Options: `scheme`, `level`, `normals`, `alpha`,
 * `normalsFromSource`; or, instead of `level`, `lod` with `spacing` (and `camera`, `size`):
 * per-edge levels from the camera every frame, drawn with the GPU tessellator's patterns by child
 * meshes, one instanced draw per part used (three-lod.js).
 */
export class TessellatedMesh extends Mesh {
  #source;
  #sourceMesh;
  #surface;
  #texture;
  #useNormals;
  #versions = null;
  #checked = null;
  #proxy = null;
  #flags;
  /** Poses a skinned or morphing source each frame (null for a plain one). */
  #pose = null;
  /** The options the surface was built with (raycasts refine the frame with them). */
  #options;
  /** Frames built so far, and the CPU refinement raycasts hit (rebuilt when a frame is newer). */
  #frames = 0;
  #hitGeometry = null;
  /** The `lod` option's drawing (three-lod.js), or null for one uniform pattern. */
  #lod = null;
  /** This mesh's own uniform values (nets texture, layout, lod's textures); the shadow materials read these objects. */
  #uniforms;
  /** The material's patch (shared by every TessellatedMesh drawing with the material). */
  #patch = null;
  /** The `evaluation` option: 'auto', 'per-frame' or 'per-draw'. */
  #asked;
  /** 'per-frame' evaluation: the baked vertices (three-bake.js), made at the first render where it runs; else null. */
  #baked = null;
  /** The renderer and frame (#frames) the baked vertices are of. */
  #bakedFor = null;
  #bakedFrame = -1;
  /** Why 'per-frame' (asked for, or 'auto''s choice) is not in effect, or null. */
  #fallback = null;
  /** 'per-frame': the welded refined mesh (three-bake.js's welded()), or null. */
  #weld = null;
  /** The drawn geometry's kind, the shaders' variant: 'instanced' (evaluated per draw) or 'baked'. */
  #mode = 'instanced';
  /** The instanced pattern geometry (drawn per draw, and every mesh's first frame). */
  #instanced;
  /** 'per-frame', once baked: the welded geometry reading the baked vertex buffers; else null. */
  #welded = null;
  /** The generated GLSL (the bake's evaluation). */
  #glsl;
  /** The `posing` option: 'auto', 'gpu' or 'cpu'. */
  #posing;
  /** GPU posing (three-gpu-nets.js), once in effect; else null. */
  #gpuNets = null;
  /** The renderer the GPU nets are of; whether they wait for a pass; whether it is the first. */
  #gpuFor = null;
  #gpuDirty = false;
  #gpuFirst = true;
  /** Why a posed source is posed on the CPU though the GPU was not ruled out by `posing: 'cpu'`, or null. */
  #posingFallback = null;

  constructor(source, material, options = {}) {
    let sourceMesh = null;
    let geometry = source;
    if (source != null && source.isMesh === true) {
      sourceMesh = source;
      geometry = source.geometry;
    }
    if (geometry == null || geometry.isBufferGeometry !== true) {
      throw new TessellaError('TessellatedMesh takes a three.js BufferGeometry or Mesh as its source');
    }
    if (options == null || typeof options !== 'object') throw new TessellaError('options must be an object');
    if (options.evaluation != null && !EVALUATIONS.includes(options.evaluation)) {
      throw new TessellaError(`evaluation: ${JSON.stringify(options.evaluation)} is none of ${EVALUATIONS.map((e) => `'${e}'`).join(', ')}`);
    }
    if (options.posing != null && !POSINGS.includes(options.posing)) {
      throw new TessellaError(`posing: ${JSON.stringify(options.posing)} is none of ${POSINGS.map((e) => `'${e}'`).join(', ')}`);
    }
    const group = groupOf(geometry, options.group);
    const owned = material === undefined || material === null;
    if (owned) {
      let from = sourceMesh?.material;
      if (Array.isArray(from)) from = group !== null ? from[group.materialIndex] : undefined;
      material = from != null && from.isMaterial === true ? cloneMaterial(from) : new MeshStandardMaterial();
    }
    if (Array.isArray(material) || material.isMaterial !== true) {
      throw new TessellaError('TessellatedMesh takes one three.js Material (not an array of them)');
    }
    if (material.positionNode != null && !patches.has(material)) {
      throw new TessellaError('the material has a positionNode: TessellatedMesh sets it (the curved surface under WebGPURenderer)');
    }
    let { indices } = sourceOf(geometry);
    if (group !== null) indices = indices.subarray(group.start, group.start + group.count);
    // Triangles without area (a vertex used twice, or corners in a line: three draws nothing
    // of them; glTF exporters leave some) are left out, as the core refuses them.
    indices = withoutCollapsed(indices, floats(geometry.getAttribute('position')));
    const lod = options.lod != null;
    const own = lod ? [...MESH_OPTIONS, ...LOD_MESH_OPTIONS] : MESH_OPTIONS;
    const rest = Object.fromEntries(Object.entries(options).filter(([k]) => !own.includes(k)));
    const surface = lod ? new AdaptiveSurface(indices, rest) : new InstancedSurface(indices, rest);
    const posing = options.posing ?? 'auto';
    const posed = sourceMesh !== null && (sourceMesh.isSkinnedMesh === true || (geometry.morphAttributes.position?.length ?? 0) > 0);
    const posingFallback = posed && posing !== 'cpu' ? gpuPosingMissing(surface, lod, options.normalsFromSource ?? geometry.getAttribute('normal') !== undefined) : null;
    if (posing === 'gpu' && posingFallback !== null) {
      surface.free();
      throw new TessellaError(`posing: 'gpu' cannot run: ${posingFallback}`);
    }
    // Every mesh starts instanced (evaluated per draw); 'per-frame' (asked for, or 'auto''s
    // choice at the first render: never with lod, nor for a ShaderMaterial unless asked, whose
    // own code may call tessella_evaluate with gl_InstanceID) then bakes the refined mesh's welded
    // vertices and draws them by one indexed draw (three-bake.js).
    const asked = options.evaluation ?? DEFAULT_EVALUATION;
    super(new InstancedBufferGeometry(), material);
    this.#instanced = this.geometry;
    this.#asked = asked;
    if (asked !== 'per-draw' && lod) this.#fallback = 'lod evaluates per draw';
    else if (asked === 'auto' && material.isShaderMaterial === true) this.#fallback = 'a ShaderMaterial evaluates per draw unless asked (evaluation: \'per-frame\')';
    this.#options = rest;
    this.#posing = posing;
    this.#posingFallback = posingFallback;
    this.#surface = surface;
    this.#source = geometry;
    this.#sourceMesh = sourceMesh;
    this.#useNormals = options.normalsFromSource ?? geometry.getAttribute('normal') !== undefined;
    /** Update when the source's position or normal attribute changes (its `version`), before each render. */
    this.autoUpdate = true;
    /** Bytes the last `update()` handed to the renderer to upload (the nets texture, or with GPU posing the joint matrices and morph weights; uvs and colours when they changed). */
    this.uploadedBytes = 0;

    const g = this.geometry;
    g.boundingBox = new Box3();
    g.boundingSphere = new Sphere();
    const uv = geometry.getAttribute('uv');
    const color = geometry.getAttribute('color');
    this.#flags = { uv: uv !== undefined, color: color === undefined ? 0 : color.itemSize };
    if (this.#flags.color !== 0 && this.#flags.color !== 3 && this.#flags.color !== 4) {
      throw new TessellaError(`the source's color attribute has ${color.itemSize} components; TessellatedMesh reads 3 or 4`);
    }
    // With lod this draws nothing itself: its children draw the parts (three-lod.js).
    if (lod) this.#lod = new LodParts(this, surface, options, this.#flags);
    // The pattern: barycentric points, drawn once per coarse triangle.
    const points = lod ? new Float32Array(0) : surface.patternPoints();
    // The corners' elements: one per coarse triangle.
    const corners = surface.faceCount;
    const Corner = InstancedBufferAttribute;
    if (!lod) {
      const tri = surface.patternIndices();
      g.setIndex(new BufferAttribute(points.length / 3 <= 0xffff ? Uint16Array.from(tri) : tri, 1));
      const barycentric = new BufferAttribute(points, 3);
      g.setAttribute('tessellaBarycentric', barycentric);
      // three shades a lit material flat (normals from screen derivatives) when the geometry has
      // no normal attribute; the shader's normal is the patch's (a local that hides the
      // attribute), so this one only has to exist: the same buffer, uploaded once.
      g.setAttribute('normal', barycentric);
      // WebGPURenderer reads a position attribute before the node replaces it (a warning if none).
      g.setAttribute('position', barycentric);
      g.instanceCount = surface.faceCount;
    } else {
      g.instanceCount = 0;
    }
    if (uv !== undefined && !lod) {
      g.setAttribute('tessellaUv01', new Corner(new Float32Array(corners * 4), 4));
      g.setAttribute('tessellaUv2', new Corner(new Float32Array(corners * 2), 2));
    }
    if (color !== undefined && !lod) {
      const c = color.itemSize;
      for (let k = 0; k < 3; k++) g.setAttribute(`tessellaColor${k}`, new Corner(new Float32Array(corners * c), c));
      // Tells three the colours' width (USE_COLOR_ALPHA for 4); the shader reads the instanced
      // ones. Ones: the factor WebGPURenderer's node materials take from it changes nothing.
      g.setAttribute('color', new BufferAttribute(new Float32Array((points.length / 3) * c).fill(1), c));
    }
    this.#indices = Uint32Array.from(indices);

    const data = new Float32Array(surface.width * surface.height * 4);
    const texture = new DataTexture(data, surface.width, surface.height, RGBAFormat, FloatType);
    texture.minFilter = NearestFilter;
    texture.magFilter = NearestFilter;
    texture.generateMipmaps = false;
    this.#texture = texture;
    // This mesh's own values: what its shaders read besides the material's own uniforms.
    const uniforms = {
      tessellaNets: { value: texture },
      tessellaFacesPerRow: { value: surface.facesPerRow },
      ...(lod ? this.#lod.uniforms : {}),
    };
    this.#uniforms = uniforms;
    if (lod) this.#lod.bind = (renderer) => this.#bind(renderer);
    const glsl = surface.glsl();
    this.#glsl = glsl;
    const key = `tessella:${lod ? `lod:${surface.spacing}:` : ''}${surface.basisLength}:${surface.normalMode}:${this.#flags.uv ? 'uv' : ''}:${this.#flags.color}`;
    // The shaders' variants: lod's one, or per draw and baked (the material's program follows
    // the mesh drawing, see #bind; the shadow materials' this mesh's #mode).
    const lodPatch = lod ? this.#lod.patch(glsl) : null;
    const variants = (m) => (lod ? { instanced: lodPatch } : vertexPatches(glsl, this.#flags, m));
    let shared = patches.get(material);
    if (shared !== undefined && shared.key !== key) {
      if (owned) material.dispose();
      this.#surface = null;
      surface.free();
      texture.dispose();
      this.#lod?.dispose();
      throw new TessellaError(`this material already draws TessellatedMeshes of another kind (${shared.key}; this one is ${key}: another scheme, lod, or uvs or colours the others lack): give it its own (material.clone())`);
    }
    if (shared === undefined) {
      // The first mesh of this material patches it: the shaders read the material's uniform
      // objects, into which each mesh's own values are copied before it draws (#bind).
      const common = Object.fromEntries(Object.entries(uniforms).map(([name, u]) => [name, { value: u.value }]));
      const saved = savedProperties(material);
      // `mode`: the variant of the material's current program, that of the mesh drawing.
      const entry = { key, uniforms: common, users: new Set(), owned, saved, set: null, mode: 'instanced' };
      patchMaterial(material, common, key, variants(material), () => entry.mode);
      // WebGPURenderer: the same surface from the WGSL, as a node (its shadow pass takes it too)
      // reading the drawn object's own nets texture, instanced (it evaluates per draw); lod's
      // parts from the adaptive WGSL reading their owner's textures (three-lod-nodes.js).
      if (lod) setupLodNodes(material, surface, this.#flags, this);
      else setupNodes(material, surface, { ...this.#flags, welded: false });
      entry.set = Object.fromEntries(PATCHED.map((name) => [name, material[name]]));
      shared = entry;
      patches.set(material, shared);
    }
    shared.users.add(this);
    this.#patch = shared;
    // The shadow materials are this mesh's own: their variant is its #mode.
    this.customDepthMaterial = new MeshDepthMaterial();
    patchMaterial(this.customDepthMaterial, uniforms, key, variants(this.customDepthMaterial), () => this.#mode);
    this.customDistanceMaterial = new MeshDistanceMaterial();
    patchMaterial(this.customDistanceMaterial, uniforms, key, variants(this.customDistanceMaterial), () => this.#mode);

    if (sourceMesh !== null && (sourceMesh.isSkinnedMesh === true || (geometry.morphAttributes.position?.length ?? 0) > 0)) {
      this.#pose = new SourcePose(sourceMesh);
    }
    if (sourceMesh !== null) {
      this.castShadow = sourceMesh.castShadow;
      this.receiveShadow = sourceMesh.receiveShadow;
      this.#follow();
      if (sourceMesh.parent !== null) sourceMesh.parent.add(this);
      this.layers.mask = sourceMesh.layers.mask;
      if (sourceMesh.children.length === 0) {
        sourceMesh.visible = false;
      } else {
        // Hidden, the source would hide its children (other meshes, lights) too: it is taken off
        // every layer instead (drawn by no camera, in no shadow map, hit by no raycaster), and
        // this follows its `visible`.
        this.#byLayers = true;
        sourceMesh.layers.disableAll();
      }
    }
    this.update();
  }

  /** The source, having children, is hidden by its layers (not `visible`). */
  #byLayers = false;

  #indices;

  /** The source geometry (the coarse mesh this draws curved). */
  get source() {
    return this.#sourceMesh ?? this.#source;
  }

  /**
   * The nets texture (RGBA32F) the vertex shader reads: the DataTexture the CPU fills, or with
   * GPU posing (`posedOn` 'gpu') the pass's render target's texture.
   */
  get netsTexture() {
    return this.#uniforms.tessellaNets.value;
  }

  /** The InstancedSurface (wasm) that builds the nets: pattern, layout, GLSL (with `lod`: the AdaptiveSurface). */
  get surface() {
    return this.#surface;
  }

  /** With `lod`: the levels' drawing (camera, size, uploadedBytes, triangleCount, setLevels); else null. */
  get lod() {
    return this.#lod;
  }

  /**
   * The evaluation in effect: 'per-frame' (the vertices evaluated into vertex buffers once per
   * change of the nets, the draws reading them; from the frame after the first bake) or
   * 'per-draw' (every draw pass evaluates the patches). Before the first render every mesh is
   * 'per-draw': 'auto' (the default) decides there, from the renderer.
   */
  get evaluation() {
    return this.#baked !== null ? 'per-frame' : 'per-draw';
  }

  /** Why the evaluation is 'per-draw' though 'per-frame' was asked for (or 'auto' would take it), or null. */
  get evaluationFallback() {
    return this.#fallback;
  }

  /**
   * Where a skinned or morphing source is posed and its nets built: 'gpu' (render passes
   * build the nets texture from the joint matrices and morph weights, three-gpu-nets.js) or
   * 'cpu' (wasm poses the coarse vertices and builds the nets, uploaded as a texture); null
   * for a source that neither skins nor morphs. Before the first render a posed mesh is 'cpu':
   * the default, 'auto', decides there, from the renderer.
   */
  get posedOn() {
    if (this.#pose === null) return null;
    return this.#gpuNets !== null ? 'gpu' : 'cpu';
  }

  /** GPU posing: the render target the pass builds the nets into (what `netsTexture` is the texture of); else null. */
  get gpuNetsTarget() {
    return this.#gpuNets?.target ?? null;
  }

  /** Why a posed source is posed on the CPU though `posing` allows the GPU (the default, 'auto'), or null. */
  get posingFallback() {
    return this.#posingFallback;
  }

  /** GPU memory of the baked vertices ('per-frame': 80 bytes a vertex drawn, see three-bake.js), else 0. */
  get bakedBytes() {
    return this.#baked?.bytes ?? 0;
  }

  /** 'per-frame': the render target of the baked vertices (textures: positions, normals), once baked; else null. */
  get bakedTarget() {
    return this.#baked?.target ?? null;
  }

  // Here, before three updates the objects it draws (which tells it of a geometry's attributes:
  // a draw seeing an attribute three does not know yet leaves it out of the vertex array it
  // keeps), the geometry drawn follows the evaluation: once baked, the welded geometry whose
  // position and normal are the baked vertex buffers (and the shaders' 'baked' variant); after
  // a fallback, the instanced one again.
  #useBaked() {
    const baked = this.#baked;
    if (baked !== null && baked.attributes !== null && this.#mode === 'instanced') {
      this.#welded ??= this.#weldedGeometry(baked);
      this.geometry = this.#welded;
      this.#setMode('baked');
    } else if (baked === null && this.#mode === 'baked') {
      this.geometry = this.#instanced;
      this.#welded.dispose();
      this.#welded = null;
      this.#weld = null;
      this.#setMode('instanced');
    }
  }

  #setMode(mode) {
    this.#mode = mode;
    // The shadow materials are this mesh's: their next program is the other variant.
    this.customDepthMaterial.needsUpdate = true;
    this.customDistanceMaterial.needsUpdate = true;
  }

  // The welded refined mesh drawn 'per-frame': refine's topology, `position` and `normal` the
  // baked vertex buffers, the corners (uvs, colours) per vertex; the bounds are the instanced
  // geometry's objects (update() sets them).
  #weldedGeometry(baked) {
    const weld = this.#weld;
    const g = new BufferGeometry();
    g.setIndex(new BufferAttribute(weld.index, 1));
    g.setAttribute('position', baked.attributes[0]);
    g.setAttribute('normal', baked.attributes[1]);
    const { uv, color } = this.#flags;
    if (uv || color > 0) g.setAttribute('tessellaBarycentric', new BufferAttribute(weld.barycentric, 3));
    if (this.material.isShaderMaterial === true) g.setAttribute('tessellaFace', new BufferAttribute(weld.face, 1));
    if (uv) {
      g.setAttribute('tessellaUv01', new BufferAttribute(new Float32Array(weld.count * 4), 4));
      g.setAttribute('tessellaUv2', new BufferAttribute(new Float32Array(weld.count * 2), 2));
    }
    if (color > 0) {
      for (let k = 0; k < 3; k++) g.setAttribute(`tessellaColor${k}`, new BufferAttribute(new Float32Array(weld.count * color), color));
      g.setAttribute('color', new BufferAttribute(new Float32Array(weld.count * color).fill(1), color));
    }
    g.boundingBox = this.#instanced.boundingBox;
    g.boundingSphere = this.#instanced.boundingSphere;
    const src = this.#source;
    this.#writeCorners(g, weld.faces, uv ? floats(src.getAttribute('uv')) : null, color > 0 ? floats(src.getAttribute('color')) : null);
    return g;
  }

  // 'per-frame' (asked for, or 'auto''s choice): at the first render where it can run, the
  // welded vertices and the bake; then evaluates them when the nets changed since the last bake
  // (or the renderer is another), in whichever pass draws this first (shadow maps, then the
  // picture). Where it cannot run, the mesh stays (or becomes again) instanced, per draw.
  #bake(renderer) {
    if (this.#asked === 'per-draw' || this.#fallback !== null) return;
    if (this.#baked === null) {
      const why = bakeMissing(renderer);
      if (why !== null) {
        this.#fallback = why;
        return;
      }
      const positions = floats(this.#source.getAttribute('position'));
      const rest = this.#options;
      this.#weld = welded(refine({ positions, indices: this.#indices }, { ...rest, origin: true, soup: rest.normals === 'real' ? true : undefined }));
      this.#baked = new BakedSurface(this.#glsl, this.#uniforms, this.#weld);
    }
    const baked = this.#baked;
    if (this.#bakedFor === renderer && this.#bakedFrame === this.#frames) return;
    let why = baked.missing(renderer);
    if (why === null && this.#bakedFor !== null && this.#bakedFor !== renderer) why = 'drawn by a second renderer (the baked buffers are the first one\'s)';
    if (why !== null) {
      // Falls back to evaluating per draw, instanced (from the next frame: #useBaked; this
      // pass skips the welded geometry, whose buffers are gone).
      baked.dispose();
      this.#baked = null;
      this.#fallback = why;
      if (this.#mode === 'baked') this.#welded.setDrawRange(0, 0);
      else this.#weld = null;
      return;
    }
    baked.bake(renderer);
    this.#bakedFor = renderer;
    this.#bakedFrame = this.#frames;
  }

  #follow() {
    const m = this.#sourceMesh;
    if (m === null) return;
    this.position.copy(m.position);
    this.quaternion.copy(m.quaternion);
    this.scale.copy(m.scale);
    if (this.#byLayers) this.visible = m.visible;
  }

  /**
   * Rebuilds the nets from the source's current position (and normal) attributes and marks
   * the texture for upload; the bounding box and sphere become those of the new control
   * points (which hold the curved surface). Returns this.
   */
  update() {
    if (this.#surface === null) throw new TessellaError('this TessellatedMesh was disposed');
    const g = this.#source;
    const position = g.getAttribute('position');
    const normal = this.#useNormals ? g.getAttribute('normal') : undefined;
    if (position === undefined) throw new TessellaError('the source geometry has no position attribute');
    if (this.#useNormals && normal === undefined) throw new TessellaError('normalsFromSource: the source geometry has no normal attribute');
    if (this.#gpuNets !== null) return this.#gpuFrame();
    const data = this.#texture.image.data;
    if (this.#pose !== null) {
      // The coarse mesh as three skins and morphs it (SkinnedMesh.getVertexPosition), posed in wasm.
      this.#pose.pose();
      this.#surface.update(this.#pose.positions, this.#useNormals ? this.#pose.normals : undefined, data);
    } else {
      this.#surface.update(floats(position), normal === undefined ? undefined : floats(normal), data);
    }
    this.#texture.needsUpdate = true;
    this.#lod?.netsChanged();
    let bytes = data.byteLength;
    bytes += this.#corners();
    this.uploadedBytes = bytes;
    const b = this.#surface.bounds;
    this.geometry.boundingBox.min.set(b[0], b[1], b[2]);
    this.geometry.boundingBox.max.set(b[3], b[4], b[5]);
    this.geometry.boundingSphere.center.set(b[6], b[7], b[8]);
    this.geometry.boundingSphere.radius = b[9];
    this.#versions = this.#sourceVersions();
    this.#frames++;
    return this;
  }

  // GPU posing's frame: the current joint matrices and weights become the drawn ones, built
  // into the nets by the pass before this mesh's next draw (#posePass); uploads those alone
  // (and the corners when they changed). The bounds come from the coarse vertices posed on
  // the CPU, positions only (SourcePose.bounds): the CPU never sees the posed nets.
  #gpuFrame() {
    this.#pose.commit();
    this.#gpuDirty = true;
    this.uploadedBytes = this.#gpuNets.uploadBytes + this.#corners();
    // The scheme's control reach, from the core (GPU posing builds only schemes that have one).
    this.#pose.bounds(this.#instanced.boundingBox, this.#instanced.boundingSphere, this.#surface.controlReach() ?? 1);
    this.#versions = this.#sourceVersions();
    this.#frames++;
    return this;
  }

  // GPU posing ('auto' where it runs, or 'gpu'): at the first render the pass is made (or the
  // reason it cannot run kept, and the CPU goes on posing; 'gpu' throws), the draws' nets
  // uniform points to its render target; then, in whichever pass draws this first (shadow
  // maps, then the picture), the nets of a new pose are built before the bake and the draws.
  #posePass(renderer) {
    if (this.#pose === null || this.#posing === 'cpu' || this.#posingFallback !== null) return;
    if (this.#gpuNets === null) {
      // WebGPURenderer builds them by compute (three-gpu-nets-nodes.js).
      const Nets = renderer?.isWebGPURenderer === true ? GpuNetsNodes : GpuNets;
      let why = Nets === GpuNetsNodes ? gpuNetsNodesMissing(renderer) : gpuNetsMissing(renderer);
      let nets = null;
      if (why === null) {
        nets = new Nets(this.#surface, this.#pose.rest);
        why = nets.missing(renderer);
      }
      if (why !== null) {
        nets?.dispose();
        if (this.#posing === 'gpu') throw new TessellaError(`posing: 'gpu' cannot run: ${why}`);
        this.#posingFallback = why;
        return;
      }
      this.#gpuNets = nets;
      this.#gpuFor = renderer;
      this.#gpuFirst = true;
      this.#uniforms.tessellaNets.value = nets.target?.texture ?? nets.texture;
      this.#gpuFrame();
    } else if (this.#gpuFor !== renderer) {
      // The render target is the first renderer's: the CPU poses from now on.
      this.#stopGpuPosing();
      this.#posingFallback = 'drawn by a second renderer (the GPU nets are the first one\'s)';
      this.update();
      return;
    }
    if (!this.#gpuDirty) return;
    this.#gpuNets.render(renderer, this.#pose.drawnMatrices, this.#pose.drawnWeights, this.#gpuFirst);
    this.#gpuDirty = false;
    this.#gpuFirst = false;
  }

  // Back to the CPU's nets texture (a new SourcePose, a second renderer, dispose).
  #stopGpuPosing() {
    if (this.#gpuNets === null) return;
    this.#gpuNets.dispose();
    this.#gpuNets = null;
    this.#gpuFor = null;
    this.#gpuDirty = false;
    this.#uniforms.tessellaNets.value = this.#texture;
  }

  // Copies the coarse uvs and colours to the per-triangle corner attributes when they changed;
  // returns the bytes marked for upload.
  #corners() {
    const g = this.#source;
    const v = this.#sourceVersions();
    const uv = g.getAttribute('uv');
    const uvChanged = this.#flags.uv && (this.#versions === null || v.uv !== this.#versions.uv);
    const colorChanged = this.#flags.color > 0 && (this.#versions === null || v.color !== this.#versions.color);
    if (!uvChanged && !colorChanged) return 0;
    if (this.#lod !== null) {
      const color = g.getAttribute('color');
      const c = color === undefined ? null : { data: floats(color), itemSize: color.itemSize };
      return this.#lod.corners(uv === undefined ? null : floats(uv), c, this.#indices);
    }
    const uvs = uvChanged ? floats(uv) : null;
    const colors = colorChanged ? floats(g.getAttribute('color')) : null;
    let bytes = this.#writeCorners(this.#instanced, null, uvs, colors);
    if (this.#welded !== null) bytes += this.#writeCorners(this.#welded, this.#weld.faces, uvs, colors);
    return bytes;
  }

  // Writes the coarse uvs (`uvs`) and colours (`colors`), where not null, into a geometry's
  // corner attributes: element e's coarse triangle is `faces[e]` (welded), or e (instanced);
  // returns the bytes marked for upload.
  #writeCorners(geometry, faces, uvs, colors) {
    const idx = this.#indices;
    let bytes = 0;
    if (uvs !== null) {
      const data = uvs;
      const a = geometry.getAttribute('tessellaUv01');
      const b = geometry.getAttribute('tessellaUv2');
      for (let e = 0; e < a.count; e++) {
        const f = faces === null ? e : faces[e];
        const [i0, i1, i2] = [idx[3 * f], idx[3 * f + 1], idx[3 * f + 2]];
        a.array.set([data[2 * i0], data[2 * i0 + 1], data[2 * i1], data[2 * i1 + 1]], 4 * e);
        b.array.set([data[2 * i2], data[2 * i2 + 1]], 2 * e);
      }
      a.needsUpdate = true;
      b.needsUpdate = true;
      bytes += a.array.byteLength + b.array.byteLength;
    }
    if (colors !== null) {
      const c = this.#flags.color;
      const data = colors;
      for (let k = 0; k < 3; k++) {
        const a = geometry.getAttribute(`tessellaColor${k}`);
        for (let e = 0; e < a.count; e++) {
          const f = faces === null ? e : faces[e];
          a.array.set(data.subarray(idx[3 * f + k] * c, idx[3 * f + k] * c + c), c * e);
        }
        a.needsUpdate = true;
        bytes += a.array.byteLength;
      }
    }
    return bytes;
  }

  #sourceVersions() {
    const g = this.#source;
    const version = (name) => g.getAttribute(name)?.version ?? -1;
    return { position: version('position'), normal: version('normal'), uv: version('uv'), color: version('color') };
  }

  // Updates when the source's attributes changed since the last update.
  #sync() {
    if (!this.autoUpdate || this.#surface === null) return;
    const v = this.#sourceVersions();
    const w = this.#versions;
    const edited = w === null || v.position !== w.position || v.normal !== w.normal || v.uv !== w.uv || v.color !== w.color;
    if (edited && this.#pose !== null && w !== null && (v.position !== w.position || v.normal !== w.normal)) {
      // New rest vertices of a skinned or morphing source: pose those from now on.
      this.#pose.free();
      this.#pose = new SourcePose(this.#sourceMesh);
      // The GPU pass holds the old rest vertices: this frame poses on the CPU, the next render makes a new pass.
      this.#stopGpuPosing();
    }
    if (edited || (this.#pose !== null && this.#pose.moved())) this.update();
  }

  /** Follows the source's transform and (autoUpdate) its moved vertices: three calls this before culling. */
  updateMatrixWorld(force) {
    if (this.#surface !== undefined) {
      this.#follow();
      this.#sync();
      this.#useBaked();
    }
    super.updateMatrixWorld(force);
    // The levels for the camera, once this mesh's place is known and before three culls.
    if (this.#lod !== null && this.#surface !== null) this.#lod.refresh();
  }

  /**
   * Checks the renderer once (a TessellaError says what it lacks), updates if the source moved,
   * and (WebGLRenderer) puts this mesh's own values into the material's uniforms.
   */
  onBeforeRender(renderer, scene, camera) {
    this.#check(renderer);
    this.#sync();
    this.#posePass(renderer);
    this.#bake(renderer);
    this.#lod?.seen(renderer, camera);
    // With lod the children draw (each binds before its draw).
    if (this.#lod === null) this.#bind(renderer);
  }

  // WebGLRenderer: three calls this (onBeforeRender) just before it sets up the draw
  // (setProgram). Several TessellatedMeshes may share the material, and with it its uniform
  // objects: this mesh's own values (its nets texture, its row width, lod's textures) are copied
  // into them. three uploads a material's uniforms when the program or the material changed
  // since the last draw (setProgram's refreshMaterial) and sets only per-object ones (matrices,
  // a SkinnedMesh's boneTexture) on every draw; when a value changed, the current program is
  // let go (state.useProgram(null)) so the next setProgram binds it again and uploads the
  // material's uniforms, this mesh's values among them: a uniform upload (cached per uniform
  // by three), never a new program. WebGPURenderer reads the values per object itself (the
  // nodes, three-nodes.js).
  #bind(renderer) {
    if (renderer == null || renderer.isWebGLRenderer !== true || this.#patch === null) return;
    const shared = this.#patch;
    if (shared.mode !== this.#mode) {
      // The material's other variant ('instanced' or 'baked'): three looks its program up again
      // (one per variant, compiled once) and uploads the material's uniforms.
      shared.mode = this.#mode;
      this.material.needsUpdate = true;
    }
    // The baked variant reads none of this mesh's values.
    if (this.#mode === 'baked') return;
    const common = shared.uniforms;
    let changed = false;
    for (const name in this.#uniforms) {
      const value = this.#uniforms[name].value;
      if (common[name].value !== value) {
        common[name].value = value;
        changed = true;
      }
    }
    if (changed) renderer.state.useProgram(null);
  }

  onBeforeShadow(renderer) {
    this.#check(renderer);
    this.#sync();
    this.#posePass(renderer);
    this.#bake(renderer);
  }

  #check(renderer) {
    if (this.#checked === renderer) return;
    const why = missing(renderer);
    if (why !== null) throw new TessellaError(why);
    // WebGPU's guaranteed 8192 texels hold every layout (at most 2048 wide and high).
    const size = renderer.isWebGPURenderer === true ? 8192 : renderer.capabilities.maxTextureSize;
    if (this.#surface.width > size || this.#surface.height > size) {
      throw new TessellaError(`the nets texture is ${this.#surface.width}x${this.#surface.height}, over this renderer's largest texture, ${size}`);
    }
    this.#checked = renderer;
  }

  /**
   * Ray hits on the refined surface of the last frame (the CPU refinement of the coarse
   * mesh this draws, at its level and scheme, placed where this is), reported with this
   * object; `face` and `uv` are the refined triangle's.
   */
  raycast(raycaster, intersects) {
    if (this.#surface === null) return;
    const hit = this.#hitGeometry;
    // The surface drawn changes with each frame's nets, and with lod's levels.
    const drawn = this.#lod === null ? `${this.#frames}` : `${this.#frames}:${this.#lod.levelsVersion}`;
    if (hit === null || hit.frame !== drawn) {
      // GPU posing: the CPU poses the drawn matrices now (the drawn shape, not the rest's).
      if (this.#gpuNets !== null) this.#pose.poseDrawn();
      hit?.geometry.dispose();
      this.#hitGeometry = null;
      this.#hitGeometry = { frame: drawn, geometry: this.#refinedFrame() };
    }
    const proxy = (this.#proxy ??= new Mesh());
    proxy.geometry = this.#hitGeometry.geometry;
    proxy.material = this.material;
    proxy.matrixWorld.copy(this.matrixWorld);
    const hits = [];
    proxy.raycast(raycaster, hits);
    for (const h of hits) {
      h.object = this;
      intersects.push(h);
    }
  }

  // The last frame's coarse mesh refined on the CPU (positions and normals; uvs when the
  // source has them).
  #refinedFrame() {
    const g = this.#source;
    const pose = this.#pose;
    const positions = pose !== null ? pose.positions : floats(g.getAttribute('position'));
    const sourceNormal = this.#useNormals ? g.getAttribute('normal') : undefined;
    const normals = pose !== null ? (this.#useNormals ? pose.normals : undefined) : sourceNormal === undefined ? undefined : floats(sourceNormal);
    const uv = g.getAttribute('uv');
    const options = this.#lod === null ? this.#options : this.#lod.refineOptions(this.#options);
    const out = refine({ positions, indices: this.#indices, normals, uvs: uv === undefined ? undefined : floats(uv) }, options);
    const geometry = new BufferGeometry();
    geometry.setIndex(new BufferAttribute(out.indices, 1));
    geometry.setAttribute('position', new BufferAttribute(out.positions, 3));
    geometry.setAttribute('normal', new BufferAttribute(out.normals, 3));
    if (out.uvs !== undefined) geometry.setAttribute('uv', new BufferAttribute(out.uvs, 2));
    geometry.computeBoundingSphere();
    return geometry;
  }

  /** Frees the wasm memory, the texture, the pattern geometry and the shadow materials. */
  dispose() {
    if (this.#surface === null) return;
    this.#surface.free();
    this.#surface = null;
    this.#stopGpuPosing();
    this.#pose?.free();
    this.#pose = null;
    this.#hitGeometry?.geometry.dispose();
    this.#hitGeometry = null;
    this.#texture.dispose();
    this.#lod?.dispose();
    this.#baked?.dispose();
    this.#baked = null;
    this.#instanced.dispose();
    this.#welded?.dispose();
    this.#welded = null;
    this.#weld = null;
    this.customDepthMaterial.dispose();
    this.customDistanceMaterial.dispose();
    const shared = this.#patch;
    this.#patch = null;
    if (shared !== null) {
      shared.users.delete(this);
      if (shared.users.size === 0 && patches.get(this.material) === shared) {
        // The last mesh of this material: a clone tessella made is disposed; a caller's
        // material gets back what patching changed.
        patches.delete(this.material);
        if (shared.owned) this.material.dispose();
        else restoreProperties(this.material, shared.saved, shared.set);
      }
    }
  }
}
