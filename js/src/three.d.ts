import type { BufferGeometry, Camera, DataTexture, InstancedBufferGeometry, Intersection, Material, Mesh, MeshDepthMaterial, MeshDistanceMaterial, Object3D, Raycaster, SkinnedMesh, Texture, WebGLRenderTarget } from 'three';
import type { Node } from 'three/webgpu';
import type { AdaptiveSurface, InstancedSurface, InstancedSurfaceOptions, RefineOptions } from './index.js';

/**
 * Refines a BufferGeometry into a new indexed one: position, normal, uv from tessella; other
 * float attributes interpolated over each coarse triangle.
 */
export function refineGeometry(geometry: BufferGeometry, options?: Omit<RefineOptions, 'origin'>): BufferGeometry;

export interface RefinedGeometryOptions extends Omit<RefineOptions, 'origin'> {
  /** Use the source's normal attribute each frame (default: when it has one); false recomputes them. */
  normalsFromSource?: boolean;
}

/** A refined geometry that follows a deforming source; `update()` rewrites its attributes in place. */
export class RefinedGeometry {
  constructor(source: BufferGeometry, options?: RefinedGeometryOptions);
  /** The refined geometry; its attribute arrays are reused by every `update()`. */
  readonly geometry: BufferGeometry;
  /** Refines the source's current positions (and normals) into `geometry`. */
  update(): BufferGeometry;
  /** Frees the wasm memory. */
  dispose(): void;
}

export interface TessellatedMeshOptions extends InstancedSurfaceOptions {
  /** Use the source's normal attribute (default: when it has one); false computes them each frame. */
  normalsFromSource?: boolean;
  /**
   * Draw only this group of the source geometry (an index into `geometry.groups`: its triangles;
   * with no material given, a clone of the source Mesh's `material[group.materialIndex]`).
   */
  group?: number;
  /**
   * Per-edge levels every frame, crack-free: 'screen:PX' (segments about PX pixels long on the
   * camera's image), 'tolerance:D' or 'distance:NEAR,FAR,MAX'; drawn with the GPU tessellator's
   * patterns (`spacing` required, `level` refused). Under WebGLRenderer (GLSL) and WebGPURenderer
   * (the WGSL of `AdaptiveSurface.wgsl()`, as TSL nodes) alike.
   */
  lod?: string;
  /** With `lod`: 'equal', 'fractional-odd' or 'fractional-even'. */
  spacing?: 'equal' | 'fractional-odd' | 'fractional-even';
  /** With `lod`: the camera the levels are for (default: the camera of the previous render). */
  camera?: Camera;
  /** With `lod`: the image size [width, height] in pixels (default: the viewport of the previous render). */
  size?: [number, number];
  /**
   * 'per-draw': every draw pass (shadow maps, the picture) evaluates the patches from the nets,
   * one instanced draw a pass; GPU memory O(coarse). 'per-frame' (WebGLRenderer, WebGL2 with
   * float render targets): when the nets change, one pass evaluates the refined mesh's vertices
   * into vertex buffers; the passes draw the welded refined mesh from them with a program of
   * its own that evaluates nothing; GPU memory O(refined), about 80 bytes a vertex more than a
   * refined Mesh. 'auto' (default): decided at the first render, 'per-frame' under WebGLRenderer
   * where it can run, else 'per-draw' (WebGPURenderer, lod, a ShaderMaterial). Every mesh draws
   * its first frame per draw (instanced); 'per-frame' from the frame after the first bake.
   * 'per-frame' falls back to evaluating per draw (`evaluationFallback` says why) with `lod`,
   * without EXT_color_buffer_float, under WebGPURenderer, past the largest texture, or drawn by
   * a second renderer.
   */
  evaluation?: 'auto' | 'per-draw' | 'per-frame';
  /**
   * Where a SkinnedMesh or morphing Mesh source is posed and its nets built. 'gpu' (WebGLRenderer,
   * WebGL2 with float render targets): two render passes (the coarse vertices posed, then the
   * nets) build the nets texture from the joint matrices and morph weights, which alone are
   * uploaded a frame (64 bytes a joint, 16 per 4 weights); under WebGPURenderer (its WebGPU backend) a compute pass builds them into a
   * storage texture (`netsTexture`), uploading 64 bytes a joint and 4 a weight. 'cpu': wasm
   * poses the coarse vertices and builds the nets, the nets texture uploaded. 'auto' (default): decided at the first render, 'gpu' where it can run, else 'cpu'
   * (`posingFallback` says why: no EXT_color_buffer_float (WebGL), no WebGPU compute, PNG1 and the
   * other schemes the GPU builds no nets of (flat, phong, pn, pn-aen it does), tags, normals
   * computed per frame (no source normals, normalsFromSource: false), lod, a second renderer).
   * 'gpu' throws a TessellaError where it cannot run. A source that neither skins nor morphs is
   * not posed (`posedOn` null).
   */
  posing?: 'auto' | 'gpu' | 'cpu';
}

