// What the three.js test pages (mesh.js, webgpu.js, lod.js, skinned.js, scene.js,
// webgpuskinned.js) share: a WebGLRenderer on a white canvas of one size, a WebGPURenderer
// likewise with the render target its pictures are read back from, calls spied on (to count
// draws and uploaded bytes), the torus-knot scene of mesh.js and webgpu.js (its camera and
// lights, its bending, its vertex colours and checker texture), and the animated creature of
// the skinned pages with the vertices three skins.
import * as THREE from 'three';

/** A WebGLRenderer on a new canvas of `width` x `height` pixels, cleared white, readable back. */
export function glRenderer(width, height) {
  const canvas = document.createElement('canvas');
  document.body.append(canvas);
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(width, height);
  renderer.setClearColor(0xffffff, 1);
  return { canvas, renderer };
}

/**
 * A WebGPURenderer (three/webgpu) on a new canvas of `width` x `height` pixels, cleared white,
 * with a render target of sRGB bytes (as the canvas would show them: the shading's differences
 * are not lost in the darks) that `readTarget` reads back; `started` is its `init()`. three/webgpu
 * is imported here on demand, so the WebGL pages never load it.
 */
export async function gpuRenderer(width, height) {
  const { WebGPURenderer } = await import('three/webgpu');
  const canvas = document.createElement('canvas');
  document.body.append(canvas);
  const renderer = new WebGPURenderer({ canvas, antialias: false });
  renderer.setPixelRatio(1);
  renderer.setSize(width, height);
  renderer.setClearColor(0xffffff, 1);
  const target = new THREE.RenderTarget(width, height, { colorSpace: THREE.SRGBColorSpace });
  return { canvas, renderer, target, started: renderer.init() };
}

/**
 * What `renderer` drew into `target` (once the queue is done), as the pages return pictures:
 * `{ width, height, rgba }`, RGBA bytes in base64, rows top first (as a PNG's).
 */
export async function readTarget(renderer, target) {
  const { width, height } = target;
  await renderer.backend.device.queue.onSubmittedWorkDone();
  const pixels = await renderer.readRenderTargetPixelsAsync(target, 0, 0, width, height);
  let binary = '';
  const bytes = new Uint8Array(pixels.buffer, pixels.byteOffset, width * height * 4);
  for (let i = 0; i < bytes.length; i += 0x8000) binary += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return { width, height, rgba: btoa(binary) };
}

/** Calls `record(args)` before each call of `target[name]` (a context, or a prototype). */
export function spy(target, name, record) {
  const original = target[name];
  target[name] = function (...args) {
    record(args);
    return original.apply(this ?? target, args);
  };
}

/** The source's pose at a frame: frame 0 is the rest pose; later frames bend it. */
export function pose(geometry, rest, frame) {
  const p = geometry.getAttribute('position');
  for (let i = 0; i < p.count; i++) {
    const [x, y, z] = [rest[3 * i], rest[3 * i + 1], rest[3 * i + 2]];
    const b = 0.25 * frame;
    p.setXYZ(i, x, y + b * x * x - 0.2 * b, z * (1 + 0.15 * frame));
  }
  p.needsUpdate = true;
  geometry.computeVertexNormals();
}

/** A 64 x 64 checker texture of 8-pixel squares, white and dark grey. */
export function checkerTexture() {
  const checker = new Uint8Array(64 * 64 * 4);
  for (let i = 0; i < 64 * 64; i++) checker.set(((i % 64 >> 3) + (i >> 9)) % 2 ? [255, 255, 255, 255] : [60, 60, 60, 255], 4 * i);
  const map = new THREE.DataTexture(checker, 64, 64);
  map.needsUpdate = true;
  return map;
}

/** Gives the torus knot's vertices colours (a `color` attribute) that vary along it. */
export function vertexColours(geometry) {
  const c = new Float32Array(geometry.getAttribute('position').count * 3);
  for (let i = 0; i < c.length; i += 3) c.set([1, (i / c.length) % 1, 0.5], i);
  geometry.setAttribute('color', new THREE.BufferAttribute(c, 3));
}

/**
 * The torus knot's scene: its camera, an ambient light and a shadow-casting directional light,
 * or (`point`) a point light, whose shadows take the distance material; `plane`: a ground that
 * receives shadows; `occluder`: a ball above the knot, casting a shadow when `occluderCasts`.
 */
export function torusScene({ width, height, point = false, plane = false, occluder = false, occluderCasts = true }) {
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(40, width / height, 0.1, 50);
  camera.position.set(0, 2.2, 5.2);
  camera.lookAt(0, -0.3, 0);
  scene.add(new THREE.AmbientLight(0xffffff, 0.4));
  const light = point ? new THREE.PointLight(0xffffff, 40, 0, 2) : new THREE.DirectionalLight(0xffffff, 2.5);
  light.position.set(1.5, 5, 1);
  light.castShadow = true;
  light.shadow.mapSize.set(1024, 1024);
  if (point) Object.assign(light.shadow.camera, { near: 0.5, far: 12 });
  else Object.assign(light.shadow.camera, { left: -3, right: 3, top: 3, bottom: -3, near: 0.5, far: 12 });
  scene.add(light);
  if (plane) {
    const ground = new THREE.Mesh(new THREE.PlaneGeometry(10, 10), new THREE.MeshStandardMaterial({ color: 0xdddddd }));
    ground.rotation.x = -Math.PI / 2;
    ground.position.y = -1.4;
    ground.receiveShadow = true;
    scene.add(ground);
  }
  if (occluder) {
    const ball = new THREE.Mesh(new THREE.SphereGeometry(0.35, 24, 12), new THREE.MeshBasicMaterial({ color: 0x222222 }));
    ball.position.set(0.45, 2.2, 0.1);
    ball.castShadow = occluderCasts;
    scene.add(ball);
  }
  return { scene, camera };
}
