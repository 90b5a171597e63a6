// tessella: curved surfaces from coarse triangle meshes, in WebAssembly.
// This file loads the wasm (the SIMD build where the engine validates SIMD, the scalar build
// otherwise) and wraps its exports: typed arrays in and out, every failure a TessellaError.

/** An error of tessella: bad input (the message says what was wrong), or an internal panic. */
export class TessellaError extends Error {
  constructor(message) {
    super(message);
    this.name = 'TessellaError';
  }
}

// A module of one function that uses a v128 instruction (i32.const 0; i8x16.splat; drop):
// engines without SIMD refuse to validate it.
const SIMD_PROBE = new Uint8Array([
  0, 97, 115, 109, 1, 0, 0, 0, 1, 4, 1, 96, 0, 0, 3, 2, 1, 0, 10, 9, 1, 7, 0, 65, 0, 253, 15, 26, 11,
]);

const isNode = typeof process !== 'undefined' && process.versions != null && process.versions.node != null;

function chooseVariant() {
  const forced = isNode ? process.env.TESSELLA_WASM : undefined;
  if (forced === 'simd' || forced === 'scalar') return forced;
  return WebAssembly.validate(SIMD_PROBE) ? 'simd' : 'scalar';
}

/** `'simd'` or `'scalar'`: which wasm build was loaded. */
export const variant = chooseVariant();

let glue = null;
let memory = null;
let panicked = null;
const PANIC_PREFIX = 'tessella panicked';

async function load() {
  const g = variant === 'simd' ? await import('../dist/simd/tessella.js') : await import('../dist/scalar/tessella.js');
  const url = new URL(`../dist/${variant}/tessella_bg.wasm`, import.meta.url);
  let source;
  if (isNode) {
    const { readFile } = await import('node:fs/promises');
    source = await readFile(url);
  } else {
    source = fetch(url);
  }
  const exports = await g.default({ module_or_path: source });
  glue = g;
  memory = exports.memory;
}

/** Resolves once the wasm is loaded; every other function needs it. */
export const ready = load();

// Runs one wasm call: its errors become TessellaErrors; after a panic (a bug) the instance is
// not trusted again, so later calls throw instead of computing from broken state.
function call(fn) {
  if (glue === null) throw new TessellaError('tessella is not loaded yet: await ready first');
  if (panicked !== null) {
    throw new TessellaError(`tessella cannot be used after an internal panic (reload it): ${panicked}`);
  }
  try {
    return fn(glue);
  } catch (e) {
    const message = e instanceof Error ? e.message : String(e);
    if (message.startsWith(PANIC_PREFIX) || e instanceof WebAssembly.RuntimeError) panicked = message;
    if (e instanceof TessellaError) throw e;
    throw new TessellaError(message);
  }
}

/**
 * The camera `tessella render` and the viewer frame `positions` (3 numbers per vertex) with:
 * their bounding sphere grown by a fifth plus `reach`, orbited by `yaw` and `pitch` (degrees),
 * `zoom > 1` closer, `pan` in framed radii, for a `width` x `height` picture. Returns
 * `{ viewProj, eye, target, lightDir, right, up, forward, distance, fovY }`: `viewProj` a
 * column-major Float32Array(16) onto wgpu's clip depth (0..w), `up` the view's, `fovY` the
 * vertical field of view in degrees.
 */
export function sceneCamera(positions, { yaw = 30, pitch = 20, zoom = 1, width, height, reach = 0, pan = [0, 0] }) {
  for (const [name, value] of [['width', width], ['height', height]]) {
    if (!(Number.isFinite(value) && value > 0)) throw new TessellaError(`sceneCamera: ${name} must be a positive number of pixels, not ${value}`);
  }
  const view = Float32Array.of(yaw, pitch, zoom, width / height, reach, pan[0], pan[1]);
  const v = call((g) => g.sceneCamera(Float32Array.from(positions), view));
  const vector = (at) => [v[at], v[at + 1], v[at + 2]];
  return {
    viewProj: v.slice(0, 16),
    eye: vector(16),
    target: vector(19),
    lightDir: vector(22),
    right: vector(25),
    up: vector(28),
    forward: vector(31),
    distance: v[34],
    fovY: v[35],
  };
}

/** The scheme names `refine` accepts. */
export function schemes() {
  return call((g) => g.schemes());
}

