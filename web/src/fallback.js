// The viewer where WebGPU is missing, drawn by gl.js with WebGL2. It answers the same calls as
// the engine's WebViewer (crates/tessella-viewer's JS contract) so the page drives both alike.
//
// At a whole level on the grid (lod fixed) it draws as the engine does: the npm package's
// InstancedSurface gives the refinement pattern and the GLSL that evaluates it, uploaded once;
// the engine's GPU-less WebCoarseViewer (pkg/, the same Rust as the WebGPU engine) loads the
// file, takes the parameters, tags, dragged vertices and the `animate`/clip poses, and hands
// each frame's control nets, which are all a frame uploads (a texture of O(coarse triangles)).
// Other levels (lod, tessellator spacings, fractional levels) are refined on the CPU by the npm
// package and uploaded whole when they change; deformation, tags and clips need the instanced
// path. Displacement lives in the WebGPU engine alone and is refused with a message; so is all
// of the above when the site was built without the engine.
import { InstancedSurface, ready, readMesh, refine, sceneCamera, writeMesh } from 'tessella';
import { toGlClip, project } from './camera.js';
import { checkParams, DEFAULTS, ENGINE_KEYS } from './params.js';
import { GlRenderer, meshArrays } from './gl.js';
import { GAP, panelWidths } from './panels.js';

/** Refined triangles the fallback draws at most (CPU refinement and a static buffer each change). */
export const MAX_TRIANGLES = 4_000_000;
/** Off values of what needs the coarse viewer and the instanced path. */
const MOTION = {
  animate: 'none',
  clip: 'none',
  tags: '',
};

/** The engine's GPU-less coarse viewer, or null when the site has no engine (or it fails to load). */
async function coarseViewer() {
  try {
    const r = await fetch('build.json');
    if (!r.ok || (await r.json()).engine !== true) return null;
  } catch {
    return null;
  }
  const engine = await import('../pkg/tessella_viewer.js');
  await engine.default();
  return new engine.WebCoarseViewer();
}

/** Whether `params` draw one whole level on the grid: the instanced pattern. */
function instanced(params) {
  return params.lod === 'fixed' && params.spacing === 'grid' && Number.isInteger(Number(params.level));
}

export class FallbackViewer {
  #gl;
  /** The engine's coarse side (WebCoarseViewer), or null. */
  #coarse = null;
  /** The coarse mesh: positions, normals, indices (the rest pose). */
  #mesh = null;
  /** The positions the camera frames (the mesh as loaded). */
  #framing = null;
  /** The file last loaded, to put the coarse viewer back when drawing the next one fails. */
  #file = null;
  /** Instanced panels: { surface (InstancedSurface), faces, level }; empty for the CPU path. */
  #surfaces = [];
  #params = Object.fromEntries(ENGINE_KEYS.map((k) => [k, structuredClone(DEFAULTS[k])]));
  #size = [1, 1];
  #refined = [];
  #dirty = true;
  #uploaded = 0;
  #pendingUpload = 0;
  #frameMs = 0;
  #lastCameraKey = '';

  static async create(canvas) {
    await ready;
    const v = new FallbackViewer();
    v.#gl = new GlRenderer(canvas);
    v.#size = [canvas.width, canvas.height];
    v.#coarse = await coarseViewer();
    return v;
  }

  adapter() {
    const how = this.#surfaces.length > 0 ? 'refinement patterns instanced, nets from wasm' : 'CPU refinement in wasm';
    return `${this.#gl.adapter()} (WebGL2, ${how})`;
  }

  samples() {
    return [];
  }

