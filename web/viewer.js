// GaussLOD's web viewer: a tileset written by `gausslod --3dtiles` (3d-tiles-renderer picks the
// level by screen-space error from each tile's geometricError, the level's certified distance)
// or a chain written by `gausslod --lod-file` (MSFT_lod: the level by the screen coverage the file
// gives, through three.js' LOD). The status line says which level is on screen, as renderers
// count them (LOD0 = full detail) and as the paper does, with its faces and its error.
// window.viewerState is what the browser test (test_viewer.mjs) reads.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { TilesRenderer } from '3d-tiles-renderer';

const params = new URLSearchParams(location.search);
const state = (window.viewerState = { ready: false, shown: [], frames: 0, error: null });
const status = document.getElementById('status');
const background = 0x20242b;

// (preserveDrawingBuffer: the test counts the pixels drawn)
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(1);
renderer.setSize(innerWidth, innerHeight);
renderer.setClearColor(background);
document.body.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.add(new THREE.HemisphereLight(0xffffff, 0x505060, 2.2));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(1, 2, 3);
scene.add(sun);
const camera = new THREE.PerspectiveCamera(45, innerWidth / innerHeight, 1e-3, 1e7);
const controls = new OrbitControls(camera, renderer.domElement);

// camera at `distance` bounding radii from the centre (a fixed direction), near and far planes
// to match
function frame(sphere) {
  const d = Number(params.get('distance') || 3) * sphere.radius;
  camera.position.copy(sphere.center).add(new THREE.Vector3(0.6, 0.45, 1).normalize().multiplyScalar(d));
  camera.near = Math.max(d - 2 * sphere.radius, d * 1e-3, 1e-6);
  camera.far = d + 4 * sphere.radius;
  camera.updateProjectionMatrix();
  controls.target.copy(sphere.center);
  controls.update();
}

function describe(list) {
  return list.map((t) => `LOD${t.lod}${t.level === null ? ' (the input)' : ` (paper level ${t.level})`}` +
    `, ${t.faces} faces, error ${t.error.toPrecision(3)}`).join('\n');
}

let update = () => {};

if (params.get('glb')) {
  // MSFT_lod: the full-detail node lists the coarser ones; MSFT_screencoverage gives, per level,
  // the screen coverage (share of the view's height) down to which it is shown
  new GLTFLoader().load(params.get('glb'), async (gltf) => {
    const json = gltf.parser.json;
    const rootIndex = json.scenes[json.scene || 0].nodes[0];
    const root = json.nodes[rootIndex];
    const ids = [rootIndex, ...((root.extensions && root.extensions.MSFT_lod && root.extensions.MSFT_lod.ids) || [])];
    const coverage = (root.extras && root.extras.MSFT_screencoverage) || [];
    const lod = new THREE.LOD();
    const nodes = await Promise.all(ids.map((i) => gltf.parser.getDependency('node', i)));
    const sphere = new THREE.Box3().setFromObject(nodes[0]).getBoundingSphere(new THREE.Sphere());
    const tanHalf = Math.tan(THREE.MathUtils.degToRad(camera.fov / 2));
    nodes.forEach((n, i) => {
      // shown from the distance at which the finer level's coverage threshold is crossed
      const c = i === 0 ? Infinity : coverage[i - 1];
      const distance = i === 0 ? 0 : (2 * sphere.radius) / (2 * Math.max(c, 1e-9) * tanHalf);
      n.userData.info = { lod: i, level: null, faces: 0, error: 0 };
      lod.addLevel(n, distance);
    });
    scene.add(lod);
    frame(sphere);
    update = () => {
      lod.update(camera);
      const i = lod.getCurrentLevel();
      state.shown = [{ lod: i, level: null, faces: 0, error: 0 }];
      status.textContent = `MSFT_lod: LOD${i} of ${ids.length} (LOD0 = full detail)`;
      state.ready = true;
    };
  }, undefined, (e) => { state.error = String(e); status.textContent = 'cannot load: ' + e; });
} else {
  const tiles = new TilesRenderer(params.get('tileset') || 'tiles/tileset.json');
  tiles.errorTarget = Number(params.get('errorTarget') || 2); // pixels
  tiles.setCamera(camera);
  tiles.setResolutionFromRenderer(camera, renderer);
  tiles.group.rotation.x = -Math.PI / 2; // (3D Tiles' z up to three.js' y up)
  scene.add(tiles.group);
  let framed = false;
  tiles.addEventListener('load-tileset', () => {
    if (framed)
      return;
    tiles.group.updateMatrixWorld(true);
    const sphere = new THREE.Sphere();
    if (tiles.getBoundingSphere(sphere)) {
      sphere.applyMatrix4(tiles.group.matrixWorld);
      frame(sphere);
      framed = true;
    }
  });
  tiles.addEventListener('load-error', (e) => { state.error = String(e.error || e); });
  let settled = 0;
  update = () => {
    camera.updateMatrixWorld();
    tiles.update();
    const shown = [...tiles.visibleTiles].map((t) => {
      const g = (t.extras && t.extras.gausslod) || {};
      return { lod: g.lod, level: g.level === undefined ? null : g.level, faces: g.faces || 0,
               error: t.geometricError, uri: t.content && t.content.uri,
               // (the screen-space errors, pixels, the renderer refined by)
               sse: t.traversal ? t.traversal.error : null, leaf: !(t.children && t.children.length),
               parentSse: t.parent && t.parent.traversal ? t.parent.traversal.error : null };
    }).sort((a, b) => a.lod - b.lod);
    state.errorTarget = tiles.errorTarget;
    const key = (l) => JSON.stringify(l.map((t) => t.uri));
    const same = key(shown) === key(state.shown);
    state.shown = shown;
    // ready once something is shown, nothing is loading and the choice held for 10 frames
    const loading = tiles.stats ? tiles.stats.downloading + tiles.stats.parsing : 0;
    settled = same && shown.length && !loading ? settled + 1 : 0;
    state.ready = framed && settled >= 10;
    status.textContent = shown.length ? describe(shown) + '\n(geometricError: the level\'s certified distance to the input; LOD0 = full detail)' : 'loading';
  };
}

addEventListener('resize', () => {
  camera.aspect = innerWidth / innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(innerWidth, innerHeight);
});

// The pixels of the last frame that are not the background (for the test).
window.drawnPixels = () => {
  const gl = renderer.getContext();
  const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
  const px = new Uint8Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
  const [r, g, b] = [(background >> 16) & 255, (background >> 8) & 255, background & 255];
  let n = 0;
  for (let i = 0; i < px.length; i += 4)
    if (Math.abs(px[i] - r) + Math.abs(px[i + 1] - g) + Math.abs(px[i + 2] - b) > 12)
      ++n;
  return n;
};

renderer.setAnimationLoop(() => {
  update();
  renderer.render(scene, camera);
  state.frames++;
});