/** The widest texture (texels a row) the package lays out: WebGL2's guaranteed 2048. */
export function maxTextureWidth() {
  return call((g) => g.maxTextureWidth());
}

function floats(values, what, width) {
  if (values instanceof Float32Array) return values;
  if (values instanceof Float64Array || Array.isArray(values)) return Float32Array.from(values);
  throw new TessellaError(`${what} must be a Float32Array or Float64Array (${width} numbers per vertex)`);
}

const INTEGER_ARRAYS = [Int8Array, Uint8Array, Uint8ClampedArray, Int16Array, Uint16Array, Int32Array];

function indexArray(indices) {
  if (indices instanceof Uint32Array) return indices;
  const big = indices instanceof BigInt64Array || indices instanceof BigUint64Array;
  if (!big && !INTEGER_ARRAYS.some((T) => indices instanceof T)) {
    throw new TessellaError('indices must be an integer typed array (Uint32Array, Uint16Array, Int32Array, ...)');
  }
  const out = new Uint32Array(indices.length);
  for (let i = 0; i < indices.length; i++) {
    const v = big ? Number(indices[i]) : indices[i];
    if (v < 0 || v > 0xffffffff) {
      throw new TessellaError(`indices[${i}] is ${indices[i]}: a vertex index is 0 or more and fits 32 bits`);
    }
    out[i] = v;
  }
  return out;
}

const OPTION_NAMES = ['scheme', 'level', 'normals', 'alpha', 'spacing', 'lod', 'camera', 'size', 'soup'];

// The options as the Rust side reads them (JSON; non-finite numbers spelt out, since JSON has
// none). Unknown keys go through, so the Rust side refuses them by name.
function optionsJson(options, ignore = []) {
  if (options == null) options = {};
  if (typeof options !== 'object') throw new TessellaError('options must be an object');
  const out = {};
  for (const [key, value] of Object.entries(options)) {
    if (value === undefined || ignore.includes(key)) continue;
    out[key] = key === 'camera' && Array.isArray(value) ? value.join(',') : value;
  }
  return JSON.stringify(out, (_, v) => (typeof v === 'number' && !Number.isFinite(v) ? String(v) : v));
}

function mesh(input) {
  if (input == null || typeof input !== 'object') throw new TessellaError('the mesh must be { positions, indices, normals?, uvs? }');
  if (input.positions == null || input.indices == null) throw new TessellaError('the mesh needs positions and indices');
  return {
    positions: floats(input.positions, 'positions', 3),
    indices: indexArray(input.indices),
    normals: input.normals == null ? undefined : floats(input.normals, 'normals', 3),
    uvs: input.uvs == null ? undefined : floats(input.uvs, 'uvs', 2),
  };
}

// Returns `use(object)` and frees the wasm object, whether `use` returns or throws.
function thenFree(object, use) {
  try {
    return use(object);
  } finally {
    object.free();
  }
}

function take(arrays) {
  return thenFree(arrays, () => {
    const out = {
      positions: arrays.takePositions(),
      normals: arrays.takeNormals(),
      indices: arrays.takeIndices(),
    };
    const uvs = arrays.takeUvs();
    if (uvs !== undefined) out.uvs = uvs;
    const faces = arrays.takeFaces();
    if (faces !== undefined) {
      out.faces = faces;
      out.barycentric = arrays.takeBarycentric();
    }
    return out;
  });
}

/**
 * Refines a coarse mesh. See index.d.ts for the options; returns new arrays
 * `{ positions, normals, indices, uvs? }`.
 */
export function refine(input, options) {
  const m = mesh(input);
  const json = optionsJson(options);
  return call((g) => take(g.refine(m.positions, m.indices, m.normals, m.uvs, json)));
}

/**
 * Reads a mesh file from bytes. `format` is 'obj', 'ply', 'stl', 'gltf', 'glb' or a file name
 * ('bunny.obj'); `options.buffers` maps a .gltf file's external buffer URIs to their bytes.
 */
export function readMesh(bytes, format, options = {}) {
  const file = fileToRead('readMesh', bytes, format, options, 'obj');
  return call((g) => {
    const arrays = withBuffers(g, file.buffers, (given) => g.readMesh(file.bytes, format, given));
    const computed = arrays.normalsComputed;
    const out = take(arrays);
    out.normalsComputed = computed;
    return out;
  });
}

