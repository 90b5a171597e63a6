// The test page of `tessella refine`'s glTF scene output read by three.js
// (web/test/three-gltf-refined.test.js, and web/scripts/scene-picture.js for the README's
// picture): three's GLTFLoader parses a GLB handed over as base64; `describe` says what the
// loaded scene graph holds (meshes, materials, textures and their decoded images, animations,
// skinned meshes, each primitive's triangles), `pose` plays a clip with three's AnimationMixer
// and returns the skinned mesh's vertices as three skins them on the CPU (getVertexPosition:
// morph targets, then skinning) in world space, and `picture` draws two GLBs side by side with
// WebGLRenderer, each panel labelled.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

function bytes(base64) {
  const s = atob(base64);
  const out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) out[i] = s.charCodeAt(i);
  return out;
}

function base64(typed) {
  const u8 = new Uint8Array(typed.buffer, typed.byteOffset, typed.byteLength);
  let s = '';
  for (let i = 0; i < u8.length; i += 0x8000) s += String.fromCharCode(...u8.subarray(i, i + 0x8000));
  return btoa(s);
}

/** The GLB (base64) parsed by GLTFLoader: `{ scene, animations, cameras, ... }`. */
function load(glb) {
  const b = bytes(glb);
  return new Promise((resolve, reject) => new GLTFLoader().parse(b.buffer, '', resolve, reject));
}

/** Colours an image holds, sampled on a grid of `n` x `n` pixels (a decoded checker has 2+). */
function colours(image, n = 16) {
  const canvas = document.createElement('canvas');
  canvas.width = image.width;
  canvas.height = image.height;
  const ctx = canvas.getContext('2d');
  ctx.drawImage(image, 0, 0);
  const seen = new Set();
  const { data } = ctx.getImageData(0, 0, image.width, image.height);
  for (let j = 0; j < n; j++) {
    for (let i = 0; i < n; i++) {
      const x = Math.floor(((i + 0.5) / n) * image.width);
      const y = Math.floor(((j + 0.5) / n) * image.height);
      const k = 4 * (y * image.width + x);
      seen.add(`${data[k]},${data[k + 1]},${data[k + 2]}`);
    }
  }
  return seen.size;
}

/**
 * What three made of the GLB: counts of meshes (Mesh, SkinnedMesh included), skinned meshes,
 * lines, points, materials, textures (with their images' sizes and colours), animations (name,
 * duration, tracks), cameras and lights, and each drawn object in traversal order with its
 * triangles (lines, points: its vertices), vertices, attributes and morph targets.
 */
async function describe({ glb }) {
  const gltf = await load(glb);
  const materials = new Set();
  const textures = new Map(); // texture -> the material slots that use it ('Checker.map')
  const objects = [];
  const count = { meshes: 0, skinned: 0, lines: 0, points: 0, cameras: 0, lights: 0 };
  gltf.scene.updateMatrixWorld(true);
  gltf.scene.traverse((o) => {
    if (o.isCamera) count.cameras++;
    if (o.isLight) count.lights++;
    if (!o.isMesh && !o.isLine && !o.isPoints) return;
    if (o.isMesh) count.meshes++;
    if (o.isSkinnedMesh) count.skinned++;
    if (o.isLine) count.lines++;
    if (o.isPoints) count.points++;
    for (const m of Array.isArray(o.material) ? o.material : [o.material]) {
      materials.add(m);
      for (const [slot, v] of Object.entries(m)) {
        if (v?.isTexture) textures.set(v, [...(textures.get(v) ?? []), `${m.name}.${slot}`]);
      }
    }
    const g = o.geometry;
    const vertices = g.getAttribute('position').count;
    const elements = g.index ? g.index.count : vertices;
    objects.push({
      name: o.name,
      type: o.type,
      material: o.material.name,
      vertices,
      triangles: o.isMesh ? elements / 3 : null,
      elements,
      attributes: Object.keys(g.attributes).sort(),
      morphTargets: g.morphAttributes.position?.length ?? 0,
      box: new THREE.Box3().setFromObject(o, true).getSize(new THREE.Vector3()).toArray(),
    });
  });
  return {
    ...count,
    materials: [...materials].map((m) => m.name).sort(),
    textures: [...textures].map(([t, slots]) => ({
      name: t.name,
      slots: [...new Set(slots)].sort(),
      width: t.image?.width ?? 0,
      height: t.image?.height ?? 0,
      colours: t.image?.width > 0 ? colours(t.image) : 0,
    })),
    animations: gltf.animations.map((a) => ({ name: a.name, duration: a.duration, tracks: a.tracks.length })),
    objects,
  };
}

