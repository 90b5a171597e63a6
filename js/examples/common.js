// What every example page shares: a WebGLRenderer filling the window, a camera with orbit
// controls framed on an object, a light rig with shadows, a line of stats, and
// `window.example` (a promise the browser test awaits, then the frames drawn).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { TessellaError } from 'tessella';
import { TessellatedMesh } from 'tessella/three';

export function stage({ shadows = true } = {}) {
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
  renderer.setSize(window.innerWidth, window.innerHeight);
  renderer.shadowMap.enabled = shadows;
  document.body.append(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf2f2f0);
  const camera = new THREE.PerspectiveCamera(40, window.innerWidth / window.innerHeight, 0.01, 500);
  const controls = new OrbitControls(camera, renderer.domElement);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.2));
  const sun = new THREE.DirectionalLight(0xffffff, 2.2);
  sun.castShadow = shadows;
  sun.shadow.mapSize.set(2048, 2048);
  sun.shadow.intensity = 0.6;
  scene.add(sun, sun.target);
  window.addEventListener('resize', () => {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
  });
  return { renderer, scene, camera, controls, sun };
}

/** Points the camera and the sun's shadow at `object`, seen from `direction`. */
export function frame({ camera, controls, sun }, object, direction = new THREE.Vector3(0.4, 0.35, 1)) {
  const box = new THREE.Box3().setFromObject(object, true);
  const centre = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3()).length();
  camera.position.copy(centre).add(direction.clone().normalize().multiplyScalar(1.5 * size));
  camera.near = size / 100;
  camera.far = size * 20;
  camera.updateProjectionMatrix();
  controls.target.copy(centre);
  controls.update();
  sun.position.copy(centre).add(new THREE.Vector3(1, 2.5, 1.5).multiplyScalar(size));
  sun.target.position.copy(centre);
  Object.assign(sun.shadow.camera, { left: -size, right: size, top: size, bottom: -size, near: size / 10, far: size * 8 });
  sun.shadow.camera.updateProjectionMatrix();
  return { centre, size };
}

/** A ground plane under `object` that receives shadows. */
export function ground(scene, object) {
  const box = new THREE.Box3().setFromObject(object, true);
  const size = box.getSize(new THREE.Vector3()).length();
  const plane = new THREE.Mesh(new THREE.PlaneGeometry(6 * size, 6 * size), new THREE.MeshStandardMaterial({ color: 0xd8d8d0 }));
  plane.rotation.x = -Math.PI / 2;
  plane.position.y = box.min.y - 0.002 * size;
  plane.receiveShadow = true;
  scene.add(plane);
  return plane;
}

/** The stats line at the top left; `show(text)` replaces it. */
export function statsLine() {
  const div = document.createElement('div');
  div.style.cssText = 'position:fixed;left:8px;top:8px;font:13px/1.4 system-ui,sans-serif;background:#fffc;padding:4px 8px;border-radius:4px;white-space:pre';
  document.body.append(div);
  return { show: (text) => (div.textContent = text), element: div };
}

/** A message in place of the picture: what went wrong, never a blank page. */
export function fail(error) {
  const div = document.createElement('div');
  div.style.cssText = 'position:fixed;inset:30% 10% auto;font:15px system-ui,sans-serif;background:#fee;border:1px solid #c66;padding:12px';
  div.textContent = error instanceof TessellaError ? `tessella: ${error.message}` : `error: ${error?.message ?? error}`;
  document.body.append(div);
  console.error(error);
}

/**
 * Runs `setup` (async: returns `{ renderer, scene, camera, tick(seconds) }`), then draws
 * every animation frame; sets `window.example` to a promise the tests wait for (after two
 * frames drawn) of `{ frames(), pause(), showTessellated(visible) }`.
 */
export function run(setup) {
  let frames = 0;
  let paused = false;
  window.example = (async () => {
    const { renderer, scene, camera, tick } = await setup();
    const timer = new THREE.Timer();
    await new Promise((drawn) => {
      renderer.setAnimationLoop(() => {
        try {
          timer.update();
          const dt = timer.getDelta();
          if (!paused) tick?.(dt);
          renderer.render(scene, camera);
        } catch (e) {
          renderer.setAnimationLoop(null);
          fail(e);
        }
        if (++frames === 2) drawn();
      });
    });
    return {
      frames: () => frames,
      /** Stops the clock (the scene holds still; frames are still drawn). */
      pause: () => (paused = true),
      /** Shows or hides every TessellatedMesh; resolves once a frame was drawn. */
      showTessellated: (visible) => {
        scene.traverse((o) => {
          if (o instanceof TessellatedMesh) o.visible = visible;
        });
        const at = frames;
        return new Promise(function wait(done) {
          if (frames > at + 1) done();
          else requestAnimationFrame(() => wait(done));
        });
      },
    };
  })();
  window.example.catch(fail);
}
