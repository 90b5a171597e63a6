// Compiled by test/types.test.js (tsc --noEmit, strict): the declarations describe the API the
// other tests exercise; the lines marked @ts-expect-error must be refused.
import { ready, refine, Refiner, readMesh, readAnimated, AnimatedMesh, writeMesh, schemes, TessellaError, variant, refineGltf, refineGltfWithReport, sceneCamera } from 'tessella';
import type { SceneCamera } from 'tessella';
import type { RefinedPrimitive } from 'tessella';
import { tessellate } from 'tessella/gltf-transform';
import { Document } from '@gltf-transform/core';
import type { MeshOutput, Pose, RefineOutput } from 'tessella';
import { refineGeometry, RefinedGeometry, TessellatedMesh, tessellaFunctions } from 'tessella/three';
import { AdaptiveSurface, InstancedSurface } from 'tessella';
import { BufferGeometry, InstancedBufferGeometry, Mesh, MeshStandardMaterial, WebGLRenderTarget } from 'three';
import { attribute, instanceIndex, texture } from 'three/tsl';

await ready;
const v: 'simd' | 'scalar' = variant;
const names: string[] = schemes();
const out: RefineOutput = refine(
  { positions: new Float64Array(9), indices: new Int32Array(3) },
  { scheme: 'png1', level: 4, normals: 'real', lod: 'tolerance:0.01', camera: [0, 0, 5, 0, 0, 0, 45], size: [64, 64], origin: true },
);
const p: Float32Array = out.positions;
const faces: Uint32Array | undefined = out.faces;
const r = new Refiner(new Uint16Array(3), { scheme: 'pn', level: 2, uvs: new Float32Array(6) });
const frame: MeshOutput = r.refine(new Float32Array(9));
const i: Uint32Array = frame.indices;
r.free();
const m = readMesh(new Uint8Array(4), 'obj', { buffers: { 'a.bin': new Uint8Array(1) } });
const computed: boolean = m.normalsComputed;
const glb: Uint8Array = writeMesh(m, 'glb');
const e: Error = new TessellaError('x');
const g: BufferGeometry = refineGeometry(new BufferGeometry(), { scheme: 'pn' });
const live = new RefinedGeometry(new BufferGeometry(), { level: 3, normalsFromSource: false });
const same: BufferGeometry = live.update();
live.dispose();
const anim: AnimatedMesh = readAnimated(new Uint8Array(4), 'glb');
const clips: string[] = anim.clips;
const seconds: number = anim.duration('wave') + anim.duration(0);
const pose: Pose = anim.pose('wave', 0.5);
const rest: Float32Array = anim.pose(null).normals;
const corners: Uint32Array = anim.indices;
const count: number = anim.vertexCount;
anim.free();
const tm = new TessellatedMesh(new Mesh(new BufferGeometry()), new MeshStandardMaterial(), { scheme: 'pn', level: 4, normalsFromSource: false });
const bytes: number = tm.update().uploadedBytes;
// Instanced while it evaluates per draw; 'per-frame' (the default under WebGLRenderer) draws a welded BufferGeometry.
const instances: number = tm.geometry instanceof InstancedBufferGeometry ? tm.geometry.instanceCount : 0;
const evaluation: 'per-draw' | 'per-frame' = new TessellatedMesh(new BufferGeometry(), undefined, { evaluation: 'auto' }).evaluation;
const posed = new TessellatedMesh(new Mesh(new BufferGeometry()), undefined, { posing: 'gpu' });
const posedOn: 'gpu' | 'cpu' | null = posed.posedOn;
const posingWhy: string | null = posed.posingFallback;
const posingTarget: WebGLRenderTarget | null = posed.gpuNetsTarget;
// @ts-expect-error: posing is 'auto', 'gpu' or 'cpu'
new TessellatedMesh(new BufferGeometry(), undefined, { posing: 'webgl' });
const { normal } = tessellaFunctions((tm.surface as InstancedSurface).wgsl());
const tsl = normal({ nets: texture(tm.netsTexture), face: instanceIndex, l: attribute('tessellaBarycentric', 'vec3') });
tm.dispose();
const surface = new InstancedSurface(new Uint32Array(3), { level: 2 });
const nets: Float32Array = surface.update(new Float32Array(9), null, new Float32Array(surface.width * surface.height * 4));
const glsl: string = surface.glsl();
const wgsl: string = surface.wgsl();
surface.free();
// @ts-expect-error: no lod on the instanced path
new InstancedSurface(new Uint32Array(3), { lod: 'tolerance:0.1' });
// @ts-expect-error: the TSL functions take named nodes
normal(texture(tm.netsTexture), instanceIndex);
const lodMesh = new TessellatedMesh(new BufferGeometry(), undefined, { lod: 'screen:4', spacing: 'fractional-odd', size: [640, 480] });
const lodBytes: number = lodMesh.lod === null ? 0 : lodMesh.lod.uploadedBytes + lodMesh.lod.triangleCount;
lodMesh.lod?.setLevels([2, 3, 4]);
const adaptive = new AdaptiveSurface(new Uint32Array(3), { spacing: 'equal', lod: 'tolerance:0.01' });
adaptive.setLod({ eye: [0, 0, 5], target: [0, 0, 0], fov: 45 }, [640, 480]);
const drawsOf: Uint32Array = adaptive.draws;
adaptive.free();
// @ts-expect-error: lod draws the tessellator's patterns, not the grid
new AdaptiveSurface(new Uint32Array(3), { spacing: 'grid' });
// @ts-expect-error: made by readAnimated only
new AnimatedMesh();
// @ts-expect-error: a clip is a name or an index
anim.pose(true, 0);
// @ts-expect-error: positions must be a float typed array
refine({ positions: [0, 0, 0], indices: new Uint32Array(3) });
// @ts-expect-error: not a normals mode
refine({ positions: new Float32Array(9), indices: new Uint32Array(3) }, { normals: 'cubic' });
// @ts-expect-error: not a format writeMesh writes
writeMesh(m, 'fbx');
const refinedGlb: Uint8Array = refineGltf(new Uint8Array(4), { scheme: 'pn', level: 3, buffers: { 'a.bin': new ArrayBuffer(4) } });
const report: RefinedPrimitive[] = refineGltfWithReport(new ArrayBuffer(4), { maxEdge: 0.1, normals: 'real', alpha: 0.5 }).primitives;
const triangles: number = report[0].triangles + report[0].coarseTriangles + report[0].level;
await new Document().transform(tessellate({ scheme: 'phong', level: 2 }));
// @ts-expect-error: the Document holds its buffers
tessellate({ buffers: {} });
// @ts-expect-error: lod works on one mesh, not on a scene
refineGltf(new Uint8Array(4), { lod: 'tolerance:0.1' });
const cam: SceneCamera = sceneCamera(new Float32Array(9), { yaw: 30, width: 800, height: 600, pan: [0.1, 0] });
const viewProj: Float32Array = cam.viewProj;
// @ts-expect-error: width and height are needed for the aspect
sceneCamera(new Float32Array(9), { yaw: 30 });
export { refinedGlb, triangles, viewProj };
export { v, names, p, faces, i, computed, glb, e, g, same, clips, seconds, pose, rest, corners, count, bytes, instances, nets, glsl, wgsl, tsl };
