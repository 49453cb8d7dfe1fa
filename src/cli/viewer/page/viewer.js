// The dieface live viewer (served by `dieface view` / `dieface watch --serve`).
//
// It loads the last good model (/model.glb, the same bytes `dieface build` writes) and
// its declarations (/info.json), and follows the build status through server-sent
// events (/events): a new model is swapped in place, keeping the camera; a failed save
// shows its diagnostic over the model already shown. Each glTF node carries
// extras { name, kind, line } (three.js puts them in `userData`), which the legend,
// the toggles and picking use. Coordinates are glTF's: metres, +Y up (press Z).
//
// `window.dieface` exposes the state the browser tests read (tests/viewer.rs).

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

// Draft limits against the press direction (primer section 11): 8 deg is the usual
// design draft, 5 deg marginal; below 0 the wall is an undercut.
const DRAFT_OK = 8;
const DRAFT_MARGINAL = 5;
// Seam normal jump: 0.5 deg is the common CAD G1 tolerance; the colour ramp ends at
// RAMP_END_DEG (red).
const SEAM_G1 = 0.5;
const SEAM_RAMP_END = 2;

const view = document.getElementById('view');
const statusEl = document.getElementById('status');
const titleEl = document.getElementById('title');
const legendEl = document.getElementById('legend');
const treeEl = document.getElementById('tree');
const pickEl = document.getElementById('pick');
const diagnosticEl = document.getElementById('diagnostic');
const diagnosticText = document.getElementById('diagnostic-text');

const state = {
  loadedVersion: 0, // model_version of the model shown
  loading: 0, // model_version being fetched
  status: null, // the last status from the server
  mode: 'kind', // kind | draft | seams
  hidden: new Set(), // names of nodes switched off (kept across updates)
  nodes: new Map(), // name -> Object3D of the model shown
  info: null, // /info.json of the model shown
  seams: null, // THREE.Points of the seam analysis (seams mode)
  picked: null, // name of the picked node
  lastPick: null, // what the pick panel shows
};

// --- renderer, camera, lights --------------------------------------------------------

// Without WebGL nothing can be drawn: say so on the page rather than leave it blank.
if (!document.createElement('canvas').getContext('webgl2')) {
  diagnosticEl.querySelector('h2').textContent = 'This browser cannot draw the model';
  diagnosticText.textContent = 'The viewer needs WebGL 2, which this browser has switched off or lacks '
    + '(check its hardware acceleration setting). `dieface render FILE.die -o view.png` draws a '
    + 'picture without a browser.';
  diagnosticEl.hidden = false;
  throw new Error('WebGL 2 is not available');
}
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setClearColor(0xeef1f5);
view.appendChild(renderer.domElement);

const scene = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(35, 1, 0.001, 100);
camera.position.set(1.5, 1.2, 2.0);
const controls = new OrbitControls(camera, renderer.domElement);
controls.enableDamping = false;
controls.addEventListener('change', render);
scene.add(new THREE.HemisphereLight(0xffffff, 0x8090a0, 1.6));
const headlight = new THREE.DirectionalLight(0xffffff, 1.6);
camera.add(headlight);
headlight.position.set(0.3, 0.5, 1);
scene.add(camera);
const modelRoot = new THREE.Group();
scene.add(modelRoot);

function resize() {
  const w = Math.max(1, view.clientWidth);
  const h = Math.max(1, view.clientHeight);
  renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  render();
}
window.addEventListener('resize', resize);

let frameQueued = false;
function render() {
  if (frameQueued) return;
  frameQueued = true;
  requestAnimationFrame(() => {
    frameQueued = false;
    renderer.render(scene, camera);
    state.renderedVersion = state.loadedVersion;
  });
}

// The camera looks at the whole model from the front-left, above (first model, `f`).
function fit() {
  const box = new THREE.Box3().setFromObject(modelRoot);
  if (box.isEmpty()) return;
  const center = box.getCenter(new THREE.Vector3());
  const radius = box.getSize(new THREE.Vector3()).length() / 2;
  const dir = new THREE.Vector3(-0.55, 0.75, 1.0).normalize();
  const dist = radius / Math.sin(THREE.MathUtils.degToRad(camera.fov / 2)) * 1.05;
  camera.position.copy(center).addScaledVector(dir, dist);
  camera.near = dist / 100;
  camera.far = dist * 10;
  camera.updateProjectionMatrix();
  controls.target.copy(center);
  controls.update();
  render();
}
window.addEventListener('keydown', (e) => {
  if (e.ctrlKey || e.metaKey || e.altKey) return;
  if (e.key === 'f') fit();
  if (e.key === 'Escape') clearPick();
});