// What readMesh and readAnimated (named `fn` in the errors) read, checked: the file's bytes,
// and its external buffers as the Rust side takes them.
function fileToRead(fn, bytes, format, options, formatExample) {
  const file = fileBytes(bytes, fn);
  if (typeof format !== 'string') throw new TessellaError(`${fn}'s format must be a string such as '${formatExample}'`);
  return { bytes: file, buffers: buffers(options) };
}

function fileBytes(bytes, fn) {
  if (bytes instanceof Uint8Array) return bytes;
  if (bytes instanceof ArrayBuffer) return new Uint8Array(bytes);
  throw new TessellaError(`${fn} takes the file as a Uint8Array or ArrayBuffer`);
}

// Runs `read` with the buffers as the wasm side's GltfBuffers, freed afterwards.
function withBuffers(g, { names, lengths, data }, read) {
  return thenFree(new g.GltfBuffers(names, lengths, data), read);
}

// A .gltf file's external buffers ({ uri: bytes }) as the Rust side takes them: names, lengths
// and the bytes one after the other.
function buffers(options) {
  const names = [];
  const parts = [];
  for (const [name, data] of Object.entries(options?.buffers ?? {})) {
    names.push(name);
    parts.push(data instanceof Uint8Array ? data : new Uint8Array(data));
  }
  const lengths = Uint32Array.from(parts, (p) => p.length);
  const data = new Uint8Array(parts.reduce((n, p) => n + p.length, 0));
  let at = 0;
  for (const p of parts) {
    data.set(p, at);
    at += p.length;
  }
  return { names, lengths, data };
}

/**
 * Encodes a mesh `{ positions, indices, normals?, uvs? }` as a file: format 'obj', 'ply'
 * (binary), 'ply-ascii', 'gltf', 'glb' or 'stl'. Returns its bytes.
 */
export function writeMesh(input, format) {
  const m = mesh(input);
  if (typeof format !== 'string') throw new TessellaError("writeMesh's format must be a string such as 'glb'");
  return call((g) => g.writeMesh(format, m.positions, m.indices, m.normals, m.uvs));
}

// refineGltf's own keys: `buffers` stays on the JS side, `maxEdge` goes to the Rust side
// beside the refine options.
function refineGltfCall(bytes, options, fn) {
  bytes = fileBytes(bytes, fn);
  if (options != null && typeof options !== 'object') throw new TessellaError('options must be an object');
  const external = buffers(options);
  const json = optionsJson(options, ['buffers']);
  return call((g) => {
    const refined = withBuffers(g, external, (given) => g.refineGltf(bytes, given, json));
    return thenFree(refined, () => ({ glb: refined.takeGlb(), primitives: JSON.parse(refined.report) }));
  });
}

/**
 * Refines a whole glTF scene (`.glb` or `.gltf` bytes; `options.buffers` maps a .gltf file's
 * external buffer URIs to their bytes) and returns it as GLB bytes: every triangle primitive
 * refined with its material, attributes, morph targets and skin; nodes, materials, textures,
 * animations, cameras, lights and extensions kept. Options: `scheme`, `level` (whole) or
 * `maxEdge` (a target edge length in world units: each primitive's own level), `alpha`,
 * `normals`, `tangents` ('recomputed' or 'carried'). The same bytes as the CLI's
 * `tessella refine in.glb -o out.glb`.
 */
export function refineGltf(bytes, options = {}) {
  return refineGltfCall(bytes, options, 'refineGltf').glb;
}

/**
 * `refineGltf` with what it did: `{ glb, primitives }`, one entry per refined primitive
 * `{ mesh, primitive, level, coarseTriangles, degenerate, vertices, triangles, notes }`.
 */
export function refineGltfWithReport(bytes, options = {}) {
  return refineGltfCall(bytes, options, 'refineGltfWithReport');
}

function view(Type, ptr, length) {
  return new Type(memory.buffer, ptr, length);
}

// A frame's positions and normals (null when left out, to have them computed): Float32Array
// and Float64Array as they are (the copy into wasm memory converts), anything else as floats.
function frameArrays(positions, normals) {
  return [frameArray(positions, 'positions'), normals == null ? null : frameArray(normals, 'normals')];
}

function frameArray(values, what) {
  return values instanceof Float32Array || values instanceof Float64Array ? values : floats(values, what, 3);
}

