// The viewer of ausbau-report's HTML page (an ES module, inlined into the
// page; 'three' and its OrbitControls resolve through the page's import map
// to inlined data: URLs, so nothing is fetched).
//
// The page's data is the JSON in #ausbau-data; meshes and labels are base64
// binary buffers in #ausbau-buf-<i> (little-endian Float32 / Uint32).
//
// Poses follow schemas/path.md: a waypoint (t, q) maps D's mesh coordinates
// x to R(q) (x - dynamic_origin) + t; between waypoints the world position of
// the artifact's reference_point r, t_r = t + R(q) (r - dynamic_origin), is
// linear and q follows slerp along the shorter arc.
//
// Test hooks: window.ausbau = {ready, error, loadMs, frames, setTime(u), time(),
// poseOfD(), selectPath(key), paths(), play(), pause(), pixelStats(),
// labelsShown()}.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const hooks = { ready: false, error: null, loadMs: null, frames: 0 };
window.ausbau = hooks;

const $ = (id) => document.getElementById(id);
const status = (text) => { $('status').textContent = text; };

function fail(message) {
  hooks.error = message;
  status('error: ' + message);
  console.error('ausbau-report: ' + message);
}

// ------------------------------------------------------------------- data

const data = JSON.parse($('ausbau-data').textContent);

function decodeBuffer(ref) {
  const text = $('ausbau-buf-' + ref.buffer).textContent.trim();
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
  if (ref.type === 'f32') return new Float32Array(bytes.buffer, 0, ref.count);
  if (ref.type === 'u32') return new Uint32Array(bytes.buffer, 0, ref.count);
  throw new Error('unknown buffer type ' + ref.type);
}

// -------------------------------------------------------------- pose math
// Quaternions as [w, x, y, z], in float64 throughout.

function rotate(q, v) {
  const [w, x, y, z] = q;
  // v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)
  const cx = y * v[2] - z * v[1], cy = z * v[0] - x * v[2], cz = x * v[1] - y * v[0];
  const dx = y * cz - z * cy, dy = z * cx - x * cz, dz = x * cy - y * cx;
  return [v[0] + 2 * (w * cx + dx), v[1] + 2 * (w * cy + dy), v[2] + 2 * (w * cz + dz)];
}

// Eigen's slerp (what the planner uses): shorter arc, linear when nearly equal.
function slerp(a, b, s) {
  let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  const absD = Math.abs(d);
  let s0, s1;
  if (absD >= 1 - Number.EPSILON) {
    s0 = 1 - s; s1 = s;
  } else {
    const theta = Math.acos(absD), sinTheta = Math.sin(theta);
    s0 = Math.sin((1 - s) * theta) / sinTheta;
    s1 = Math.sin(s * theta) / sinTheta;
  }
  if (d < 0) s1 = -s1;
  const q = [s0 * a[0] + s1 * b[0], s0 * a[1] + s1 * b[1], s0 * a[2] + s1 * b[2], s0 * a[3] + s1 * b[3]];
  const n = Math.hypot(q[0], q[1], q[2], q[3]);
  return q.map((c) => c / n);
}

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];

// The scene-convention pose of D at animation time u in [0, 1] on `path`.
function poseAt(path, u) {
  const wps = path.waypoints, times = path.times, n = wps.length;
  if (n === 0) return { t: data.scene.start.t, q: data.scene.start.q, segment: -1, s: 0 };
  if (n === 1 || u <= 0) return { t: wps[0].t, q: wps[0].q, segment: 0, s: 0 };
  if (u >= 1) return { t: wps[n - 1].t, q: wps[n - 1].q, segment: n - 2, s: 1 };
  let i = 0;
  while (i < n - 2 && times[i + 1] <= u) ++i;
  const span = times[i + 1] - times[i];
  const s = span > 0 ? Math.min(1, Math.max(0, (u - times[i]) / span)) : 0;
  const offset = sub(path.reference_point, path.dynamic_origin);
  const a = wps[i], b = wps[i + 1];
  const ra = add(a.t, rotate(a.q, offset)), rb = add(b.t, rotate(b.q, offset));
  const tr = [ra[0] + s * (rb[0] - ra[0]), ra[1] + s * (rb[1] - ra[1]), ra[2] + s * (rb[2] - ra[2])];
  const q = slerp(a.q, b.q, s);
  return { t: sub(tr, rotate(q, offset)), q, segment: i, s };
}

