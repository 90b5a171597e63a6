// tessella/three: refine three.js BufferGeometry. `three` is a peer dependency (the caller's
// own copy), never bundled.
import { BufferAttribute, BufferGeometry } from 'three';
import { refine, Refiner, TessellaError } from './index.js';

// Attributes tessella computes itself; every other float attribute is interpolated.
const OWN = new Set(['position', 'normal', 'uv']);

function source(geometry) {
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
  if (!(a instanceof Float32Array || a instanceof Float64Array)) return null;
  return a instanceof Float32Array && a.length === n ? a : Float32Array.from(a.subarray(0, n));
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
  const { position, indices } = source(geometry);
  const normal = geometry.getAttribute('normal');
  const uv = geometry.getAttribute('uv');
  const extra = Object.entries(geometry.attributes)
    .filter(([name]) => !OWN.has(name))
    .map(([name, a]) => [name, a, values(a)])
    .filter(([, , data]) => data !== null);
  const out = refine(
    {
      positions: values(position),
      indices,
      normals: normal === undefined ? undefined : values(normal),
      uvs: uv === undefined ? undefined : values(uv),
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
    const { indices } = source(geometry);
    const uv = geometry.getAttribute('uv');
    this.#source = geometry;
    this.#useNormals = options.normalsFromSource ?? geometry.getAttribute('normal') !== undefined;
    const { normalsFromSource, ...rest } = options;
    this.#refiner = new Refiner(indices, { ...rest, uvs: uv === undefined ? undefined : values(uv) });
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
    return this.#refiner.refine(values(g.getAttribute('position')), normal === undefined ? undefined : values(normal));
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