// --- the model ------------------------------------------------------------------------

const loader = new GLTFLoader();

async function loadModel(version) {
  state.loading = version;
  const [glb, info] = await Promise.all([
    fetch(`/model.glb?v=${version}`).then((r) => {
      if (!r.ok) throw new Error(`model.glb: HTTP ${r.status}`);
      return r.arrayBuffer();
    }),
    fetch(`/info.json?v=${version}`).then((r) => r.json()),
  ]);
  const fetched = performance.now();
  const gltf = await loader.parseAsync(glb, '');
  const parsed = performance.now();
  if (version < state.loadedVersion) return; // a newer model arrived first
  swapModel(gltf.scene, info);
  state.loadedVersion = version;
  const first = !state.fitted;
  if (first) {
    fit();
    state.fitted = true;
  }
  if (state.mode === 'seams') await showSeams();
  render();
  requestAnimationFrame(() => {
    const drawn = performance.now();
    state.timings = {
      fetch_ms: fetched - state.heardAt, parse_ms: parsed - fetched, draw_ms: drawn - parsed,
      heard_epoch_ms: performance.timeOrigin + state.heardAt, drawn_epoch_ms: performance.timeOrigin + drawn,
    };
  });
}

// Replaces the model shown by `root`, keeping the camera, the toggles and the mode.
function swapModel(root, info) {
  for (const old of [...modelRoot.children]) {
    modelRoot.remove(old);
    dispose(old);
  }
  state.nodes.clear();
  const darkened = new Set(); // line materials are shared by the lines of a kind
  root.traverse((o) => {
    if (o.userData && typeof o.userData.name === 'string') state.nodes.set(o.userData.name, o);
    if (o.isMesh) {
      o.material.side = THREE.DoubleSide;
      o.userData.kindMaterial = o.material;
    }
    // Curves in a darker shade of their kind's colour, so light ones (a sketch's grey)
    // stand out against the background and the surfaces.
    if (o.isLine && o.material.color && !darkened.has(o.material)) {
      darkened.add(o.material);
      o.material.color.multiplyScalar(0.6);
    }
  });
  modelRoot.add(root);
  state.info = info;
  titleEl.textContent = info.source;
  for (const [name, o] of state.nodes) o.visible = !state.hidden.has(name);
  applyMode();
  buildTree();
  buildLegend();
  if (state.picked && !state.nodes.has(state.picked)) clearPick();
  else if (state.picked) highlight(state.picked);
}

function dispose(object) {
  object.traverse((o) => {
    if (o.geometry) o.geometry.dispose();
    for (const m of [o.material, o.userData.kindMaterial, o.userData.analysisMaterial]) {
      if (m && m.dispose) m.dispose();
    }
  });
}

// The node a scene object belongs to: the nearest ancestor with an extras name.
function ownerOf(object) {
  for (let o = object; o; o = o.parent) {
    if (o.userData && typeof o.userData.name === 'string') return o;
  }
  return null;
}

function isShown(object) {
  for (let o = object; o; o = o.parent) if (!o.visible) return false;
  return true;
}

// The swatch colour of a node: its first mesh or line material.
function colorOf(object) {
  let color = null;
  object.traverse((o) => {
    const m = o.userData.kindMaterial || o.material;
    if (!color && m && m.color) color = '#' + m.color.getHexString(THREE.SRGBColorSpace);
  });
  return color || '#888888';
}

// --- legend and toggles ---------------------------------------------------------------

