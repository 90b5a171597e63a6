// `tessella refine`'s glTF scene output read by three.js in headless Chromium (WebGL2 on
// SwiftShader): the bundled scene.glb (textured, two materials, lines and points, camera, light,
// clips) and animated-creature.glb (skinned, morph targets, clips), refined at level 4 by the CLI
// (`cargo build -p tessella-cli`; TESSELLA_CLI names another binary), load in three's
// GLTFLoader without an error or warning, their textures decode, the scene graph has what the
// input's has (meshes, skinned meshes, lines, points, materials, textures, animations, cameras,
// lights, morph targets) and every triangle primitive has 16x the input's triangles. The refined
// creature posed by three's AnimationMixer and skinned on the CPU (getVertexPosition) lies
// within 3% of the bounding box's diagonal of `tessella refine --clip NAME --time T` (pose the
// coarse mesh, then refine) at each vertex. The page is web/test/three/index.html?page=gltf
// (three/gltf.js), served from the repository with three from js/node_modules: build js/ first
// (`cd js && npm ci && npm run build`; the harness checks for its wasm).
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { openRepoPage, REPO } from './harness.js';

const cli = process.env.TESSELLA_CLI ?? join(REPO, 'target', 'debug', 'tessella');
const LEVEL = 4;
/** The largest distance allowed between three's pose and the CLI's, as a share of the box's diagonal. */
const MAX_POSE_DISTANCE = 0.03;

let work;
let three;
before(async () => {
  if (!existsSync(cli)) throw new Error(`${cli} is missing: run \`cargo build -p tessella-cli\` first`);
  work = mkdtempSync(join(tmpdir(), 'tessella-gltf-'));
  three = await openRepoPage('web/test/three/index.html?page=gltf', { global: 'tessellaGltf' });
});
after(async () => {
  await three?.close();
  if (work) rmSync(work, { recursive: true, force: true });
});

/** Runs `tessella refine` with `args` after the input and output; returns the output's path. */
function refine(input, output, args = []) {
  const out = join(work, output);
  execFileSync(cli, ['refine', join(REPO, input), '-o', out, '--level', String(LEVEL), ...args], { stdio: ['ignore', 'ignore', 'pipe'] });
  return out;
}

const b64 = (path) => readFileSync(path).toString('base64');
const call = (name, arg) => three.page.evaluate(([n, a]) => window.tessellaGltf[n](a), [name, arg]);

function floats(base64) {
  const b = Buffer.from(base64, 'base64');
  return new Float32Array(b.buffer, b.byteOffset, b.byteLength / 4);
}

/** A PLY file's vertex positions (ASCII or binary little endian; x, y, z among its properties). */
function readPlyPositions(path) {
  const data = readFileSync(path);
  const end = data.indexOf('end_header\n');
  assert.ok(end > 0, `${path}: no PLY header`);
  const header = data.subarray(0, end).toString('latin1').split('\n');
  const format = header.find((l) => l.startsWith('format')).split(/\s+/)[1];
  const sizes = { char: 1, uchar: 1, int8: 1, uint8: 1, short: 2, ushort: 2, int16: 2, uint16: 2, int: 4, uint: 4, int32: 4, uint32: 4, float: 4, float32: 4, double: 8, float64: 8 };
  let count = 0;
  const props = [];
  let inVertex = false;
  for (const l of header) {
    const w = l.trim().split(/\s+/);
    if (w[0] === 'element') {
      if (inVertex) break; // the vertex element is taken to come first, as tessella writes it
      inVertex = w[1] === 'vertex';
      if (inVertex) count = Number(w[2]);
    } else if (w[0] === 'property' && inVertex) {
      assert.notEqual(w[1], 'list', 'a list property on vertices');
      props.push({ type: w[1], name: w[2] });
    }
  }
  const at = ['x', 'y', 'z'].map((n) => props.findIndex((p) => p.name === n));
  assert.ok(at.every((i) => i >= 0), `${path}: no x, y, z`);
  const out = new Float64Array(3 * count);
  const body = end + 'end_header\n'.length;
  if (format === 'ascii') {
    const lines = data.subarray(body).toString('latin1').split('\n');
    for (let v = 0; v < count; v++) {
      const w = lines[v].trim().split(/\s+/).map(Number);
      for (let k = 0; k < 3; k++) out[3 * v + k] = w[at[k]];
    }
    return out;
  }
  assert.equal(format, 'binary_little_endian', `${path}: ${format}`);
  const offsets = [];
  let stride = 0;
  for (const p of props) {
    offsets.push(stride);
    stride += sizes[p.type];
  }
  const view = new DataView(data.buffer, data.byteOffset + body);
  const get = { float: 'getFloat32', float32: 'getFloat32', double: 'getFloat64', float64: 'getFloat64' };
  for (let v = 0; v < count; v++) {
    for (let k = 0; k < 3; k++) out[3 * v + k] = view[get[props[at[k]].type]](v * stride + offsets[at[k]], true);
  }
  return out;
}

