// Writes the whole static site to web/dist/:
//   dist/index.html, style.css, src/      the page
//   dist/bench.html                       the benchmark page (Figure 7)
//   dist/pkg/                             the WebGPU engine (crates/tessella-viewer/build-web.sh)
//   dist/tessella/                        the npm package `tessella` (js/), for the WebGL2 fallback
//   dist/samples/ + samples/index.json    the bundled sample meshes (samples/)
// The npm package's wasm is reused when js/dist already holds it (scripts/test.sh builds it in
// its js/ section); otherwise `npm run build` runs in js/. TESSELLA_WEB_NO_ENGINE=1 builds the
// site without the engine (the page then always uses the fallback).
import { execFileSync } from 'node:child_process';
import { cpSync, existsSync, mkdirSync, readdirSync, rmSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const web = join(dirname(fileURLToPath(import.meta.url)), '..');
const root = join(web, '..');
const dist = join(web, 'dist');
const js = join(root, 'js');

function run(cmd, args, cwd) {
  console.log(`$ (cd ${cwd}) ${cmd} ${args.join(' ')}`);
  execFileSync(cmd, args, { cwd, stdio: 'inherit' });
}

rmSync(dist, { recursive: true, force: true });
mkdirSync(dist, { recursive: true });

// The page itself.
for (const name of ['index.html', 'bench.html', 'style.css', 'src']) {
  cpSync(join(web, name), join(dist, name), { recursive: true });
}

// The engine (its own build script installs the wasm32 target and wasm-bindgen-cli).
const engineScript = join(root, 'crates', 'tessella-viewer', 'build-web.sh');
if (process.env.TESSELLA_WEB_NO_ENGINE === '1') {
  console.log('TESSELLA_WEB_NO_ENGINE=1: building without the WebGPU engine (the fallback only)');
} else if (existsSync(engineScript)) {
  run('bash', [engineScript, join(dist, 'pkg')], root);
} else {
  console.log(`${engineScript} is missing: the site is built without the WebGPU engine (the fallback only)`);
}

// The npm package for the fallback: its sources and both wasm builds, laid out as in js/ so
// its `new URL('../dist/...', import.meta.url)` finds them.
const wasmBuilt = ['simd', 'scalar'].every((v) => existsSync(join(js, 'dist', v, 'tessella_bg.wasm')));
if (!wasmBuilt) run('npm', ['run', 'build'], js);
const pkg = join(dist, 'tessella');
cpSync(join(js, 'src', 'index.js'), join(pkg, 'src', 'index.js'));
for (const v of ['simd', 'scalar']) {
  for (const f of ['tessella.js', 'tessella_bg.wasm']) {
    cpSync(join(js, 'dist', v, f), join(pkg, 'dist', v, f));
  }
}

// The samples, and a list of them for the page's menu.
const samples = readdirSync(join(root, 'samples'))
  .filter((f) => /\.(obj|ply|stl|glb|gltf)$/i.test(f))
  .sort();
for (const f of samples) cpSync(join(root, 'samples', f), join(dist, 'samples', f));
writeFileSync(join(dist, 'samples', 'index.json'), JSON.stringify(samples, null, 1) + '\n');

const engine = existsSync(join(dist, 'pkg', 'tessella_viewer.js'));
// The page reads this before importing the engine, so a site without it requests nothing missing.
writeFileSync(join(dist, 'build.json'), JSON.stringify({ engine }) + '\n');
console.log(`web/dist: page, ${samples.length} samples, fallback (tessella npm), engine ${engine ? 'pkg/' : 'missing'}`);