function buildLegend() {
  legendEl.replaceChildren();
  if (state.mode === 'draft') {
    legendEl.append(
      heading('draft against the press direction'),
      ramp([
        ['undercut (< 0°)', '#8e24aa'],
        [`< ${DRAFT_MARGINAL}°`, '#d32f2f'],
        [`${DRAFT_MARGINAL}–${DRAFT_OK}° marginal`, '#f9a825'],
        [`≥ ${DRAFT_OK}°`, '#2e7d32'],
        ['flat (90°)', '#9ccc65'],
      ]),
    );
    return;
  }
  if (state.mode === 'seams') {
    const s = state.seamsInfo;
    legendEl.append(heading('normal jump at patch seams'));
    const bar = document.createElement('div');
    bar.className = 'ramp';
    bar.style.background = 'linear-gradient(to right, #2e7d32, #f9a825 25%, #d32f2f)';
    const labels = document.createElement('div');
    labels.className = 'ramp-labels';
    labels.innerHTML = `<span>0°</span><span>${SEAM_G1}° (G1)</span><span>≥ ${SEAM_RAMP_END}°</span>`;
    legendEl.append(bar, labels);
    if (s) {
      const p = document.createElement('div');
      p.id = 'seam-summary';
      p.textContent = s.count === 0
        ? 'no seams found'
        : `${s.count} seam points; largest ${s.max_deg.toFixed(3)}° between ${s.max_between.join(' and ')}`;
      legendEl.append(p);
    }
    return;
  }
  legendEl.append(heading('kinds'));
  const kinds = new Map();
  for (const o of modelRoot.children[0] ? modelRoot.children[0].children : []) {
    const kind = o.userData.kind;
    if (kind && !kinds.has(kind)) kinds.set(kind, colorOf(o));
  }
  for (const [kind, color] of kinds) legendEl.append(swatchRow(color, kind));
}

function heading(text) {
  const h = document.createElement('div');
  h.innerHTML = `<b></b>`;
  h.firstChild.textContent = text;
  return h;
}

function swatchRow(color, text) {
  const row = document.createElement('div');
  row.className = 'legend-row';
  const sw = document.createElement('span');
  sw.className = 'swatch';
  sw.style.background = color;
  row.append(sw, document.createTextNode(text));
  return row;
}

function ramp(entries) {
  const box = document.createElement('div');
  for (const [text, color] of entries) box.append(swatchRow(color, text));
  return box;
}

// One row per declaration (with its kind's swatch) and, folded under it, one per piece.
function buildTree() {
  const open = new Set([...treeEl.querySelectorAll('details[open]')].map((d) => d.dataset.name));
  treeEl.replaceChildren();
  const top = modelRoot.children[0] ? modelRoot.children[0].children : [];
  for (const o of top) {
    if (typeof o.userData.name !== 'string') continue;
    const pieces = [];
    o.traverse((c) => {
      if (c !== o && typeof c.userData.name === 'string') pieces.push(c);
    });
    const row = toggleRow(o);
    if (pieces.length === 0) {
      treeEl.append(row);
      continue;
    }
    const details = document.createElement('details');
    details.dataset.name = o.userData.name;
    if (open.has(o.userData.name)) details.open = true;
    const summary = document.createElement('summary');
    summary.append(row);
    const list = document.createElement('div');
    list.className = 'pieces';
    for (const p of pieces) list.append(toggleRow(p));
    details.append(summary, list);
    treeEl.append(details);
  }
}

function toggleRow(object) {
  const name = object.userData.name;
  const row = document.createElement('label');
  row.className = 'row';
  row.style.display = 'block';
  const box = document.createElement('input');
  box.type = 'checkbox';
  box.checked = !state.hidden.has(name);
  box.dataset.name = name;
  box.addEventListener('change', () => {
    if (box.checked) state.hidden.delete(name);
    else state.hidden.add(name);
    object.visible = box.checked;
    if (state.mode === 'seams' && state.seamsInfo) drawSeams();
    render();
  });
  const sw = document.createElement('span');
  sw.className = 'swatch';
  sw.style.background = colorOf(object);
  const kind = document.createElement('span');
  kind.className = 'kind';
  kind.textContent = ` ${object.userData.kind}`;
  row.append(box, sw, document.createTextNode(name.split('/').pop()), kind);
  row.title = `${name} (${object.userData.kind}, line ${object.userData.line})`;
  return row;
}

// --- display modes --------------------------------------------------------------------

for (const input of document.querySelectorAll('input[name=mode]')) {
  input.addEventListener('change', async () => {
    state.mode = input.value;
    applyMode();
    if (state.mode === 'seams') await showSeams();
    else hideSeams();
    buildLegend();
    render();
  });
}
document.getElementById('edges').addEventListener('change', () => { applyOverlays(); render(); });
document.getElementById('wire').addEventListener('change', () => { applyOverlays(); render(); });

const GREY = new THREE.MeshLambertMaterial({ color: 0xb8bec6, side: THREE.DoubleSide });

