// tessella/three's TessellatedMesh without a GPU: its options and errors, the nets texture's
// layout (evaluated here with the cubic Bernstein basis, it gives the CPU's refined surface),
// the bounds that cover the refined surface, following the source, the patched shaders, and a
// renderer that lacks what it needs, the WGSL for WebGPURenderer as TSL reads it. The GPU side
// is tested in a browser: web/test/three-mesh.test.js (WebGL2), three-webgpu.test.js (WebGPU).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  BufferAttribute,
  IcosahedronGeometry,
  Mesh,
  MeshStandardMaterial,
  Raycaster,
  Scene,
  ShaderLib,
  ShaderMaterial,
  TorusKnotGeometry,
  Vector3,
} from 'three';
import { ready, refine, TessellaError } from '../src/index.js';
import { TessellatedMesh, tessellaFunctions } from '../src/three.js';
import { cubicPoint, netEntry } from './helpers.js';
import WGSLNodeFunction from 'three/src/renderers/webgpu/nodes/WGSLNodeFunction.js';

await ready;

// The cubic patch's point and (quadratic normal net) unit normal of face f at l.
function evaluate(mesh, f, l) {
  const p = cubicPoint(mesh, f, l);
  const nw = [l[0] * l[0], l[1] * l[1], l[2] * l[2], l[0] * l[1], l[1] * l[2], l[2] * l[0]];
  const n = [0, 0, 0];
  nw.forEach((w, c) => {
    const q = netEntry(mesh, f, 10 + c);
    for (let a = 0; a < 3; a++) n[a] += w * q[a];
  });
  const len = Math.hypot(...n);
  return { p, n: n.map((x) => x / len) };
}

function arrays(g) {
  return { positions: g.getAttribute('position').array, normals: g.getAttribute('normal').array, indices: g.index.array };
}

test('the nets texture, evaluated with the cubic basis at the pattern points, is the CPU refinement', () => {
  const source = new TorusKnotGeometry(1, 0.3, 16, 4);
  for (const scheme of ['pn', 'phong', 'pn-aen', 'flat']) {
    const mesh = new TessellatedMesh(source, new MeshStandardMaterial(), { scheme, level: 3 });
    assert.equal(mesh.surface.basisLength, 10);
    // The soup keeps every face's own points; origin gives each one's face and barycentric point.
    const cpu = refine(arrays(source), { scheme, level: 3, soup: true, origin: true });
    const pattern = mesh.surface.patternPoints();
    const points = new Set();
    for (let i = 0; i < pattern.length; i += 3) points.add(pattern.slice(i, i + 3).join());
    let worst = 0;
    let worstNormal = 0;
    for (let v = 0; v < cpu.faces.length; v++) {
      const l = Array.from(cpu.barycentric.subarray(3 * v, 3 * v + 3));
      assert.ok(points.has(Float32Array.from(l).join()), `${l} is a pattern point`);
      const { p, n } = evaluate(mesh, cpu.faces[v], l);
      for (let a = 0; a < 3; a++) {
        worst = Math.max(worst, Math.abs(p[a] - cpu.positions[3 * v + a]));
        worstNormal = Math.max(worstNormal, Math.abs(n[a] - cpu.normals[3 * v + a]));
      }
    }
    assert.ok(worst < 1e-5, `${scheme}: positions differ by ${worst}`);
    // Flat and Phong take linear normals, PN and PN-AEN quadratic ones: one net serves both.
    assert.ok(worstNormal < 1e-5, `${scheme}: normals differ by ${worstNormal}`);
    mesh.dispose();
  }
});

test('the pattern is the grid: (N+1)(N+2)/2 points, N² triangles, one instance per coarse triangle', () => {
  const source = new IcosahedronGeometry(1, 1);
  const mesh = new TessellatedMesh(source, undefined, { scheme: 'png1', level: 5 });
  assert.equal(mesh.geometry.getAttribute('tessellaBarycentric').count, 21);
  assert.equal(mesh.geometry.index.count, 3 * 25);
  assert.equal(mesh.geometry.instanceCount, source.getAttribute('position').count / 3);
  assert.equal(mesh.surface.basisLength, 21);
  assert.ok(mesh.material.isMeshStandardMaterial);
  mesh.dispose();
});

