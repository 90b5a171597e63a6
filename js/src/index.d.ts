/** An error of tessella: bad input (the message says what was wrong) or an internal panic. */
export class TessellaError extends Error {
  name: 'TessellaError';
}

/** Resolves once the wasm is loaded; call nothing else before. */
export const ready: Promise<void>;

/** Which wasm build was loaded: the SIMD one where the engine validates SIMD. */
export const variant: 'simd' | 'scalar';

/** The scheme names `refine` accepts: flat, phong, pn, png1, pn-aen, st, quadratic. */
export function schemes(): string[];
/** The widest texture (texels a row) the package lays out: WebGL2's guaranteed 2048. */
export function maxTextureWidth(): number;

/** A framed view: `viewProj` column-major onto wgpu's clip depth (0..w); `up` the view's. */
export interface SceneCamera {
  viewProj: Float32Array;
  eye: number[];
  target: number[];
  lightDir: number[];
  right: number[];
  up: number[];
  forward: number[];
  distance: number;
  /** Vertical field of view, degrees. */
  fovY: number;
}
/** The camera `tessella render` and the viewer frame `positions` with (3 numbers per vertex). */
export function sceneCamera(
  positions: Float32Array | Float64Array | number[],
  view: { yaw?: number; pitch?: number; zoom?: number; width: number; height: number; reach?: number; pan?: [number, number] },
): SceneCamera;

export type IndexArray =
  | Uint32Array
  | Uint16Array
  | Uint8Array
  | Uint8ClampedArray
  | Int32Array
  | Int16Array
  | Int8Array
  | BigInt64Array
  | BigUint64Array;

/** A coarse mesh: 3 numbers per vertex (positions, normals), 2 per vertex (uvs), 3 indices per triangle. */
export interface MeshInput {
  positions: Float32Array | Float64Array;
  indices: IndexArray;
  /** Unit normals per vertex; left out, they are computed (angle-weighted). */
  normals?: Float32Array | Float64Array;
  uvs?: Float32Array | Float64Array;
}

export interface RefineOptions {
  /** 'flat', 'phong', 'pn' (default), 'png1', 'pn-aen', 'st' or 'quadratic'; see `schemes()`. */
  scheme?: string;
  /** Segments per coarse edge (default 8); fractional with a tessellator spacing or geomorphing. */
  level?: number;
  /** 'linear', 'quadratic' or 'real'; default: the scheme's own. */
  normals?: 'linear' | 'quadratic' | 'real';
  /** Phong's shape factor (default 0.75). */
  alpha?: number;
  /** 'grid' (default), 'equal', 'fractional-odd' or 'fractional-even'. */
  spacing?: 'grid' | 'equal' | 'fractional-odd' | 'fractional-even';
  /** Per-edge levels: 'tolerance:D', 'screen:PX' or 'distance:NEAR,FAR,MAX' (the last two need `camera`). */
  lod?: string;
  /** [eyeX, eyeY, eyeZ, targetX, targetY, targetZ, fovYDegrees] or the same as a string. */
  camera?: number[] | string;
  /** Viewport [width, height] in pixels for 'screen:PX'. */
  size?: [number, number];
  /** true: every coarse triangle gets its own vertices (no sharing across edges). */
  soup?: boolean;
  /** Also return `faces` and `barycentric`: each refined vertex's coarse face and coordinates in it. */
  origin?: boolean;
}

export interface MeshOutput {
  positions: Float32Array;
  normals: Float32Array;
  indices: Uint32Array;
  /** When the input had uvs. */
  uvs?: Float32Array;
}

export interface RefineOutput extends MeshOutput {
  /** With `origin: true`: each vertex's coarse face (0xffffffff for a vertex no face uses). */
  faces?: Uint32Array;
  /** With `origin: true`: 3 barycentric coordinates per vertex. */
  barycentric?: Float32Array;
}

/** Refines a coarse mesh into new arrays. Throws TessellaError on bad input. */
export function refine(mesh: MeshInput, options?: RefineOptions): RefineOutput;

