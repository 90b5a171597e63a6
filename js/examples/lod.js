// LOD on a scene of many meshes: 16 coarse meshes (three kinds), each a TessellatedMesh with
// `lod: 'screen:PX'`: every coarse edge gets its level from its length on the screen, every
// frame, crack-free (the tessellator's fractional-odd patterns). The camera flies through the
// rows; near meshes get fine, far ones coarse; the stats line counts what is drawn and uploaded.
import * as THREE from 'three';
import { ready } from 'tessella';
import { TessellatedMesh } from 'tessella/three';
import { frame, ground, run, stage, statsLine } from './common.js';

const $ = (id) => document.getElementById(id);
const stats = statsLine();
const GRID = 4;

run(async () => {
  await ready;
  const s = stage();
  const kinds = [
    () => new THREE.IcosahedronGeometry(0.8, 1),
    () => new THREE.TorusKnotGeometry(0.55, 0.2, 48, 6),
    () => new THREE.TorusGeometry(0.6, 0.25, 6, 12),
  ];
  const colours = [0x3377cc, 0xcc7733, 0x55aa66];
  const field = new THREE.Group();
  s.scene.add(field);
  const meshes = [];
  let coarse = 0;
  const build = () => {
    for (const m of meshes) {
      m.removeFromParent();
      m.dispose();
    }
    meshes.length = 0;
    coarse = 0;
    for (let i = 0; i < GRID; i++) {
      for (let j = 0; j < GRID; j++) {
        const k = (i + j) % kinds.length;
        const source = new THREE.Mesh(kinds[k](), new THREE.MeshStandardMaterial({ color: colours[k], roughness: 0.5 }));
        source.position.set((i - (GRID - 1) / 2) * 2.4, 0.9, (j - (GRID - 1) / 2) * 2.4);
        source.rotation.set(0.3 * i, 0.5 * j, 0);
        source.castShadow = true;
        field.add(source);
        const p = source.geometry.getAttribute('position');
        coarse += (source.geometry.index?.count ?? p.count) / 3;
        // The camera and size given: the levels are the camera's from the first frame.
        const size = [s.renderer.domElement.width, s.renderer.domElement.height];
        meshes.push(new TessellatedMesh(source, undefined, { scheme: 'pn', lod: `screen:${$('pixels').value}`, spacing: 'fractional-odd', camera: s.camera, size }));
      }
    }
  };
  build();
  $('pixels').oninput = () => {
    $('pixels-value').textContent = $('pixels').value;
    build();
  };
  field.updateMatrixWorld(true);
  ground(s.scene, field);
  frame(s, field, new THREE.Vector3(0.2, 0.5, 1));
  window.addEventListener('resize', () => {
    for (const m of meshes) m.lod.size = [s.renderer.domElement.width, s.renderer.domElement.height];
  });
  let t = 0;
  return {
    ...s,
    tick(dt) {
      if ($('fly').checked) {
        // Low over the field, in and out along a figure of eight.
        t += dt;
        s.camera.position.set(9 * Math.sin(0.25 * t), 2.2 + Math.sin(0.4 * t), 9 * Math.sin(0.5 * t));
        s.controls.target.set(0, 0.9, 0);
        s.controls.update();
      }
      const triangles = meshes.reduce((n, m) => n + m.lod.triangleCount, 0);
      const bytes = meshes.reduce((n, m) => n + m.lod.uploadedBytes, 0);
      const draws = meshes.reduce((n, m) => n + m.lod.children.filter((c) => c.visible).length, 0);
      stats.show(`${meshes.length} meshes, ${coarse} coarse triangles → ${triangles} drawn in ${draws} instanced draws\nlevels uploaded this frame: ${bytes} bytes (${(bytes / coarse).toFixed(1)} per coarse triangle)`);
    },
  };
});
