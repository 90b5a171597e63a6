// The viewer's picture against `tessella render` of the same mesh, scheme, level, camera and
// size (the CLI built by `cargo build -p tessella-cli`; TESSELLA_CLI names another binary).
// Both backends: the WebGL2 fallback (CPU refinement, the npm package's sceneCamera: the CLI's
// framing, and gl.js's shading, the one hand-kept copy of shade.wgsl, which this test pins) and the
// WebGPU engine (tessella-gpu's renderer) when dist/pkg holds it.
//
// Tolerances: the silhouettes (pixels not the white background) must overlap with IoU >= 0.98
// (anti-aliasing differs at the rim: the CLI resolves 4x MSAA into sRGB, the canvas blends in
// its own way); pixels whose colour differs by more than 48 of 255 in a channel must be under 2%
// of the silhouette's pixels (the fallback shades the CPU's normals per vertex with the CLI's
// Blinn-Phong formulas and light; what differs is interpolation and the rim).
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { DIST } from '../scripts/serve.js';
import { assertClean, capture, count, differing, iou, mask, open, readPng, start } from './harness.js';

const repo = fileURLToPath(new URL('../../', import.meta.url));
const cli = process.env.TESSELLA_CLI ?? join(repo, 'target', 'debug', 'tessella');
const MIN_IOU = 0.98;
const COLOR_THRESHOLD = 48;
const MAX_DIFFERING = 0.02;

const CASES = [
  { mesh: 'icosphere.obj', scheme: 'pn', level: 8, yaw: 30, pitch: 20, zoom: 1, size: [320, 240] },
  { mesh: 'creature.obj', scheme: 'png1', level: 6, yaw: -40, pitch: 10, zoom: 1.3, size: [300, 300] },
  { mesh: 'torus.obj', scheme: 'phong', level: 5, yaw: 75, pitch: 35, zoom: 0.9, size: [256, 200] },
  { mesh: 'tetrahedron.obj', scheme: 'flat', level: 1, yaw: 10, pitch: -15, zoom: 1, size: [240, 240] },
];

let work;
before(() => {
  if (!existsSync(cli)) throw new Error(`${cli} is missing: run \`cargo build -p tessella-cli\` first`);
  work = mkdtempSync(join(tmpdir(), 'tessella-web-'));
});
after(() => rmSync(work, { recursive: true, force: true }));

function reference(c) {
  const out = join(work, `${c.mesh}-${c.scheme}.png`);
  execFileSync(cli, [
    'render', join(repo, 'samples', c.mesh), '-o', out, '--scheme', c.scheme, '--level', String(c.level),
    '--size', `${c.size[0]}x${c.size[1]}`, '--yaw', String(c.yaw), '--pitch', String(c.pitch), '--zoom', String(c.zoom),
  ], { stdio: ['ignore', 'ignore', 'pipe'] });
  return readPng(readFileSync(out));
}

function query(c) {
  return `?mesh=samples/${c.mesh}&scheme=${c.scheme}&level=${c.level}&yaw=${c.yaw}&pitch=${c.pitch}&zoom=${c.zoom}&size=${c.size[0]}x${c.size[1]}`;
}

const engineBuilt = existsSync(join(DIST, 'pkg', 'tessella_viewer.js'));
const noEngine = process.env.TESSELLA_WEB_NO_ENGINE === '1';

for (const backend of ['webgl2', 'webgpu']) {
  const skip = backend === 'webgpu' && noEngine ? 'TESSELLA_WEB_NO_ENGINE=1: the site was built without the engine' : false;
  describe(`${backend} against tessella render`, { skip }, () => {
    let env;
    before(async () => {
      if (backend === 'webgpu' && !engineBuilt) throw new Error('dist/pkg has no engine: npm run build (or TESSELLA_WEB_NO_ENGINE=1)');
      env = await start({ webgpu: backend === 'webgpu' });
    });
    after(async () => env?.close());

    for (const c of CASES) {
      test(`${c.mesh} ${c.scheme} level ${c.level}, yaw ${c.yaw} pitch ${c.pitch} zoom ${c.zoom}`, async () => {
        const page = await open(env, query(c));
        assert.equal(await page.evaluate(() => window.viewer.backend), backend);
        const got = await capture(page);
        const want = reference(c);
        assert.deepEqual([got.width, got.height], [want.width, want.height]);
        const [a, b] = [mask(got), mask(want)];
        const overlap = iou(a, b);
        const diff = differing(got, want, COLOR_THRESHOLD) / Math.max(count(b), 1);
        console.log(`${backend} ${c.mesh} ${c.scheme}: IoU ${overlap.toFixed(4)}, differing ${(100 * diff).toFixed(2)}% of the silhouette`);
        assert.ok(count(b) > 0.05 * b.length, 'the reference picture is nearly empty');
        assert.ok(overlap >= MIN_IOU, `silhouette IoU ${overlap} < ${MIN_IOU}`);
        // The shading, beyond the silhouette: this caught the engine resolving into the
        // canvas's sRGB view, which SwiftShader leaves unencoded (tessella-viewer's present.rs).
        assert.ok(diff <= MAX_DIFFERING, `${(100 * diff).toFixed(2)}% of the pixels differ by more than ${COLOR_THRESHOLD}`);
        assertClean(assert, page);
        await page.close();
      });
    }
  });
}