function diagonal(p) {
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < p.length; i += 3) {
    for (let k = 0; k < 3; k++) {
      lo[k] = Math.min(lo[k], p[i + k]);
      hi[k] = Math.max(hi[k], p[i + k]);
    }
  }
  return Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

/** Largest and mean distance between vertex i of `a` and vertex i of `b`. */
function pairwise(a, b) {
  let max = 0;
  let sum = 0;
  for (let i = 0; i < a.length; i += 3) {
    const d = Math.hypot(a[i] - b[i], a[i + 1] - b[i + 1], a[i + 2] - b[i + 2]);
    max = Math.max(max, d);
    sum += d;
  }
  return { max, mean: sum / (a.length / 3) };
}

/** Largest distance from a vertex of `a` to the nearest vertex of `b` (brute force). */
function nearest(a, b) {
  let max = 0;
  for (let i = 0; i < a.length; i += 3) {
    let best = Infinity;
    for (let j = 0; j < b.length; j += 3) {
      const d = (a[i] - b[j]) ** 2 + (a[i + 1] - b[j + 1]) ** 2 + (a[i + 2] - b[j + 2]) ** 2;
      if (d < best) best = d;
    }
    max = Math.max(max, best);
  }
  return Math.sqrt(max);
}

const pct = (x) => `${(100 * x).toPrecision(3)}%`;
const num = (x) => x.toPrecision(3);

for (const sample of ['scene.glb', 'animated-creature.glb']) {
  test(`${sample} refined at level ${LEVEL} loads in GLTFLoader with what the input has, and 16x the triangles`, async () => {
    const out = refine(`samples/${sample}`, `${sample}-l${LEVEL}.glb`);
    const input = await call('describe', { glb: b64(join(REPO, 'samples', sample)) });
    const output = await call('describe', { glb: b64(out) });
    const summary = (d) => `${d.meshes} meshes (${d.skinned} skinned), ${d.lines} lines, ${d.points} points, materials [${d.materials}], ${d.textures.length} textures, animations [${d.animations.map((a) => a.name)}], ${d.cameras} cameras, ${d.lights} lights`;
    console.log(`${sample} input: ${summary(input)}`);
    console.log(`${sample} level ${LEVEL}: ${summary(output)}`);
    for (const key of ['meshes', 'skinned', 'lines', 'points', 'cameras', 'lights', 'materials']) {
      assert.deepEqual(output[key], input[key], `${sample}: ${key}`);
    }
    assert.deepEqual(output.animations, input.animations, `${sample}: animations (name, duration, tracks)`);
    assert.equal(output.textures.length, input.textures.length, `${sample}: textures`);
    for (const [i, t] of output.textures.entries()) {
      console.log(`${sample} level ${LEVEL}: texture ${t.name || i} (${t.slots}) decoded ${t.width} x ${t.height}, ${t.colours} colours on a 16 x 16 sample`);
      assert.ok(t.width > 0 && t.height > 0, `${sample}: texture ${i} did not decode`);
      assert.deepEqual(t.slots, input.textures[i].slots, `${sample}: texture ${i}'s slots`);
      assert.equal(t.width, input.textures[i].width);
      assert.equal(t.height, input.textures[i].height);
      assert.ok(t.colours >= 2, `${sample}: texture ${i} is one colour`);
    }
    assert.equal(output.objects.length, input.objects.length);
    for (const [i, a] of input.objects.entries()) {
      const b = output.objects[i];
      const what = `${sample}: ${a.type} ${a.name} (${a.material})`;
      assert.deepEqual([b.name, b.type, b.material], [a.name, a.type, a.material], what);
      assert.deepEqual(b.attributes, a.attributes, `${what}: attributes`);
      assert.equal(b.morphTargets, a.morphTargets, `${what}: morph targets`);
      if (a.triangles !== null) {
        console.log(`${what}: ${a.triangles} -> ${b.triangles} triangles (${b.triangles / a.triangles}x), ${a.vertices} -> ${b.vertices} vertices`);
        assert.equal(b.triangles, LEVEL * LEVEL * a.triangles, `${what}: triangles`);
      } else {
        assert.equal(b.elements, a.elements, `${what}: a line or point primitive is kept as it is`);
      }
      // The refined surface lies near the coarse one: the boxes agree within 10 %.
      for (let k = 0; k < 3; k++) assert.ok(Math.abs(b.box[k] - a.box[k]) <= 0.1 * Math.max(...a.box), `${what}: box ${b.box} against ${a.box}`);
    }
    assert.deepEqual(three.problems, []);
  });
}