// ------------------------------------------------------------- JSON tables

function renderJsonTables() {
  const box = $('jsontables');
  for (const file of data.json_files) {
    const h = document.createElement('h2');
    h.textContent = (file.name === 'verdict' ? 'Verdict' : 'Statistics') + ' (' + file.file + ')';
    box.appendChild(h);
    const table = document.createElement('table');
    table.id = 'json-' + file.name;
    const addRow = (key, value) => {
      const tr = table.insertRow();
      const th = document.createElement('th');
      th.textContent = key;
      tr.appendChild(th);
      tr.insertCell().textContent = value;
    };
    let parsed;
    try {
      parsed = JSON.parse(file.text);
    } catch (e) {
      addRow('error', 'not valid JSON: ' + e.message);
      box.appendChild(table);
      continue;
    }
    const walk = (prefix, value) => {
      if (value !== null && typeof value === 'object' && !Array.isArray(value)) {
        for (const [k, v] of Object.entries(value)) walk(prefix ? prefix + '.' + k : k, v);
      } else {
        addRow(prefix || '(value)', typeof value === 'string' ? value : JSON.stringify(value));
      }
    };
    walk('', parsed);
    box.appendChild(table);
  }
}

// ------------------------------------------------------------------ colours

const VIRIDIS = [[0.267, 0.005, 0.329], [0.229, 0.322, 0.546], [0.128, 0.567, 0.551], [0.369, 0.789, 0.383],
  [0.993, 0.906, 0.144]];
function colormap(x) {
  const f = Math.min(1, Math.max(0, x)) * (VIRIDIS.length - 1);
  const i = Math.min(VIRIDIS.length - 2, Math.floor(f)), s = f - i;
  return VIRIDIS[i].map((c, k) => c + s * (VIRIDIS[i + 1][k] - c));
}

// ------------------------------------------------------------------- scene

const state = { u: 0, playing: false, speed: 1, path: null, lastFrame: null };
const DURATION_S = 8;  // the whole path at 1x

let renderer, scene3d, camera, controls, staticMesh, dynamicMesh, trace, ghosts, dynamicGeometry;

function geometryOf(mesh) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(decodeBuffer(mesh.positions), 3));
  g.setIndex(new THREE.BufferAttribute(decodeBuffer(mesh.indices), 1));
  g.computeBoundingBox();
  g.computeBoundingSphere();
  return g;
}

// Where D's geometry (stored as mesh coordinates minus dynamic_shift) goes
// for a scene-convention pose: x_world = R(q) (geo + shift - origin) + t.
function placeD(object, pose) {
  const p = add(pose.t, rotate(pose.q, sub(data.dynamic_shift, data.scene.dynamic_origin)));
  object.position.set(p[0], p[1], p[2]);
  object.quaternion.set(pose.q[1], pose.q[2], pose.q[3], pose.q[0]);
  object.updateMatrixWorld(true);
}

let renderQueued = false;
function requestRender() {
  if (renderQueued) return;
  renderQueued = true;
  requestAnimationFrame(frame);
}

function frame(now) {
  renderQueued = false;
  hooks.frames += 1;
  if (state.playing) {
    if (state.lastFrame !== null) {
      const dt = Math.min(0.5, (now - state.lastFrame) / 1000);  // slow renderers: jump, do not crawl
      state.u = Math.min(1, state.u + dt * state.speed / DURATION_S);
      if (state.u >= 1) setPlaying(false);
    }
    state.lastFrame = now;
    applyTime();
    requestRender();
  }
  controls.update();
  renderer.render(scene3d, camera);
}