/** TessellatedMesh's `lod` drawing: the levels' camera and size, and what they draw and upload. */
export interface TessellatedMeshLod {
  /** The camera the levels are for; null: the camera of the previous render. */
  camera: Camera | null;
  /** The image size the levels are for; null: the viewport of the previous render. */
  size: [number, number] | null;
  /** Bytes the last level change marked for upload (records and instances; 0 when the levels did not change). */
  readonly uploadedBytes: number;
  /** Bytes of the parts (strips and interiors), uploaded once. */
  readonly partBytes: number;
  /** Triangles the last levels draw. */
  readonly triangleCount: number;
  /** The child meshes that draw the parts (one per part used so far; hidden when unused). */
  readonly children: Mesh[];
  /** The corners texture (per face its corners' uvs, then colours), or null. */
  readonly cornersTexture: DataTexture | null;
  /** The packed records (RGBA32UI, three texels a face). */
  readonly recordsTexture: DataTexture;
  /** The instance words as an R32UI texture (what WebGPURenderer's nodes read, each part from its first). */
  readonly instancesTexture: DataTexture;
  /** Draws these per-edge levels (one per unique edge, `surface.edgeCount`) from now on instead of the lod function's. */
  setLevels(levels: Float32Array | number[]): void;
}

/**
 * A curved surface drawn by WebGLRenderer (WebGL2) or WebGPURenderer (its WebGPU backend) in
 * one instanced draw: the refinement pattern once per coarse triangle, the vertex stage
 * evaluating each triangle's patch from control nets in a float texture. A Mesh source is
 * replaced (same parent, transform, shadow flags, layers) and hidden: `visible = false`, or,
 * when it has children (which that would hide too), taken off every layer (`layers.mask = 0`;
 * this then follows its `visible`). A SkinnedMesh's skeleton and a Mesh's morph influences are
 * followed every frame (posed in wasm, as getVertexPosition poses them). Triangles without area
 * are left out.
 *
 * **The material is patched in place** (no material given: a clone of the source's, which is
 * untouched): `onBeforeCompile` and `customProgramCacheKey` (chained after its own) for
 * WebGLRenderer; `positionNode`, and `contextNode`/`colorNode` for uvs/colours unless it has its
 * own, for WebGPURenderer. Any number of TessellatedMeshes of one kind (scheme basis, normals,
 * uvs, colours, lod) may share it, each drawing its own nets; one of another kind is refused.
 * When the last one is disposed, the properties it set are put back (a clone it made is
 * disposed). A material with a positionNode of its own is refused.
 */