// The wasm object's `which` input ('positions' or 'normals') of `length` floats as a view; the
// one kept in `views` while the memory and the place are the same.
function inputView(inner, views, which, length) {
  const ptr = which === 'positions' ? inner.positionsInput(length) : inner.normalsInput(length);
  const old = views[which];
  if (old && old.buffer === memory.buffer && old.byteOffset === ptr && old.length === length) return old;
  return (views[which] = view(Float32Array, ptr, length));
}

// Copies a frame (see frameArrays) into the wasm object's inputs and has it build the frame.
function buildFrame(inner, views, positions, normals) {
  inputView(inner, views, 'positions', positions.length).set(positions);
  if (normals !== null) inputView(inner, views, 'normals', normals.length).set(normals);
  inner.frame(normals !== null);
}

// What the classes owning a wasm object share (see WasmOwner); symbols keep them off the API.
const LIVE = Symbol('tessella live wasm object');
const CALL_LIVE = Symbol('tessella call on the live wasm object');

// A JS object owning one wasm object until `free()`; any use afterwards throws.
class WasmOwner {
  #inner;
  #name;

  constructor(inner, name) {
    this.#inner = inner;
    this.#name = name;
  }

  // The wasm object, or a TessellaError once it was freed.
  [LIVE]() {
    if (this.#inner === null) throw new TessellaError(`this ${this.#name} was freed`);
    return this.#inner;
  }

  // `fn(inner)` run by `call` on the wasm object, once it is known not to be freed.
  [CALL_LIVE](fn) {
    const inner = this[LIVE]();
    return call(() => fn(inner));
  }

  /** Frees the wasm memory it holds; it cannot be used afterwards. */
  free() {
    if (this.#inner !== null) this.#inner.free();
    this.#inner = null;
  }
}

/**
 * A refinement plan for a deforming mesh: the topology (indices, uvs) and options are fixed,
 * each `refine(positions, normals?)` refines one frame into the same output arrays.
 */
export class Refiner extends WasmOwner {
  #views = null;
  #inputs = {};

  constructor(indices, options = {}) {
    const idx = indexArray(indices);
    const uvs = options?.uvs == null ? undefined : floats(options.uvs, 'uvs', 2);
    const json = optionsJson(options, ['uvs']);
    super(call((g) => new g.Refiner(idx, uvs, json)), 'Refiner');
  }

  /**
   * Refines one frame. `positions` (and `normals`, or leave them out to have them computed)
   * must have the vertex count of the first frame. Returns the output views (see `positions`).
   */
  refine(positions, normals) {
    const inner = this[LIVE]();
    const [p, n] = frameArrays(positions, normals);
    call(() => buildFrame(inner, this.#inputs, p, n));
    return this.output;
  }

  /**
   * The last frame's output, `{ positions, normals, indices, uvs? }`: views over wasm memory,
   * overwritten by the next `refine` (no copy, no allocation). They become detached (length 0)
   * if the wasm memory grows, which a later tessella call may do: read `output` again after
   * each `refine` (it is the same object while the memory has not grown), copy what you keep.
   */
  get output() {
    const inner = this[LIVE]();
    const v = this.#views;
    if (v !== null && v.positions.buffer === memory.buffer) return v;
    const nv = inner.vertexCount();
    if (nv === 0) throw new TessellaError('no frame refined yet: call refine(positions) first');
    const out = {
      positions: view(Float32Array, inner.positionsOutput(), nv * 3),
      normals: view(Float32Array, inner.normalsOutput(), nv * 3),
      indices: view(Uint32Array, inner.indicesOutput(), inner.triangleCount() * 3),
    };
    if (inner.hasUvs()) out.uvs = view(Float32Array, inner.uvsOutput(), nv * 2);
    return (this.#views = out);
  }

  /** Frees the wasm memory this refiner holds; it cannot be used afterwards. */
  free() {
    super.free();
    this.#views = null;
    this.#inputs = {};
  }
}

// What InstancedSurface and AdaptiveSurface share: the wasm object, the nets texture's layout,
// per frame the nets and their bounds, and the vertex shader's code.
class NetsSurface extends WasmOwner {
  #inputs = {};

  constructor(inner, name) {
    super(inner, name);
    /** Control points per net: 10 (cubic basis) or 21 (PNG1). */
    this.basisLength = inner.basisLength();
    /** The normal mode in effect: 'linear', 'quadratic' or 'real'. */
    this.normalMode = inner.normalMode();
    /** Coarse triangles: the instances. */
    this.faceCount = inner.faceCount();
    /** RGBA texels per net; `facesPerRow` nets to a texture row. */
    this.texelsPerFace = inner.texelsPerFace();
    this.facesPerRow = inner.facesPerRow();
    this.width = inner.textureWidth();
    this.height = inner.textureHeight();
    /** The last frame's control-point bounds: box min xyz, box max xyz, sphere centre xyz, radius. */
    this.bounds = new Float32Array(10);
  }

  /**
   * Builds one frame's nets from `positions` (and `normals`, or leave them out to have them
   * computed), copies them into `out` (a Float32Array of `width * height * 4` floats) and the
   * bounds into `bounds`. Returns `out`.
   */
  update(positions, normals, out) {
    const inner = this[LIVE]();
    const [p, n] = frameArrays(positions, normals);
    const length = this.width * this.height * 4;
    if (!(out instanceof Float32Array) || out.length !== length) {
      throw new TessellaError(`the nets go into a Float32Array of ${length} floats (width * height * 4)`);
    }
    call(() => {
      buildFrame(inner, this.#inputs, p, n);
      out.set(view(Float32Array, inner.netsOutput(), length));
      this.bounds.set(view(Float32Array, inner.boundsOutput(), 10));
    });
    return out;
  }

  /**
   * The vertex shader's GLSL ES 3.00. InstancedSurface's declares `tessella_evaluate(int face,
   * vec3 l, out vec3 position, out vec3 normal)`, AdaptiveSurface's
   * `tessella_adaptive_evaluate(uint code, uint inst, out vec3 position, out vec3 normal)`.
   */
  glsl() {
    return this[CALL_LIVE]((inner) => inner.glsl());
  }

  /**
   * The same in WGSL, for three.js's WebGPURenderer (TSL `wgslFn`). InstancedSurface's ends
   * with `fn tessella_position(nets: texture_2d<f32>, face: u32, l: vec3<f32>) -> vec3<f32>` and
   * `fn tessella_normal(...)` (same parameters, a unit normal); AdaptiveSurface's with
   * `fn tessella_adaptive_point(nets: texture_2d<f32>, records: texture_2d<u32>, instances: texture_2d<u32>, code: u32, instance: u32) -> mat3x3<f32>`
   * (columns: the point, its unit normal, its barycentric coordinates; the instance word read
   * at `instance` of the R32UI `instances` texture).
   */
  wgsl() {
    return this[CALL_LIVE]((inner) => inner.wgsl());
  }

  /** Frees the wasm memory; it cannot be used afterwards. */
  free() {
    super.free();
    this.#inputs = {};
  }
}

/**
 * What a GPU draws a curved surface from in one instanced call (`tessella/three`'s
 * `TessellatedMesh` is built on it): fixed by the topology and options, the refinement pattern
 * (`patternPoints()`, barycentric, and `patternIndices()`), the nets' texture layout and the
 * vertex shader's GLSL (`glsl()`, generated from the core's formulas); every frame,
 * `update(positions, normals?, out)` packs the coarse mesh's control nets as RGBA float texels
 * into `out` and their bounds into `bounds`. Options: `scheme`, `level` (a whole number, at
 * most 256), `normals`, `alpha`.
 */
export class InstancedSurface extends NetsSurface {
  constructor(indices, options = {}) {
    const idx = indexArray(indices);
    const json = optionsJson(options);
    const inner = call((g) => new g.InstancedSurface(idx, json));
    super(inner, 'InstancedSurface');
    /** Segments per coarse edge. */
    this.level = inner.level();
  }

  /** The pattern's points, barycentric (l1, l2, l3) on the coarse triangle, 3 per point. */
  patternPoints() {
    return this[CALL_LIVE]((inner) => inner.patternPoints());
  }

  /** The pattern's triangles, 3 point indices each. */
  patternIndices() {
    return this[CALL_LIVE]((inner) => inner.patternIndices());
  }

  /**
   * How far the scheme's control points may lie from their triangle, in lengths of its longest
   * edge (0.5 for PN and PN-AEN, |alpha| for Phong, 0 for flat), or null for the schemes
   * without such a bound (PNG1, scalar-tagged, quadratic).
   */
  controlReach() {
    return this[CALL_LIVE]((inner) => inner.controlReach()) ?? null;
  }

  /** Why WebGL2's net pass cannot build these nets (PNG1 and the other CPU-only schemes, tags), or null. */
  netsPassMissing() {
    return this[CALL_LIVE]((inner) => inner.netsPassMissing()) ?? null;
  }

  /**
   * GLSL ES 3.00 for WebGL2's pass that builds the nets on the GPU (three-gpu-nets.js):
   * `tessella_skin_normal` and `tessella_nets_texel_of(p, n, across, j)`, texel `j` of a face's
   * net as `update` packs it, from the posed corners (the scheme's generated builders, each
   * texel computing only the part of the net it holds).
   * Throws where `netsPassMissing()` says why.
   */
  netsPassGlsl() {
    return this[CALL_LIVE]((inner) => inner.netsPassGlsl());
  }

  /**
   * The net pass's face indices (a Uint32Array): each face's 3 corners, then for PN-AEN the 6
   * vertices whose normals its edges' other sides use. Known after the first `update`.
   */
  netsPassTopology() {
    return this[CALL_LIVE]((inner) => inner.netsPassTopology());
  }

  /**
   * WGSL for WebGPURenderer's compute that builds the nets on the GPU (three-gpu-nets-nodes.js):
   * `{ nets, skinNormal }`, `nets` ending with `fn tessella_net_texel(j: u32, p0, p1, p2, n0,
   * n1, n2[, m0 .. m5]: vec3<f32>) -> vec4<f32>` (texel `j` of a face's net, as `update` packs
   * it; PN-AEN's `m` the normals of netsPassTopology's across vertices), `skinNormal` `fn
   * tessella_skin_normal(m: mat3x3<f32>, n: vec3<f32>) -> vec3<f32>` (the Deformer's posed
   * normal). Throws where `netsPassMissing()` says why.
   */
  netsComputeWgsl() {
    return this[CALL_LIVE]((inner) => ({ nets: inner.netsComputeWgsl(), skinNormal: inner.skinNormalWgsl() }));
  }

}

/**
 * What a GPU draws an adaptive curved surface from (`TessellatedMesh`'s `lod` option): the GPU
 * tessellator's parts (strips and interiors of its patterns for `spacing`) built once; per
 * frame the nets (as `InstancedSurface` packs them) and, from per-edge levels (`setLevels`, or
 * `setLod` with the `lod` function and a camera), one packed record per face (three RGBA32UI
 * texels) and one instance per face and part, drawn one instanced draw per part used.
 * `options`: `scheme`, `normals`, `alpha`, `spacing` (`'equal'`, `'fractional-odd'` or
 * `'fractional-even'`), `lod` (`'tolerance:D'`, `'screen:PX'`, `'distance:NEAR,FAR,MAX'`).
 */
export class AdaptiveSurface extends NetsSurface {
  constructor(indices, options = {}) {
    const idx = indexArray(indices);
    if (options == null || typeof options !== 'object') throw new TessellaError('options must be an object');
    const lod = options.lod ?? '';
    if (typeof lod !== 'string') throw new TessellaError('lod must be a string: tolerance:D, screen:PX or distance:NEAR,FAR,MAX');
    const json = optionsJson(options, ['lod']);
    const inner = call((g) => new g.AdaptiveSurface(idx, json, lod));
    super(inner, 'AdaptiveSurface');
    /** The LOD function's text ('' when the levels are given by `setLevels`). */
    this.lod = lod;
    /** The spacing's name. */
    this.spacing = inner.spacing();
    /** The records texture's layout (RGBA32UI, three texels per face). */
    this.recordsPerRow = inner.recordsPerRow();
    this.recordsWidth = inner.recordsWidth();
    this.recordsHeight = inner.recordsHeight();
    /** The last levels' draws: part id, first instance, instance count, one triple per part used. */
    this.draws = new Uint32Array(0);
    /** Instances and triangles the last levels draw. */
    this.instanceCount = 0;
    this.triangleCount = 0;
  }

  /** The parts' point codes, one per vertex (built once). */
  partCodes() {
    return this[CALL_LIVE]((inner) => inner.partCodes());
  }

  /** The parts' triangles, indices into `partCodes()`. */
  partIndices() {
    return this[CALL_LIVE]((inner) => inner.partIndices());
  }

  /** Per part id its first index and index count. */
  partRanges() {
    return this[CALL_LIVE]((inner) => inner.partRanges());
  }

  /** Unique edges (once a frame was built): `setLevels` takes one level each. */
  get edgeCount() {
    return this[CALL_LIVE]((inner) => inner.edgeCount());
  }

  /**
   * Levels from the `lod` function on the last frame: `camera` `{ eye: [x, y, z], target:
   * [x, y, z], fov }` (degrees, vertical) in the mesh's coordinates and the image `size`
   * `[width, height]` (`tolerance` reads neither). Then `read(records, instances)`.
   */
  setLod(camera, size) {
    const inner = this[LIVE]();
    const { eye, target, fov } = camera ?? {};
    if (!(eye?.length === 3 && target?.length === 3 && typeof fov === 'number' && size?.length === 2)) {
      throw new TessellaError('setLod takes { eye: [x, y, z], target: [x, y, z], fov } and size [width, height]');
    }
    call(() => inner.setLod(eye[0], eye[1], eye[2], target[0], target[1], target[2], fov, size[0], size[1]));
    this.#levelsSet(inner);
  }

  /** Per-edge levels given: one per unique edge (`edgeCount`). Then `read(records, instances)`. */
  setLevels(levels) {
    const inner = this[LIVE]();
    const l = floats(levels, 'levels', 1);
    call(() => inner.setLevels(l));
    this.#levelsSet(inner);
  }

  #levelsSet(inner) {
    this.draws = call(() => inner.draws());
    this.instanceCount = inner.instanceCount();
    this.triangleCount = inner.triangleCount();
  }

  /** The last levels, one per unique edge. */
  edgeLevels() {
    return this[CALL_LIVE]((inner) => inner.edgeLevels());
  }

  /**
   * Copies the last levels' records into `records` (a Uint32Array of `recordsWidth *
   * recordsHeight * 4`) and instances into `instances` (`face | side << 30`, grouped by part,
   * a Uint32Array of at least `4 * faceCount`); returns the bytes copied that matter.
   */
  read(records, instances) {
    const inner = this[LIVE]();
    const length = this.recordsWidth * this.recordsHeight * 4;
    if (!(records instanceof Uint32Array) || records.length !== length) {
      throw new TessellaError(`the records go into a Uint32Array of ${length} words (recordsWidth * recordsHeight * 4)`);
    }
    if (!(instances instanceof Uint32Array) || instances.length < 4 * this.faceCount) {
      throw new TessellaError(`the instances go into a Uint32Array of at least ${4 * this.faceCount} words (4 * faceCount)`);
    }
    call(() => {
      records.set(view(Uint32Array, inner.recordsOutput(), length));
      instances.set(view(Uint32Array, inner.instancesOutput(), this.instanceCount));
    });
    return records.byteLength + 4 * this.instanceCount;
  }

}

/**
 * A mesh posed by an engine's own skeleton (what `TessellatedMesh` follows a three.js
 * `SkinnedMesh` or morphing `Mesh` with): built once from the rest `positions` and `normals`,
 * four `joints` indices and `weights` per vertex with the skeleton's `jointCount` (0: no
 * skeleton), and `targets` morph targets' `positionDeltas` (and `normalDeltas`), each
 * `targets × vertices × 3` numbers. `pose(matrices, weights, positions, normals)` then poses it
 * with the core's skinning (the code `readAnimated`'s poses run).
 */
export class Deformer extends WasmOwner {
  constructor({ positions, normals, joints, weights, jointCount = 0, positionDeltas, normalDeltas, targets = 0 }) {
    const p = floats(positions, 'positions', 3);
    const n = normals == null ? new Float32Array(0) : floats(normals, 'normals', 3);
    const j = joints == null ? new Uint32Array(0) : Uint32Array.from(joints);
    const w = weights == null ? new Float32Array(0) : floats(weights, 'weights', 4);
    const dp = positionDeltas == null ? new Float32Array(0) : floats(positionDeltas, 'positionDeltas', 3);
    const dn = normalDeltas == null ? new Float32Array(0) : floats(normalDeltas, 'normalDeltas', 3);
    const inner = call((g) => new g.Deformer(p, n, j, w, jointCount, dp, dn, targets));
    super(inner, 'Deformer');
    /** Matrices a pose takes: the joint count, or 1 without a skeleton. */
    this.matrixCount = inner.matrixCount();
    this.vertexCount = inner.vertexCount();
    /** Whether poses carry normals (the source had them). */
    this.hasNormals = inner.hasNormals();
  }

  /**
   * Poses with `matrices` (Float32Array, 16 column-major numbers each: a joint's matrix from
   * the mesh's bind space to its posed space) and the morph `weights`, into `positions` and
   * `normals` (Float32Arrays of `vertexCount * 3`; `normals` ignored without `hasNormals`).
   */
  pose(matrices, weights, positions, normals) {
    this[CALL_LIVE]((inner) => inner.pose(matrices, weights, positions, this.hasNormals ? normals : new Float32Array(0)));
  }

  /**
   * The box that holds the curved surface of a pose without building its nets: the vertices
   * posed with `matrices` and `weights` (positions only), each of the `indices` triangles'
   * box (Uint32Array, 3 a triangle) grown on every side by `reach` times its longest edge; the
   * scheme's control reach: 0.5 for PN and PN-AEN, `|alpha|` for Phong, 0 for flat. Returns
   * a Float32Array of 6 numbers, the low corner then the high one.
   */
  posedBounds(matrices, weights, indices, reach) {
    return this[CALL_LIVE]((inner) => inner.posedBounds(matrices, weights, indices, reach));
  }
}

// Makes AnimatedMesh's constructor private to readAnimated.
const INTERNAL = Symbol('tessella internal');

/**
 * An animated mesh read by `readAnimated`: its triangles, clips, and poses at any time of a
 * clip (or the rest pose), each a new `{ positions, normals }`.
 */
export class AnimatedMesh extends WasmOwner {
  constructor(token, inner) {
    if (token !== INTERNAL) throw new TessellaError('an AnimatedMesh comes from readAnimated(bytes, format)');
    super(inner, 'AnimatedMesh');
    /** The triangles' corners, 3 vertex indices per triangle (Uint32Array). */
    this.indices = inner.indices();
    /** The clips' names, in the file's order (a clip is given by name or by index). */
    this.clips = inner.clips();
    /** The number of vertices of a pose. */
    this.vertexCount = inner.vertexCount();
  }

  /** A clip's duration in seconds; `clip` is its name or its index. */
  duration(clip) {
    return this[CALL_LIVE]((inner) => {
      if (clip == null) throw new TessellaError('duration: which clip? Give its name or its index');
      return inner.duration(clipIndex(inner, clip, 'duration'));
    });
  }

  /**
   * The mesh posed at `time` seconds of `clip` (a name or an index; past the end, the last
   * pose), or the rest pose for a null/undefined clip: new Float32Arrays `{ positions, normals }`,
   * 3 numbers per vertex. Normals are the file's posed, or computed when the file has none.
   */
  pose(clip, time) {
    return this[CALL_LIVE]((inner) => {
      const index = clipIndex(inner, clip, 'pose');
      if (index === undefined && time === undefined) time = 0;
      if (typeof time !== 'number') throw new TessellaError(`pose: time must be a number of seconds, got ${typeof time}`);
      return thenFree(inner.pose(index, time), (pose) => ({ positions: pose.takePositions(), normals: pose.takeNormals() }));
    });
  }
}

// A clip (a name or an index) as the index AnimatedMesh's wasm object takes; null/undefined:
// undefined. `what` names the method in the error.
function clipIndex(inner, clip, what) {
  if (clip == null) return undefined;
  if (typeof clip === 'string') return inner.clipIndex(clip);
  if (typeof clip === 'number' && Number.isInteger(clip) && clip >= 0 && clip <= 0xffffffff) return clip;
  throw new TessellaError(`${what}: a clip is a name (string) or an index (an integer from 0), got ${typeof clip === 'number' ? clip : typeof clip}`);
}

/**
 * Reads an animated glTF file from bytes: format 'gltf', 'glb' or a file name ('walk.glb');
 * `options.buffers` maps a .gltf file's external buffer URIs to their bytes. Validates the
 * skins, morph targets and clips; returns an AnimatedMesh.
 */
export function readAnimated(bytes, format, options = {}) {
  const file = fileToRead('readAnimated', bytes, format, options, 'glb');
  return call((g) => {
    const inner = withBuffers(g, file.buffers, (given) => g.readAnimated(file.bytes, format, given));
    try {
      return new AnimatedMesh(INTERNAL, inner);
    } catch (e) {
      inner.free();
      throw e;
    }
  });
}

/** Test hook: panics inside the wasm (see test/panic.test.js). Not part of the API. */
export function __panicForTests() {
  return call((g) => g.__panicForTests());
}
