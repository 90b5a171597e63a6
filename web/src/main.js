// The page: controls, pointer and keyboard input, the URL state and `window.viewer`, over
// whichever backend draws (backend.js). Every failure is a message on the page; the previous
// mesh and parameters stay in effect.
import { createBackend } from './backend.js';
import { checkParams, DEFAULTS, ENGINE_KEYS, fromSearch, toSearch } from './params.js';
import { project } from './camera.js';
import { showMessage, clearMessage, download } from './ui.js';
import { bindControls } from './controls.js';

const $ = (id) => document.getElementById(id);

window.addEventListener('error', (e) => showMessage(`error: ${e.message}`));
window.addEventListener('unhandledrejection', (e) => {
  e.preventDefault();
  showMessage(`error: ${e.reason instanceof Error ? e.reason.message : String(e.reason)}`);
});

const PAGE_KEYS = ['size', 'backend'];

/** The page's whole state: the engine's parameters plus `mesh` and the canvas `size`. */
const state = { ...structuredClone(DEFAULTS), size: 'auto' };
let core = null;
let canvas = $('canvas');
let dirty = true;
let benching = false; // viewer.bench() runs: the page draws nothing meanwhile
let coarse = null; // the coarse mesh's positions/indices as the page read them (for dragging)
let fps = { frames: 0, since: performance.now(), value: 0 };

function asError(e) {
  return e instanceof Error ? e : new Error(String(e));
}

function updateUrl() {
  const q = toSearch(state);
  const extra = new URLSearchParams(q);
  if (state.size !== 'auto') extra.set('size', state.size);
  const forced = new URLSearchParams(location.search).get('backend');
  if (forced) extra.set('backend', forced);
  const s = extra.toString();
  history.replaceState(null, '', s ? `?${s}` : location.pathname);
}

function parseSize(v) {
  if (v === 'auto') return null;
  const m = /^(\d+)x(\d+)$/.exec(String(v));
  if (!m || +m[1] < 1 || +m[2] < 1 || +m[1] > 8192 || +m[2] > 8192) {
    throw new Error(`size must be WIDTHxHEIGHT within 1x1..8192x8192 or auto, got ${JSON.stringify(String(v))}`);
  }
  return [+m[1], +m[2]];
}

function applySize() {
  const fixed = parseSize(state.size);
  const dpr = window.devicePixelRatio || 1;
  const [w, h] = fixed ?? [
    Math.max(1, Math.round(Math.min($('view').clientWidth, 1600) * dpr)),
    Math.max(1, Math.round(Math.min($('view').clientWidth, 1600) * dpr * 0.75)),
  ];
  if (canvas.width !== w || canvas.height !== h) {
    canvas.width = w;
    canvas.height = h;
  }
  canvas.style.width = `${w / dpr}px`;
  core.resize(w, h);
  dirty = true;
}

async function fetchBytes(url) {
  let response;
  try {
    response = await fetch(url);
  } catch (e) {
    throw new Error(`cannot fetch ${url}: ${asError(e).message}`);
  }
  if (!response.ok) throw new Error(`cannot fetch ${url}: HTTP ${response.status}`);
  return new Uint8Array(await response.arrayBuffer());
}

/**
 * The coarse mesh as the page keeps it for vertex dragging (read by the npm package), with the
 * package's `sceneCamera` (the framing `tessella render` and the engine use; the page passes no
 * displacement reach, so with displacement on a drag maps slightly off), to map a drag.
 */
async function readCoarse(name, bytes) {
  try {
    const { ready, readMesh, sceneCamera } = await import('tessella');
    await ready;
    const m = readMesh(bytes, name);
    return { positions: Float32Array.from(m.positions), indices: m.indices, sceneCamera };
  } catch {
    return null; // only dragging needs it; the backend's own error is what the page shows
  }
}

