// Builds the viewer's engine for the browser: crates/tessella-viewer for wasm32 (profile
// `wasm`, as the npm package), then wasm-bindgen --target web into OUT_DIR (default
// web/dist/pkg/): tessella_viewer.js + tessella_viewer_bg.wasm. Installs the wasm32 target and
// the locked wasm-bindgen-cli when missing (js/scripts/wasm-tools.js, shared with js/).
import { rmSync, statSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { ensureWasmTools, root, run, target } from '../../js/scripts/wasm-tools.js';

const out = resolve(process.argv[2] ?? join(root, 'web', 'dist', 'pkg'));
ensureWasmTools();
// Its own target folder: the wasm build's flags differ from the native one's.
const dir = join('target', 'wasm-viewer');
run('cargo', ['build', '--profile', 'wasm', '-p', 'tessella-viewer', '--target', target, '--target-dir', dir]);
rmSync(out, { recursive: true, force: true });
run('wasm-bindgen', [
  join(root, dir, target, 'wasm', 'tessella_viewer.wasm'),
  '--target', 'web', '--out-dir', out, '--out-name', 'tessella_viewer',
]);
const size = statSync(join(out, 'tessella_viewer_bg.wasm')).size;
console.log(`${out}: tessella_viewer_bg.wasm ${(size / 1024).toFixed(0)} KiB`);