test('the bounds cover the refined surface as the source deforms, and the upload is the nets alone', () => {
  const source = new IcosahedronGeometry(1, 2);
  const faces = source.getAttribute('position').count / 3;
  for (const scheme of ['pn', 'png1', 'phong']) {
    const mesh = new TessellatedMesh(source.clone(), new MeshStandardMaterial(), { scheme, level: 6 });
    const g = mesh.source;
    const position = g.getAttribute('position');
    for (let frame = 0; frame < 3; frame++) {
      for (let i = 0; i < position.count; i++) position.setY(i, position.getY(i) * (1 + 0.3 * frame) + 0.1 * frame);
      position.needsUpdate = true;
      const before = mesh.netsTexture.version;
      mesh.updateMatrixWorld(); // what three does before culling: follows the source
      assert.equal(mesh.netsTexture.version, before + 1, 'the nets are marked for upload once');
      const cpu = refine(
        { positions: position.array, normals: g.getAttribute('normal').array, indices: Uint32Array.from({ length: position.count }, (_, i) => i) },
        { scheme, level: 6 },
      );
      const sphere = mesh.geometry.boundingSphere;
      const box = mesh.geometry.boundingBox;
      const v = new Vector3();
      for (let i = 0; i < cpu.positions.length; i += 3) {
        v.fromArray(cpu.positions, i);
        assert.ok(v.distanceTo(sphere.center) <= sphere.radius * (1 + 1e-6), `${scheme}: a refined vertex outside the sphere`);
        assert.ok(box.containsPoint(v), `${scheme}: a refined vertex outside the box`);
      }
      const perTriangle = scheme === 'png1' ? 21 * 16 : 12 * 16;
      assert.ok(mesh.uploadedBytes <= perTriangle * faces * 1.01, `${scheme}: ${mesh.uploadedBytes} bytes for ${faces} triangles`);
      assert.equal(mesh.uploadedBytes, mesh.netsTexture.image.data.byteLength);
      if (scheme !== 'png1') assert.ok(mesh.uploadedBytes <= 256 * faces);
    }
    // Nothing moved: no update, no upload.
    const version = mesh.netsTexture.version;
    mesh.updateMatrixWorld();
    assert.equal(mesh.netsTexture.version, version);
    mesh.dispose();
  }
});

test('a Mesh source is hidden and replaced in its parent; the transform follows it; rays hit it', () => {
  const scene = new Scene();
  const source = new Mesh(new IcosahedronGeometry(1, 1), new MeshStandardMaterial({ color: 0xff0000 }));
  source.position.set(1, 2, 3);
  source.castShadow = true;
  scene.add(source);
  const mesh = new TessellatedMesh(source, undefined, { scheme: 'pn', level: 4 });
  assert.equal(mesh.parent, scene);
  assert.equal(source.visible, false);
  assert.equal(mesh.castShadow, true);
  assert.notEqual(mesh.material, source.material, 'the source keeps its own material');
  assert.equal(mesh.material.color.getHex(), 0xff0000);
  source.position.set(-5, 0, 0);
  source.rotation.y = 1;
  scene.updateMatrixWorld();
  assert.ok(mesh.matrixWorld.equals(source.matrixWorld));
  // (three's raycaster also hits the hidden source: it ignores visibility.)
  const hits = new Raycaster(new Vector3(-5, 0, 10), new Vector3(0, 0, -1)).intersectObject(mesh);
  assert.equal(hits.length, 1, 'the front face (FrontSide)');
  assert.equal(hits[0].object, mesh);
  assert.ok(Math.abs(hits[0].point.z - 1) < 0.1, `hit at ${hits[0].point.z}`);
  mesh.dispose();
});

