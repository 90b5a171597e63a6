// Shared by the glTF scene tests: the GLB container, what a document holds, the Khronos
// validator, the native CLI and the ecosystem's command-line tools (devDependencies).
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import validator from 'gltf-validator';
import { repo } from './helpers.js';

/** The JSON and the BIN chunk of a GLB. */
export function glbParts(glb) {
  const view = new DataView(glb.buffer, glb.byteOffset, glb.byteLength);
  if (view.getUint32(0, true) !== 0x46546c67) throw new Error('not a GLB');
  const jsonLength = view.getUint32(12, true);
  const json = JSON.parse(new TextDecoder().decode(glb.subarray(20, 20 + jsonLength)));
  const at = 20 + jsonLength;
  const bin = at + 8 <= glb.byteLength ? glb.subarray(at + 8, at + 8 + view.getUint32(at, true)) : null;
  return { json, bin };
}

/** A GLB of `json` and `bin` (chunks padded to 4 bytes). */
export function makeGlb(json, bin) {
  const text = new TextEncoder().encode(JSON.stringify(json));
  const jsonLength = Math.ceil(text.length / 4) * 4;
  const binLength = bin ? Math.ceil(bin.length / 4) * 4 : 0;
  const total = 12 + 8 + jsonLength + (bin ? 8 + binLength : 0);
  const out = new Uint8Array(total);
  const view = new DataView(out.buffer);
  view.setUint32(0, 0x46546c67, true);
  view.setUint32(4, 2, true);
  view.setUint32(8, total, true);
  view.setUint32(12, jsonLength, true);
  view.setUint32(16, 0x4e4f534a, true);
  out.fill(0x20, 20, 20 + jsonLength);
  out.set(text, 20);
  if (bin) {
    const at = 20 + jsonLength;
    view.setUint32(at, binLength, true);
    view.setUint32(at + 4, 0x004e4942, true);
    out.set(bin, at + 8);
  }
  return out;
}

export const KINDS = ['scenes', 'nodes', 'meshes', 'materials', 'textures', 'images', 'samplers', 'animations', 'skins', 'cameras'];

/** How many of each kind of object a document's JSON holds. */
export function counts(json) {
  return Object.fromEntries(KINDS.map((k) => [k, (json[k] ?? []).length]));
}

const TRIANGLES = 4;
const STRIP = 5;
const FAN = 6;

/** Whether a primitive draws triangles (a list, a strip or a fan). */
export function isTriangles(primitive) {
  return [TRIANGLES, STRIP, FAN].includes(primitive.mode ?? TRIANGLES);
}

/** The triangles a triangle primitive draws, from its accessors' counts (compressed or not). */
export function triangleCount(json, primitive) {
  const n = json.accessors[primitive.indices ?? primitive.attributes.POSITION].count;
  return (primitive.mode ?? TRIANGLES) === TRIANGLES ? n / 3 : Math.max(n - 2, 0);
}

/** Every primitive as [mesh, primitive, object]. */
export function primitives(json) {
  return (json.meshes ?? []).flatMap((mesh, m) => mesh.primitives.map((p, i) => [m, i, p]));
}

/**
 * Checks `out` (a refined document's JSON) against `input`'s at `level`: the same counts of
 * every kind, each primitive with its material, attributes (NORMAL may be added) and morph
 * targets, each triangle primitive with level² times its triangles, the others as they were.
 */
export function assertRefinedScene(assert, input, out, level, where) {
  assert.deepEqual(counts(out), counts(input), `${where}: counts`);
  const before = primitives(input);
  const after = primitives(out);
  assert.equal(after.length, before.length, `${where}: primitives`);
  before.forEach(([m, i, p], k) => {
    const q = after[k][2];
    const at = `${where}: mesh ${m} primitive ${i}`;
    assert.equal(q.material, p.material, `${at}: material`);
    const names = Object.keys(p.attributes).sort();
    const added = Object.keys(q.attributes).filter((a) => !names.includes(a));
    assert.ok(added.every((a) => a === 'NORMAL'), `${at}: attributes added ${added}`);
    assert.deepEqual(Object.keys(q.attributes).filter((a) => !added.includes(a)).sort(), names, `${at}: attributes`);
    const targetNames = (prim) => (prim.targets ?? []).map((t) => Object.keys(t).sort());
    assert.deepEqual(targetNames(q), targetNames(p), `${at}: morph targets`);
    if (isTriangles(p)) {
      assert.equal(triangleCount(out, q), level * level * triangleCount(input, p), `${at}: triangles`);
    } else {
      assert.equal(q.mode ?? TRIANGLES, p.mode ?? TRIANGLES, `${at}: mode`);
      assert.equal(out.accessors[q.attributes.POSITION].count, input.accessors[p.attributes.POSITION].count, `${at}: vertices`);
    }
  });
}

/** The Khronos validator's report; asserts no errors (listing them when there are). */
export async function assertValid(assert, glb, where) {
  const report = await validator.validateBytes(new Uint8Array(glb), { maxIssues: 0 });
  const errors = report.issues.messages.filter((m) => m.severity === 0);
  assert.equal(report.issues.numErrors, 0, `${where}: ${JSON.stringify(errors.slice(0, 5), null, 1)}`);
  return report;
}

/** The native CLI (`cargo build -p tessella-cli`; TESSELLA_CLI names another binary). */
export const cli = process.env.TESSELLA_CLI ?? join(repo, 'target', 'debug', process.platform === 'win32' ? 'tessella.exe' : 'tessella');
export const hasCli = existsSync(cli);
export const NO_CLI = `the native CLI ${cli} is absent: build it with \`cargo build -p tessella-cli\` (or name one in TESSELLA_CLI)`;

/** Runs a command; its output (stdout and stderr) on success, an Error with both otherwise. */
export function runTool(file, args) {
  try {
    return execFileSync(file, args, { encoding: 'utf8', stdio: ['ignore', 'pipe', 'pipe'] });
  } catch (e) {
    const error = new Error(`${file} ${args.join(' ')} failed (${e.status}):\n${e.stdout ?? ''}${e.stderr ?? ''}`);
    error.stderr = String(e.stderr ?? '');
    throw error;
  }
}

/** `tessella ARGS` (the native CLI). */
export function tessella(...args) {
  return runTool(cli, args);
}

const bin = (relative) => fileURLToPath(new URL(`../node_modules/${relative}`, import.meta.url));

/** `gltf-transform ARGS` (@gltf-transform/cli). */
export function gltfTransform(...args) {
  return runTool(process.execPath, [bin('@gltf-transform/cli/bin/cli.js'), ...args]);
}

/** `gltfpack ARGS` (the npm package's wasm build of meshoptimizer's gltfpack). */
export function gltfpack(...args) {
  return runTool(process.execPath, [bin('gltfpack/cli.js'), ...args]);
}

/** A new scratch folder. */
export function scratch() {
  return mkdtempSync(join(tmpdir(), 'tessella-gltf-'));
}
