// A glTF file loaded by three's GLTFLoader (the bundled creature, `?file=URL`, or one picked),
// every Mesh and SkinnedMesh in it replaced by a TessellatedMesh with a clone of its own
// material; its first clip plays through an AnimationMixer.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { ready } from 'tessella';
import { TessellatedMesh } from 'tessella/three';
import { fail, frame, ground, run, stage, statsLine } from './common.js';

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);
const stats = statsLine();

run(async () => {
  await ready;
  const s = stage();
  const loader = new GLTFLoader();
  let shown = null; // { model, floor, mixer, sources, tessellated, clips, triangles }

  const options = () => ({ scheme: $('scheme').value, level: Number($('level').value) });
  // Replaces every mesh of the shown model by a TessellatedMesh (again, after a change of options).
  const tessellate = () => {
    for (const t of shown.tessellated) {
      t.removeFromParent();
      t.dispose();
    }
    shown.tessellated = shown.sources.map((m) => new TessellatedMesh(m, undefined, options()));
    showCoarse();
  };
  const showCoarse = () => {
    const coarse = $('coarse').checked;
    for (const m of shown.sources) m.visible = coarse;
    for (const t of shown.tessellated) t.visible = !coarse;
  };
  const open = (gltf) => {
    if (shown !== null) {
      for (const t of shown.tessellated) t.dispose();
      s.scene.remove(shown.model, shown.floor);
    }
    const model = gltf.scene;
    s.scene.add(model);
    const mixer = new THREE.AnimationMixer(model);
    if (gltf.animations.length > 0) mixer.clipAction(gltf.animations[0]).play();
    model.updateMatrixWorld(true);
    const sources = [];
    model.traverse((o) => {
      if (o.isMesh) sources.push(o);
    });
    for (const m of sources) m.castShadow = true;
    const floor = ground(s.scene, model);
    frame(s, model);
    const triangles = sources.reduce((n, m) => n + (m.geometry.index?.count ?? m.geometry.getAttribute('position').count) / 3, 0);
    shown = { model, floor, mixer, sources, tessellated: [], clips: gltf.animations.length, triangles };
    tessellate();
  };

  $('scheme').onchange = () => guard(tessellate);
  $('level').oninput = () => {
    $('level-value').textContent = $('level').value;
    guard(tessellate);
  };
  $('coarse').onchange = showCoarse;
  $('file').onchange = async () => {
    const file = $('file').files[0];
    if (file === undefined) return;
    try {
      open(await loader.parseAsync(await file.arrayBuffer(), ''));
    } catch (e) {
      fail(e);
    }
  };
  open(await loader.loadAsync(params.get('file') ?? '/samples/animated-creature.glb'));
  return {
    ...s,
    tick(dt) {
      shown.mixer.update(dt);
      const { level } = options();
      const bytes = shown.tessellated.reduce((n, t) => n + t.uploadedBytes, 0);
      const { sources, triangles, clips } = shown;
      stats.show(`${sources.length} meshes, ${triangles} coarse triangles → ${triangles * level * level} drawn in ${sources.length} instanced draws\nlast update uploaded ${bytes} bytes (the nets); ${clips} clips`);
    },
  };
});

function guard(fn) {
  try {
    fn();
  } catch (e) {
    fail(e);
  }
}