export interface RefinerOptions extends Omit<RefineOptions, 'origin'> {
  /** Texture coordinates (2 per vertex), fixed for every frame. */
  uvs?: Float32Array | Float64Array;
}

/**
 * A plan for a deforming mesh: indices, uvs and options fixed; each `refine` writes one frame
 * into the same output arrays (views over wasm memory) without allocating.
 */
export class Refiner {
  constructor(indices: IndexArray, options?: RefinerOptions);
  /**
   * Refines one frame; `normals` left out are computed. The vertex count must stay that of the
   * first frame. Returns `output`.
   */
  refine(positions: Float32Array | Float64Array, normals?: Float32Array | Float64Array): MeshOutput;
  /**
   * The last frame: views over wasm memory, overwritten by the next `refine`, detached if the
   * wasm memory grows (read `output` again after each `refine`; copy what you keep).
   */
  readonly output: MeshOutput;
  /** Frees its wasm memory. */
  free(): void;
}

export interface ReadMeshOptions {
  /** A .gltf file's external buffers by their URI (as written in the file). */
  buffers?: Record<string, Uint8Array | ArrayBuffer>;
}

export interface ReadMeshOutput extends MeshOutput {
  /** true when the file had no normals and they were computed. */
  normalsComputed: boolean;
}

/**
 * Reads and validates a mesh file from bytes: format 'obj', 'ply', 'stl', 'gltf', 'glb' or a
 * file name ('bunny.ply'). Throws TessellaError with the reason for a broken file.
 */
export function readMesh(bytes: Uint8Array | ArrayBuffer, format: string, options?: ReadMeshOptions): ReadMeshOutput;

/** Encodes a mesh as 'obj', 'ply' (binary), 'ply-ascii', 'gltf', 'glb' or 'stl'. */
export function writeMesh(mesh: MeshInput, format: 'obj' | 'ply' | 'ply-ascii' | 'gltf' | 'glb' | 'stl'): Uint8Array;

export interface RefineGltfOptions {
  /** 'flat', 'phong', 'pn' (default), 'png1', 'pn-aen', 'st' or 'quadratic'; see `schemes()`. */
  scheme?: string;
  /** Segments per coarse edge, a whole number, the same for every primitive (default 8). */
  level?: number;
  /** Instead of `level`: refined edges about this long in world units, each primitive its own level (at most 64). */
  maxEdge?: number;
  /** 'linear', 'quadratic' or 'real'; default: the scheme's own. */
  normals?: 'linear' | 'quadratic' | 'real';
  /** Phong's shape factor (default 0.75). */
  alpha?: number;
  /** The refined TANGENT of primitives that have one: 'recomputed' (MikkTSpace on the refined mesh, the default) or 'carried' (the file's tangents interpolated and made orthogonal to the refined normals, about twice as fast). */
  tangents?: 'recomputed' | 'carried';
  /** Skin influence sets: 'input' (as many JOINTS_n/WEIGHTS_n sets as the file has, the default; three.js and Bevy read the first only) or up to this many (1-8) where a refined vertex blends more influences than the file's sets hold. */
  jointSets?: 'input' | number;
  /** A .gltf file's external buffers by their URI (as written in the file). */
  buffers?: Record<string, Uint8Array | ArrayBuffer>;
}

/** What refining one triangle primitive made. */
export interface RefinedPrimitive {
  /** Its mesh's index and its index in the mesh. */
  mesh: number;
  primitive: number;
  level: number;
  coarseTriangles: number;
  /** Zero-area triangles among the coarse ones, refined flat. */
  degenerate: number;
  vertices: number;
  triangles: number;
  /** Anything carried by a fallback (a morph target whose shape cannot be refined). */
  notes: string[];
}

/**
 * Refines a whole glTF scene (.glb or .gltf bytes) into GLB bytes: every triangle primitive
 * refined, keeping its material, attributes, morph targets and skin; everything else kept.
 * Throws TessellaError for a broken file, a required extension tessella cannot read, or bad options.
 */