/**
 * Plays `clip` of the GLB with an AnimationMixer to `time` seconds (held at the clip's end past
 * it, as `tessella refine --clip --time` does) and returns the first skinned mesh's vertices as
 * three skins them on the CPU (`SkinnedMesh.getVertexPosition`: morph targets, then bones), in
 * world space, as base64 float32 x, y, z; `rest`, the same before the clip is applied.
 */
async function pose({ glb, clip, time }) {
  const gltf = await load(glb);
  let skinned = null;
  gltf.scene.traverse((o) => {
    if (o.isSkinnedMesh && skinned === null) skinned = o;
  });
  if (skinned === null) throw new Error('the file has no skinned mesh');
  const read = () => {
    gltf.scene.updateMatrixWorld(true);
    const n = skinned.geometry.getAttribute('position').count;
    const out = new Float32Array(3 * n);
    const v = new THREE.Vector3();
    for (let i = 0; i < n; i++) skinned.getVertexPosition(i, v).applyMatrix4(skinned.matrixWorld).toArray(out, 3 * i);
    return out;
  };
  const rest = read();
  const found = THREE.AnimationClip.findByName(gltf.animations, clip);
  if (!found) throw new Error(`no clip named ${clip}`);
  const mixer = new THREE.AnimationMixer(gltf.scene);
  const action = mixer.clipAction(found);
  action.setLoop(THREE.LoopOnce, 1);
  action.clampWhenFinished = true;
  action.play();
  mixer.setTime(time);
  const posed = read();
  return {
    positions: base64(posed),
    rest: base64(rest),
    duration: found.duration,
    morphInfluences: Array.from(skinned.morphTargetInfluences ?? []),
    influences: skinned.geometry.getAttribute('skinWeight').itemSize,
  };
}

/**
 * Draws each GLB of `panels` (`{ glb, label }`) in its own panel of `width` x `height` pixels,
 * side by side, with three's WebGLRenderer (scissored viewports on one canvas), the file's
 * lights plus an ambient and a hemisphere light, a camera looking at the point `target` from
 * `eye` (fov in degrees), then writes each label under its panel. Returns the PNG as a data URL
 * and, per panel, the pixels that are not the background.
 */
async function picture({ panels, width = 600, height = 400, eye = [-2.6, 1.6, 4.4], target = [-0.15, 0.05, 0], fov = 35, background = 0xffffff, labelHeight = 40, pixelRatio = 1 }) {
  const canvas = document.createElement('canvas');
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(pixelRatio);
  renderer.setSize(width * panels.length, height);
  renderer.setClearColor(background, 1);
  renderer.setScissorTest(true);
  const camera = new THREE.PerspectiveCamera(fov, width / height, 0.05, 100);
  camera.position.fromArray(eye);
  camera.lookAt(new THREE.Vector3().fromArray(target));
  const drawn = [];
  for (const [k, panel] of panels.entries()) {
    const gltf = await load(panel.glb);
    const scene = gltf.scene;
    scene.add(new THREE.HemisphereLight(0xffffff, 0x8899aa, 1.2));
    const key = new THREE.DirectionalLight(0xffffff, 1.6);
    key.position.set(-3, 4, 5);
    scene.add(key);
    let triangles = 0;
    scene.traverse((o) => {
      if (o.isMesh) triangles += (o.geometry.index ? o.geometry.index.count : o.geometry.getAttribute('position').count) / 3;
    });
    drawn.push({ triangles });
    renderer.setViewport(k * width, 0, width, height);
    renderer.setScissor(k * width, 0, width, height);
    renderer.render(scene, camera);
  }
  // The labels: the WebGL picture copied onto a 2D canvas with a strip of text below.
  const out = document.createElement('canvas');
  out.width = canvas.width;
  out.height = canvas.height + labelHeight * pixelRatio;
  const ctx = out.getContext('2d');
  ctx.fillStyle = '#ffffff';
  ctx.fillRect(0, 0, out.width, out.height);
  ctx.drawImage(canvas, 0, 0);
  ctx.fillStyle = '#222222';
  ctx.font = `${Math.round(20 * pixelRatio)}px sans-serif`;
  ctx.textAlign = 'center';
  ctx.textBaseline = 'middle';
  for (const [k, panel] of panels.entries()) {
    ctx.fillText(panel.label, (k + 0.5) * width * pixelRatio, canvas.height + 0.5 * labelHeight * pixelRatio);
  }
  ctx.strokeStyle = '#cccccc';
  ctx.lineWidth = pixelRatio;
  for (let k = 1; k < panels.length; k++) {
    ctx.beginPath();
    ctx.moveTo(k * width * pixelRatio, 0);
    ctx.lineTo(k * width * pixelRatio, out.height);
    ctx.stroke();
  }
  renderer.dispose();
  return { png: out.toDataURL('image/png'), panels: drawn };
}

window.tessellaGltf = { describe, pose, picture, ready: Promise.resolve(true) };