test("the materials' vertex shaders evaluate the patch and hide three's attributes", () => {
  const source = new IcosahedronGeometry(1, 1);
  source.setAttribute('color', new BufferAttribute(new Float32Array(source.getAttribute('position').count * 4).fill(0.5), 4));
  const material = new MeshStandardMaterial({ vertexColors: true });
  const mesh = new TessellatedMesh(source, material, { scheme: 'pn', level: 3 });
  for (const [m, lib] of [[material, 'standard'], [mesh.customDepthMaterial, 'depth'], [mesh.customDistanceMaterial, 'distance']]) {
    const shader = { vertexShader: ShaderLib[lib].vertexShader, fragmentShader: ShaderLib[lib].fragmentShader, uniforms: {} };
    m.onBeforeCompile(shader);
    assert.equal(shader.uniforms.tessellaNets.value, mesh.netsTexture);
    assert.equal(shader.uniforms.tessellaFacesPerRow.value, mesh.surface.facesPerRow);
    const main = shader.vertexShader.indexOf('void main() {');
    const evaluate = shader.vertexShader.indexOf('void tessella_evaluate(int face, vec3 l, out vec3 position, out vec3 normal)');
    assert.ok(evaluate >= 0 && evaluate < main);
    const body = shader.vertexShader.slice(main);
    assert.ok(body.indexOf('vec3 position = tessellaPosition;') < body.indexOf('#include <begin_vertex>'));
    assert.ok(body.includes('vec2 uv = tessellaBarycentric.x * tessellaUv01.xy'));
    assert.ok(body.includes('vec4 color = tessellaColor;'));
    assert.match(m.customProgramCacheKey(), /^tessella:10:quadratic:uv:4:instanced\|/);
  }
  assert.equal(mesh.geometry.getAttribute('tessellaColor2').array[3], 0.5);
  // A changed colour (or uv) attribute is copied to the corners before the next render.
  const color = source.getAttribute('color');
  color.setXYZW(2, 0.25, 0.25, 0.25, 1); // the source is not indexed: corner 2 of triangle 0
  color.needsUpdate = true;
  mesh.updateMatrixWorld();
  assert.deepEqual(Array.from(mesh.geometry.getAttribute('tessellaColor2').array.subarray(0, 4)), [0.25, 0.25, 0.25, 1]);
  assert.ok(mesh.uploadedBytes > mesh.netsTexture.image.data.byteLength, 'the colours are uploaded too');
  mesh.dispose();
});

