// The benchmark page: GMR's Figure 7, the PNG1 paper's scheme table and levels moving every
// frame, run by the WebGPU engine's bench() on this browser's device. The form's fields (and
// the same names in the URL: ?faces=10,100&levels=8,16&frames=3&run=1) are bench()'s
// configuration; the report shows as tables and as JSON, and is `window.bench.report`.
import { createBackend } from './backend.js';
import { showMessage, clearMessage, download } from './ui.js';

const $ = (id) => document.getElementById(id);
const form = $('config');
const LISTS = ['faces', 'levels', 'schemeFaces', 'schemeLevels'];

/** The form as bench()'s configuration; a malformed field throws, naming it. */
function readConfig() {
  const field = (name) => form.elements[name].value.trim();
  const integer = (name, text) => {
    const n = Number(text.trim());
    if (text.trim() === '' || !Number.isInteger(n)) throw new Error(`bench: ${name}: ${JSON.stringify(field(name))} is not a whole number or a list of them`);
    return n;
  };
  const numbers = (name) => field(name).split(',').map((t) => integer(name, t));
  const size = /^(\d+)x(\d+)$/.exec(field('size'));
  if (!size) throw new Error(`bench: size: ${JSON.stringify(field('size'))} is not WIDTHxHEIGHT`);
  const movingTop = Number(field('movingTop'));
  if (field('movingTop') === '' || !Number.isFinite(movingTop)) throw new Error(`bench: movingTop: ${JSON.stringify(field('movingTop'))} is not a number`);
  const config = {
    frames: integer('frames', field('frames')),
    size: [+size[1], +size[2]],
    scheme: field('scheme'),
    movingTop,
    parts: field('parts').split(',').map((p) => p.trim()).filter(Boolean),
  };
  for (const name of LISTS) config[name] = numbers(name);
  return config;
}

/** The report's Markdown (headings, pipe tables, lines) as DOM nodes, text set as text. */
function renderMarkdown(markdown) {
  const out = document.createDocumentFragment();
  let table = null;
  for (const line of markdown.split('\n')) {
    if (line.startsWith('|')) {
      const cells = line.slice(1, -1).split('|').map((c) => c.trim());
      if (cells.every((c) => /^-+:?$/.test(c))) continue; // the rule under the header
      const header = table === null;
      if (header) table = out.appendChild(document.createElement('table'));
      const row = table.appendChild(document.createElement('tr'));
      for (const c of cells) {
        const cell = row.appendChild(document.createElement(header ? 'th' : 'td'));
        cell.textContent = c;
        if (!header && /^[\d.]+(x|%)?$|^—$/.test(c)) cell.className = 'num';
      }
      continue;
    }
    table = null;
    if (line.startsWith('## ')) out.appendChild(document.createElement('h2')).textContent = line.slice(3);
    else if (line.trim()) out.appendChild(document.createElement('p')).textContent = line;
  }
  return out;
}

let core = null;
let adapterInfo = null;
let running = false;

/** Runs bench() with `config` (default: the form's); the outcome is shown on the page too. */
async function run(config) {
  if (!core) throw new Error('the benchmark needs the WebGPU engine, which did not start');
  if (running) throw new Error('a benchmark is running already');
  running = true;
  $('run').disabled = true;
  $('status').textContent = 'running… (each frame is awaited; this can take minutes on a CPU adapter)';
  const start = performance.now();
  try {
    const report = await core.bench(config ?? readConfig());
    // wgpu sees only the adapter's description, which browsers usually leave empty.
    report.browserAdapter = adapterInfo;
    report.markdown = `Browser's adapter: ${adapterInfo}\n\n${report.markdown}`;
    bench.report = report;
    $('tables').replaceChildren(renderMarkdown(report.markdown));
    $('json').textContent = JSON.stringify(report, null, 1);
    $('save').disabled = false;
    $('status').textContent = `done in ${((performance.now() - start) / 1000).toFixed(1)} s on ${report.adapter}, ${adapterInfo}`;
    clearMessage();
    return report;
  } catch (e) {
    const message = e instanceof Error ? e.message : String(e);
    $('status').textContent = 'failed';
    showMessage(message);
    throw e;
  } finally {
    running = false;
    $('run').disabled = false;
  }
}

const bench = { ready: null, run, report: null };
window.bench = bench;

async function start() {
  const query = new URLSearchParams(location.search);
  for (const [k, v] of query) {
    const input = form.elements.namedItem(k);
    if (input instanceof HTMLInputElement) input.value = v;
  }
  // The engine opens its device for a canvas; nothing is drawn on it here.
  const canvas = document.createElement('canvas');
  canvas.width = canvas.height = 8;
  canvas.hidden = true;
  document.body.appendChild(canvas);
  const made = await createBackend(canvas, { fallback: false });
  $('backend').textContent = made.backend === 'webgpu' ? 'WebGPU' : 'no WebGPU';
  $('backend').className = `badge ${made.backend}`;
  if (made.backend !== 'webgpu') {
    $('status').textContent = '';
    showMessage(`the benchmark needs the WebGPU engine: ${made.reason}`);
    return;
  }
  core = made.core;
  adapterInfo = made.adapterInfo;
  $('adapter').textContent = `${core.adapter()}: ${adapterInfo}`;
  $('status').textContent = 'ready';
  $('run').disabled = false;
  form.addEventListener('submit', (e) => {
    e.preventDefault();
    run().catch(() => {}); // shown on the page by run()
  });
  $('save').addEventListener('click', () => {
    if (bench.report) download('tessella-bench.json', JSON.stringify(bench.report, null, 1), 'application/json');
  });
  if (query.get('run') === '1') await run().catch(() => {});
}

bench.ready = start().catch((e) => {
  showMessage(`the benchmark page could not start: ${e instanceof Error ? e.message : String(e)}`);
  throw e;
});
