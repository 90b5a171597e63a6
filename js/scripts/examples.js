// Serves the repository (the examples at /js/examples/, three from js/node_modules, the package
// from js/src and js/dist, the bundled samples) on 127.0.0.1: `npm run examples [-- --port N]`.
// Build the package first (`npm run build`).
import { existsSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { serve } from '../../web/scripts/serve.js';

const root = fileURLToPath(new URL('../../', import.meta.url));
const at = process.argv.indexOf('--port');
const port = at >= 0 ? Number(process.argv[at + 1]) : 8090;
if (!Number.isInteger(port) || port < 0 || port > 65535) {
  console.error(`--port must be 0..65535, got ${process.argv[at + 1]}`);
  process.exit(2);
}
for (const need of ['js/dist/simd/tessella_bg.wasm', 'js/node_modules/three/build/three.module.js']) {
  if (!existsSync(root + need)) {
    console.error(`${need} is missing: run \`npm ci && npm run build\` in js/ first`);
    process.exit(1);
  }
}
serve({ root, port }).then(
  ({ url }) => console.log(`the examples: ${url}js/examples/`),
  (e) => {
    console.error(`cannot serve on 127.0.0.1:${port}: ${e.message}`);
    process.exit(1);
  },
);