function applyMode() {
  modelRoot.traverse((o) => {
    if (!o.isMesh || !o.userData.kindMaterial) return;
    if (state.mode === 'draft') {
      if (!o.userData.analysisMaterial) o.userData.analysisMaterial = draftMaterial(o);
      o.material = o.userData.analysisMaterial;
    } else if (state.mode === 'seams') {
      o.material = GREY;
    } else {
      o.material = o.userData.kindMaterial;
    }
  });
  applyOverlays();
  if (state.picked) highlight(state.picked);
}

// Colours each vertex of a mesh by its draft: the angle between the surface and the
// press direction (90 deg for a flat face, 0 for a vertical wall, below 0 an undercut).
// A piece whose normals run mostly downwards is taken the other way round.
function draftMaterial(mesh) {
  const normals = mesh.geometry.getAttribute('normal');
  if (!normals) return mesh.userData.kindMaterial;
  const m = new THREE.Matrix3().getNormalMatrix(mesh.matrixWorld);
  const n = new THREE.Vector3();
  let mean = 0;
  for (let i = 0; i < normals.count; i++) mean += n.fromBufferAttribute(normals, i).applyMatrix3(m).y;
  const sign = mean < 0 ? -1 : 1;
  const colors = new Float32Array(normals.count * 3);
  const c = new THREE.Color();
  for (let i = 0; i < normals.count; i++) {
    n.fromBufferAttribute(normals, i).applyMatrix3(m).normalize();
    const draft = THREE.MathUtils.radToDeg(Math.asin(THREE.MathUtils.clamp(sign * n.y, -1, 1)));
    draftColor(draft, c);
    colors.set([c.r, c.g, c.b], i * 3);
  }
  mesh.geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
  return new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide });
}

function draftColor(draft, c) {
  if (draft < 0) return c.set('#8e24aa');
  if (draft < DRAFT_MARGINAL) return c.set('#d32f2f');
  if (draft < DRAFT_OK) return c.set('#f9a825');
  // Above the design draft: green, lighter towards a flat face.
  return c.set('#2e7d32').lerp(new THREE.Color('#9ccc65'), (draft - DRAFT_OK) / (90 - DRAFT_OK));
}

async function showSeams() {
  const version = state.loadedVersion;
  if (!state.seamsInfo || state.seamsVersion !== version) {
    const s = await fetch(`/seams.json?v=${version}`).then((r) => r.json());
    if (version !== state.loadedVersion) return; // a newer model came meanwhile
    state.seamsInfo = s;
    state.seamsVersion = version;
  }
  if (state.mode === 'seams') drawSeams();
}

// Whether the node `name` and every group above it (`binder` for `binder/front`) are on.
function nameShown(name) {
  const parts = name.split('/');
  for (let i = 1; i <= parts.length; i++) {
    if (state.hidden.has(parts.slice(0, i).join('/'))) return false;
  }
  return true;
}

// The seam points whose two pieces are both shown, coloured by their normal jump.
function drawSeams() {
  hideSeams();
  const s = state.seamsInfo;
  const positions = [];
  const colors = [];
  const c = new THREE.Color();
  const green = new THREE.Color('#2e7d32');
  const amber = new THREE.Color('#f9a825');
  const red = new THREE.Color('#d32f2f');
  s.jumps.forEach((j, i) => {
    if (!nameShown(s.names[s.pieces[2 * i]]) || !nameShown(s.names[s.pieces[2 * i + 1]])) return;
    if (j <= SEAM_G1) c.copy(green).lerp(amber, j / SEAM_G1);
    else c.copy(amber).lerp(red, Math.min(1, (j - SEAM_G1) / (SEAM_RAMP_END - SEAM_G1)));
    positions.push(s.positions[3 * i], s.positions[3 * i + 1], s.positions[3 * i + 2]);
    colors.push(c.r, c.g, c.b);
  });
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
  geometry.setAttribute('color', new THREE.Float32BufferAttribute(colors, 3));
  const material = new THREE.PointsMaterial({ size: 5, sizeAttenuation: false, vertexColors: true, depthTest: false });
  state.seams = new THREE.Points(geometry, material);
  state.seams.renderOrder = 10;
  scene.add(state.seams);
  buildLegend();
  render();
}

