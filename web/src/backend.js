// Picks what draws: the WebGPU engine (pkg/, crates/tessella-viewer built by build-web.sh)
// where the browser gives a WebGPU device, the WebGL2 fallback otherwise. Returns the backend
// and, for the fallback, why the engine was not used (the page shows it in a banner).

async function engineBuilt() {
  try {
    const r = await fetch('build.json');
    return r.ok && (await r.json()).engine === true;
  } catch {
    return false; // no build record: treat as no engine
  }
}

/**
 * What the browser says of its WebGPU adapter ("vendor architecture device", from
 * `GPUAdapterInfo`; wgpu sees only the description, which browsers usually leave empty).
 */
function describe(info) {
  const parts = [info?.vendor, info?.architecture, info?.device, info?.description].filter((p) => p);
  return parts.length > 0 ? parts.join(' ') : 'an adapter the browser does not name';
}

/**
 * `{ core, backend: 'webgpu' | 'webgl2', reason, adapterInfo }`; `canvas` must not have a
 * context yet. `adapterInfo` (WebGPU only) is the browser's own description of its adapter.
 * With `fallback: false` there is no WebGL2 fallback: `{ core: null, backend: 'none', reason }`.
 */
export async function createBackend(canvas, { allowWebGpu = true, fallback = true } = {}) {
  let reason;
  let adapter = null;
  if (!allowWebGpu) reason = 'WebGPU was switched off (?backend=webgl2)';
  else if (!('gpu' in navigator)) reason = 'this browser has no WebGPU (navigator.gpu is missing)';
  else if (!(await engineBuilt())) reason = 'this site was built without the WebGPU engine (dist/pkg)';
  else if ((adapter = await navigator.gpu.requestAdapter().catch(() => null)) === null) reason = 'the browser offers no WebGPU adapter';
  else {
    try {
      const engine = await import('../pkg/tessella_viewer.js');
      await engine.default();
      const core = await engine.WebViewer.create(canvas);
      return { core, backend: 'webgpu', reason: null, adapterInfo: describe(adapter.info) };
    } catch (e) {
      reason = `the WebGPU engine could not start: ${e instanceof Error ? e.message : String(e)}`;
    }
  }
  if (!fallback) return { core: null, backend: 'none', reason };
  // A canvas that got a WebGPU context cannot give a WebGL2 one: draw into a fresh canvas.
  const fresh = canvas.cloneNode(false);
  canvas.replaceWith(fresh);
  const { FallbackViewer } = await import('./fallback.js');
  const core = await FallbackViewer.create(fresh);
  return { core, backend: 'webgl2', reason, canvas: fresh };
}
