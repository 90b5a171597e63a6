// Builds the two wasm files of the package from the Rust sources (crates/tessella-wasm):
// dist/simd (simd128, the hot loops vectorised) and dist/scalar (for engines without SIMD),
// each with its wasm-bindgen glue. Installs what it needs: the wasm32 target (rustup) and
// wasm-bindgen-cli at exactly the version of the `wasm-bindgen` crate in Cargo.lock.
import { execFileSync } from 'node:child_process';
import { readFileSync, rmSync, statSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const js = join(root, 'js');
const target = 'wasm32-unknown-unknown';

function run(cmd, args, env = {}) {
  console.log(`$ ${cmd} ${args.join(' ')}`);
  execFileSync(cmd, args, { cwd: root, stdio: 'inherit', env: { ...process.env, ...env } });
}

function output(cmd, args) {
  try {
    return execFileSync(cmd, args, { cwd: root, encoding: 'utf8' }).trim();
  } catch {
    return '';
  }
}

function lockedVersion(name) {
  const lock = readFileSync(join(root, 'Cargo.lock'), 'utf8');
  const m = lock.match(new RegExp(`name = "${name}"\\nversion = "([^"]+)"`));
  if (!m) throw new Error(`${name} is not in Cargo.lock`);
  return m[1];
}

if (!output('rustup', ['target', 'list', '--installed']).split('\n').includes(target)) {
  run('rustup', ['target', 'add', target]);
}
const version = lockedVersion('wasm-bindgen');
if (output('wasm-bindgen', ['--version']) !== `wasm-bindgen ${version}`) {
  // --locked first (the CLI's own lock file); if a crate it pins is missing from the registry,
  // the same CLI version resolved afresh.
  try {
    run('cargo', ['install', 'wasm-bindgen-cli', '--version', version, '--locked']);
  } catch {
    run('cargo', ['install', 'wasm-bindgen-cli', '--version', version]);
  }
}

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