test('bad options, sources and materials throw TessellaErrors that say what is wrong', () => {
  const g = new IcosahedronGeometry(1, 0);
  const cases = [
    [() => new TessellatedMesh(g, undefined, { scheme: 'loop' }), /see schemes\(\)/],
    [() => new TessellatedMesh(g, undefined, { level: 2.5 }), /whole level on the grid/],
    [() => new TessellatedMesh(g, undefined, { lod: 'tolerance:0.1' }), /spacing: lod draws the GPU tessellator's patterns/],
    [() => new TessellatedMesh(g, undefined, { level: 300 }), /over 256/],
    [() => new TessellatedMesh(g, undefined, { soup: true }), /soup/],
    [() => new TessellatedMesh(g, undefined, { levle: 3 }), /levle: unknown option/],
    [() => new TessellatedMesh(g, undefined, { alpha: NaN }), /alpha/],
    [() => new TessellatedMesh({}, undefined), /BufferGeometry or Mesh/],
    [() => new TessellatedMesh(g, [new MeshStandardMaterial()]), /not an array/],
    [() => new TessellatedMesh(g, undefined, { normalsFromSource: true }).update(), null],
  ];
  for (const [make, message] of cases) {
    if (message === null) {
      make();
      continue;
    }
    assert.throws(make, (e) => e instanceof TessellaError && message.test(e.message), String(message));
  }
  const material = new MeshStandardMaterial();
  const first = new TessellatedMesh(g, material);
  // One material draws any number of meshes of one kind (each its own nets), not another kind.
  const twin = new TessellatedMesh(g, material);
  assert.equal(twin.material, first.material);
  assert.throws(() => new TessellatedMesh(g, material, { scheme: 'png1' }), /another kind/);
  twin.dispose();
  const noNormals = g.clone();
  noNormals.deleteAttribute('normal');
  assert.throws(() => new TessellatedMesh(noNormals, undefined, { normalsFromSource: true }), /no normal attribute/);
  // Without normals they are computed, as refine does.
  new TessellatedMesh(noNormals).dispose();
  first.dispose();
  // The last mesh of a caller's material puts back what patching set.
  assert.equal(Object.hasOwn(material, 'onBeforeCompile'), false);
  assert.equal(material.positionNode ?? null, null);
  assert.throws(() => first.update(), /disposed/);
});

test('a renderer without instancing, float textures or vertex textures is refused by name', () => {
  const mesh = new TessellatedMesh(new IcosahedronGeometry(1, 0), undefined, { level: 2 });
  const webgl2 = { drawElementsInstanced() {}, vertexAttribDivisor() {}, texStorage2D() {}, RGBA32F: 0x8814 };
  const renderer = (gl, caps = {}) => ({ getContext: () => gl, capabilities: { maxVertexTextures: 16, maxTextureSize: 4096, ...caps } });
  mesh.onBeforeRender(renderer(webgl2));
  const { drawElementsInstanced, ...noInstancing } = webgl2;
  assert.throws(() => mesh.onBeforeRender(renderer(noInstancing)), (e) => e instanceof TessellaError && /lacks instanced drawing/.test(e.message));
  const { RGBA32F, texStorage2D, ...noFloat } = webgl2;
  assert.throws(() => mesh.onBeforeRender(renderer(noFloat)), /lacks float \(RGBA32F\) textures/);
  assert.throws(() => mesh.onBeforeShadow(renderer(webgl2, { maxVertexTextures: 0 })), /lacks textures in the vertex shader/);
  assert.throws(() => mesh.onBeforeRender(renderer(webgl2, { maxTextureSize: 8 })), /over this renderer's largest texture/);
  assert.throws(() => mesh.onBeforeRender({}), /WebGLRenderer/);
  // WebGPURenderer: its WebGPU backend draws the nodes; its WebGL2 fallback is refused by name.
  mesh.onBeforeRender({ isWebGPURenderer: true, backend: { isWebGPUBackend: true } });
  assert.throws(() => mesh.onBeforeRender({ isWebGPURenderer: true, backend: { isWebGLBackend: true } }), (e) => e instanceof TessellaError && /needs its WebGPU backend/.test(e.message));
  mesh.dispose();
});

/** The terms of a generated sum that `code` assigns to `name` (`p = t5 * c0 + ...`). */
function sumTerms(code, name) {
  const line = code.split('\n').find((l) => l.trimStart().startsWith(`${name} = `) && l.includes(' * '));
  return line.match(/ \* [cm]\d+/g).length;
}

test("the WGSL for WebGPURenderer: TSL's parser finds tessella_position and tessella_normal with the parameters the node passes", () => {
  for (const scheme of ['pn', 'png1']) {
    const mesh = new TessellatedMesh(new IcosahedronGeometry(1, 0), undefined, { scheme, level: 3 });
    const code = mesh.surface.wgsl();
    const { position, normal } = tessellaFunctions(code);
    for (const [fn, name] of [[position, 'tessella_position'], [normal, 'tessella_normal']]) {
      // What wgslFn does with the code: three's WGSL function parser (the first function's
      // signature; the rest of its text is its body).
      const parsed = new WGSLNodeFunction(fn.code);
      assert.equal(parsed.name, name);
      assert.equal(parsed.type, 'vec3');
      assert.deepEqual(parsed.inputs.map((i) => [i.name, i.type]), [['nets', 'texture'], ['face', 'uint'], ['l', 'vec3']]);
      // One function each: the helpers are the include, shared.
      assert.equal(fn.code.match(/\bfn /g).length, 1);
      assert.equal(fn.includes.length, 1);
    }
    assert.equal(position.includes[0], normal.includes[0]);
    // The same text, the same nodes: a user's material calling them includes the helpers once.
    assert.equal(tessellaFunctions(code), tessellaFunctions(code));
    const helpers = position.includes[0].code;
    assert.match(helpers, /fn tessella_texel\(/);
    // The sums are the core's straight-line code (shader::patch_sum), one term a control
    // point: 10 for PN, 21 for PNG1.
    assert.equal(sumTerms(position.code, 'p'), scheme === 'pn' ? 10 : 21);
    // The normal net's sum too (shader::normal_net_sum): its six entries.
    assert.equal(sumTerms(normal.code, 'n'), 6);
    // The nets texture's layout is the GLSL's: the same texels per face.
    assert.match(code, new RegExp(`const TESSELLA_TEXELS_PER_FACE: u32 = ${mesh.surface.texelsPerFace}u;`));
    // The material draws the node under WebGPURenderer (and its onBeforeCompile under WebGLRenderer).
    assert.equal(mesh.material.positionNode.isNode, true);
    mesh.dispose();
  }
  const material = new MeshStandardMaterial();
  material.positionNode = tessellaFunctions(new TessellatedMesh(new IcosahedronGeometry(1, 0)).surface.wgsl()).position;
  assert.throws(() => new TessellatedMesh(new IcosahedronGeometry(1, 0), material), /has a positionNode/);
  assert.throws(() => tessellaFunctions('fn f() {}'), (e) => e instanceof TessellaError);
});

test("evaluation: 'auto' (the default) and 'per-frame' start instanced, per draw, until a WebGLRenderer bakes; lod and a ShaderMaterial ('auto') evaluate per draw; the shaders' variants are programs of their own", () => {
  const source = new IcosahedronGeometry(1, 1);
  const plain = new TessellatedMesh(source, undefined, { scheme: 'pn', level: 4, evaluation: 'per-draw' });
  assert.equal(plain.evaluation, 'per-draw');
  assert.equal(plain.evaluationFallback, null);
  assert.equal(plain.geometry.isInstancedBufferGeometry, true);
  assert.equal(plain.bakedBytes, 0);
  // Before a render neither the default nor 'per-frame' has baked: both draw the pattern instanced.
  const auto = new TessellatedMesh(source, undefined, { scheme: 'pn', level: 4 });
  const baked = new TessellatedMesh(source, undefined, { scheme: 'pn', level: 4, evaluation: 'per-frame' });
  for (const m of [auto, baked]) {
    assert.equal(m.evaluation, 'per-draw');
    assert.equal(m.evaluationFallback, null);
    assert.equal(m.geometry.isInstancedBufferGeometry, true);
    assert.equal(m.bakedBytes, 0);
  }
  // The instanced variant evaluates the patch at the instance's coarse triangle; the program
  // cache key names the variant (a baked mesh's is ':baked', evaluating nothing: the browser
  // tests read its shader).
  const shader = { vertexShader: ShaderLib.standard.vertexShader, fragmentShader: ShaderLib.standard.fragmentShader, uniforms: {} };
  auto.material.onBeforeCompile(shader);
  assert.ok(shader.vertexShader.includes('int tessellaFaceIndex = gl_InstanceID;'));
  assert.ok(shader.vertexShader.includes('tessella_evaluate(tessellaFaceIndex, tessellaBarycentric, tessellaPosition, tessellaNormal);'));
  assert.equal(shader.uniforms.tessellaBaked, undefined);
  assert.match(auto.material.customProgramCacheKey(), /:instanced\|/);
  assert.match(auto.customDepthMaterial.customProgramCacheKey(), /:instanced\|/);
  // 'auto' with a ShaderMaterial (its own code may call tessella_evaluate with gl_InstanceID),
  // and lod, stay per draw.
  const custom = new TessellatedMesh(source, new ShaderMaterial(), { scheme: 'pn', level: 4 });
  assert.match(custom.evaluationFallback, /ShaderMaterial/);
  const lod = new TessellatedMesh(source, undefined, { scheme: 'pn', lod: 'screen:8', spacing: 'equal', evaluation: 'per-frame' });
  assert.equal(lod.evaluation, 'per-draw');
  assert.match(lod.evaluationFallback, /lod/);
  const lodAuto = new TessellatedMesh(source, undefined, { scheme: 'pn', lod: 'screen:8', spacing: 'equal' });
  assert.match(lodAuto.evaluationFallback, /lod/);
  assert.throws(() => new TessellatedMesh(source, undefined, { evaluation: 'per-vertex' }), (e) => e instanceof TessellaError && /evaluation/.test(e.message));
  for (const m of [plain, auto, baked, custom, lod, lodAuto]) m.dispose();
});