test(`the refined creature posed by three's AnimationMixer lies within ${100 * MAX_POSE_DISTANCE}% of the diagonal of refine --clip --time`, async () => {
  const glb = b64(refine('samples/animated-creature.glb', 'creature.glb'));
  // Vertex order: the scene output and the flattened PLY come from the same refinement plan, so
  // vertex i is vertex i in both; checked on the rest pose, where the two must agree exactly.
  const restCli = readPlyPositions(refine('samples/animated-creature.glb', 'rest.ply'));
  const first = await call('pose', { glb, clip: 'wave', time: 0 });
  const rest = floats(first.rest);
  assert.equal(rest.length, restCli.length, 'three and the CLI have as many vertices');
  const restDiag = diagonal(restCli);
  const restOff = pairwise(rest, restCli);
  console.log(`rest pose: ${rest.length / 3} vertices, vertex i against vertex i: max ${restOff.max.toExponential(2)} (${pct(restOff.max / restDiag)} of the diagonal ${restDiag.toFixed(4)})`);
  assert.ok(restOff.max <= 1e-4 * restDiag, 'the two outputs list their vertices in one order');
  assert.equal(first.influences, 4);
  for (const [clip, time] of [['wave', 0.5], ['hop', 0.3], ['breathe', 1.2]]) {
    const posedCli = readPlyPositions(refine('samples/animated-creature.glb', `${clip}.ply`, ['--clip', clip, '--time', String(time)]));
    const res = await call('pose', { glb, clip, time });
    assert.ok(time <= res.duration, `${clip}: ${time} s lies past the clip's end (${res.duration} s)`);
    const posed = floats(res.positions);
    assert.equal(posed.length, posedCli.length);
    const diag = diagonal(posedCli);
    const moved = pairwise(posed, rest).max;
    const off = pairwise(posed, posedCli);
    const near = Math.max(nearest(posed, posedCli), nearest(posedCli, posed));
    console.log(
      `${clip} at ${time} s: three's pose against refine --clip ${clip} --time ${time} (diagonal ${diag.toFixed(4)}): ` +
        `vertex by vertex max ${num(off.max)} (${pct(off.max / diag)}), mean ${num(off.mean)} (${pct(off.mean / diag)}); ` +
        `nearest point max ${num(near)} (${pct(near / diag)}); the clip moved vertices up to ${num(moved)} (${pct(moved / diag)}); ` +
        `morph weights [${res.morphInfluences.map((w) => w.toFixed(3))}]`,
    );
    assert.ok(moved > 0.01 * diag, `${clip}: three's pose hardly moved (${moved})`);
    assert.ok(off.max <= MAX_POSE_DISTANCE * diag, `${clip} at ${time}: ${pct(off.max / diag)} of the diagonal`);
  }
  assert.deepEqual(three.problems, []);
});

test('the refined scene draws: the picture is not blank and the textured parts show', async () => {
  const coarse = b64(join(REPO, 'samples', 'scene.glb'));
  const refined = b64(refine('samples/scene.glb', 'scene-picture.glb'));
  const { png, panels } = await call('picture', { panels: [{ glb: coarse, label: 'coarse' }, { glb: refined, label: 'refined' }], width: 240, height: 160, labelHeight: 0 });
  const { PNG } = await import('pngjs');
  const img = PNG.sync.read(Buffer.from(png.split(',')[1], 'base64'));
  // Per panel: pixels that are not white, and the distinct (coarsely quantised) colours.
  for (let k = 0; k < 2; k++) {
    let drawn = 0;
    const colours = new Set();
    for (let y = 0; y < img.height; y++) {
      for (let x = k * 240; x < (k + 1) * 240; x++) {
        const i = 4 * (y * img.width + x);
        const [r, g, b] = [img.data[i], img.data[i + 1], img.data[i + 2]];
        if (r < 240 || g < 240 || b < 240) {
          drawn++;
          colours.add(`${r >> 5},${g >> 5},${b >> 5}`);
        }
      }
    }
    console.log(`picture panel ${k}: ${panels[k].triangles} triangles, ${drawn} pixels drawn, ${colours.size} colours`);
    // 898 triangles in the file's meshes; the ring's mesh is drawn twice (RingA, RingB).
    assert.equal(panels[k].triangles, (k === 0 ? 1 : LEVEL * LEVEL) * (152 + 170 + 2 * 576));
    assert.ok(drawn > 0.1 * 240 * 160, `panel ${k}: ${drawn} pixels drawn`);
    assert.ok(colours.size >= 8, `panel ${k}: ${colours.size} colours`);
  }
  assert.deepEqual(three.problems, []);
});