function setupScene() {
  const canvas = $('canvas3d');
  renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  scene3d = new THREE.Scene();
  scene3d.background = new THREE.Color(0xeef1f5);

  const sGeometry = geometryOf(data.static);
  staticMesh = new THREE.Mesh(sGeometry, new THREE.MeshStandardMaterial({
    color: 0x5b8fd6, flatShading: true, side: THREE.DoubleSide, transparent: true, opacity: 0.35,
    depthWrite: false, roughness: 0.8, metalness: 0.0,
  }));
  staticMesh.renderOrder = 1;
  scene3d.add(staticMesh);

  dynamicGeometry = geometryOf(data.dynamic);
  const dMaterial = new THREE.MeshStandardMaterial({
    color: 0xe8771e, flatShading: true, side: THREE.DoubleSide, roughness: 0.6, metalness: 0.0,
  });
  if (data.labels) {
    const values = decodeBuffer(data.labels.values);
    const colours = new Float32Array(values.length * 3);
    const span = data.labels.max - data.labels.min;
    for (let i = 0; i < values.length; ++i) {
      const c = colormap(span > 0 ? (values[i] - data.labels.min) / span : 0.5);
      colours.set(c, 3 * i);
    }
    dynamicGeometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
    dMaterial.color.set(0xffffff);
    dMaterial.vertexColors = true;
    const legend = $('legend');
    const stops = VIRIDIS.map((c, i) => `rgb(${c.map((x) => Math.round(255 * x)).join(',')}) ${100 * i / (VIRIDIS.length - 1)}%`);
    legend.innerHTML = '';
    const title = document.createElement('div');
    title.textContent = 'D: ' + data.labels.name;
    const bar = document.createElement('div');
    bar.className = 'bar';
    bar.style.background = `linear-gradient(to right, ${stops.join(', ')})`;
    const range = document.createElement('div');
    range.textContent = `${data.labels.min.toPrecision(3)} … ${data.labels.max.toPrecision(3)}`;
    legend.append(title, bar, range);
    legend.style.display = 'block';
  }
  dynamicMesh = new THREE.Mesh(dynamicGeometry, dMaterial);
  dynamicMesh.renderOrder = 0;
  scene3d.add(dynamicMesh);

  ghosts = new THREE.Group();
  ghosts.visible = false;
  scene3d.add(ghosts);

  scene3d.add(new THREE.HemisphereLight(0xffffff, 0x8090a0, 1.6));
  camera = new THREE.PerspectiveCamera(40, 1, 1, 1000);
  const light = new THREE.DirectionalLight(0xffffff, 1.6);
  light.position.set(0.5, 1, 1);
  camera.add(light);
  scene3d.add(camera);

  controls = new OrbitControls(camera, canvas);
  controls.addEventListener('change', requestRender);
  new ResizeObserver(resize).observe(canvas);
}

// A box around S and D's swept reference positions: the camera's first view.
function fitCamera() {
  const box = staticMesh.geometry.boundingBox.clone();
  const r = dynamicGeometry.boundingSphere.radius;
  for (const path of data.paths) {
    for (let k = 0; k <= 50; ++k) {
      const pose = poseAt(path, k / 50);
      box.expandByPoint(new THREE.Vector3(...pose.t).addScalar(r));
      box.expandByPoint(new THREE.Vector3(...pose.t).addScalar(-r));
    }
  }
  const centre = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3()).length() || 1;
  camera.near = size / 1000;
  camera.far = size * 20;
  camera.position.copy(centre).add(new THREE.Vector3(0.55, 0.45, 0.75).normalize().multiplyScalar(size * 1.15));
  camera.updateProjectionMatrix();
  controls.target.copy(centre);
  controls.update();
}

