// TessellatedMesh's GPU posing under three.js's WebGPURenderer: a skinned or morphing source's
// control nets built by compute from three's pose (its bones' matrices, as SourcePose composes
// them, and the morph influences), so a frame uploads the joint matrices and morph weights
// alone; the rest vertices, influences, morph deltas and face indices once. Two dispatches in
// one compute pass: a thread a coarse vertex poses it as the CPU's Deformer does, then a thread
// a texel builds its face's net with the WGSL the wasm generates from the core's Rust
// (InstancedSurface.netsComputeWgsl(), nets_wgsl.rs: the builders, the packing, the skinned
// normal) and stores the texel in a storage texture laid out as the CPU's nets texture, which
// the mesh's nodes then read. three-gpu-nets.js is the WebGL2 counterpart.
import { FloatType, NearestFilter, RGBAFormat, Texture } from 'three';
import {
  Fn,
  If,
  instanceIndex,
  Loop,
  mat3,
  storage,
  StorageBufferAttribute,
  textureStore,
  uint,
  uvec2,
  vec4,
  wgsl,
  wgslFn,
} from 'three/tsl';
import { TessellaError } from './index.js';

const TEXEL = 'fn tessella_net_texel(';

// Storage buffers the pose pass binds (WebGPU guarantees 8 per compute stage).
const POSE_BUFFERS = 5;

/**
 * Why `renderer` cannot build the nets by compute (then the CPU poses), or null: a
 * WebGPURenderer on its WebGPU backend (not the WebGL2 fallback) binding enough storage buffers.
 */
export function gpuNetsNodesMissing(renderer) {
  if (renderer?.isWebGPURenderer !== true || renderer.backend?.isWebGPUBackend !== true) {
    return 'GPU posing under WebGPURenderer builds the nets by WebGPU compute; this renderer has none';
  }
  const limit = renderer.backend.device?.limits?.maxStorageBuffersPerShaderStage ?? 8;
  if (limit < POSE_BUFFERS) return `the device binds ${limit} storage buffers a compute stage; the posing takes ${POSE_BUFFERS}`;
  return null;
}

// A storage buffer of `data`, `count` elements of `type` (read-only unless `writable`), and
// its attribute, added to `owned` (disposed with the nets: three frees a storage buffer's GPU
// memory only when its attribute is disposed).
function buffer(owned, data, itemSize, type, count, writable = false) {
  const attribute = new StorageBufferAttribute(data, itemSize);
  owned.push(attribute);
  const node = storage(attribute, type, count);
  return { attribute, node: writable ? node : node.toReadOnly() };
}

/**
 * One TessellatedMesh's nets built by WebGPURenderer's compute from its posed source, the
 * counterpart of three-gpu-nets.js's GpuNets (the same arguments and calls). `surface`: the
 * InstancedSurface (a frame built: its layout, netsComputeWgsl() and netsPassTopology()); `rest`:
 * the source's rest data (SourcePose.rest: positions, normals, joints, weights, deltas,
 * targets, matrixCount). `render(renderer, matrices, weights, first)` poses and builds into
 * `texture`, a storage texture of the nets DataTexture's size and layout (RGBA32F, nearest)
 * that the mesh's nodes read in its place; `uploadBytes` is what each frame uploads.
 */
export class GpuNetsNodes {
  #matrices;
  #weights;
  #skinned;
  #targets;
  #nodes;
  /** Every storage buffer's attribute, disposed with the nets. */
  #buffers = [];
  /** The largest storage buffer's bytes (the morph deltas, or the rest or posed vertices). */
  #largest;

