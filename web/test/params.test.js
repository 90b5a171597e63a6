// The parameters without a browser: checking (NaN, unknown names, bad specs), the URL round
// trip, the served MIME types and paths, the camera's framing against its defining properties.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { checkParams, DEFAULTS, fromSearch, toSearch } from '../src/params.js';
import { project, toGlClip } from '../src/camera.js';
import { ready, sceneCamera } from '../../js/src/index.js';
import { panelWidths } from '../src/panels.js';
import { MIME, resolvePath } from '../scripts/serve.js';

test('bad values are refused with the parameter named', () => {
  for (const [params, word] of [
    [{ level: 'NaN' }, 'level'],
    [{ level: '' }, 'level'],
    [{ level: 0 }, 'level'],
    [{ zoom: '-1' }, 'zoom'],
    [{ yaw: 'Infinity' }, 'yaw'],
    [{ scheme: 'bezier' }, 'scheme'],
    [{ lod: 'screen:0' }, 'lod'],
    [{ lod: 'distance:5,1,8' }, 'lod'],
    [{ displace: 'sine:0.1' }, 'displace'],
    [{ wireframe: 'maybe' }, 'wireframe'],
    [{ panels: 'flat,cubic' }, 'panels'],
    [{ tags: '{' }, 'tags'],
    [{ colour: 'red' }, 'colour'],
  ]) {
    assert.throws(() => checkParams(params), (e) => e.message.includes(word), JSON.stringify(params));
  }
});

test('URL strings become typed values', () => {
  const p = checkParams({ level: '5.5', wireframe: '1', pan: '0.1,-0.2', panels: 'flat,pn', lod: 'screen:8', yaw: '-40' });
  assert.deepEqual(p, { level: 5.5, wireframe: true, pan: [0.1, -0.2], panels: ['flat', 'pn'], lod: 'screen:8', yaw: -40 });
});

test('the URL holds what differs from the defaults and reads back the same', () => {
  const state = { ...structuredClone(DEFAULTS), scheme: 'png1', level: 12, wireframe: true, yaw: -15, panels: ['flat', 'pn'], mesh: 'samples/torus.obj' };
  const q = toSearch(state);
  assert.equal(q, 'mesh=samples%2Ftorus.obj&scheme=png1&level=12&wireframe=1&yaw=-15&panels=flat%2Cpn');
  const back = { ...structuredClone(DEFAULTS), ...checkParams(fromSearch(q)) };
  assert.deepEqual(back, state);
  assert.equal(toSearch(DEFAULTS), '');
});

test("the page's camera (the npm package's sceneCamera) frames the points inside the view, and toGlClip keeps its planes", async () => {
  await ready;
  // Corners of a box: its bounding sphere, grown by a fifth, is what is framed.
  const corners = [];
  for (const x of [-1, 3]) for (const y of [0, 4]) for (const z of [1, 3]) corners.push(x, y, z);
  const c = [1, 2, 2];
  for (const [yaw, pitch, w, h] of [[0, 0, 100, 100], [45, 30, 200, 100], [200, -60, 50, 100]]) {
    const cam = sceneCamera(corners, { yaw, pitch, zoom: 1, width: w, height: h });
    const centre = project(cam.viewProj, c, w, h);
    assert.ok(Math.abs(centre[0] - w / 2) < 1e-3 && Math.abs(centre[1] - h / 2) < 1e-3, String(centre));
    for (let i = 0; i < corners.length; i += 3) {
      const q = project(cam.viewProj, corners.slice(i, i + 3), w, h);
      assert.ok(q[0] >= 0 && q[0] <= w && q[1] >= 0 && q[1] <= h && q[2] > 0 && q[2] < 1, String(q));
      // OpenGL's clip depth: the same point, depth moved from 0..1 to -1..1.
      const g = project(toGlClip(cam.viewProj), corners.slice(i, i + 3), w, h);
      assert.ok(Math.abs(g[0] - q[0]) < 1e-3 && Math.abs(g[2] - (2 * q[2] - 1)) < 1e-5, String(g));
    }
    assert.equal(cam.fovY, 30);
    assert.ok(Math.abs(Math.hypot(...cam.eye.map((e, k) => e - cam.target[k])) - cam.distance) < 1e-3 * cam.distance);
  }
  // yaw 0, pitch 0 looks along -Z from +Z.
  const cam = sceneCamera(corners, { yaw: 0, pitch: 0, width: 1, height: 1 });
  assert.ok(cam.eye[2] > 3 && Math.abs(cam.eye[0] - 1) < 1e-6 && Math.abs(cam.eye[1] - 2) < 1e-6);
  assert.throws(() => sceneCamera(corners, { width: 0, height: 1 }), /width must be a positive number/);
});

test('panel widths are tessella-view panel_widths', () => {
  // 803 - 3 gaps of 2 = 797 = 4 x 199 + 1: the first panel one pixel wider.
  assert.deepEqual(panelWidths(803, 4), [200, 199, 199, 199]);
  assert.deepEqual(panelWidths(802, 4), [199, 199, 199, 199]);
  assert.equal(panelWidths(3, 4), null);
  assert.deepEqual(panelWidths(100, 1), [100]);
});

test('the server maps module scripts and wasm to the MIME types browsers require, and stays in its root', () => {
  assert.match(MIME['.js'], /^text\/javascript/);
  assert.match(MIME['.mjs'], /^text\/javascript/);
  assert.equal(MIME['.wasm'], 'application/wasm');
  assert.equal(MIME['.json'], 'application/json');
  assert.equal(MIME['.glb'], 'model/gltf-binary');
  assert.equal(resolvePath('/srv/site', '/../../etc/passwd'), '/srv/site/etc/passwd');
  assert.equal(resolvePath('/srv/site', '/%2e%2e/x'), '/srv/site/x');
  assert.equal(resolvePath('/srv/site', '/a%ZZ'), null);
  assert.equal(resolvePath('/srv/site', '/samples/x.obj?v=1'), '/srv/site/samples/x.obj');
});
