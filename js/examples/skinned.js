// The bundled creature (a SkinnedMesh with a morph target) played by three's AnimationMixer,
// twice: on the left three's own coarse SkinnedMesh, on the right a TessellatedMesh that
// follows its skeleton; each frame uploads the nets alone.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import * as SkeletonUtils from 'three/addons/utils/SkeletonUtils.js';
import { ready } from 'tessella';
import { TessellatedMesh } from 'tessella/three';
import { frame, ground, run, stage, statsLine } from './common.js';

const $ = (id) => document.getElementById(id);
const stats = statsLine();

run(async () => {
  await ready;
  const s = stage();
  const gltf = await new GLTFLoader().loadAsync('/samples/animated-creature.glb');
  const coarse = gltf.scene;
  const smooth = SkeletonUtils.clone(coarse);
  const pair = new THREE.Group();
  pair.add(coarse, smooth);
  s.scene.add(pair);
  pair.updateMatrixWorld(true);
  const width = new THREE.Box3().setFromObject(coarse, true).getSize(new THREE.Vector3()).x;
  coarse.position.x = -0.65 * width;
  smooth.position.x = 0.65 * width;
  const mixers = [new THREE.AnimationMixer(coarse), new THREE.AnimationMixer(smooth)];
  let skinned = null;
  smooth.traverse((o) => {
    if (o.isSkinnedMesh) skinned = o;
  });
  coarse.traverse((o) => {
    if (o.isMesh) o.castShadow = true;
  });
  skinned.castShadow = true;
  let tessellated = null;
  const build = () => {
    tessellated?.removeFromParent();
    tessellated?.dispose();
    tessellated = new TessellatedMesh(skinned, undefined, { scheme: 'pn', level: Number($('level').value) });
  };
  build();
  for (const clip of gltf.animations) $('clip').append(new Option(clip.name, clip.name));
  const play = () => {
    for (const m of mixers) {
      m.stopAllAction();
      m.clipAction(THREE.AnimationClip.findByName(gltf.animations, $('clip').value)).play();
    }
  };
  $('clip').onchange = play;
  $('level').oninput = () => {
    $('level-value').textContent = $('level').value;
    build();
  };
  play();
  pair.updateMatrixWorld(true);
  ground(s.scene, pair);
  frame(s, pair, new THREE.Vector3(0, 0.3, 1));
  const faces = skinned.geometry.index.count / 3;
  return {
    ...s,
    tick(dt) {
      for (const m of mixers) m.update(dt);
      const level = Number($('level').value);
      stats.show(`left: three's SkinnedMesh, ${faces} triangles\nright: TessellatedMesh, ${faces * level * level} triangles in one instanced draw\nuploaded per frame: ${tessellated.uploadedBytes} bytes (${(tessellated.uploadedBytes / faces).toFixed(0)} per coarse triangle)`);
    },
  };
});
