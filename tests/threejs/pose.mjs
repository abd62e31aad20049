// three.js's pose of a glTF file at a moment, as JSON on stdout: for every mesh primitive
// (three.js's traversal order), its vertex positions in world coordinates after morph
// targets and skinning, computed on the CPU by three.js itself (Mesh.getVertexPosition).
// Usage: node pose.mjs FILE ANIMATION SECONDS   (ANIMATION -1: the static pose)
import fs from 'node:fs';
import * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';

// GLTFLoader looks for a worker global and a URL maker; images then fail quietly.
globalThis.self = globalThis;
const [file, anim, seconds] = process.argv.slice(2);
// Images need a DOM; positions do not. Their failures are expected, so they are quiet.
console.error = () => {};
console.warn = () => {};
const bytes = fs.readFileSync(file);
const data = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
new GLTFLoader().parse(data, '', (gltf) => {
  const a = Number(anim);
  if (a >= 0) {
    const mixer = new THREE.AnimationMixer(gltf.scene);
    const action = mixer.clipAction(gltf.animations[a]);
    // glTF holds the last key after the end; three.js would loop.
    action.setLoop(THREE.LoopOnce, 1);
    action.clampWhenFinished = true;
    action.play();
    mixer.setTime(Number(seconds));
  }
  gltf.scene.updateMatrixWorld(true);
  const meshes = [];
  const v = new THREE.Vector3();
  gltf.scene.traverse((o) => {
    if (!o.isMesh) return;
    const n = o.geometry.attributes.position.count;
    const out = new Array(n * 3);
    for (let i = 0; i < n; i++) {
      o.getVertexPosition(i, v);
      v.applyMatrix4(o.matrixWorld);
      out[i * 3] = v.x;
      out[i * 3 + 1] = v.y;
      out[i * 3 + 2] = v.z;
    }
    meshes.push(out);
  });
  process.stdout.write(JSON.stringify(meshes));
}, (e) => {
  process.stdout.write(JSON.stringify({ error: String(e) }));
  process.exit(1);
});