  constructor(surface, rest) {
    const code = surface.netsComputeWgsl();
    const words = surface.netsPassTopology();
    const n = rest.positions.length / 3;
    const skinned = rest.joints !== undefined;
    const targets = rest.targets;
    this.#skinned = skinned;
    this.#targets = targets;

    // Per vertex: position, normal, and when skinned the weights then the joint indices (as
    // floats: exact below 2^24), a vec4 each.
    const per = skinned ? 4 : 2;
    const restData = new Float32Array(4 * per * n);
    for (let v = 0; v < n; v++) {
      const r = 4 * per * v;
      restData.set(rest.positions.subarray(3 * v, 3 * v + 3), r);
      restData.set(rest.normals.subarray(3 * v, 3 * v + 3), r + 4);
      if (skinned) {
        restData.set(rest.weights.subarray(4 * v, 4 * v + 4), r + 8);
        for (let i = 0; i < 4; i++) restData[r + 12 + i] = rest.joints[4 * v + i];
      }
    }
    const restNode = buffer(this.#buffers, restData, 4, 'vec4', per * n).node;
    // The morph targets' displacements, position then normal, 2 vec4 a target and vertex.
    const deltas = new Float32Array(8 * Math.max(1, targets * n));
    for (let t = 0; t < targets; t++) {
      for (let v = 0; v < n; v++) {
        const s = 3 * (t * n + v);
        deltas.set(rest.positionDeltas.subarray(s, s + 3), 8 * (t * n + v));
        if (rest.normalDeltas !== undefined) deltas.set(rest.normalDeltas.subarray(s, s + 3), 8 * (t * n + v) + 4);
      }
    }
    const deltaNode = buffer(this.#buffers, deltas, 4, 'vec4', 2 * Math.max(1, targets * n)).node;
    // Per frame: the joint matrices (bind space to posed mesh space, SourcePose's) and the weights.
    this.#matrices = buffer(this.#buffers, new Float32Array(16 * rest.matrixCount), 16, 'mat4', rest.matrixCount);
    this.#weights = buffer(this.#buffers, new Float32Array(Math.max(1, targets)), 1, 'float', Math.max(1, targets));
    // The posed vertices: position then unit normal, 2 vec4 a vertex.
    const posed = buffer(this.#buffers, new Float32Array(8 * n), 4, 'vec4', 2 * n, true).node;
    const skinNormal = wgslFn(code.skinNormal);

    // As the CPU's Deformer (tessella_core's Poser): p + Σ w Δp and n + Σ w Δn over the
    // targets whose weight is not 0; the vertex's matrix (its joints' blended, the weights
    // divided by their sum; a rigid source's one matrix) moves the point, and its cofactors
    // the normal, normalised (tessella_skin_normal, generated from the core).
    const pose = Fn(() => {
      const v = instanceIndex;
      const at = v.mul(uint(per));
      const p = restNode.element(at).xyz.toVar();
      const nn = restNode.element(at.add(uint(1))).xyz.toVar();
      if (targets > 0) {
        const w = this.#weights.node;
        Loop(targets, ({ i }) => {
          const weight = w.element(i);
          If(weight.notEqual(0), () => {
            const d = uint(i).mul(uint(n)).add(v).mul(uint(2));
            p.addAssign(deltaNode.element(d).xyz.mul(weight));
            nn.addAssign(deltaNode.element(d.add(uint(1))).xyz.mul(weight));
          });
        });
      }
      const matrices = this.#matrices.node;
      let m;
      if (skinned) {
        const weight = restNode.element(at.add(uint(2))).toVar();
        const joint = restNode.element(at.add(uint(3)));
        weight.divAssign(weight.x.add(weight.y).add(weight.z).add(weight.w));
        const bone = (c) => matrices.element(uint(joint[c]));
        m = bone('x').mul(weight.x).add(bone('y').mul(weight.y)).add(bone('z').mul(weight.z)).add(bone('w').mul(weight.w)).toVar();
      } else {
        m = matrices.element(uint(0)).toVar();
      }
      posed.element(v.mul(uint(2))).assign(m.mul(vec4(p, 1)));
      posed.element(v.mul(uint(2)).add(uint(1))).assign(vec4(skinNormal({ m: mat3(m), n: nn }), 0));
    })().compute(n);

    // One thread a texel: its face's net from the posed corners (and PN-AEN's across normals),
    // stored where the draw's tessella_texel reads it.
    const head = code.nets.indexOf(TEXEL);
    if (head < 0) throw new TessellaError('the nets WGSL has no tessella_net_texel');
    const texel = wgslFn(code.nets.slice(head), [wgsl(code.nets.slice(0, head))]);
    // 3 corners a face, or 9 with PN-AEN's across vertices.
    const stride = words.length / surface.faceCount;
    const across = stride === 9;
    const topology = buffer(this.#buffers, words, 1, 'uint', words.length).node;
    const texels = surface.texelsPerFace;
    const perRow = surface.facesPerRow;
    // A StorageTexture (three/webgpu's is this: a Texture flagged isStorageTexture, made with
    // STORAGE_BINDING), read by the draw's textureLoad: nearest, no mipmaps.
    const texture = new Texture();
    texture.isStorageTexture = true;
    texture.image = { width: surface.width, height: surface.height };
    Object.assign(texture, { format: RGBAFormat, type: FloatType, minFilter: NearestFilter, magFilter: NearestFilter, generateMipmaps: false });
    /** The nets, in the layout of the nets DataTexture. */
    this.texture = texture;
    const build = Fn(() => {
      const i = instanceIndex;
      const face = i.div(uint(texels));
      const j = i.sub(face.mul(uint(texels)));
      const words = face.mul(uint(stride));
      const vertex = (k) => topology.element(words.add(uint(k)));
      const args = { j };
      for (let c = 0; c < 3; c++) {
        args[`p${c}`] = posed.element(vertex(c).mul(uint(2))).xyz;
        args[`n${c}`] = posed.element(vertex(c).mul(uint(2)).add(uint(1))).xyz;
      }
      if (across) for (let k = 0; k < 6; k++) args[`m${k}`] = posed.element(vertex(3 + k).mul(uint(2)).add(uint(1))).xyz;
      const row = face.div(uint(perRow));
      const column = face.sub(row.mul(uint(perRow))).mul(uint(texels)).add(j);
      textureStore(texture, uvec2(column, row), texel(args)).toWriteOnly();
    })().compute(surface.faceCount * texels);
    this.#nodes = [pose, build];
    this.#largest = Math.max(restData.byteLength, deltas.byteLength, 32 * n, words.byteLength, 64 * rest.matrixCount);
    /** Bytes a frame uploads: the joint matrices (a skeleton's) and the morph weights (when there are targets). */
    this.uploadBytes = (skinned ? this.#matrices.attribute.array.byteLength : 0) + (targets > 0 ? this.#weights.attribute.array.byteLength : 0);
  }

  /** Why `renderer` cannot run this compute, or null. */
  missing(renderer) {
    const why = gpuNetsNodesMissing(renderer);
    if (why !== null) return why;
    const limit = renderer.backend.device?.limits?.maxStorageBufferBindingSize ?? 128 << 20;
    if (this.#largest > limit) return `the posing inputs need a storage buffer of ${this.#largest} bytes, over the device's ${limit}`;
    return null;
  }

  /**
   * Builds the nets of the pose `matrices` (16 floats a joint, SourcePose's) and morph
   * `weights` into `texture`: one compute pass of two dispatches (pose, then a texel a thread),
   * submitted at once, so before the frame's passes that read it (submitted at the end of
   * `render`). Uploads the matrices (skinned; a rigid source's one matrix when `first`) and the
   * weights.
   */
  render(renderer, matrices, weights, first) {
    if (this.#skinned || first) {
      this.#matrices.attribute.array.set(matrices);
      this.#matrices.attribute.needsUpdate = true;
    }
    if (this.#targets > 0) {
      this.#weights.attribute.array.set(weights);
      this.#weights.attribute.needsUpdate = true;
    }
    renderer.compute(this.#nodes);
  }

  dispose() {
    for (const node of this.#nodes) node.dispose();
    this.texture.dispose();
    for (const attribute of this.#buffers) attribute.dispose();
  }
}
