// The viewer where WebGPU is missing: the npm package `tessella` refines on the CPU (wasm) and
// gl.js draws the result with WebGL2. It answers the same calls as the engine's WebViewer
// (crates/tessella-viewer's JS contract) so the page drives both alike; what it cannot do
// (displacement, tags, animation, which live in the GPU engine) it refuses with a message.
import { ready, readMesh, refine, writeMesh } from 'tessella';
import { sceneCamera, toGlClip, project, FOV_Y_DEGREES } from './camera.js';
import { checkParams, DEFAULTS, ENGINE_KEYS } from './params.js';
import { GlRenderer, meshArrays } from './gl.js';
import { GAP, panelWidths } from './panels.js';

/** Refined triangles the fallback draws at most (CPU refinement and a static buffer each change). */
export const MAX_TRIANGLES = 4_000_000;
const UNSUPPORTED = {
  displace: 'none',
  animate: 'none',
  clip: 'none',
  tags: '',
};

export class FallbackViewer {
  #gl;
  #mesh = null;
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
    return v;
  }

  adapter() {
    return `${this.#gl.adapter()} (WebGL2, CPU refinement in wasm)`;
  }

  samples() {
    return [];
  }

  /** Reads a mesh file; on any error the previous mesh stays. */
  load(name, bytes) {
    const mesh = readMesh(bytes, name);
    if (mesh.indices.length === 0) throw new Error(`${name} has no triangles`);
    this.#rebuild(mesh, this.#params);
    this.#mesh = mesh;
  }

  set(params) {
    const checked = checkParams(params);
    if ('mesh' in checked) throw new Error('mesh is loaded with load(), not set()');
    for (const [key, off] of Object.entries(UNSUPPORTED)) {
      if (key in checked && JSON.stringify(checked[key]) !== JSON.stringify(off)) {
        throw new Error(`${key} needs the WebGPU engine; this browser uses the WebGL2 fallback`);
      }
    }
    const next = { ...this.#params, ...checked };
    if (this.#mesh !== null && this.#needsRefine(checked)) this.#rebuild(this.#mesh, next);
    this.#params = next;
    this.#dirty = true;
  }

  get() {
    return structuredClone(this.#params);
  }

  resize(width, height) {
    if (!(width >= 1 && height >= 1)) throw new Error(`canvas size ${width}x${height} must be at least 1x1`);
    this.#size = [Math.round(width), Math.round(height)];
    this.#dirty = true;
  }

  /** Draws; with a view-dependent LOD the mesh is refined again first when the camera moved. */
  frame() {
    const t0 = performance.now();
    if (this.#mesh === null) return;
    const lod = this.#params.lod;
    if ((lod.startsWith('screen:') || lod.startsWith('distance:')) && this.#cameraKey() !== this.#lastCameraKey) {
      this.#rebuild(this.#mesh, this.#params);
    }
    const { viewports, cameras } = this.#layout(this.#params);
    this.#gl.draw(viewports, cameras, this.#params.wireframe);
    // What this frame sent: the refined mesh when it changed since the last frame.
    this.#uploaded = this.#pendingUpload;
    this.#pendingUpload = 0;
    this.#dirty = false;
    this.#frameMs = performance.now() - t0;
  }

  needsFrame() {
    return this.#dirty;
  }

  stats() {
    const refinedTriangles = this.#refined.reduce((n, r) => n + r.indices.length / 3, 0);
    const staticBytes = this.#refined.reduce((n, r) => n + r.positions.byteLength * 2 + r.indices.byteLength, 0);
    return {
      adapter: this.adapter(),
      frameMs: this.#frameMs,
      coarseTriangles: this.#mesh ? this.#mesh.indices.length / 3 : 0,
      refinedTriangles,
      uploadedBytes: this.#uploaded,
      // No patterns here: the CPU refines, and the refined mesh is a static buffer.
      patternBytes: 0,
      staticBytes,
      level: this.#params.level,
      backend: 'webgl2',
    };
  }

  /** The coarse vertex nearest to pixel (x, y) within 16 pixels and the coarse edge nearest to it. */
  pick(x, y) {
    if (this.#mesh === null) return null;
    const { cameras, viewports } = this.#layout(this.#params);
    const panel = viewports.findIndex((v) => x >= v.x && x < v.x + v.width);
    if (panel < 0) return null;
    const v = viewports[panel];
    const vp = cameras[panel].viewProj;
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

  setEdgeSharpness() {
    throw new Error('tags need the WebGPU engine; this browser uses the WebGL2 fallback');
  }

  setVertexTension() {
    throw new Error('tags need the WebGPU engine; this browser uses the WebGL2 fallback');
  }

  tagsJson() {
    return JSON.stringify({ edges: [], vertices: [] });
  }

  /** The refined mesh (first panel's scheme) as GLB, welded, from the same options. */
  exportGlb() {
    if (this.#mesh === null) throw new Error('no mesh loaded');
    const out = refine(this.#mesh, this.#options(this.#params, this.#panelSchemes(this.#params)[0], false));
    return writeMesh(out, 'glb');
  }

  async bench() {
    throw new Error('the Figure 7 benchmark needs the WebGPU engine; this browser uses the WebGL2 fallback');
  }

  free() {}

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
      const cam = sceneCamera(this.#mesh.positions, { ...params, width: v.width, height: v.height });
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
        const cam = sceneCamera(this.#mesh.positions, { ...params, width: viewports[0].width, height: viewports[0].height });
        const target = cam.eye.map((e, k) => e + cam.forward[k] * cam.distance);
        o.camera = [...cam.eye, ...target, FOV_Y_DEGREES];
        o.size = [viewports[0].width, viewports[0].height];
      }
    }
    if (forDrawing && params.wireframe) {
      o.soup = true;
      o.origin = true;
    }
    return o;
  }

  // Refines `mesh` with `params` for every panel and uploads it; throws (leaving what is drawn
  // unchanged) when refinement fails or the result is too large.
  #rebuild(mesh, params) {
    const saved = this.#mesh;
    this.#mesh = mesh; // #options frames this mesh
    try {
      const refined = this.#panelSchemes(params).map((scheme) => refine(mesh, this.#options(params, scheme, true)));
      const triangles = refined.reduce((n, r) => n + r.indices.length / 3, 0);
      if (triangles > MAX_TRIANGLES) {
        throw new Error(
          `${triangles} refined triangles are more than the WebGL2 fallback draws (${MAX_TRIANGLES}): lower the level`,
        );
      }
      this.#pendingUpload += this.#gl.upload(refined.map((r) => meshArrays(r, params.wireframe)));
      this.#refined = refined;
      this.#lastCameraKey = JSON.stringify([params.yaw, params.pitch, params.zoom, params.pan, this.#size]);
      this.#dirty = true;
    } finally {
      this.#mesh = saved;
    }
  }
}

function segmentDistance(x, y, a, b) {
  const dx = b[0] - a[0];
  const dy = b[1] - a[1];
  const len2 = dx * dx + dy * dy;
  const t = len2 > 0 ? Math.max(0, Math.min(1, ((x - a[0]) * dx + (y - a[1]) * dy) / len2)) : 0;
  return Math.hypot(x - (a[0] + t * dx), y - (a[1] + t * dy));
}