  /** Reads a mesh file; on any error the previous mesh stays. */
  load(name, bytes) {
    const coarse = this.#coarse;
    if (coarse === null) {
      const mesh = readMesh(bytes, name);
      if (mesh.indices.length === 0) throw new Error(`${name} has no triangles`);
      this.#rebuild(mesh, this.#params, mesh.positions);
      this.#mesh = mesh;
      this.#framing = mesh.positions;
      return;
    }
    coarse.load(name, bytes);
    const mesh = this.#coarseMesh();
    const framing = coarse.modelPositions();
    try {
      this.#rebuild(mesh, this.#params, framing);
    } catch (e) {
      if (this.#file !== null) coarse.load(this.#file.name, this.#file.bytes);
      throw e;
    }
    this.#file = { name, bytes };
    this.#mesh = mesh;
    this.#framing = framing;
    // A new file keeps the clip only when it has one of that name (as the engine does).
    this.#params = { ...this.#params, ...this.#coarseParams() };
  }

  set(params) {
    const checked = checkParams(params);
    if ('mesh' in checked) throw new Error('mesh is loaded with load(), not set()');
    if ('displace' in checked && checked.displace !== 'none') {
      throw new Error('displace needs the WebGPU engine; this browser uses the WebGL2 fallback');
    }
    const next = { ...this.#params, ...checked };
    for (const [key, off] of Object.entries(MOTION)) {
      if (JSON.stringify(next[key]) === JSON.stringify(off)) continue;
      if (this.#coarse === null) {
        throw new Error(`${key} needs the WebGPU engine (this site was built without it); this browser uses the WebGL2 fallback`);
      }
      if (!instanced(next)) {
        throw new Error(`${key} needs a whole level on the grid with lod fixed in the WebGL2 fallback (its refinement patterns)`);
      }
    }
    const rebuild = this.#mesh !== null && this.#needsRefine(checked);
    // Nothing changes on an error: the new surfaces are made first, the coarse viewer takes
    // the values (its checks are the engine's), then the new surfaces replace the old.
    const prepared = rebuild ? this.#prepare(this.#mesh, next) : null;
    try {
      this.#coarse?.set(checked);
    } catch (e) {
      prepared?.free();
      throw e;
    }
    if (prepared) this.#commit(prepared, next);
    this.#params = { ...next, ...this.#coarseParams() };
    this.#dirty = true;
  }

  get() {
    return { ...structuredClone(this.#params), ...this.#coarseParams() };
  }

  resize(width, height) {
    if (!(width >= 1 && height >= 1)) throw new Error(`canvas size ${width}x${height} must be at least 1x1`);
    this.#size = [Math.round(width), Math.round(height)];
    this.#dirty = true;
  }

  /**
   * Draws the frame at page time `timeMs`: instanced, the coarse viewer poses the mesh (clip,
   * `animate`) and the nets that moved are uploaded; on the CPU path with a view-dependent LOD
   * the mesh is refined again first when the camera moved.
   */
  frame(timeMs = performance.now()) {
    const t0 = performance.now();
    if (this.#mesh === null) return;
    if (this.#surfaces.length > 0) {
      this.#coarse.frame(timeMs);
      this.#params.time = this.#coarse.get().time;
      this.#surfaces.forEach(({ surface }, i) => {
        if (!this.#coarse.changed(i)) return;
        this.#pendingUpload += this.#gl.setNets(i, this.#coarse.nets(i, surface.facesPerRow, surface.texelsPerFace));
      });
    } else {
      const lod = this.#params.lod;
      if ((lod.startsWith('screen:') || lod.startsWith('distance:')) && this.#cameraKey() !== this.#lastCameraKey) {
        this.#rebuild(this.#mesh, this.#params);
      }
    }
    const { viewports, cameras } = this.#layout(this.#params);
    this.#gl.draw(viewports, cameras, this.#params.wireframe);
    // What this frame sent: the nets that moved, or the refined mesh when it changed.
    this.#uploaded = this.#pendingUpload;
    this.#pendingUpload = 0;
    this.#dirty = false;
    this.#frameMs = performance.now() - t0;
  }

  needsFrame() {
    return this.#dirty;
  }

  stats() {
    const coarseTriangles = this.#mesh ? this.#mesh.indices.length / 3 : 0;
    let refinedTriangles;
    let staticBytes;
    let patternBytes = 0;
    if (this.#surfaces.length > 0) {
      refinedTriangles = this.#surfaces.reduce((n, s) => n + s.faces * s.level * s.level, 0);
      // A static welded refined mesh: V + E(N-1) + F(N-1)(N-2)/2 vertices of 24 bytes, 4-byte indices.
      const edges = this.#edgeCount();
      staticBytes = this.#surfaces.reduce((n, { faces, level: l }) => {
        const vertices = this.#mesh.positions.length / 3 + edges * (l - 1) + (faces * (l - 1) * (l - 2)) / 2;
        return n + vertices * 24 + faces * l * l * 12;
      }, 0);
      // The patterns and the nets textures.
      patternBytes = this.#gl.bytes();
    } else {
      refinedTriangles = this.#refined.reduce((n, r) => n + r.indices.length / 3, 0);
      staticBytes = this.#refined.reduce((n, r) => n + r.positions.byteLength * 2 + r.indices.byteLength, 0);
    }
    const c = this.#coarse;
    return {
      adapter: this.adapter(),
      frameMs: this.#frameMs,
      coarseTriangles,
      refinedTriangles,
      uploadedBytes: this.#uploaded,
      patternBytes,
      staticBytes,
      level: this.#params.level,
      backend: 'webgl2',
      clips: c ? c.clips() : [],
      duration: c ? c.duration() : 0,
      poseError: c ? (c.poseError() ?? null) : null,
      instanced: this.#surfaces.length > 0,
    };
  }

  #edgeCount() {
    const idx = this.#mesh.indices;
    const seen = new Set();
    const n = this.#mesh.positions.length / 3;
    for (let t = 0; t < idx.length; t += 3) {
      for (let k = 0; k < 3; k++) {
        const a = idx[t + k];
        const b = idx[t + ((k + 1) % 3)];
        seen.add(Math.min(a, b) * n + Math.max(a, b));
      }
    }
    return seen.size;
  }

  /**
   * The coarse vertex and edge under pixel (x, y): with the engine's coarse viewer its ray cast
   * (as the WebGPU engine picks); without, the vertex nearest on screen within 16 pixels and
   * its edge nearest to the pixel.
   */
  pick(x, y) {
    if (this.#mesh === null) return null;
    const { cameras, viewports } = this.#layout(this.#params);
    const panel = viewports.findIndex((v) => x >= v.x && x < v.x + v.width);
    if (panel < 0) return null;
    const v = viewports[panel];
    const vp = cameras[panel].viewProj;
    if (this.#coarse !== null) {
      // The engine's pick: a ray through the pixel cast against the coarse mesh as drawn.
      const ndc = [(2 * (x - v.x)) / v.width - 1, 1 - (2 * y) / v.height];
      return this.#coarse.pick(Float32Array.from(vp), ndc[0], ndc[1]);
    }
    const p = this.#mesh.positions;
    const screen = [];
    for (let i = 0; i < p.length / 3; i++) screen.push(project(vp, [p[3 * i], p[3 * i + 1], p[3 * i + 2]], v.width, v.height));
    const px = x - v.x;
    let best = -1;
    let bestD = 16;
    screen.forEach((s, i) => {
      if (s === null) return;
      const d = Math.hypot(s[0] - px, s[1] - y);
      if (d < bestD) [best, bestD] = [i, d];
    });
    if (best < 0) return null;
    const idx = this.#mesh.indices;
    let edge = null;
    let edgeD = Infinity;
    for (let t = 0; t < idx.length; t += 3) {
      for (let k = 0; k < 3; k++) {
        const a = idx[t + k];
        const b = idx[t + ((k + 1) % 3)];
        if (a !== best && b !== best) continue;
        const [sa, sb] = [screen[a], screen[b]];
        if (sa === null || sb === null) continue;
        const d = segmentDistance(px, y, sa, sb);
        if (d < edgeD) [edge, edgeD] = [[a, b], d];
      }
    }
    return { vertex: best, edge };
  }

  moveVertex(index, x, y, z) {
    const m = this.#mesh;
    if (m === null) throw new Error('no mesh loaded');
    if (this.#coarse !== null) {
      // The engine's move (every vertex at that position, normals as the engine keeps them).
      const before = this.#coarse.restPositions();
      this.#coarse.moveVertex(index, x, y, z);
      const moved = this.#coarseMesh();
      if (this.#surfaces.length === 0) {
        try {
          this.#rebuild(moved, this.#params);
        } catch (e) {
          this.#coarse.moveVertex(index, before[3 * index], before[3 * index + 1], before[3 * index + 2]);
          throw e;
        }
      }
      this.#mesh = moved;
      this.#dirty = true;
      return;
    }
    if (!Number.isInteger(index) || index < 0 || index >= m.positions.length / 3) {
      throw new Error(`vertex ${index} is not one of the mesh's ${m.positions.length / 3} vertices`);
    }
    if (![x, y, z].every(Number.isFinite)) throw new Error('a vertex position must be finite');
    const positions = m.positions.slice();
    positions.set([x, y, z], index * 3);
    const moved = { ...m, positions };
    this.#rebuild(moved, this.#params);
    this.#mesh = moved;
  }

  setEdgeSharpness(a, b, s) {
    this.#tagging().setEdgeSharpness(a, b, s);
    this.#params.tags = this.#coarse.get().tags;
    this.#dirty = true;
  }

  setVertexTension(v, tension, bias) {
    this.#tagging().setVertexTension(v, tension, bias);
    this.#params.tags = this.#coarse.get().tags;
    this.#dirty = true;
  }

  tagsJson() {
    return this.#coarse !== null ? this.#coarse.tagsJson() : JSON.stringify({ edges: [], vertices: [] });
  }

  /** The coarse viewer when tags can be drawn, else a thrown message why not. */
  #tagging() {
    if (this.#coarse === null) throw new Error('tags need the WebGPU engine (this site was built without it); this browser uses the WebGL2 fallback');
    if (this.#surfaces.length === 0) throw new Error('tags need a whole level on the grid with lod fixed in the WebGL2 fallback (its refinement patterns)');
    return this.#coarse;
  }

  /** The refined mesh (first panel's scheme) as GLB, welded, from the same options. */
  exportGlb() {
    if (this.#mesh === null) throw new Error('no mesh loaded');
    // Instanced: as drawn (pose, tags), refined by the engine's CPU code.
    if (this.#surfaces.length > 0) return this.#coarse.exportGlb();
    const out = refine(this.#mesh, this.#options(this.#params, this.#panelSchemes(this.#params)[0], false));
    return writeMesh(out, 'glb');
  }

  async bench() {
    throw new Error('the Figure 7 benchmark needs the WebGPU engine; this browser uses the WebGL2 fallback');
  }

  free() {
    for (const s of this.#surfaces) s.surface.free();
    this.#surfaces = [];
  }

  /** The coarse viewer's rest pose as the fallback keeps a mesh. */
  #coarseMesh() {
    const c = this.#coarse;
    return { positions: c.restPositions(), normals: c.restNormals(), indices: c.indices() };
  }

  /** What the coarse viewer holds of the parameters the page reads back (clip state, tags). */
  #coarseParams() {
    if (this.#coarse === null) return {};
    const { clip, time, playing, tags } = this.#coarse.get();
    return { clip, time, playing, tags };
  }

  #panelSchemes(params) {
    return params.panels.length > 0 ? params.panels : [params.scheme];
  }

  #needsRefine(changed) {
    return ['scheme', 'level', 'spacing', 'lod', 'alpha', 'normals', 'wireframe', 'panels'].some((k) => k in changed);
  }

  #cameraKey() {
    const p = this.#params;
    return JSON.stringify([p.yaw, p.pitch, p.zoom, p.pan, this.#size]);
  }

  #layout(params) {
    const n = this.#panelSchemes(params).length;
    const [w, h] = this.#size;
    const widths = panelWidths(w, n) ?? [w];
    let x = 0;
    const viewports = widths.map((width) => {
      const v = { x, y: 0, width, height: h };
      x += width + GAP;
      return v;
    });
    const cameras = viewports.map((v) => {
      const cam = sceneCamera(this.#framing, { ...params, width: v.width, height: v.height });
      return { ...cam, glViewProj: toGlClip(cam.viewProj) };
    });
    return { viewports, cameras };
  }

  #options(params, scheme, forDrawing) {
    const o = { scheme, level: params.level, spacing: params.spacing, alpha: params.alpha };
    if (params.normals !== 'default') o.normals = params.normals;
    if (params.lod !== 'fixed') {
      o.lod = params.lod;
      if (!params.lod.startsWith('tolerance:')) {
        // The view's camera as `tessella render` passes it to the LOD (lod_camera): eye, the
        // framed centre, the field of view; the first panel's size.
        const { viewports } = this.#layout(params);
        const cam = sceneCamera(this.#framing ?? this.#mesh.positions, { ...params, width: viewports[0].width, height: viewports[0].height });
        o.camera = [...cam.eye, ...cam.target, cam.fovY];
        o.size = [viewports[0].width, viewports[0].height];
      }
    }
    if (forDrawing && params.wireframe) {
      o.soup = true;
      o.origin = true;
    }
    return o;
  }

  // Makes `mesh`'s surfaces for `params` and uploads them; throws (leaving what is drawn
  // unchanged) when that fails or the result is too large.
  #rebuild(mesh, params, framing = this.#framing) {
    this.#commit(this.#prepare(mesh, params, framing), params);
  }

  // The surfaces of every panel, not uploaded yet: InstancedSurfaces (pattern, GLSL, nets
  // layout) at a whole grid level with the coarse viewer, else CPU refinements.
  #prepare(mesh, params, framing = this.#framing) {
    const schemes = this.#panelSchemes(params);
    if (this.#coarse !== null && instanced(params)) {
      const level = Number(params.level);
      const surfaces = [];
      try {
        for (const scheme of schemes) {
          const o = { scheme, level, alpha: params.alpha };
          if (params.normals !== 'default') o.normals = params.normals;
          surfaces.push({ surface: new InstancedSurface(mesh.indices, o), faces: mesh.indices.length / 3, level });
        }
        const triangles = schemes.length * (mesh.indices.length / 3) * level * level;
        if (triangles > MAX_TRIANGLES) {
          throw new Error(`${triangles} refined triangles are more than the WebGL2 fallback draws (${MAX_TRIANGLES}): lower the level`);
        }
      } catch (e) {
        for (const s of surfaces) s.surface.free();
        throw e;
      }
      return { mesh, surfaces, free: () => surfaces.forEach((s) => s.surface.free()) };
    }
    const saved = this.#mesh;
    const savedFraming = this.#framing;
    // #options frames these.
    this.#mesh = mesh;
    this.#framing = framing ?? mesh.positions;
    try {
      const refined = schemes.map((scheme) => refine(mesh, this.#options(params, scheme, true)));
      const triangles = refined.reduce((n, r) => n + r.indices.length / 3, 0);
      if (triangles > MAX_TRIANGLES) {
        throw new Error(
          `${triangles} refined triangles are more than the WebGL2 fallback draws (${MAX_TRIANGLES}): lower the level`,
        );
      }
      return { mesh, refined, free: () => {} };
    } finally {
      this.#mesh = saved;
      this.#framing = savedFraming;
    }
  }

  #commit(prepared, params) {
    for (const s of this.#surfaces) s.surface.free();
    this.#surfaces = [];
    this.#refined = [];
    if (prepared.surfaces) {
      this.#pendingUpload += this.#gl.uploadInstanced(
        prepared.surfaces.map(({ surface, faces }) => ({
          glsl: surface.glsl(),
          points: surface.patternPoints(),
          indices: surface.patternIndices(),
          wireframe: params.wireframe,
          faces,
          width: surface.width,
          height: surface.height,
          facesPerRow: surface.facesPerRow,
        })),
      );
      this.#surfaces = prepared.surfaces;
      // The new textures are empty: every panel's nets as they are now.
      this.#surfaces.forEach(({ surface }, i) => {
        this.#pendingUpload += this.#gl.setNets(i, this.#coarse.nets(i, surface.facesPerRow, surface.texelsPerFace));
      });
    } else {
      this.#pendingUpload += this.#gl.upload(prepared.refined.map((r) => meshArrays(r, params.wireframe)));
      this.#refined = prepared.refined;
    }
    this.#lastCameraKey = JSON.stringify([params.yaw, params.pitch, params.zoom, params.pan, this.#size]);
    this.#dirty = true;
  }
}

function segmentDistance(x, y, a, b) {
  const dx = b[0] - a[0];
  const dy = b[1] - a[1];
  const len2 = dx * dx + dy * dy;
  const t = len2 > 0 ? Math.max(0, Math.min(1, ((x - a[0]) * dx + (y - a[1]) * dy) / len2)) : 0;
  return Math.hypot(x - (a[0] + t * dx), y - (a[1] + t * dy));
}
