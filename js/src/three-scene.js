// tessella/three at scene scale: `tessellate(object3d, options)` replaces every triangle Mesh
// and SkinnedMesh of a loaded scene (what GLTFLoader gives) by a TessellatedMesh, one patched
// clone per source material shared by all the meshes that shared it; `untessellate` (or the
// handle's `dispose()`) puts the scene back as it was. Re-exported by three.js.
import { TessellaError } from './index.js';
import { cloneMaterial, TessellatedMesh } from './three.js';

// Every TessellatedMesh `tessellate` made, to the handle that owns it (untessellate finds them).
const owners = new WeakMap();

// What a mesh's vertices give the patched shaders besides positions and normals: uvs, and
// colours of 3 or 4 components. Meshes of one source material with different layouts need
// different shaders, so each layout gets its own patched clone.
function layoutOf(geometry) {
  const color = geometry.getAttribute('color');
  return `${geometry.getAttribute('uv') !== undefined ? 'uv' : ''}:${color === undefined ? 0 : color.itemSize}`;
}

function triangles(geometry) {
  const n = geometry.index !== null ? geometry.index.count : geometry.getAttribute('position').count;
  return Math.floor(n / 3);
}

// Why `object` is not tessellated (a reason for `skipped`), or null when it is a triangle mesh
// to tessellate. Objects that draw nothing (groups, bones, cameras, lights) are neither.
function skipReason(object) {
  if (object.isPoints === true) return 'points: tessella refines triangles';
  if (object.isLine === true) return 'lines: tessella refines triangles';
  if (object.isMesh !== true) return undefined;
  if (object.isInstancedMesh === true) return 'an InstancedMesh: TessellatedMesh draws one mesh (its instancing is the pattern\'s)';
  if (object.isBatchedMesh === true) return 'a BatchedMesh: TessellatedMesh draws one mesh';
  const g = object.geometry;
  if (g == null || g.isBufferGeometry !== true) return 'no BufferGeometry';
  if (g.getAttribute('position') === undefined) return 'its geometry has no position attribute';
  if (triangles(g) === 0) return 'its geometry has no triangles';
  if (object.parent === null) return 'no parent: a TessellatedMesh takes the mesh\'s place in its parent';
  if (Array.isArray(object.material) && g.groups.length === 0) return 'a material array without geometry groups (three draws nothing of it)';
  return null;
}

/**
 * What `tessellate` made of a scene: the TessellatedMeshes, the objects it left as they were
 * (and why), and the patched materials, one per source material (and vertex layout). `dispose()`
 * puts the scene back as it was.
 */
export class TessellatedScene {
  /** The TessellatedMeshes drawing in the sources' places (one per mesh; per geometry group for a material array). */
  meshes = [];
  /** Objects left as they were: `{ object, reason }`. */
  skipped = [];
  /** Source material to the patched clones drawing its meshes (one per vertex layout: usually one). */
  materials = new Map();
  #sources = new Map(); // source Mesh -> { visible, layers, meshes }: what it was, what replaced it
  #clones = new Map(); // source material -> Map(layout -> clone)
  #users = new Map(); // clone -> TessellatedMeshes drawing with it

  /** @internal */
  _material(source, geometry) {
    if (source == null || source.isMaterial !== true) throw new TessellaError('a mesh has no material to draw with');
    const layout = layoutOf(geometry);
    let byLayout = this.#clones.get(source);
    if (byLayout === undefined) this.#clones.set(source, (byLayout = new Map()));
    let clone = byLayout.get(layout);
    if (clone === undefined) {
      clone = cloneMaterial(source);
      byLayout.set(layout, clone);
      this.materials.set(source, [...(this.materials.get(source) ?? []), clone]);
      this.#users.set(clone, new Set());
    }
    return clone;
  }

  /** @internal */
  _add(source, mesh, { visible, layers }) {
    let entry = this.#sources.get(source);
    if (entry === undefined) this.#sources.set(source, (entry = { visible, layers, meshes: [] }));
    entry.meshes.push(mesh);
    this.meshes.push(mesh);
    this.#users.get(mesh.material).add(mesh);
    owners.set(mesh, this);
  }

  /**
   * Puts back the sources of `meshes` (default: all): each source Mesh visible as before in its
   * place, its TessellatedMeshes removed and disposed, and a patched clone disposed once no mesh
   * draws with it. The source materials were never changed.
   */
  restore(meshes = this.meshes) {
    const gone = new Set();
    for (const [source, entry] of this.#sources) {
      if (!entry.meshes.some((m) => meshes.includes(m))) continue;
      // A source drawn as several groups comes back whole.
      for (const m of entry.meshes) {
        m.removeFromParent();
        m.dispose();
        owners.delete(m);
        gone.add(m);
        const users = this.#users.get(m.material);
        users.delete(m);
        if (users.size === 0) this.#dropMaterial(m.material);
      }
      source.visible = entry.visible;
      source.layers.mask = entry.layers;
      this.#sources.delete(source);
    }
    this.meshes = this.meshes.filter((m) => !gone.has(m));
  }