export function refineGltf(bytes: Uint8Array | ArrayBuffer, options?: RefineGltfOptions): Uint8Array;

/** `refineGltf` with a report per refined primitive. */
export function refineGltfWithReport(
  bytes: Uint8Array | ArrayBuffer,
  options?: RefineGltfOptions,
): { glb: Uint8Array; primitives: RefinedPrimitive[] };

/** A pose of an animated mesh: 3 numbers per vertex. */
export interface Pose {
  positions: Float32Array;
  /** The file's normals posed, or computed from the posed positions when the file has none. */
  normals: Float32Array;
}

/** A clip of an animated mesh: its name, or its index in `clips`. */
export type Clip = string | number;

/**
 * An animated mesh read by `readAnimated`: the triangles and clips, and the mesh posed at any
 * time of a clip (or at rest). Made by `readAnimated` only.
 */
export class AnimatedMesh {
  private constructor();
  /** The triangles' corners, 3 vertex indices per triangle; the same for every pose. */
  readonly indices: Uint32Array;
  /** The clips' names, in the file's order. */
  readonly clips: string[];
  /** The number of vertices of a pose. */
  readonly vertexCount: number;
  /** A clip's duration in seconds. Throws TessellaError for an unknown clip. */
  duration(clip: Clip): number;
  /**
   * The mesh at `time` seconds of `clip` (past the end: the last pose), or the rest pose when
   * `clip` is null or undefined (`time` may then be left out). New arrays each call. Throws
   * TessellaError for an unknown clip or a time that is not finite.
   */
  pose(clip: Clip | null | undefined, time?: number): Pose;
  /** Frees its wasm memory. */
  free(): void;
}

/**
 * Reads an animated glTF file from bytes: format 'gltf', 'glb' or a file name ('walk.glb').
 * Throws TessellaError for a broken file, an invalid animation or another format.
 */
export function readAnimated(bytes: Uint8Array | ArrayBuffer, format: string, options?: ReadMeshOptions): AnimatedMesh;

/** The options of an InstancedSurface (and of tessella/three's TessellatedMesh). */
export interface InstancedSurfaceOptions {
  /** 'flat', 'phong', 'pn' (default), 'png1', 'pn-aen', 'st' or 'quadratic'; see `schemes()`. */
  scheme?: string;
  /** Segments per coarse edge: a whole number from 1 to 256 (default 8). */
  level?: number;
  /** 'linear', 'quadratic' or 'real'; default: the scheme's own. */
  normals?: 'linear' | 'quadratic' | 'real';
  /** Phong's shape factor (default 0.75). */
  alpha?: number;
}

/**
 * What a GPU draws a curved surface from in one instanced call: the pattern and the GLSL fixed
 * by the topology and options; per frame, the control nets packed as RGBA float texels (face
 * `f`'s `texelsPerFace` texels start at texel `((f % facesPerRow) * texelsPerFace,
 * floor(f / facesPerRow))`: its control points, then its 6 normal-net entries, 3 floats each).
 */
