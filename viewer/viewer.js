// subsurf viewer: shows a .glb written by `subsurf tessellate ... -o OUT.glb [--control-mesh]`.
//
// Open a file with the file input, or pass ?model=URL. Drag to orbit, wheel to zoom,
// right-drag to pan. For tests the page sets window.__viewerReady (true once a model is
// shown) or window.__viewerError, and exposes __toggleZebra(on), __toggleControlMesh(on),
// __toggleChecker(on) and __snapshot().

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const BACKGROUND = 0xf2f2f2;
const CONTROL_MESH = 'control mesh'; // node name written by subsurf

const status = document.getElementById('status');
const zebraBox = document.getElementById('zebra');
const controlBox = document.getElementById('control');
const checkerBox = document.getElementById('checker');

let renderer;
try {
  renderer = new THREE.WebGLRenderer({ antialias: true });
} catch (e) {
  fail(e); // no WebGL
  throw e;
}
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setSize(window.innerWidth, window.innerHeight);
document.getElementById('view').appendChild(renderer.domElement);

const scene = new THREE.Scene();
scene.background = new THREE.Color(BACKGROUND);
const camera = new THREE.PerspectiveCamera(40, window.innerWidth / window.innerHeight, 0.01, 100);
camera.position.set(3, 2, 4);
scene.add(camera);
scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.2));
const key = new THREE.DirectionalLight(0xffffff, 2.0);
key.position.set(1, 1.5, 2);
camera.add(key); // the light follows the camera

const controls = new OrbitControls(camera, renderer.domElement);
controls.enableDamping = true;

// Frames are drawn on demand: after a change, and while the orbit is still gliding.
let framePending = false;
function render() {
  if (framePending) return;
  framePending = true;
  requestAnimationFrame(() => {
    framePending = false;
    controls.update(); // dispatches 'change' (so another frame) while damping moves
    renderer.render(scene, camera);
  });
}
controls.addEventListener('change', render);

// Zebra stripes, as `subsurf`'s renderer draws them (crates/subsurf/src/render/zebra.rs):
// the surface as a mirror in an environment of parallel light planes. The view ray is
// reflected by the normal, r = d - 2 (d.n) n, and the stripe is cos(k pi r.A) for a fixed
// axis A in view space: kinks in the stripes show curvature jumps, breaks show normal jumps.
const zebra = new THREE.ShaderMaterial({
  uniforms: {
    stripes: { value: 10.0 },
    axis: { value: new THREE.Vector3(0.45, 1.0, 0.25).normalize() },
  },
  side: THREE.DoubleSide,
  vertexShader: /* glsl */ `
    varying vec3 vNormal;
    varying vec3 vPosition;
    void main() {
      vec4 p = modelViewMatrix * vec4(position, 1.0);
      vPosition = p.xyz; // view space: the eye at the origin
      vNormal = normalMatrix * normal;
      gl_Position = projectionMatrix * p;
    }`,
  fragmentShader: /* glsl */ `
    uniform float stripes;
    uniform vec3 axis;
    varying vec3 vNormal;
    varying vec3 vPosition;
    void main() {
      vec3 d = normalize(vPosition);
      vec3 n = normalize(vNormal);
      if (dot(d, n) > 0.0) n = -n; // the side facing the eye
      vec3 r = d - 2.0 * dot(d, n) * n;
      float x = clamp(dot(r, axis), -1.0, 1.0);
      float s = smoothstep(-0.25, 0.25, cos(stripes * 3.14159265 * x));
      gl_FragColor = vec4(vec3(0.02 + 0.96 * s), 1.0);
      #include <colorspace_fragment>
    }`,
});

const lineMaterial = new THREE.LineBasicMaterial({ color: 0x1f4fbf });

// A checker texture through the model's texture coordinates (TEXCOORD_0, written by
// `subsurf tessellate` from the mesh's vt at their exact limit), in the colours of
// `subsurf render --texture checker`: 8 x 8 squares over the unit square, repeated beyond.
const CHECKER_SQUARES = 8;
const checkerTexture = (() => {
  const n = CHECKER_SQUARES;
  const data = new Uint8Array(4 * n * n);
  for (let i = 0; i < n * n; i++) {
    const odd = ((i % n) + Math.floor(i / n)) % 2 === 1;
    data.set(odd ? [56, 77, 107, 255] : [235, 230, 214, 255], 4 * i);
  }
  const t = new THREE.DataTexture(data, n, n);
  t.colorSpace = THREE.SRGBColorSpace;
  t.magFilter = THREE.NearestFilter;
  t.wrapS = t.wrapT = THREE.RepeatWrapping;
  t.needsUpdate = true;
  return t;
})();
const checker = new THREE.MeshStandardMaterial({
  map: checkerTexture,
  roughness: 0.6,
  side: THREE.DoubleSide,
});

