// TessellatedMesh's `lod` option under three.js's WebGPURenderer: the same adaptive evaluation
// as three-lod.js's GLSL (placement of the part's point from the face's packed record, the
// patch there, points on a coarse edge from the edge's own control points in canonical order),
// in the WGSL the wasm generates from the same core pieces (AdaptiveSurface.wgsl()), called
// from a TSL node graph as the material's positionNode. The parts, records and instances are
// three-lod.js's (LodParts): the same child meshes draw under either renderer. One difference:
// WebGPU takes no attribute offset past the stride and three gives a draw no first instance,
// so a part reads its instance words from the instances texture at its first (a per-object
// uniform) plus the instance index.
import { Fn, attribute, context, instanceIndex, materialColor, normalLocal, texture, uint, uniform, varying, vec4, wgsl, wgslFn } from 'three/tsl';
import { TessellaError } from './index.js';

const ENTRY = 'fn tessella_adaptive_point(';

// The corners texture's reader (uvs, colours per face, as three-lod.js's GLSL tessella_corner):
// the instance word from the instances texture as the adaptive WGSL reads it.
const CORNER = wgslFn(`fn tessella_lod_corner(corners: texture_2d<f32>, instances: texture_2d<u32>, instance: u32, texels: u32, j: u32) -> vec4<f32> {
    let width = textureDimensions(instances).x;
    let at = instance / width;
    let face = textureLoad(instances, vec2<u32>(instance - at * width, at), 0).x & 0x3fffffffu;
    let per_row = textureDimensions(corners).x / texels;
    let row = face / per_row;
    return textureLoad(corners, vec2<u32>((face - row * per_row) * texels + j, row), 0);
}`);

// One function node per WGSL text (a basis and normal mode): the helpers included once.
const functions = new Map();

/**
 * The TSL function of `AdaptiveSurface.wgsl()`: a `wgslFn` taking
 * `{ nets, records, instances, code, instance }` (the nets, records and instances texture
 * nodes, the part vertex's point code, the instance word's index) and returning a mat3 whose
 * columns are the point, its unit normal and its barycentric coordinates in the coarse triangle.
 */
export function adaptiveFunction(code) {
  let f = functions.get(code);
  if (f !== undefined) return f;
  const at = code.indexOf(ENTRY);
  if (at < 0) throw new TessellaError('the WGSL has no tessella_adaptive_point');
  f = wgslFn(code.slice(at), [wgsl(code.slice(0, at))]);
  functions.set(code, f);
  return f;
}

// The LodParts a drawn object stands for: a part child's parent's, or the mesh's own.
function partsOf(object) {
  return object?.lod != null ? object.lod : object?.parent?.lod;
}

/**
 * Sets up `material` (shared by TessellatedMeshes with `lod` of one kind) to draw the parts of
 * whichever TessellatedMesh's child it draws: `positionNode` evaluating the part's point from
 * that mesh's nets, records and instances textures (texture uniforms of three's per-object
 * group, set before each object's draw from the object's parent), setting `normalLocal` to the
 * patch's normal; with uvs (`flags.uv`) a `contextNode` whose `getUV` gives the coarse uvs
 * blended at the point, with colours (`flags.color`) a `colorNode` multiplying the material's
 * colour by the blended corner colours when `vertexColors` is on (as setupNodes does).
 * `owner` is the first TessellatedMesh (its textures give the nodes their types).
 */
export function setupLodNodes(material, surface, flags, owner) {
  const f = adaptiveFunction(surface.wgsl());
  const parts = owner.lod;
  const nets = texture(owner.netsTexture).onObjectUpdate(({ object }) => {
    const o = object?.lod != null ? object : object?.parent;
    return o?.netsTexture;
  });
  const records = texture(parts.recordsTexture).onObjectUpdate(({ object }) => partsOf(object)?.recordsTexture);
  const instances = texture(parts.instancesTexture).onObjectUpdate(({ object }) => partsOf(object)?.instancesTexture);
  // The part's first instance word (0 for the owner, which draws nothing).
  const first = uniform(0, 'uint').onObjectUpdate(({ object }) => object?.userData?.tessellaFirst ?? 0);
  const instance = first.add(instanceIndex);
  const m = f({ nets, records, instances, code: attribute('tessellaCode', 'uint'), instance });
  material.positionNode = Fn(() => {
    const v = m.toVar();
    normalLocal.assign(v.element(1));
    return v.element(0);
  })();
  if (!(flags.uv || flags.color > 0)) return;
  const corners = texture(parts.cornersTexture).onObjectUpdate(({ object }) => partsOf(object)?.cornersTexture);
  const texels = (flags.uv ? 2 : 0) + (flags.color > 0 ? 3 : 0);
  const corner = (j) => CORNER({ corners, instances, instance, texels: uint(texels), j: uint(j) });
  const l = Fn(() => m.toVar().element(2))();
  if (flags.uv && material.contextNode == null) {
    const a = corner(0);
    const b = corner(1);
    const uv = varying(a.xy.mul(l.x).add(a.zw.mul(l.y)).add(b.xy.mul(l.z)));
    material.contextNode = context({ getUV: () => uv });
  }
  if (flags.color > 0 && material.colorNode == null) {
    const at = flags.uv ? 2 : 0;
    const blend = varying(corner(at).mul(l.x).add(corner(at + 1).mul(l.y)).add(corner(at + 2).mul(l.z)));
    const colour = flags.color === 4 ? blend : vec4(blend.xyz, 1);
    material.colorNode = Fn(({ material: mat }) => (mat.vertexColors === true ? vec4(materialColor).mul(colour) : materialColor))();
  }
}
