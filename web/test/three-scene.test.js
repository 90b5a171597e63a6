// tessella/three's `tessellate` in headless Chromium (WebGL2 on SwiftShader, and WebGPU on
// SwiftShader): the repository's samples/scene.glb loaded by three's GLTFLoader (with a
// half-size copy of each mesh sharing its geometry and material) has every triangle Mesh
// replaced by a TessellatedMesh, one patched material per source material shared by the meshes
// that shared it, the source materials untouched; the picture equals the same scene drawn with
// one TessellatedMesh and one material per mesh (the path three-mesh.test.js checks) and
// refineGeometry's CPU refinement drawn as plain Meshes; `untessellate` gives back the coarse
// scene's picture, pixel for pixel. The file's normal maps are removed for the comparisons
// (TessellatedMesh does not carry the uv1 and tangents they read); under WebGLRenderer the
// shared materials are compared with per-mesh ones with them too. The page is web/test/three/index.html?page=scene
// (three/scene.js); build js/ first (`cd js && npm ci && npm run build`).
import { after, before, test } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync } from 'node:fs';
import { PNG } from 'pngjs';
import { count, differing, iou, mask, openRepoPage } from './harness.js';

const SHOT = process.env.TESSELLA_SCENE_SHOT;

let three;
before(async () => {
  three = await openRepoPage('web/test/three/index.html?page=scene', { webgpu: true, global: 'tessellaScene', needs: ['samples/scene.glb'] });
});
after(() => three?.close());
const run = (config) => three.run(config);

function save(path, images) {
  const { width, height } = images[0];
  const out = new PNG({ width: width * images.length, height });
  images.forEach((img, i) => PNG.bitblt(img, out, 0, 0, width, height, i * width, 0));
  writeFileSync(path, PNG.sync.write(out));
}