function hideSeams() {
  if (!state.seams) return;
  scene.remove(state.seams);
  state.seams.geometry.dispose();
  state.seams.material.dispose();
  state.seams = null;
}

// Patch edges (boundaries and creases over 20 deg) and mesh lines, drawn over meshes.
function applyOverlays() {
  const edges = document.getElementById('edges').checked;
  const wire = document.getElementById('wire').checked;
  modelRoot.traverse((o) => {
    if (!o.isMesh) return;
    setOverlay(o, 'edgeLines', edges, () => new THREE.LineSegments(
      new THREE.EdgesGeometry(o.geometry, 20),
      new THREE.LineBasicMaterial({ color: 0x1d2430 })));
    setOverlay(o, 'wireLines', wire, () => new THREE.LineSegments(
      new THREE.WireframeGeometry(o.geometry),
      new THREE.LineBasicMaterial({ color: 0x1d2430, transparent: true, opacity: 0.25 })));
  });
}

function setOverlay(mesh, key, on, make) {
  if (on && !mesh.userData[key]) {
    const lines = make();
    lines.raycast = () => {}; // overlays are not picked
    mesh.userData[key] = lines;
    mesh.add(lines);
  } else if (!on && mesh.userData[key]) {
    const lines = mesh.userData[key];
    mesh.remove(lines);
    lines.geometry.dispose();
    lines.material.dispose();
    delete mesh.userData[key];
  }
}

// --- picking --------------------------------------------------------------------------

const raycaster = new THREE.Raycaster();
let down = null;
renderer.domElement.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
renderer.domElement.addEventListener('pointerup', (e) => {
  if (!down) return;
  const moved = Math.hypot(e.clientX - down[0], e.clientY - down[1]);
  down = null;
  if (moved > 4) return; // a drag turned the camera
  const hit = pickAt(e.clientX, e.clientY);
  if (hit) showPick(hit);
  else clearPick();
});

// The named node under a point of the window (CSS pixels), or null.
function pickAt(x, y) {
  const rect = renderer.domElement.getBoundingClientRect();
  const ndc = new THREE.Vector2(((x - rect.left) / rect.width) * 2 - 1, -((y - rect.top) / rect.height) * 2 + 1);
  const box = new THREE.Box3().setFromObject(modelRoot);
  raycaster.params.Line.threshold = box.isEmpty() ? 0.001 : box.getSize(new THREE.Vector3()).length() * 0.003;
  raycaster.setFromCamera(ndc, camera);
  for (const hit of raycaster.intersectObject(modelRoot, true)) {
    if (!isShown(hit.object)) continue;
    const owner = ownerOf(hit.object);
    if (owner) return owner;
  }
  return null;
}

async function showPick(object) {
  const { name, kind, line } = object.userData;
  state.picked = name;
  highlight(name);
  const decl = (state.info?.declarations || []).find((d) => d.name === name.split('/')[0]);
  const pick = { name, kind, line, source: state.info?.source, figures: figuresOf(name, decl), summary: null };
  state.lastPick = pick;
  renderPick(pick);
  try {
    const piece = await fetch(`/piece.json?name=${encodeURIComponent(name)}`);
    if (piece.ok && state.lastPick === pick) {
      pick.summary = (await piece.json()).summary;
      renderPick(pick);
    }
  } catch (_) {
    // The summary is a detail; the name, kind and line are already shown.
  }
}

// The quality report lines that concern a node: all of a declaration's, or for a
// piece (`binder/front_nose`) the worst figures and the lines that name it.
function figuresOf(name, decl) {
  if (!decl) return [];
  const parts = name.split('/');
  if (parts.length === 1) return decl.figures;
  const piece = parts[parts.length - 1];
  const names = (line) => line.split(/[^A-Za-z0-9_]+/).includes(piece);
  return decl.figures.filter((line) => line.startsWith('worst:') || names(line));
}

function renderPick(p) {
  pickEl.replaceChildren();
  const h = document.createElement('h3');
  h.textContent = p.name;
  const where = document.createElement('div');
  where.id = 'pick-where';
  where.textContent = `${p.kind} · ${p.source}:${p.line} (line ${p.line})`;
  pickEl.append(h, where);
  if (p.summary) {
    const s = document.createElement('div');
    s.textContent = p.summary;
    pickEl.append(s);
  }
  if (p.figures.length) {
    const ul = document.createElement('ul');
    for (const f of p.figures) {
      const li = document.createElement('li');
      li.textContent = f;
      ul.append(li);
    }
    pickEl.append(ul);
  }
  pickEl.hidden = false;
}

