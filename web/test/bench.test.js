// The benchmark page and viewer.bench() on the WebGPU engine (SwiftShader): the report counts
// what the papers count, both Figure 7 paths draw the same picture, the page keeps drawing
// animation frames while it runs, a bad configuration is a message, and without WebGPU the page
// says the benchmark needs it. Needs dist/pkg (the engine); TESSELLA_WEB_NO_ENGINE=1 skips.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { assertClean, capture, count, mask, message, open, start } from './harness.js';

const skip = process.env.TESSELLA_WEB_NO_ENGINE === '1' ? 'TESSELLA_WEB_NO_ENGINE=1: the site was built without the engine' : false;
const SMALL = 'faces=10,40&levels=8&frames=2&size=96x96&schemeFaces=20&schemeLevels=4&movingTop=6';

/** Opens the benchmark page at `query` and waits for it to start. */
async function openBench(env, query) {
  const page = await open(env, `bench.html?${query}`, { waitReady: false });
  await page.waitForFunction(() => window.bench !== undefined && window.bench.ready !== null);
  await page.evaluate(() => window.bench.ready);
  return page;
}

describe('the benchmark on WebGPU', { skip }, () => {
  let env;
  before(async () => {
    env = await start({ webgpu: true });
  });
  after(async () => env?.close());

  test('the page runs Figure 7, the scheme table and moving levels without blocking the page', async () => {
    const page = await openBench(env, SMALL);
    // Count animation frames while the benchmark runs: a blocked thread would give none.
    const [report, frames] = await page.evaluate(async () => {
      let frames = 0;
      let on = true;
      const tick = () => {
        frames++;
        if (on) requestAnimationFrame(tick);
      };
      requestAnimationFrame(tick);
      const r = await window.bench.run();
      on = false;
      return [r, frames];
    });
    assert.ok(frames >= 3, `only ${frames} animation frames while the benchmark ran`);
    assert.match(report.adapter, /^\S.* \(BrowserWebGpu/);
    assert.match(report.browserAdapter, /\S/);
    assert.ok(report.markdown.startsWith(`Browser's adapter: ${report.browserAdapter}`));
    assert.equal(report.figure7.length, 2);
    for (const [row, faces] of report.figure7.map((r, i) => [r, [10, 40][i]])) {
      assert.equal(row.faces, faces);
      assert.equal(row.level, 8);
      // The pattern is one triangle's (N+1)(N+2)/2 points, whatever the mesh.
      assert.equal(row.patternVertices, (9 * 10) / 2);
      // The welded refined mesh has at least a pattern's worth of points per coarse triangle
      // beyond its shared edges: more than faces * interior points.
      assert.ok(row.staticVertices > faces * ((7 * 6) / 2), JSON.stringify(row));
      assert.ok(row.patternMs > 0 && row.staticMs > 0, JSON.stringify(row));
      assert.ok(Math.abs(row.frameRatio - row.patternMs / row.staticMs) < 1e-9);
      assert.ok(row.picturesDiffer < 0.02, `the two paths drew different pictures: ${row.picturesDiffer}`);
      assert.equal(row.footprintGoal, 1 / faces);
    }
    // Four times the coarse triangles: the static buffer grows, the pattern's part barely.
    const [a, b] = report.figure7;
    assert.ok(b.staticBytes > 3.5 * a.staticBytes && b.patternBytes < 2 * a.patternBytes);
    assert.equal(report.schemes.length, 1);
    assert.ok(report.schemes[0].png1RateOverPn > 0 && report.schemes[0].pnOverFlat > 0);
    assert.equal(report.moving.length, 2);
    // The tables on the page: one per part, with a row per result.
    const rows = await page.evaluate(() => [...document.querySelectorAll('#tables table')].map((t) => t.rows.length - 1));
    assert.deepEqual(rows, [2, 1, 2]);
    assert.match(await page.locator('#status').textContent(), /^done in/);
    assert.equal(JSON.parse(await page.locator('#json').textContent()).adapter, report.adapter);
    assertClean(assert, page);
    await page.close();
  });

  test('a bad configuration is a message naming the field; the page can run again', async () => {
    const page = await openBench(env, `${SMALL.replace('levels=8', 'levels=0')}&run=1`);
    await page.waitForFunction(() => document.getElementById('status').textContent === 'failed');
    assert.match(await message(page), /bench: level 0/);
    await page.fill('input[name=faces]', '10.5');
    await page.click('#run');
    await page.waitForFunction(() => document.getElementById('message').textContent.includes('faces'));
    assert.match(await message(page), /bench: faces: "10.5" is not a whole number/);
    await page.fill('input[name=faces]', '10');
    const again = await page.evaluate(() =>
      window.bench.run({ faces: [10], levels: [4], frames: 1, size: [32, 32], parts: ['figure7'] }).then((r) => r.figure7.length),
    );
    assert.equal(again, 1);
    assert.equal(await message(page), '');
    assertClean(assert, page);
    await page.close();
  });

  test('viewer.bench() in the viewer page runs the parts asked for, then the page draws again', async () => {
    const page = await open(env, '?mesh=samples/icosphere.obj&size=160x120');
    const report = await page.evaluate(() =>
      window.viewer.bench({ faces: [10], levels: [4], frames: 1, size: [32, 32], parts: ['figure7', 'schemes'], schemeFaces: [20], schemeLevels: [4] }),
    );
    assert.equal(report.figure7.length, 1);
    assert.equal(report.figure7[0].patternVertices, 15);
    assert.equal(report.schemes.length, 1);
    assert.deepEqual(report.moving, []);
    const m = mask(await capture(page));
    assert.ok(count(m) > 0.1 * m.length, 'the page draws again after the benchmark');
    assertClean(assert, page);
    await page.close();
  });
});

describe('the benchmark without WebGPU', () => {
  let env;
  before(async () => {
    env = await start({ webgpu: false });
  });
  after(async () => env?.close());

  test('says it needs the WebGPU engine', async () => {
    const page = await openBench(env, SMALL);
    assert.match(await message(page), /the benchmark needs the WebGPU engine/);
    assert.equal(await page.locator('#run').isDisabled(), true);
    assertClean(assert, page);
    await page.close();
  });
});