function resize() {
  const canvas = renderer.domElement;
  const w = canvas.clientWidth, h = canvas.clientHeight;
  if (w === 0 || h === 0) return;
  renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  requestRender();
  drawPlot();
}

function rebuildPathObjects() {
  if (trace) { scene3d.remove(trace); trace.geometry.dispose(); }
  ghosts.clear();
  const path = state.path;
  if (!path || path.waypoints.length === 0) return;
  const points = [];
  const offset = sub(path.reference_point, path.dynamic_origin);
  for (let k = 0; k <= 400; ++k) {
    const pose = poseAt(path, k / 400);
    points.push(new THREE.Vector3(...add(pose.t, rotate(pose.q, offset))));
  }
  trace = new THREE.Line(new THREE.BufferGeometry().setFromPoints(points),
    new THREE.LineBasicMaterial({ color: 0x222a33 }));
  trace.visible = $('showtrace').checked;
  scene3d.add(trace);
  const ghostMaterial = new THREE.MeshBasicMaterial({ color: 0x8a4a10, wireframe: true, transparent: true, opacity: 0.25 });
  for (const u of [0, 1]) {
    const ghost = new THREE.Mesh(dynamicGeometry, ghostMaterial);
    placeD(ghost, poseAt(path, u));
    ghosts.add(ghost);
  }
}

// ----------------------------------------------------------------- plot

function currentSeries() {
  return state.path && state.path.series.length ? state.path.series[0] : null;
}

function drawPlot() {
  const canvas = $('plot');
  const dpr = window.devicePixelRatio || 1;
  const w = canvas.clientWidth, h = canvas.clientHeight;
  if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
    canvas.width = Math.round(w * dpr);
    canvas.height = Math.round(h * dpr);
  }
  const ctx = canvas.getContext('2d');
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  ctx.clearRect(0, 0, w, h);
  ctx.font = '12px system-ui, sans-serif';
  const series = currentSeries();
  const left = 64, right = 16, top = 22, bottom = 26;
  const pw = w - left - right, ph = h - top - bottom;
  ctx.fillStyle = '#1d232b';
  if (!series) {
    ctx.fillText('no per-pose values (no path)', left, top + 20);
    return;
  }
  const path = state.path;
  const xs = series.x.length ? series.x : path.times;
  const ys = series.x.length ? series.y : series.waypoints;
  const all = ys.concat(series.waypoints).filter((v) => v !== null);
  const ymax = Math.max(...all, 0) * 1.08 || 1;
  const X = (u) => left + u * pw, Y = (v) => top + ph - (v / ymax) * ph;
  ctx.fillText(series.label + (data.scene.units ? ' [' + data.scene.units + ']' : ''), left, 14);
  // Axes and grid.
  ctx.strokeStyle = '#d5dbe3';
  ctx.lineWidth = 1;
  ctx.textAlign = 'right';
  for (let k = 0; k <= 4; ++k) {
    const v = ymax * k / 4, y = Y(v);
    ctx.beginPath(); ctx.moveTo(left, y); ctx.lineTo(left + pw, y); ctx.stroke();
    ctx.fillText(v.toPrecision(3), left - 6, y + 4);
  }
  ctx.textAlign = 'center';
  for (let k = 0; k <= 10; ++k) ctx.fillText((k / 10).toFixed(1), X(k / 10), top + ph + 16);
  ctx.textAlign = 'left';
  // Waypoint positions.
  ctx.strokeStyle = '#eceff3';
  for (const t of path.times) { ctx.beginPath(); ctx.moveTo(X(t), top); ctx.lineTo(X(t), top + ph); ctx.stroke(); }
  // The curve.
  ctx.strokeStyle = '#2f6db5';
  ctx.lineWidth = 1.6;
  ctx.beginPath();
  xs.forEach((u, k) => (k ? ctx.lineTo(X(u), Y(ys[k])) : ctx.moveTo(X(u), Y(ys[k]))));
  ctx.stroke();
  ctx.fillStyle = '#e8771e';
  path.times.forEach((u, k) => {
    ctx.beginPath(); ctx.arc(X(u), Y(series.waypoints[k]), 3.2, 0, 2 * Math.PI); ctx.fill();
  });
  // Cursor.
  ctx.strokeStyle = '#c8302b';
  ctx.lineWidth = 1.5;
  ctx.beginPath(); ctx.moveTo(X(state.u), top); ctx.lineTo(X(state.u), top + ph); ctx.stroke();
}

