// Builds the two wasm files of the package from the Rust sources (crates/tessella-wasm):
// dist/simd (simd128, the hot loops vectorised) and dist/scalar (for engines without SIMD),
// each with its wasm-bindgen glue. Installs what it needs: the wasm32 target (rustup) and
// wasm-bindgen-cli at exactly the version of the `wasm-bindgen` crate in Cargo.lock.
import { rmSync, statSync } from 'node:fs';
import { join } from 'node:path';
import { ensureWasmTools, root, run, target } from './wasm-tools.js';

const js = join(root, 'js');

ensureWasmTools();

for (const [variant, features] of [['simd', '+simd128'], ['scalar', '-simd128']]) {
  // One target folder per variant: RUSTFLAGS differ, and sharing one would rebuild each time.
  const dir = join('target', `wasm-${variant}`);
  // Profile `wasm` (Cargo.toml): release without cross-crate LTO, more codegen units.
  run('cargo', ['build', '--profile', 'wasm', '-p', 'tessella-wasm', '--target', target, '--target-dir', dir], {
    RUSTFLAGS: `-C target-feature=${features}`,
  });
  const out = join(js, 'dist', variant);
  rmSync(out, { recursive: true, force: true });
  run('wasm-bindgen', [
    join(dir, target, 'wasm', 'tessella_wasm.wasm'),
    '--target', 'web', '--out-dir', out, '--out-name', 'tessella', '--no-typescript',
  ]);
  const size = statSync(join(out, 'tessella_bg.wasm')).size;
  console.log(`${variant}: ${(size / 1024).toFixed(0)} KiB`);
}