  #dropMaterial(clone) {
    clone.dispose();
    this.#users.delete(clone);
    for (const [source, byLayout] of this.#clones) {
      for (const [layout, c] of byLayout) if (c === clone) byLayout.delete(layout);
      if (byLayout.size === 0) this.#clones.delete(source);
      const left = (this.materials.get(source) ?? []).filter((c) => c !== clone);
      if (left.length === 0) this.materials.delete(source);
      else this.materials.set(source, left);
    }
  }

  /** Puts the whole scene back (see `restore`). */
  dispose() {
    this.restore();
  }
}

/**
 * Replaces every triangle `Mesh` and `SkinnedMesh` under `object3d` (itself included) by a
 * `TessellatedMesh` with `options` (those of TessellatedMesh, and `filter(mesh)`: false leaves
 * a mesh as it is). Meshes that shared a material share one patched clone of it; the source
 * materials are not changed. A mesh with a material array is drawn as one TessellatedMesh per
 * geometry group (each with its material's clone). Points, lines, instanced and batched meshes,
 * meshes without positions or triangles, and TessellatedMeshes are left as they are, listed in
 * `skipped` with the reason. Any other error (a TessellaError from a TessellatedMesh) puts back
 * what was done and is thrown.
 */
export function tessellate(object3d, options = {}) {
  if (object3d == null || object3d.isObject3D !== true) throw new TessellaError('tessellate takes a three.js Object3D (a scene, or a part of one)');
  if (options == null || typeof options !== 'object') throw new TessellaError('options must be an object');
  const { filter, ...meshOptions } = options;
  if (filter !== undefined && typeof filter !== 'function') throw new TessellaError('filter: a function of a mesh, false to leave it as it is');
  if (meshOptions.group !== undefined) throw new TessellaError('group: tessellate draws each group of a material array itself');
  const result = new TessellatedScene();
  const found = [];
  const walk = (o) => {
    // A TessellatedMesh (and its lod children) is left alone.
    if (o instanceof TessellatedMesh) {
      result.skipped.push({ object: o, reason: 'already a TessellatedMesh' });
      return;
    }
    found.push(o);
    for (const child of o.children) walk(child);
  };
  walk(object3d);
  try {
    for (const o of found) {
      const reason = skipReason(o);
      if (reason === undefined) continue;
      if (reason === null && filter !== undefined && !filter(o)) {
        result.skipped.push({ object: o, reason: 'left out by filter' });
        continue;
      }
      if (reason !== null) {
        result.skipped.push({ object: o, reason });
        continue;
      }
      const visible = o.visible;
      const layers = o.layers.mask;
      const g = o.geometry;
      const parts = Array.isArray(o.material)
        ? g.groups.map((group, i) => ({ group: i, material: o.material[group.materialIndex ?? 0], count: group.count }))
          .filter((p) => p.material != null && p.count > 0)
        : [{ group: undefined, material: o.material }];
      for (const part of parts) {
        const material = result._material(part.material, g);
        const mesh = new TessellatedMesh(o, material, part.group === undefined ? meshOptions : { ...meshOptions, group: part.group });
        mesh.visible = visible;
        mesh.renderOrder = o.renderOrder;
        mesh.layers.mask = layers;
        mesh.frustumCulled = o.frustumCulled;
        result._add(o, mesh, { visible, layers });
      }
    }
  } catch (e) {
    result.dispose();
    throw e;
  }
  return result;
}

/**
 * Puts back every mesh `tessellate` replaced under `object3d` (itself included): the sources
 * visible as before in their places, the TessellatedMeshes removed and disposed, the patched
 * clones disposed. Returns how many TessellatedMeshes it removed.
 */
export function untessellate(object3d) {
  if (object3d == null || object3d.isObject3D !== true) throw new TessellaError('untessellate takes a three.js Object3D');
  const byOwner = new Map();
  object3d.traverse((o) => {
    const owner = owners.get(o);
    if (owner !== undefined) byOwner.set(owner, [...(byOwner.get(owner) ?? []), o]);
  });
  let n = 0;
  for (const [owner, meshes] of byOwner) {
    const before = owner.meshes.length;
    owner.restore(meshes);
    n += before - owner.meshes.length;
  }
  return n;
}