function plotSeek(event) {
  const canvas = $('plot');
  const rect = canvas.getBoundingClientRect();
  const left = 64, right = 16;
  const u = (event.clientX - rect.left - left) / (rect.width - left - right);
  setTime(Math.min(1, Math.max(0, u)));
}

// ------------------------------------------------------------- animation

function applyTime() {
  const pose = poseAt(state.path || { waypoints: [] }, state.u);
  placeD(dynamicMesh, pose);
  state.pose = pose;
  $('scrubber').value = String(Math.round(state.u * 1000));
  const path = state.path;
  let info = `u = ${state.u.toFixed(3)}`;
  if (path && path.waypoints.length > 1) info += `, segment ${pose.segment + 1}/${path.waypoints.length - 1}`;
  const series = currentSeries();
  if (series && series.x.length) {
    const k = Math.round(state.u * (series.x.length - 1));
    info += `, clearance ≈ ${Number(series.y[k]).toPrecision(3)}`;
  }
  $('timeinfo').textContent = info;
  drawPlot();
  requestRender();
}

function setTime(u) {
  state.u = Math.min(1, Math.max(0, Number(u)));
  applyTime();
}

function setPlaying(playing) {
  if (playing && state.u >= 1) state.u = 0;
  state.playing = playing && !!state.path && state.path.waypoints.length > 1;
  state.lastFrame = null;
  $('play').textContent = state.playing ? 'Pause' : 'Play';
  if (state.playing) requestRender();
}

function selectPath(key) {
  state.path = data.paths.find((p) => p.key === key) || null;
  if (state.path) $('pathselect').value = key;
  const series = currentSeries();
  $('plotnote').textContent = series
    ? 'Curve: ' + series.label + ' at ' + series.x.length + ' poses evenly spaced in animation time; dots: waypoints;' +
      ' x: animation time (each segment takes time in proportion to how far D moves). Click or drag to seek.'
    : '';
  rebuildPathObjects();
  applyTime();
}

function setupControls() {
  $('play').addEventListener('click', () => setPlaying(!state.playing));
  $('scrubber').addEventListener('input', (e) => { setPlaying(false); setTime(e.target.value / 1000); });
  $('speed').addEventListener('change', (e) => { state.speed = Number(e.target.value); });
  const select = $('pathselect');
  for (const p of data.paths) {
    const option = document.createElement('option');
    option.value = p.key;
    option.textContent = p.key + (p.success ? '' : ' (no path)');
    select.appendChild(option);
  }
  select.disabled = data.paths.length < 2;
  select.addEventListener('change', (e) => selectPath(e.target.value));
  $('opacity').addEventListener('input', (e) => {
    const o = Number(e.target.value), m = staticMesh.material;
    m.opacity = o;
    m.transparent = o < 1;
    m.depthWrite = o >= 1;
    staticMesh.visible = o > 0;
    m.needsUpdate = true;
    requestRender();
  });
  $('showtrace').addEventListener('change', (e) => { if (trace) trace.visible = e.target.checked; requestRender(); });
  $('showghosts').addEventListener('change', (e) => { ghosts.visible = e.target.checked; requestRender(); });
  const plot = $('plot');
  let dragging = false;
  plot.addEventListener('pointerdown', (e) => { dragging = true; setPlaying(false); plotSeek(e); });
  plot.addEventListener('pointermove', (e) => { if (dragging) plotSeek(e); });
  window.addEventListener('pointerup', () => { dragging = false; });
  window.addEventListener('keydown', (e) => {
    if (e.code === 'Space' && e.target.tagName !== 'INPUT' && e.target.tagName !== 'SELECT') {
      e.preventDefault();
      setPlaying(!state.playing);
    }
  });
  window.addEventListener('resize', drawPlot);
}

