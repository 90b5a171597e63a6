// A small static file server for dist/, on 127.0.0.1 only, with the MIME types browsers insist
// on for module scripts (.js/.mjs) and streaming wasm compilation (.wasm). Used by `npm run
// serve` and by the tests (which start it on a free port: `serve({ port: 0 })`).
import { createServer } from 'node:http';
import { readFile, stat } from 'node:fs/promises';
import { extname, join, normalize, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

export const MIME = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.json': 'application/json',
  '.wasm': 'application/wasm',
  '.glb': 'model/gltf-binary',
  '.gltf': 'model/gltf+json',
  '.obj': 'text/plain; charset=utf-8',
  '.ply': 'application/octet-stream',
  '.stl': 'model/stl',
  '.png': 'image/png',
  '.svg': 'image/svg+xml',
  '.txt': 'text/plain; charset=utf-8',
};

export const DIST = fileURLToPath(new URL('../dist/', import.meta.url));

/** The file under `root` a request path names, or null when it would leave `root`. */
export function resolvePath(root, urlPath) {
  let path;
  try {
    path = decodeURIComponent(urlPath.split('?')[0].split('#')[0]);
  } catch {
    return null; // a malformed %-escape names no file
  }
  if (path.includes('\0')) return null;
  const full = resolve(root, '.' + normalize('/' + path));
  const base = resolve(root);
  if (full !== base && !full.startsWith(base + sep)) return null;
  return full;
}

async function handle(root, req, res) {
  if (req.method !== 'GET' && req.method !== 'HEAD') {
    res.writeHead(405, { Allow: 'GET, HEAD' }).end();
    return;
  }
  let file = resolvePath(root, req.url ?? '/');
  if (file === null) {
    res.writeHead(400).end('bad path');
    return;
  }
  try {
    if ((await stat(file)).isDirectory()) file = join(file, 'index.html');
    const body = await readFile(file);
    res.writeHead(200, {
      'Content-Type': MIME[extname(file).toLowerCase()] ?? 'application/octet-stream',
      'Content-Length': body.length,
      'Cache-Control': 'no-store',
    });
    res.end(req.method === 'HEAD' ? undefined : body);
  } catch (e) {
    const missing = e.code === 'ENOENT' || e.code === 'ENOTDIR';
    res.writeHead(missing ? 404 : 500, { 'Content-Type': 'text/plain; charset=utf-8' });
    res.end(missing ? 'not found' : `cannot read ${req.url}: ${e.message}`);
  }
}

/**
 * Serves `root` on 127.0.0.1:`port` (0: a free port). Resolves to `{ url, port, close() }`.
 */
export function serve({ root = DIST, port = 0 } = {}) {
  return new Promise((resolveServer, reject) => {
    const server = createServer((req, res) => {
      handle(root, req, res).catch((e) => {
        if (!res.headersSent) res.writeHead(500);
        res.end(String(e));
      });
    });
    server.once('error', reject);
    server.listen(port, '127.0.0.1', () => {
      const { port: actual } = server.address();
      resolveServer({
        url: `http://127.0.0.1:${actual}/`,
        port: actual,
        close: () => new Promise((done) => server.close(() => done())),
      });
    });
  });
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const args = process.argv.slice(2);
  const at = args.indexOf('--port');
  const port = at >= 0 ? Number(args[at + 1]) : 8080;
  const root = args.find((a, i) => !a.startsWith('--') && args[i - 1] !== '--port') ?? DIST;
  if (!Number.isInteger(port) || port < 0 || port > 65535) {
    console.error(`--port must be 0..65535, got ${args[at + 1]}`);
    process.exit(2);
  }
  try {
    if (!(await stat(join(root, 'index.html'))).isFile()) throw new Error('no index.html');
  } catch {
    console.error(`${root} has no index.html: run \`npm run build\` first`);
    process.exit(1);
  }
  serve({ root, port }).then(
    ({ url }) => console.log(`serving ${root} at ${url}`),
    (e) => {
      console.error(`cannot serve on 127.0.0.1:${port}: ${e.message}`);
      process.exit(1);
    },
  );
}