export class InstancedSurface {
  constructor(indices: IndexArray, options?: InstancedSurfaceOptions);
  readonly level: number;
  /** Control points per net: 10 (cubic basis) or 21 (PNG1). */
  readonly basisLength: number;
  readonly normalMode: 'linear' | 'quadratic' | 'real';
  /** Coarse triangles: the instances. */
  readonly faceCount: number;
  readonly texelsPerFace: number;
  readonly facesPerRow: number;
  /** The nets texture's size in texels. */
  readonly width: number;
  readonly height: number;
  /** The last frame's control-point bounds: box min xyz, box max xyz, sphere centre xyz, radius. */
  readonly bounds: Float32Array;
  /** The pattern's barycentric points (l1, l2, l3), 3 per point. */
  patternPoints(): Float32Array;
  /** The pattern's triangles, 3 point indices each. */
  patternIndices(): Uint32Array;
  /** GLSL ES 3.00 declaring `tessella_evaluate(int face, vec3 l, out vec3 position, out vec3 normal)`. */
  glsl(): string;
  /**
   * WGSL ending with `fn tessella_position(nets: texture_2d<f32>, face: u32, l: vec3<f32>) -> vec3<f32>`
   * and `fn tessella_normal(nets: texture_2d<f32>, face: u32, l: vec3<f32>) -> vec3<f32>` (unit length),
   * for three.js's TSL `wgslFn`; the nets texture's layout is `glsl()`'s.
   */
  wgsl(): string;
  /**
   * How far the scheme's control points may lie from their triangle, in lengths of its
   * longest edge (0.5 for PN and PN-AEN, |alpha| for Phong, 0 for flat), or null (PNG1,
   * scalar-tagged, quadratic).
   */
  controlReach(): number | null;
  /** Why WebGL2's net pass cannot build these nets (PNG1 and the other CPU-only schemes, tags), or null. */
  netsPassMissing(): string | null;
  /**
   * GLSL ES 3.00 for a pass building the nets on the GPU: `tessella_skin_normal` and
   * `vec4 tessella_nets_texel_of(vec3 p[3], vec3 n[3], vec3 across[6], int j)` (texel `j` as
   * `update` packs it, from the posed corners; each texel computes only what it holds).
   */
  netsPassGlsl(): string;
  /** Each face's 3 corners, then for PN-AEN its 6 across vertices; known after the first `update`. */
  netsPassTopology(): Uint32Array;
  /**
   * WGSL for WebGPURenderer's compute that builds the nets (tessella/three): `nets` ends with
   * `fn tessella_net_texel(j: u32, p0, p1, p2, n0, n1, n2[, m0 .. m5]: vec3<f32>) -> vec4<f32>`
   * (texel `j` of a face's net as `update` packs it), `skinNormal` is
   * `fn tessella_skin_normal(m: mat3x3<f32>, n: vec3<f32>) -> vec3<f32>`. Throws where
   * `netsPassMissing()` says why.
   */
  netsComputeWgsl(): { nets: string; skinNormal: string };
  /**
   * Builds one frame's nets (normals left out are computed) into `out`, a Float32Array of
   * `width * height * 4` floats, and the bounds into `bounds`. Returns `out`.
   */
  update(positions: Float32Array | Float64Array, normals: Float32Array | Float64Array | undefined | null, out: Float32Array): Float32Array;
  /** Frees its wasm memory. */
  free(): void;
}

/** The options of an AdaptiveSurface (and of TessellatedMesh with `lod`). */
export interface AdaptiveSurfaceOptions {
  /** 'flat', 'phong', 'pn' (default), 'png1', 'pn-aen', 'st' or 'quadratic'; see `schemes()`. */
  scheme?: string;
  /** 'linear', 'quadratic' or 'real'; default: the scheme's own. */
  normals?: 'linear' | 'quadratic' | 'real';
  /** Phong's shape factor (default 0.75). */
  alpha?: number;
  /** The GPU tessellator's patterns (required: the grid is not drawn adaptively here). */
  spacing: 'equal' | 'fractional-odd' | 'fractional-even';
  /** 'tolerance:D', 'screen:PX' or 'distance:NEAR,FAR,MAX'; left out, the levels come from `setLevels`. */
  lod?: string;
}

/**
 * What a GPU draws an adaptive surface from: the tessellator's parts (strips and interiors of
 * its patterns) built once; per frame the nets (as InstancedSurface packs them) and, from
 * per-edge levels (given, or the `lod` function's for a camera), one packed record per face
 * (three RGBA32UI texels) and one instance (`face | side << 30`) per face and part, grouped
 * into one draw per part used.
 */
