// What every wasm build of the workspace needs, shared by js/scripts/build.js (the npm
// package) and crates/tessella-viewer/build-web.mjs (the viewer's engine): the wasm32 target
// (rustup) and wasm-bindgen-cli at exactly the version of the `wasm-bindgen` crate in
// Cargo.lock, installed when missing.
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

export const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
export const target = 'wasm32-unknown-unknown';

export function run(cmd, args, env = {}) {
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

export function lockedVersion(name) {
  const lock = readFileSync(join(root, 'Cargo.lock'), 'utf8');
  const m = lock.match(new RegExp(`name = "${name}"\\nversion = "([^"]+)"`));
  if (!m) throw new Error(`${name} is not in Cargo.lock`);
  return m[1];
}

export function ensureWasmTools() {
  if (!output('rustup', ['target', 'list', '--installed']).split('\n').includes(target)) {
    run('rustup', ['target', 'add', target]);
  }
  const version = lockedVersion('wasm-bindgen');
  if (output('wasm-bindgen', ['--version']) !== `wasm-bindgen ${version}`) {
    // --locked first (the CLI's own lock file); if a crate it pins is missing from the
    // registry, the same CLI version resolved afresh.
    try {
      run('cargo', ['install', 'wasm-bindgen-cli', '--version', version, '--locked']);
    } catch {
      run('cargo', ['install', 'wasm-bindgen-cli', '--version', version]);
    }
  }
}