// Reads the 3D view's pixels: how many differ from the background, how many
// change when D (S) is hidden, i.e. where D (S) is seen, and a hash.
function readPixels() {
  renderer.render(scene3d, camera);
  const src = renderer.domElement;
  const c = document.createElement('canvas');
  c.width = src.width;
  c.height = src.height;
  const ctx = c.getContext('2d', { willReadFrequently: true });
  ctx.drawImage(src, 0, 0);
  return ctx.getImageData(0, 0, c.width, c.height).data;
}

function pixelStats() {
  const shown = readPixels();
  const differing = (object) => {
    const visible = object.visible;
    object.visible = false;
    const hidden = readPixels();
    object.visible = visible;
    let n = 0;
    for (let i = 0; i < shown.length; i += 4) {
      if (Math.abs(shown[i] - hidden[i]) + Math.abs(shown[i + 1] - hidden[i + 1]) + Math.abs(shown[i + 2] - hidden[i + 2]) > 6) ++n;
    }
    return n;
  };
  const dPixels = differing(dynamicMesh), sPixels = differing(staticMesh);
  renderer.render(scene3d, camera);
  const bgHex = scene3d.background.getHex();  // sRGB, as drawn
  const br = (bgHex >> 16) & 255, bgG = (bgHex >> 8) & 255, bb = bgHex & 255;
  let nonBackground = 0, hash = 0;
  for (let i = 0; i < shown.length; i += 4) {
    const r = shown[i], g = shown[i + 1], b = shown[i + 2];
    hash = (hash * 31 + r * 7 + g * 3 + b) >>> 0;
    if (Math.abs(r - br) + Math.abs(g - bgG) + Math.abs(b - bb) > 12) ++nonBackground;
  }
  return { width: renderer.domElement.width, height: renderer.domElement.height, pixels: shown.length / 4,
    nonBackground, dPixels, sPixels, hash };
}

// ------------------------------------------------------------------ start

try {
  renderJsonTables();
  setupScene();
  setupControls();
  const initial = data.paths.find((p) => p.key === 'smoothed' && p.waypoints.length) ||
    data.paths.find((p) => p.waypoints.length) || data.paths[0];
  selectPath(initial ? initial.key : '');
  fitCamera();
  resize();
  renderer.render(scene3d, camera);
  Object.assign(hooks, {
    setTime,
    time: () => state.u,
    poseOfD: () => ({ t: state.pose.t.slice(), q: state.pose.q.slice(), path: state.path ? state.path.key : null,
      segment: state.pose.segment, s: state.pose.s }),
    selectPath,
    paths: () => data.paths.map((p) => ({ key: p.key, waypoints: p.waypoints.length, times: p.times.slice(),
      reference_point: p.reference_point.slice(), dynamic_origin: p.dynamic_origin.slice() })),
    play: () => setPlaying(true),
    pause: () => setPlaying(false),
    pixelStats,
    labelsShown: () => !!data.labels && dynamicMesh.material.vertexColors === true &&
      $('legend').style.display === 'block',
  });
  hooks.loadMs = performance.now();
  hooks.ready = true;
  const tri = data.static.triangles + data.dynamic.triangles;
  status(`${tri.toLocaleString('en')} triangles; ready in ${(hooks.loadMs / 1000).toFixed(2)} s`);
} catch (e) {
  fail(e && e.message ? e.message : String(e));
}