function clearPick() {
  state.picked = null;
  state.lastPick = null;
  pickEl.hidden = true;
  highlight(null);
}

// Lights the picked node's meshes up (emissive), on whichever material they wear.
function highlight(name) {
  const target = name ? state.nodes.get(name) : null;
  modelRoot.traverse((o) => {
    if (!o.isMesh || !o.material.emissive) return;
    let lit = false;
    for (let p = o; p; p = p.parent) if (p === target) lit = true;
    if (o.material === GREY) return;
    if (lit) {
      if (!o.userData.litMaterial || o.userData.litMaterial.base !== o.material) {
        const m = o.material.clone();
        m.emissive = new THREE.Color(0x3a3a10);
        o.userData.litMaterial = { base: o.material, lit: m };
      }
      o.material = o.userData.litMaterial.lit;
    } else if (o.userData.litMaterial && o.material === o.userData.litMaterial.lit) {
      o.material = o.userData.litMaterial.base;
    }
  });
  render();
}

// --- status and diagnostics -----------------------------------------------------------

function showStatus(s) {
  state.status = s;
  state.heardAt = performance.now();
  statusEl.dataset.state = s.state;
  if (s.state === 'building') statusEl.textContent = 'rebuilding…';
  else if (s.state === 'error') statusEl.textContent = 'the last save has errors';
  else {
    const reran = s.reran.length ? `; re-ran ${s.reran.length}` : '';
    statusEl.textContent = `built in ${s.took_ms} ms${reran}`;
  }
  if (s.state === 'error') {
    diagnosticText.textContent = s.error;
    diagnosticEl.hidden = false;
  } else if (s.state === 'ok') {
    diagnosticEl.hidden = true;
  }
  if (s.model_version > state.loadedVersion && s.model_version > state.loading) {
    loadModel(s.model_version).catch((e) => {
      state.loading = 0;
      statusEl.textContent = `cannot load the model: ${e.message}`;
    });
  }
}

const events = new EventSource('/events');
events.onmessage = (e) => showStatus(JSON.parse(e.data));

resize();

// --- test hooks -----------------------------------------------------------------------

// A point of the window (CSS pixels) where a click lands on the node `name` (the first
// of its triangles, sampled across it, whose centre is visible), or null.
function screenPointOf(name) {
  const target = state.nodes.get(name);
  if (!target || !isShown(target)) return null;
  const rect = renderer.domElement.getBoundingClientRect();
  const meshes = [];
  target.traverse((o) => { if (o.isMesh) meshes.push(o); });
  const v = new THREE.Vector3();
  for (const mesh of meshes) {
    const pos = mesh.geometry.getAttribute('position');
    const index = mesh.geometry.getIndex();
    const triangles = index ? index.count / 3 : pos.count / 3;
    const step = Math.max(1, Math.floor(triangles / 400));
    for (let t = 0; t < triangles; t += step) {
      const c = new THREE.Vector3();
      for (let k = 0; k < 3; k++) {
        const i = index ? index.getX(3 * t + k) : 3 * t + k;
        c.add(v.fromBufferAttribute(pos, i).applyMatrix4(mesh.matrixWorld));
      }
      c.divideScalar(3).project(camera);
      if (Math.abs(c.x) > 0.95 || Math.abs(c.y) > 0.95 || c.z > 1) continue;
      const x = rect.left + ((c.x + 1) / 2) * rect.width;
      const y = rect.top + ((1 - c.y) / 2) * rect.height;
      const owner = pickAt(x, y);
      if (owner && owner.userData.name === name) return { x, y };
    }
  }
  return null;
}

window.dieface = {
  get loadedVersion() { return state.loadedVersion; },
  get renderedVersion() { return state.renderedVersion || 0; },
  get status() { return state.status; },
  get mode() { return state.mode; },
  get lastPick() { return state.lastPick; },
  get timings() { return state.timings || null; },
  get seams() { return state.seamsInfo || null; },
  get seamPointsDrawn() { return state.seams ? state.seams.geometry.getAttribute('position').count : 0; },
  get camera() { return [...camera.position.toArray(), ...controls.target.toArray()]; },
  pieces: () => [...state.nodes.keys()],
  screenPointOf,
};