/** Loads a mesh from a URL (a sample's path too) or a File; the previous one stays on error. */
async function load(source) {
  const isFile = typeof File !== 'undefined' && source instanceof File;
  const name = isFile ? source.name : String(source).split(/[?#]/)[0].split('/').pop();
  try {
    const bytes = isFile ? new Uint8Array(await source.arrayBuffer()) : await fetchBytes(String(source));
    core.load(name, bytes);
    coarse = await readCoarse(name, bytes);
    state.mesh = isFile ? name : String(source);
    syncClip();
    dirty = true;
    clearMessage();
    updateUrl();
    controls.refresh();
  } catch (e) {
    const err = asError(e);
    showMessage(`cannot open ${name}: ${err.message} (the previous mesh stays)`);
    throw err;
  }
}

/** The clip state as the engine has it (a new file may not have the clip that played). */
function syncClip() {
  const p = core.get();
  if (p.clip === undefined) return; // the WebGL2 fallback plays no clips
  state.clip = p.clip;
  state.time = p.time;
  state.playing = p.playing;
}

/** Sets parameters (URL names); all are checked first and nothing changes on an error. */
async function set(params) {
  try {
    const { mesh, size, ...rest } = params;
    if (size !== undefined) parseSize(size);
    const checked = checkParams(rest);
    // Pausing keeps the time the engine is at (it moves while the clip plays).
    if (checked.playing === false && checked.time === undefined && state.playing) syncClip();
    if (Object.keys(checked).length > 0) core.set(checked);
    Object.assign(state, checked);
    if (size !== undefined) {
      state.size = String(size);
      applySize();
    }
    dirty = true;
    updateUrl();
    controls.refresh();
    if (mesh !== undefined && mesh !== state.mesh) await load(mesh);
    else clearMessage();
  } catch (e) {
    const err = asError(e);
    showMessage(err.message);
    controls.refresh();
    throw err;
  }
}

function drawFrame(time) {
  core.frame(time);
  dirty = false;
  fps.frames++;
  const now = performance.now();
  if (now - fps.since > 500) {
    fps = { frames: 0, since: now, value: (fps.frames * 1000) / (now - fps.since) };
  }
}

function loop(time) {
  try {
    const playing = state.clip !== 'none' && state.playing;
    const moving = !benching && (state.animate !== 'none' || playing || dirty);
    if (moving) drawFrame(time);
    if (playing) controls.showTime(core.get().time);
  } catch (e) {
    showMessage(`drawing failed: ${asError(e).message}`);
    dirty = false;
  }
  requestAnimationFrame(loop);
}

function stats() {
  return { ...core.stats(), fps: fps.value, backend: viewer.backend };
}

async function capture() {
  drawFrame(performance.now());
  // toBlob takes its snapshot now, in the task that drew the frame.
  const blob = await new Promise((resolve) => canvas.toBlob(resolve, 'image/png'));
  if (!blob) throw new Error('the canvas could not be encoded as PNG');
  return new Uint8Array(await blob.arrayBuffer());
}

// --- pointer, wheel, keys ---------------------------------------------------------------

const pointers = new Map();
let drag = null;

function pixel(e) {
  const r = canvas.getBoundingClientRect();
  return [((e.clientX - r.left) * canvas.width) / r.width, ((e.clientY - r.top) * canvas.height) / r.height];
}

function orbit(dx, dy) {
  const pitch = Math.max(-89, Math.min(89, state.pitch + dy * 0.4));
  set({ yaw: state.yaw - dx * 0.4, pitch }).catch(() => {});
}

function pan(dx, dy) {
  const k = 2 / canvas.clientHeight / state.zoom;
  set({ pan: [state.pan[0] - dx * k, state.pan[1] + dy * k] }).catch(() => {});
}

function zoomBy(f) {
  set({ zoom: Math.max(0.05, Math.min(200, state.zoom * f)) }).catch(() => {});
}

function startVertexDrag(e) {
  const [x, y] = pixel(e);
  const hit = core.pick(x, y);
  if (!hit || !coarse) return false;
  drag = { vertex: hit.vertex };
  return true;
}

function moveDraggedVertex(e) {
  const i = drag.vertex;
  const p = coarse.positions;
  const cam = coarse.sceneCamera(p, { ...state, width: canvas.width, height: canvas.height });
  const at = [p[3 * i], p[3 * i + 1], p[3 * i + 2]];
  const s = project(cam.viewProj, at, canvas.width, canvas.height);
  if (!s) return;
  const [x, y] = pixel(e);
  // World units per pixel at the vertex's depth.
  const depth = (at[0] - cam.eye[0]) * cam.forward[0] + (at[1] - cam.eye[1]) * cam.forward[1] + (at[2] - cam.eye[2]) * cam.forward[2];
  const perPixel = (2 * depth * Math.tan((cam.fovY * Math.PI) / 360)) / canvas.height;
  const dx = (x - s[0]) * perPixel;
  const dy = -(y - s[1]) * perPixel;
  const to = at.map((c, k) => c + cam.right[k] * dx + cam.up[k] * dy);
  core.moveVertex(i, to[0], to[1], to[2]);
  p.set(to, 3 * i);
  dirty = true;
}

async function pickTag(e, tool) {
  const [x, y] = pixel(e);
  const hit = core.pick(x, y);
  if (!hit) return;
  controls.editTag(tool === 'edge' ? { edge: hit.edge } : { vertex: hit.vertex });
}

function bindPointer() {
  const view = $('view');
  view.addEventListener('pointerdown', (e) => {
    view.focus();
    canvas.setPointerCapture?.(e.pointerId);
    pointers.set(e.pointerId, [e.clientX, e.clientY]);
    const tool = $('tool').value;
    try {
      if (tool === 'drag' && pointers.size === 1) startVertexDrag(e);
      else if ((tool === 'edge' || tool === 'vertex') && pointers.size === 1) pickTag(e, tool).catch((err) => showMessage(asError(err).message));
    } catch (err) {
      showMessage(asError(err).message);
    }
  });
  view.addEventListener('pointermove', (e) => {
    const last = pointers.get(e.pointerId);
    if (!last) return;
    const [dx, dy] = [e.clientX - last[0], e.clientY - last[1]];
    if (drag) {
      try {
        moveDraggedVertex(e);
      } catch (err) {
        showMessage(asError(err).message);
        drag = null;
      }
    } else if (pointers.size === 2) {
      const [a, b] = [...pointers.values()];
      const before = Math.hypot(a[0] - b[0], a[1] - b[1]);
      pointers.set(e.pointerId, [e.clientX, e.clientY]);
      const [c, d] = [...pointers.values()];
      const after = Math.hypot(c[0] - d[0], c[1] - d[1]);
      if (before > 0 && after > 0) zoomBy(after / before);
      pan(dx / 2, dy / 2);
      return;
    } else if ($('tool').value === 'orbit' || pointers.size === 1) {
      if (e.shiftKey || e.buttons === 4 || e.buttons === 2) pan(dx, dy);
      else orbit(dx, dy);
    }
    pointers.set(e.pointerId, [e.clientX, e.clientY]);
  });
  const end = (e) => {
    pointers.delete(e.pointerId);
    if (pointers.size === 0) drag = null;
  };
  view.addEventListener('pointerup', end);
  view.addEventListener('pointercancel', end);
  view.addEventListener('contextmenu', (e) => e.preventDefault());
  view.addEventListener(
    'wheel',
    (e) => {
      e.preventDefault();
      zoomBy(Math.exp(-e.deltaY * 0.001));
    },
    { passive: false },
  );
  view.addEventListener('keydown', (e) => {
    const step = e.shiftKey ? 20 : 5;
    const keys = {
      ArrowLeft: () => (e.altKey ? pan(-step * 4, 0) : orbit(-step / 0.4, 0)),
      ArrowRight: () => (e.altKey ? pan(step * 4, 0) : orbit(step / 0.4, 0)),
      ArrowUp: () => (e.altKey ? pan(0, -step * 4) : orbit(0, -step / 0.4)),
      ArrowDown: () => (e.altKey ? pan(0, step * 4) : orbit(0, step / 0.4)),
      '+': () => zoomBy(1.1),
      '=': () => zoomBy(1.1),
      '-': () => zoomBy(1 / 1.1),
      w: () => set({ wireframe: !state.wireframe }).catch(() => {}),
    };
    if (keys[e.key]) {
      e.preventDefault();
      keys[e.key]();
    }
  });
  // Drag and drop of a mesh file.
  view.addEventListener('dragover', (e) => {
    e.preventDefault();
    $('drop').hidden = false;
  });
  view.addEventListener('dragleave', () => ($('drop').hidden = true));
  view.addEventListener('drop', (e) => {
    e.preventDefault();
    $('drop').hidden = true;
    const file = e.dataTransfer?.files?.[0];
    if (file) load(file).catch(() => {});
  });
}

// --- start ------------------------------------------------------------------------------

const viewer = {
  backend: null,
  set,
  load,
  stats,
  capture,
  get: () => structuredClone(state),
  pick: (x, y) => core.pick(x, y),
  moveVertex: (i, x, y, z) => {
    core.moveVertex(i, x, y, z);
    if (coarse) coarse.positions.set([x, y, z], 3 * i);
    dirty = true;
  },
  setEdgeSharpness: (a, b, sharpness) => {
    core.setEdgeSharpness(a, b, sharpness);
    state.tags = core.tagsJson();
    dirty = true;
    updateUrl();
  },
  setVertexTension: (v, tension, bias) => {
    core.setVertexTension(v, tension, bias);
    state.tags = core.tagsJson();
    dirty = true;
    updateUrl();
  },
  tagsJson: () => core.tagsJson(),
  exportGlb: () => core.exportGlb(),
  bench: async (config) => {
    if (typeof core.bench !== 'function') throw new Error('this engine has no Figure 7 benchmark');
    // The page's own frames would share the GPU with the timed ones: none while it runs.
    benching = true;
    try {
      return await core.bench(config);
    } finally {
      benching = false;
      dirty = true;
    }
  },
};
window.viewer = viewer;

const controls = bindControls({
  state,
  set: (p) => set(p).catch(() => {}),
  load: (s) => load(s).catch(() => {}),
  getCore: () => core,
  capture,
});

async function start() {
  const query = fromSearch(location.search);
  const { core: c, backend, reason, canvas: fresh, adapterInfo } = await createBackend(canvas, {
    allowWebGpu: query.backend !== 'webgl2',
  });
  core = c;
  if (fresh) canvas = fresh;
  viewer.backend = backend;
  $('backend').textContent = backend === 'webgpu' ? 'WebGPU' : 'WebGL2 fallback';
  $('backend').className = `badge ${backend}`;
  $('adapter').textContent = adapterInfo ? `${core.adapter()}: ${adapterInfo}` : core.adapter();
  if (reason) {
    $('banner').hidden = false;
    $('banner').textContent = `Drawing with the WebGL2 fallback: ${reason}. Displacement needs WebGPU.`;
  }
  bindPointer();
  // Resizing the canvas inside the observer's callback changes the observed layout again
  // (the browser reports a "ResizeObserver loop" error): resize on the next frame instead, if
  // the size is still 'auto' then (the first callback comes before the URL's size is read: a
  // fixed size must not get a second, spurious frame).
  new ResizeObserver(() => {
    if (state.size === 'auto') requestAnimationFrame(() => {
      if (state.size === 'auto') applySize();
    });
  }).observe($('view'));
  await controls.fillSamples();

  // The URL's state: the page's own keys, then the engine's (a bad one is reported, the rest kept).
  const { mesh = DEFAULTS.mesh, size = 'auto', clip, time, playing, ...params } = query;
  for (const k of PAGE_KEYS) delete params[k];
  try {
    parseSize(size);
    state.size = size;
  } catch (e) {
    showMessage(asError(e).message);
  }
  applySize();
  // The page's defaults, whatever the engine's own are; then the URL's values one by one.
  core.set(Object.fromEntries(ENGINE_KEYS.map((k) => [k, state[k]])));
  for (const [key, value] of Object.entries(params)) {
    await set({ [key]: value }).catch(() => {});
  }
  const problem = $('message').hidden ? null : $('message').textContent;
  await load(mesh).catch(() => {});
  // A clip names one of the loaded file's: set after the load. A given time opens paused there.
  if (clip !== undefined) {
    const at = time === undefined ? {} : { time, playing: false };
    await set({ clip, ...at, ...(playing === undefined ? {} : { playing }) }).catch(() => {});
  }
  if (problem && $('message').hidden) showMessage(problem);
  // The first picture is drawn before `ready` resolves, so stats() then describe a drawn frame.
  try {
    drawFrame(performance.now());
  } catch (e) {
    showMessage(`drawing failed: ${asError(e).message}`);
  }
  requestAnimationFrame(loop);
}

viewer.ready = start().catch((e) => {
  showMessage(`the viewer could not start: ${asError(e).message}`);
  throw e;
});