for (const renderer of ['webgl', 'webgpu']) {
  test(`${renderer}: tessellate replaces every triangle mesh, one patched material per source material, and draws what per-mesh TessellatedMeshes and the CPU refinement draw`, async () => {
    const coarse = await run({ way: 'coarse', renderer });
    // The instanced path, pinned ('per-draw'; the default bakes from the second frame under
    // WebGLRenderer: its own test below).
    const scene = await run({ way: 'scene', renderer, evaluation: 'per-draw' });
    const separate = await run({ way: 'separate', renderer, evaluation: 'per-draw' });
    const cpu = await run({ way: 'cpu', renderer });
    if (SHOT) save(SHOT.replace(/\.png$/, `-${renderer}.png`), [coarse.img, scene.img, separate.img, cpu.img]);
    console.log(`${renderer}: ${scene.triangleMeshes} triangle meshes (${scene.faces.join(', ')} triangles), ${scene.sourceMaterials} source materials -> ${scene.meshes} TessellatedMeshes, ${scene.patchedMaterials} patched materials; skipped: ${scene.skipped.join('; ')}`);
    assert.ok(scene.triangleMeshes >= 6, `only ${scene.triangleMeshes} triangle meshes`);
    // The scene does share materials: fewer materials than meshes.
    assert.ok(scene.sourceMaterials < scene.triangleMeshes);
    assert.equal(scene.replaced, scene.triangleMeshes, 'every triangle mesh replaced');
    assert.equal(scene.meshes, scene.triangleMeshes);
    assert.equal(scene.patchedMaterials, scene.sourceMaterials);
    assert.equal(scene.handleMaterials, scene.sourceMaterials);
    assert.equal(scene.sharedKept, true, 'meshes share a patched material exactly when they shared the source one');
    assert.equal(scene.patchedAreClones, true, 'the patched materials are clones');
    assert.equal(scene.sourcesUntouched, true, 'a source material changed');
    // The file's lines and points are left, with the reason.
    assert.ok(scene.skipped.some((s) => /lines/.test(s)), 'no line skipped');
    assert.ok(scene.skipped.some((s) => /points/.test(s)), 'no points skipped');
    // Each TessellatedMesh one instanced draw of level² = 36 triangles per coarse triangle.
    const draws = scene.instanced.map((d) => `${d.count}x${d.instances}`).sort();
    const expected = scene.instances.map((f) => `${3 * 36}x${f}`).sort();
    // The file's two triangles without area are left out (refine refuses them; they draw nothing).
    assert.equal(scene.instances.reduce((a, b) => a + b), scene.faces.reduce((a, b) => a + b) - 4);
    // RingA holds RingB: hidden by its layers, not `visible`, so RingB (and its TessellatedMesh) still draws.
    assert.deepEqual(scene.hiddenByLayers, ['RingA', 'RingA']);
    assert.deepEqual(draws, expected);
    const [a, b, c, d] = [scene, separate, cpu, coarse].map((r) => mask(r.img));
    const withSeparate = iou(a, b);
    const withCpu = iou(a, c);
    const offSeparate = differing(scene.img, separate.img, 12);
    const offCpu = differing(scene.img, cpu.img, 12);
    const fromCoarse = iou(a, d);
    console.log(`${renderer}: silhouette IoU ${withSeparate.toFixed(5)} with per-mesh TessellatedMeshes (${offSeparate} pixels of other colours), ${withCpu.toFixed(5)} with refineGeometry (${offCpu}), ${fromCoarse.toFixed(5)} with the coarse scene; ${count(a)} pixels drawn`);
    assert.ok(count(a) > 0.1 * a.length, `only ${count(a)} pixels drawn`);
    assert.ok(withSeparate >= 0.99, `IoU ${withSeparate} with per-mesh TessellatedMeshes`);
    assert.ok(offSeparate < 0.01 * count(a), `${offSeparate} pixels differ from per-mesh TessellatedMeshes`);
    assert.ok(withCpu >= 0.99, `IoU ${withCpu} with refineGeometry`);
    assert.ok(offCpu < 0.01 * count(a), `${offCpu} pixels differ from refineGeometry`);
    // The curved surface is not the coarse one.
    assert.ok(differing(scene.img, coarse.img, 12) > 0.01 * count(a), 'the tessellated scene looks coarse');
    assert.deepEqual(three.problems, []);
  });

  if (renderer === 'webgl') {
    test("webgl: by default ('auto': per-frame from the second frame) the tessellated scene draws what 'per-draw' draws, none instanced; meshes of both evaluations sharing materials too", async () => {
      const perDraw = await run({ way: 'scene', renderer, evaluation: 'per-draw', frames: 3 });
      const auto = await run({ way: 'scene', renderer, frames: 3 });
      const mixed = await run({ way: 'mixed', renderer, frames: 3 });
      assert.ok(auto.evaluations.length >= 6);
      assert.deepEqual(new Set(auto.evaluations), new Set(['per-frame']));
      assert.deepEqual(auto.instanced, [], 'a baked mesh drawn instanced');
      assert.equal(perDraw.instanced.length, perDraw.triangleMeshes);
      // Mixed: half the meshes baked, the others instanced, sharing materials.
      const baked = mixed.evaluations.filter((e) => e === 'per-frame').length;
      assert.ok(baked >= 1);
      assert.equal(mixed.instanced.length, mixed.triangleMeshes - baked);
      assert.ok(mixed.bothEvaluations >= 1, 'no material draws both evaluations');
      console.log(`webgl mixed: ${baked} of ${mixed.triangleMeshes} meshes per-frame, ${mixed.mixedMaterials} materials, ${mixed.bothEvaluations} drawing both evaluations`);
      for (const [name, r] of [['default', auto], ['mixed', mixed]]) {
        const score = iou(mask(perDraw.img), mask(r.img));
        const off = differing(perDraw.img, r.img, 12);
        console.log(`webgl ${name} against per-draw: IoU ${score.toFixed(5)}, ${off} pixels of other colours`);
        assert.ok(score >= 0.99, `${name}: IoU ${score}`);
        assert.ok(off < 0.01 * count(mask(perDraw.img)), `${name}: ${off} pixels of other colours`);
      }
      assert.deepEqual(three.problems, []);
    });

    test('webgl: with the file\'s normal maps (uv1, tangents: not carried by TessellatedMesh), shared materials draw what per-mesh ones draw', async () => {
      const scene = await run({ way: 'scene', renderer, normalMaps: true });
      const separate = await run({ way: 'separate', renderer, normalMaps: true });
      const cpu = await run({ way: 'cpu', renderer, normalMaps: true });
      const [a, b, c] = [scene, separate, cpu].map((r) => mask(r.img));
      const off = differing(scene.img, separate.img, 12);
      console.log(`webgl with normal maps: IoU ${iou(a, b).toFixed(5)} with per-mesh TessellatedMeshes (${off} pixels of other colours); silhouette IoU ${iou(a, c).toFixed(5)} with refineGeometry (${differing(scene.img, cpu.img, 12)} pixels shaded otherwise: its tangents and uv1 are interpolated)`);
      assert.equal(scene.patchedMaterials, scene.sourceMaterials);
      assert.ok(iou(a, b) >= 0.99 && off < 0.01 * count(a), 'shared materials draw otherwise than per-mesh ones');
      assert.ok(iou(a, c) >= 0.99, 'silhouette');
      assert.deepEqual(three.problems, []);
    });
  }

  test(`${renderer}: untessellate gives back the coarse scene, pixel for pixel, and disposes the patched materials`, async () => {
    const coarse = await run({ way: 'coarse', renderer });
    const restored = await run({ way: 'restored', renderer });
    const off = differing(coarse.img, restored.img, 0);
    const score = iou(mask(coarse.img), mask(restored.img));
    console.log(`${renderer}: restored: IoU ${score.toFixed(5)} with the coarse scene, ${off} pixels differ; ${restored.removed} TessellatedMeshes removed, ${restored.disposedMaterials} patched materials disposed`);
    assert.equal(restored.tessellatedInstanced.length, restored.triangleMeshes, 'it was tessellated before');
    assert.equal(restored.removed, restored.triangleMeshes);
    assert.deepEqual(restored.left, []);
    assert.equal(restored.handleMeshesAfter, 0);
    assert.equal(restored.visibleAgain, restored.triangleMeshes);
    assert.equal(restored.disposedMaterials, restored.sourceMaterials);
    assert.equal(restored.sourcesUntouchedAfter, true);
    assert.deepEqual(restored.instanced, []);
    assert.equal(off, 0);
    assert.deepEqual(three.problems, []);
  });
}