export class TessellatedMesh extends Mesh<InstancedBufferGeometry | BufferGeometry, Material> {
  /**
   * The evaluation in effect: 'per-frame' (baked once per change of the nets; `geometry` is then
   * the welded refined mesh from the next frame) or 'per-draw' (before the first render too).
   */
  readonly evaluation: 'per-draw' | 'per-frame';
  /** Why the evaluation is 'per-draw' though 'per-frame' was asked for (or 'auto' would take it), or null. */
  readonly evaluationFallback: string | null;
  /** 'per-frame': GPU memory of the baked vertices (targets, origins, vertex buffers); else 0. */
  readonly bakedBytes: number;
  constructor(source: BufferGeometry | Mesh | SkinnedMesh, material?: Material, options?: TessellatedMeshOptions);
  /** The source (the coarse Mesh, SkinnedMesh or BufferGeometry). */
  readonly source: BufferGeometry | Mesh | SkinnedMesh;
  /**
   * Where the source is posed: 'gpu', 'cpu' (a posed mesh before its first render too), or null
   * for a source that neither skins nor morphs.
   */
  readonly posedOn: 'gpu' | 'cpu' | null;
  /** Why a posed source is posed on the CPU though `posing` allows the GPU, or null. */
  readonly posingFallback: string | null;
  /** GPU posing: the render target the nets are built into; else null. */
  readonly gpuNetsTarget: WebGLRenderTarget | null;
  /** The nets texture (RGBA32F) the vertex shader reads: the CPU's DataTexture, or GPU posing's render target texture. */
  readonly netsTexture: DataTexture | Texture;
  /** The wasm side: pattern, texture layout, GLSL and WGSL (with `lod`, an AdaptiveSurface). */
  readonly surface: InstancedSurface | AdaptiveSurface;
  /** With `lod`: its levels and children; else null. */
  readonly lod: TessellatedMeshLod | null;
  /** Update before each render when the source's position, normal, uv or color attribute changed (default true). */
  autoUpdate: boolean;
  /** Bytes the last `update()` marked for upload: the nets texture, or with GPU posing the joint matrices and morph weights (and uvs or colours when they changed). */
  uploadedBytes: number;
  customDepthMaterial: MeshDepthMaterial;
  customDistanceMaterial: MeshDistanceMaterial;
  /** Rebuilds the nets from the source's current attributes (posed, for a skinned or morphing source); the bounds follow. */
  update(): this;
  /** Hits on the curved surface of the last frame (its CPU refinement), reported with this object. */
  raycast(raycaster: Raycaster, intersects: Intersection[]): void;
  /**
   * Frees the wasm memory, the nets texture, the pattern and the shadow materials; the last mesh
   * of a material puts back what patching set on it (or disposes the clone it made). The source
   * stays hidden (`untessellate` shows it again for meshes `tessellate` made).
   */
  dispose(): void;
}

export interface TessellateOptions extends Omit<TessellatedMeshOptions, 'group'> {
  /** Return false to leave a mesh as it is (listed in `skipped`). */
  filter?: (mesh: Mesh) => boolean;
}

/** What `tessellate` made of a scene. */
export class TessellatedScene {
  /** The TessellatedMeshes drawing in the sources' places (one per mesh; one per geometry group for a material array). */
  readonly meshes: TessellatedMesh[];
  /** Objects left as they are, and why: points, lines, instanced or batched meshes, meshes without positions or triangles, TessellatedMeshes, filtered ones. */
  readonly skipped: { object: Object3D; reason: string }[];
  /**
   * Source material to the patched clones its meshes draw with: one, unless meshes of the
   * material differ in vertex layout (uvs; colours of 3 or 4 components), one per layout.
   */
  readonly materials: Map<Material, Material[]>;
  /** Puts back the sources of these meshes (default: all), as `untessellate` does. */
  restore(meshes?: TessellatedMesh[]): void;
  /** Puts the whole scene back: `restore()`. */
  dispose(): void;
}

/**
 * Replaces every triangle Mesh and SkinnedMesh under `object3d` (itself included) by a
 * TessellatedMesh with `options`; a mesh with a material array by one per geometry group.
 * Meshes that shared a material share one patched clone of it (three's WebGLRenderer and
 * WebGPURenderer each draw each mesh with its own nets through the shared material, without
 * new programs); **the source materials are never changed**. The sources are hidden as
 * TessellatedMesh hides them; the TessellatedMesh takes their `visible`, `layers`,
 * `renderOrder`, `frustumCulled`. Other objects are listed in `skipped`; an error (a
 * TessellaError) puts back what was done and is thrown.
 */
export function tessellate(object3d: Object3D, options?: TessellateOptions): TessellatedScene;

/**
 * Puts back every mesh `tessellate` replaced under `object3d` (itself included): the sources
 * visible (and on their layers) as before, in their places; the TessellatedMeshes removed and
 * disposed; the patched clones disposed. Returns how many TessellatedMeshes it removed.
 */
export function untessellate(object3d: Object3D): number;

/** A TSL function of the surface: `{ nets: texture(mesh.netsTexture), face: instanceIndex, l: attribute('tessellaBarycentric', 'vec3') }` to a vec3. */
export type TessellaFunction = (args: { nets: Node; face: Node; l: Node }) => Node;

/**
 * TSL (`wgslFn`) functions from `InstancedSurface.wgsl()`: the patch's point and its unit
 * normal, for a node material's own graph beside TessellatedMesh's. The same text gives the
 * same nodes.
 */
export function tessellaFunctions(wgsl: string): { position: TessellaFunction; normal: TessellaFunction };
