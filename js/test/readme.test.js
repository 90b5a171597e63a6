// The README's examples run, and print what their comments say (`console.log(...); // TEXT`:
// the printed line starts with TEXT).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { format } from 'node:util';
import { pathToFileURL } from 'node:url';

const readme = readFileSync(new URL('../README.md', import.meta.url), 'utf8');
const blocks = [...readme.matchAll(/```js\n([\s\S]*?)```/g)].map((m) => m[1]);
const scratch = new URL('../node_modules/.cache/tessella-readme/', import.meta.url);
const index = pathToFileURL(new URL('../src/index.js', import.meta.url).pathname).href;
const three = pathToFileURL(new URL('../src/three.js', import.meta.url).pathname).href;
const gltfTransform = pathToFileURL(new URL('../src/gltf-transform.js', import.meta.url).pathname).href;

test('the README has an example per function', () => {
  for (const name of ['refine(', 'new Refiner(', 'readMesh(', 'writeMesh(', 'readAnimated(', 'refineGltf(', 'refineGltfWithReport(', 'tessellate(', 'refineGeometry(', 'new RefinedGeometry(', 'new TessellatedMesh(', 'schemes()', 'sceneCamera(', 'TessellaError']) {
    assert.ok(blocks.some((b) => b.includes(name)), name);
  }
});

blocks.forEach((block, n) => {
  test(`README example ${n + 1} runs and prints what it says`, async () => {
    const expected = [];
    const source = block
      .replaceAll("from 'tessella/three'", `from '${three}'`)
      .replaceAll("from 'tessella/gltf-transform'", `from '${gltfTransform}'`)
      .replaceAll("from 'tessella'", `from '${index}'`)
      .split('\n')
      .map((line) => {
        const m = line.match(/console\.log\((.*)\); \/\/ (.*)$/);
        if (!m) return line;
        expected.push(m[2]);
        return line.replace('console.log(', `globalThis.__readmeLog(${expected.length - 1}, `);
      })
      .join('\n');
    const printed = [];
    globalThis.__readmeLog = (i, ...args) => printed.push([i, format(...args)]);
    mkdirSync(scratch, { recursive: true });
    const file = new URL(`example-${n}.mjs`, scratch);
    writeFileSync(file, source);
    try {
      await import(file.href);
    } finally {
      rmSync(file);
    }
    assert.ok(expected.length > 0, 'an example that shows its result');
    for (let i = 0; i < expected.length; i++) {
      const lines = printed.filter(([k]) => k === i).map(([, text]) => text);
      assert.ok(lines.length > 0, `example line ${i} printed nothing`);
      for (const text of lines) assert.ok(text.startsWith(expected[i]), `${JSON.stringify(text)} does not start with ${JSON.stringify(expected[i])}`);
    }
  });
});