export class AdaptiveSurface {
  constructor(indices: IndexArray, options: AdaptiveSurfaceOptions);
  /** The LOD function's text ('' without one). */
  readonly lod: string;
  readonly basisLength: number;
  readonly normalMode: 'linear' | 'quadratic' | 'real';
  readonly spacing: string;
  readonly faceCount: number;
  readonly texelsPerFace: number;
  readonly facesPerRow: number;
  /** The nets texture's size in texels. */
  readonly width: number;
  readonly height: number;
  /** The records texture (RGBA32UI, three texels per face): faces per row and size. */
  readonly recordsPerRow: number;
  readonly recordsWidth: number;
  readonly recordsHeight: number;
  readonly bounds: Float32Array;
  /** The last levels' draws: part id, first instance, instance count per part used. */
  readonly draws: Uint32Array;
  readonly instanceCount: number;
  readonly triangleCount: number;
  /** Unique edges (after the first frame): the length of `setLevels`' array. */
  readonly edgeCount: number;
  /** The parts' point codes, one per vertex. */
  partCodes(): Uint32Array;
  /** The parts' triangles, indices into `partCodes()`. */
  partIndices(): Uint32Array;
  /** Per part id its first index and index count. */
  partRanges(): Uint32Array;
  /** GLSL ES 3.00 declaring `tessella_adaptive_evaluate(uint code, uint inst, out vec3 position, out vec3 normal, out vec3 bary)`. */
  glsl(): string;
  /**
   * The same in WGSL for three.js's WebGPURenderer (TSL `wgslFn`), ending with
   * `fn tessella_adaptive_point(nets: texture_2d<f32>, records: texture_2d<u32>, instances: texture_2d<u32>, code: u32, instance: u32) -> mat3x3<f32>`
   * (columns: the point, its unit normal, its barycentric coordinates; the instance word read at `instance` of the R32UI `instances` texture).
   */
  wgsl(): string;
  /** One frame's nets into `out` and the bounds, as InstancedSurface's. */
  update(positions: Float32Array | Float64Array, normals: Float32Array | Float64Array | undefined | null, out: Float32Array): Float32Array;
  /** Levels of the `lod` function on the last frame for a camera (the mesh's coordinates, vertical fov in degrees) and image size. */
  setLod(camera: { eye: ArrayLike<number>; target: ArrayLike<number>; fov: number }, size: [number, number]): void;
  /** Levels given, one per unique edge. */
  setLevels(levels: Float32Array | number[]): void;
  /** The last levels, one per unique edge. */
  edgeLevels(): Float32Array;
  /** Copies the records (`recordsWidth * recordsHeight * 4` words) and instances (room for `4 * faceCount`); returns the bytes that matter. */
  read(records: Uint32Array, instances: Uint32Array): number;
  free(): void;
}

/**
 * A mesh posed by an engine's own skeleton (what TessellatedMesh follows a SkinnedMesh or a
 * morphing Mesh with), by the core's skinning: built once from the rest pose, four joint
 * indices and weights per vertex, and morph target displacements.
 */
export class Deformer {
  constructor(source: {
    positions: Float32Array | Float64Array;
    normals?: Float32Array | Float64Array;
    /** Four joint indices per vertex (with a skeleton). */
    joints?: ArrayLike<number>;
    /** Four weights per vertex (with a skeleton). */
    weights?: Float32Array | Float64Array;
    /** The skeleton's joints; 0 (default) for none: poses then take one matrix. */
    jointCount?: number;
    /** `targets × vertices × 3` position displacements. */
    positionDeltas?: Float32Array | Float64Array;
    normalDeltas?: Float32Array | Float64Array;
    targets?: number;
  });
  readonly matrixCount: number;
  readonly vertexCount: number;
  readonly hasNormals: boolean;
  /** Poses with `matrices` (16 column-major numbers each) and the morph `weights` into `positions` and `normals`. */
  pose(matrices: Float32Array, weights: Float32Array, positions: Float32Array, normals?: Float32Array): void;
  /**
   * The box holding the curved surface of a pose: each of the `indices` triangles' posed box
   * grown by `reach` times its longest edge. Six numbers: low corner, high corner.
   */
  posedBounds(matrices: Float32Array, weights: Float32Array, indices: Uint32Array, reach: number): Float32Array;
  free(): void;
}