let model = null; // the loaded glTF scene
const shaded = new Map(); // mesh -> its own material

// Each surface's material: zebra stripes, else the checker where the surface has texture
// coordinates, else its own.
function paint() {
  for (const [mesh, material] of shaded) {
    const uv = mesh.geometry.getAttribute('uv') !== undefined;
    mesh.material = zebraBox.checked ? zebra : checkerBox.checked && uv ? checker : material;
  }
  render();
}

function setZebra(on) {
  zebraBox.checked = on;
  if (on) checkerBox.checked = false;
  paint();
}

function setChecker(on) {
  checkerBox.checked = on && !checkerBox.disabled;
  if (checkerBox.checked) zebraBox.checked = false;
  paint();
}

function setControlMesh(on) {
  controlBox.checked = on;
  model?.traverse((o) => {
    if (o.userData.name === CONTROL_MESH || o.isLineSegments) o.visible = on;
  });
  render();
}

function fit() {
  if (!model) return;
  const box = new THREE.Box3().setFromObject(model);
  const sphere = box.getBoundingSphere(new THREE.Sphere());
  const r = Math.max(sphere.radius, 1e-9);
  const distance = (1.15 * r) / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2));
  const dir = camera.position.clone().sub(controls.target).normalize();
  controls.target.copy(sphere.center);
  camera.position.copy(sphere.center).addScaledVector(dir, distance);
  camera.near = distance / 100;
  camera.far = distance * 100;
  camera.updateProjectionMatrix();
  controls.update();
  render();
}

function show(gltf, name) {
  if (model) scene.remove(model);
  shaded.clear();
  model = gltf.scene;
  model.traverse((o) => {
    if (o.isMesh) shaded.set(o, o.material);
    if (o.isLineSegments) o.material = lineMaterial;
  });
  scene.add(model);
  // The checker needs texture coordinates: offered only when a surface has them.
  const textured = [...shaded.keys()].some((m) => m.geometry.getAttribute('uv') !== undefined);
  checkerBox.disabled = !textured;
  checkerBox.parentElement.title = textured ? '' : 'the model has no texture coordinates';
  if (!textured) checkerBox.checked = false;
  setZebra(zebraBox.checked);
  setControlMesh(controlBox.checked);
  fit();
  let triangles = 0;
  for (const mesh of shaded.keys()) triangles += (mesh.geometry.index?.count ?? 0) / 3;
  status.className = '';
  status.textContent = `${name}: ${triangles} triangles`;
  // Ready once a frame with the model has been drawn.
  requestAnimationFrame(() => requestAnimationFrame(() => { window.__viewerReady = true; }));
}

function fail(error) {
  console.error(error);
  status.className = 'error';
  status.textContent = `error: ${error.message ?? error}`;
  window.__viewerError = String(error.message ?? error);
}

const loader = new GLTFLoader();

function loadUrl(url) {
  window.__viewerReady = false;
  status.textContent = `loading ${url}`;
  loader.load(url, (gltf) => show(gltf, url.split('/').pop()), undefined, fail);
}

async function loadFile(file) {
  window.__viewerReady = false;
  try {
    const gltf = await loader.parseAsync(await file.arrayBuffer(), '');
    show(gltf, file.name);
  } catch (e) {
    fail(e);
  }
}

document.getElementById('file').addEventListener('change', (e) => {
  if (e.target.files[0]) loadFile(e.target.files[0]);
});
zebraBox.addEventListener('change', () => setZebra(zebraBox.checked));
controlBox.addEventListener('change', () => setControlMesh(controlBox.checked));
checkerBox.addEventListener('change', () => setChecker(checkerBox.checked));
document.getElementById('fit').addEventListener('click', fit);
window.addEventListener('resize', () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(window.innerWidth, window.innerHeight);
  render();
});

window.__toggleZebra = (on = !zebraBox.checked) => setZebra(on);
window.__toggleControlMesh = (on = !controlBox.checked) => setControlMesh(on);
window.__toggleChecker = (on = !checkerBox.checked) => setChecker(on);
// The picture as PNG (a data: URL), drawn now: what the canvas shows, without the toolbar.
window.__snapshot = () => {
  controls.update();
  renderer.render(scene, camera);
  return renderer.domElement.toDataURL('image/png');
};

render();

const param = new URLSearchParams(window.location.search).get('model');
if (param) loadUrl(param);
