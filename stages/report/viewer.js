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
// The 3D view needs WebGL; the headline, plots and tables do not: where the
// browser offers no WebGL (locked-down or virtual desktops) the 3D area says
// so in one sentence and everything else works (the plots are 2D canvases).
//
// The view is upright for the scene's up axis (data.scene.up: the scene's
// `up_axis`, else the mesh files' convention; common/scene/scene.h
// SceneUpAxis): the camera's up vector, its first view direction and the
// sky light follow it.
//
// Test hooks: window.ausbau = {ready, error, loadMs, frames, webgl, up
// (read-only: {axis, source, vector}, vector the camera's up), view()
// ({up, target, position} of the camera), setTime(u), time(), poseOfD(),
// selectPath(key), paths(), play(), pause(), pixelStats(), labelsShown(),
// plots(), waypointRows(), setSection(axis, fraction), section(),
// setMeasuring(on), pickAt(clientX, clientY), measurement(), project([x, y,
// z]) (world point to client pixel coordinates)}; without WebGL
// pixelStats, pickAt and project return null.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const hooks = { ready: false, error: null, loadMs: null, frames: 0, webgl: false };
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
const UNIT = data.scene.length_unit || data.scene.units || 'scene units';
const withUnit = (text) => text + ' ' + UNIT;

// The scene's up axis as a unit vector: 'z' -> [0, 0, 1], '-y' -> [0, -1, 0].
const UP_AXIS = data.scene.up || { axis: 'y', source: 'not given' };
const UP = (() => {
  const v = [0, 0, 0];
  v['xyz'.indexOf(UP_AXIS.axis.slice(-1))] = UP_AXIS.axis[0] === '-' ? -1 : 1;
  return v;
})();
Object.defineProperty(hooks, 'up', {
  enumerable: true,
  get: () => ({ axis: UP_AXIS.axis, source: UP_AXIS.source, vector: camera ? camera.up.toArray() : UP.slice() }),
});

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

// A value of verdict.json as a cell: an angle (a key
// "rotation") in radians and degrees, null as "none".
function valueText(key, value) {
  if (value === null) return 'none';
  if (typeof value === 'string') return value;
  if (typeof value === 'number' && /(^|\.)rotation$/.test(key)) return fmtAngle(value);
  return JSON.stringify(value);
}

function renderJsonTables() {
  const box = $('jsontables');
  for (const file of data.json_files) {
    const h = document.createElement('h2');
    h.textContent = (file.name === 'verdict' ? 'Verdict' : 'Statistics') + ' (' + file.file + ')';
    box.appendChild(h);
    const table = document.createElement('table');
    table.id = 'json-' + file.name;
    // Long keys and values wrap; the box scrolls should a table still not fit.
    const tableBox = document.createElement('div');
    tableBox.className = 'tablebox';
    tableBox.appendChild(table);
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
      box.appendChild(tableBox);
      continue;
    }
    const walk = (prefix, value) => {
      if (value !== null && typeof value === 'object' && !Array.isArray(value)) {
        for (const [k, v] of Object.entries(value)) walk(prefix ? prefix + '.' + k : k, v);
      } else {
        addRow(prefix || '(value)', valueText(prefix, value));
      }
    };
    walk('', parsed);
    box.appendChild(tableBox);
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
let view3d = false;  // the 3D view is up (WebGL)

// Whether the browser offers WebGL: asked of a throw-away canvas, so that a
// browser without it never reaches three.js's renderer (which would throw
// and log an error).
function webglAvailable() {
  try {
    const c = document.createElement('canvas');
    return !!(window.WebGLRenderingContext && (c.getContext('webgl2') || c.getContext('webgl')));
  } catch (e) {
    return false;
  }
}

const NO_WEBGL = '3D view needs WebGL, which this browser does not offer; the plots and tables below do not.';

// The 3D area without WebGL: the one sentence, and the controls that act on
// the 3D view only are switched off. The scrubber and Play still move the
// plots' cursor.
function showWithoutWebGL() {
  const view = $('view');
  view.classList.add('nowebgl');
  const p = document.createElement('p');
  p.id = 'nowebgl';
  p.textContent = NO_WEBGL;
  view.prepend(p);
  for (const id of ['opacity', 'showtrace', 'showghosts', 'section-axis', 'section-pos', 'measure']) $(id).disabled = true;
}

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
  if (view3d) {
    controls.update();
    renderer.render(scene3d, camera);
  }
}

function setupScene() {
  const canvas = $('canvas3d');
  renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  renderer.localClippingEnabled = true;
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

  const sky = new THREE.HemisphereLight(0xffffff, 0x8090a0, 1.6);
  sky.position.set(...UP);  // the sky above, the ground below, for the scene's up
  scene3d.add(sky);
  camera = new THREE.PerspectiveCamera(40, 1, 1, 1000);
  camera.up.set(...UP);  // before OrbitControls, which orbits about camera.up
  const light = new THREE.DirectionalLight(0xffffff, 1.6);
  light.position.set(0.5, 1, 1);
  camera.add(light);
  scene3d.add(camera);

  controls = new OrbitControls(camera, canvas);
  controls.addEventListener('change', requestRender);
  new ResizeObserver(resize).observe(canvas);
}

// Grows `box` by D's reach (radius r) about its reference point along `path`
// (the world position of the reference point, not the pose's t: D's mesh
// may lie far from its origin).
function expandByPath(box, path, r) {
  const offset = sub(path.reference_point, path.dynamic_origin);
  for (let k = 0; k <= 50; ++k) {
    const pose = poseAt(path, k / 50);
    const p = new THREE.Vector3(...add(pose.t, rotate(pose.q, offset)));
    box.expandByPoint(p.clone().addScalar(r));
    box.expandByPoint(p.clone().addScalar(-r));
  }
}

// The area vectors (twice the area times the normal) of a mesh's triangles,
// turned by `rotation` (a THREE.Quaternion, or null).
function areaVectors(geometry, rotation, out) {
  const p = geometry.attributes.position.array, index = geometry.index.array;
  for (let i = 0; i < index.length; i += 3) {
    const a = 3 * index[i], b = 3 * index[i + 1], c = 3 * index[i + 2];
    const u = new THREE.Vector3(p[b] - p[a], p[b + 1] - p[a + 1], p[b + 2] - p[a + 2]);
    const v = new THREE.Vector3(p[c] - p[a], p[c + 1] - p[a + 1], p[c + 2] - p[a + 2]);
    const m = u.cross(v);
    if (rotation) m.applyQuaternion(rotation);
    out.push(m);
  }
  return out;
}

// The first view's direction from the target: a little above (0.45 along
// up) and from the side that shows the most of S and D (their area as seen
// from there, of eight directions around up), so that a tilted panel is
// seen from its face, not its edge. The first candidate, kept on a tie, is
// (0.55, 0.45, 0.75) for y up.
function viewDirection() {
  const k = 'xyz'.indexOf(UP_AXIS.axis.slice(-1)), a = (k + 1) % 3, b = (k + 2) % 3;
  const areas = areaVectors(dynamicGeometry, dynamicMesh.quaternion, areaVectors(staticMesh.geometry, null, []));
  const horizontal = Math.sqrt(1 - 0.45 * 0.45), first = Math.atan2(0.55, 0.75);
  let best = null, bestSeen = -1;
  for (let j = 0; j < 8; ++j) {
    const phi = first + j * Math.PI / 4;
    const d = new THREE.Vector3();
    d.setComponent(k, 0.45 * UP[k]);
    d.setComponent(a, horizontal * Math.cos(phi));
    d.setComponent(b, horizontal * Math.sin(phi));
    let seen = 0;
    for (const m of areas) seen += Math.abs(m.dot(d));
    if (seen > bestSeen * (1 + 1e-9)) { best = d; bestSeen = seen; }
  }
  return best.normalize();
}

// A box around S and D's swept reference positions on the path shown: the
// camera's first view.
function fitCamera() {
  const box = staticMesh.geometry.boundingBox.clone();
  const r = dynamicGeometry.boundingSphere.radius;
  // The path shown (a planned path may wander far before smoothing).
  for (const path of state.path ? [state.path] : data.paths) expandByPath(box, path, r);
  const centre = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3()).length() || 1;
  camera.near = size / 1000;
  camera.far = size * 20;
  camera.position.copy(centre).add(viewDirection().multiplyScalar(size * 1.15));
  camera.updateProjectionMatrix();
  controls.target.copy(centre);
  controls.update();
}

function resize() {
  if (!view3d) { drawPlot(); return; }
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
  if (!view3d) return;
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

// ----------------------------------------------------------------- plots
// One panel per series (clearance, rigid penetration, clip intersection,
// and the volume model's intersection where profile.csv has it), one above
// the other on the same x: the path parameter u (animation time, 0 at the
// installed pose, 1 at the end; each segment in proportion to how far D's
// points move). Click or drag in a panel to seek.

const PLOT = { left: 70, right: 16, top: 20, bottom: 22, height: 132 };
const SERIES_COLOURS = { clearance: '#2f6db5', rigid: '#c8302b', clip: '#8a4fb0', volume: '#2f8f5b' };

function currentSeries() {
  return state.path && state.path.series.length ? state.path.series[0] : null;
}

let plotDragging = null;

function buildPlots() {
  const box = $('plots');
  box.innerHTML = '';
  const list = state.path ? state.path.series : [];
  if (!list.length) {
    const p = document.createElement('p');
    p.className = 'note';
    p.textContent = 'no per-pose values (no path)';
    box.appendChild(p);
    return;
  }
  for (const series of list) {
    const canvas = document.createElement('canvas');
    canvas.className = 'plot';
    canvas.dataset.series = series.name;
    canvas.style.height = PLOT.height + 'px';
    canvas.addEventListener('pointerdown', (e) => { plotDragging = canvas; setPlaying(false); plotSeek(canvas, e); });
    canvas.addEventListener('pointermove', (e) => { if (plotDragging === canvas) plotSeek(canvas, e); });
    box.appendChild(canvas);
  }
}

function finiteValues(values) { return values.filter((v) => v !== null && Number.isFinite(v)); }

function drawSeries(canvas, series, path) {
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
  const { left, right, top, bottom } = PLOT;
  const pw = w - left - right, ph = h - top - bottom;
  const dense = series.x.length > 0;
  const xs = dense ? series.x : path.times, ys = dense ? series.y : series.waypoints;
  const wx = path.times.slice(0, series.waypoints.length);
  const limit = series.name === 'rigid' && Number.isFinite(data.rigid_tolerance) ? data.rigid_tolerance : null;
  const all = finiteValues(ys.concat(series.waypoints)).concat(limit !== null ? [limit] : []);
  const ymin = Math.min(0, ...all);
  const ymax = (Math.max(...all, 0) - ymin) * 1.08 + ymin || 1;
  const X = (u) => left + u * pw, Y = (v) => top + ph - ((v - ymin) / (ymax - ymin)) * ph;
  ctx.fillStyle = '#1d232b';
  const unit = ' [' + (series.unit || UNIT) + ']';
  ctx.fillText(series.label + unit + (all.length ? '' : ': not measured'), left, 14);
  ctx.strokeStyle = '#d5dbe3';
  ctx.lineWidth = 1;
  ctx.textAlign = 'right';
  for (let k = 0; k <= 3; ++k) {
    const v = ymin + (ymax - ymin) * k / 3, y = Y(v);
    ctx.beginPath(); ctx.moveTo(left, y); ctx.lineTo(left + pw, y); ctx.stroke();
    ctx.fillText(Number(v.toPrecision(3)).toString(), left - 6, y + 4);
  }
  ctx.textAlign = 'center';
  for (let k = 0; k <= 10; ++k) ctx.fillText((k / 10).toFixed(1), X(k / 10), top + ph + 15);
  ctx.textAlign = 'right';
  ctx.fillText('u', left - 18, top + ph + 15);  // the x axis: the path parameter (no unit)
  ctx.textAlign = 'left';
  ctx.strokeStyle = '#eceff3';
  for (const t of path.times) { ctx.beginPath(); ctx.moveTo(X(t), top); ctx.lineTo(X(t), top + ph); ctx.stroke(); }
  if (limit !== null) {
    ctx.strokeStyle = '#c8302b';
    ctx.setLineDash([5, 4]);
    ctx.beginPath(); ctx.moveTo(left, Y(limit)); ctx.lineTo(left + pw, Y(limit)); ctx.stroke();
    ctx.setLineDash([]);
    ctx.fillStyle = '#c8302b';
    ctx.fillText('tolerance', left + pw - 60, Y(limit) - 3);
  }
  // The curve, with gaps where a value is missing; an unmeasured
  // intersection (null) is marked at the top in red.
  ctx.strokeStyle = SERIES_COLOURS[series.name] || '#2f6db5';
  ctx.lineWidth = 1.6;
  ctx.beginPath();
  let pen = false;
  xs.forEach((u, k) => {
    const v = ys[k];
    if (v === null || !Number.isFinite(v)) { pen = false; return; }
    if (pen) ctx.lineTo(X(u), Y(v)); else ctx.moveTo(X(u), Y(v));
    pen = true;
  });
  ctx.stroke();
  ctx.fillStyle = '#c8302b';
  xs.forEach((u, k) => { if (ys[k] === null) ctx.fillRect(X(u) - 1, top, 2, 6); });
  ctx.fillStyle = '#e8771e';
  wx.forEach((u, k) => {
    const v = series.waypoints[k];
    if (v === null || !Number.isFinite(v)) return;
    ctx.beginPath(); ctx.arc(X(u), Y(v), 2.6, 0, 2 * Math.PI); ctx.fill();
  });
  ctx.strokeStyle = '#c8302b';
  ctx.lineWidth = 1.5;
  ctx.beginPath(); ctx.moveTo(X(state.u), top); ctx.lineTo(X(state.u), top + ph); ctx.stroke();
}

function drawPlot() {
  if (!state.path) return;
  const canvases = $('plots').querySelectorAll('canvas.plot');
  canvases.forEach((canvas) => {
    const series = state.path.series.find((s) => s.name === canvas.dataset.series);
    if (series) drawSeries(canvas, series, state.path);
  });
}

function plotSeek(canvas, event) {
  const rect = canvas.getBoundingClientRect();
  const u = (event.clientX - rect.left - PLOT.left) / (rect.width - PLOT.left - PLOT.right);
  setTime(Math.min(1, Math.max(0, u)));
}

// -------------------------------------------------------- waypoint table

// A number for a cell or a label; a missing one in words, never "–" or "NaN".
function fmt(v, digits = 4) {
  if (v === null || v === undefined || Number.isNaN(v)) return 'not measured';
  if (!Number.isFinite(v)) return v > 0 ? 'unbounded' : 'not measured';
  return Number(v.toPrecision(digits)).toString();
}

// An angle in radians and degrees: "0.221 rad (12.7°)".
function fmtAngle(radians) {
  if (radians === null || !Number.isFinite(radians)) return 'not measured';
  return `${fmt(radians, 3)} rad (${fmt(radians * 180 / Math.PI, 3)}°)`;
}

// The rotation angle of a unit quaternion [w, x, y, z] (shorter arc).
function quaternionAngle(q) {
  return 2 * Math.atan2(Math.hypot(q[1], q[2], q[3]), Math.abs(q[0]));
}

function buildWaypointTable() {
  const box = $('waypointbox');
  box.innerHTML = '';
  const path = state.path;
  if (!path || !path.table || !path.waypoints.length) return;
  const table = document.createElement('table');
  table.id = 'waypoints';
  const units = ' [' + UNIT + ']';
  const hasVolume = path.table.rows.some((r) => r[3] !== null);
  const hasRigid = path.table.rows.some((r) => r[1] !== null);
  const header = ['waypoint', 'u', 't = (x, y, z)' + units, 'q = (w, x, y, z)', 'rotation (angle of q)',
    'clearance' + units]
    .concat(hasRigid ? ['rigid penetration' + units, 'clip intersection' + units] : [])
    .concat(hasVolume ? ['clip volume [' + (path.series.find((x) => x.name === 'volume') || {}).unit + ']'] : [])
    .concat(['part of D', 'part of S']);
  const head = table.createTHead().insertRow();
  for (const h of header) { const th = document.createElement('th'); th.textContent = h; head.appendChild(th); }
  const body = table.createTBody();
  path.table.rows.forEach((r, i) => {
    const wp = path.waypoints[i];
    const tr = body.insertRow();
    tr.dataset.index = String(i);
    const cells = [String(i), fmt(path.times[i], 3), wp.t.map((c) => fmt(c, 6)).join(', '),
      wp.q.map((c) => fmt(c, 4)).join(', '), fmtAngle(quaternionAngle(wp.q)), fmt(r[0])]
      .concat(hasRigid ? [r[1] === null ? 'intersects (unmeasured)' : fmt(r[1]), fmt(r[2])] : [])
      .concat(hasVolume ? [fmt(r[3])] : [])
      .concat([path.table.names[r[4]], path.table.names[r[5]]]);
    for (const c of cells) tr.insertCell().textContent = c;
    if (r[6]) tr.className = 'contact';
    tr.addEventListener('click', () => { setPlaying(false); setTime(path.times[i]); });
  });
  const note = document.createElement('p');
  note.className = 'explain';
  note.textContent = 'Parts: where D\'s rigid part penetrates S (rows marked), the deepest pair; elsewhere the ' +
    'nearest pair of triangles (FCL). Names: mesh file › node/mesh as in the file; "(shell k)": its k-th ' +
    'connected solid.';
  box.append(table, note);
}

// ------------------------------------------------------------- animation

function applyTime() {
  const pose = poseAt(state.path || { waypoints: [] }, state.u);
  if (view3d) placeD(dynamicMesh, pose);
  state.pose = pose;
  $('scrubber').value = String(Math.round(state.u * 1000));
  const path = state.path;
  let info = `u = ${state.u.toFixed(3)}`;
  if (path && path.waypoints.length > 1) info += `, segment ${pose.segment + 1}/${path.waypoints.length - 1}`;
  const series = currentSeries();
  if (series && series.x.length) {
    const k = Math.round(state.u * (series.x.length - 1));
    const c = series.y[k];
    info += c === null || !Number.isFinite(c) ? ', clearance not measured' : `, clearance ≈ ${withUnit(fmt(c, 3))}`;
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
    ? 'Curves at ' + series.x.length + ' poses evenly spaced along the path and at the waypoints (dots); ' +
      'x: the path parameter u (0: installed, 1: out; each segment in proportion to how far D\'s points move). ' +
      'Click or drag to seek.'
    : '';
  buildPlots();
  buildWaypointTable();
  rebuildPathObjects();
  section.box = null;
  applySection();
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
  window.addEventListener('pointerup', () => { plotDragging = null; });
  $('section-axis').addEventListener('change', () => applySection());
  $('section-pos').addEventListener('input', () => applySection());
  $('measure').addEventListener('click', () => setMeasuring(!measure.on));
  // A click (no drag) on the 3D view picks a point while measuring.
  const canvas = $('canvas3d');
  let down = null;
  canvas.addEventListener('pointerdown', (e) => { down = { x: e.clientX, y: e.clientY }; });
  canvas.addEventListener('pointerup', (e) => {
    if (measure.on && down && Math.hypot(e.clientX - down.x, e.clientY - down.y) < 4) pickAt(e.clientX, e.clientY);
    down = null;
  });
  window.addEventListener('keydown', (e) => {
    if (e.code === 'Space' && e.target.tagName !== 'INPUT' && e.target.tagName !== 'SELECT') {
      e.preventDefault();
      setPlaying(!state.playing);
    }
  });
  window.addEventListener('resize', drawPlot);
}

// --------------------------------------------------------- section plane
// A clipping plane across one axis: what lies beyond it (larger coordinate)
// is cut away from S, D and the ghosts, so that the inside shows. The
// slider runs over the box of S and the path.

const section = { axis: '', position: 0, plane: new THREE.Plane(new THREE.Vector3(-1, 0, 0), 0), box: null };

function sectionBox() {
  if (!section.box) {
    section.box = staticMesh.geometry.boundingBox.clone();
    if (state.path && state.path.waypoints.length) {
      expandByPath(section.box, state.path, dynamicGeometry.boundingSphere.radius);
    }
  }
  return section.box;
}

function clippedMaterials() {
  if (!view3d) return [];
  const list = [staticMesh.material, dynamicMesh.material];
  ghosts.children.forEach((g) => list.push(g.material));
  return list;
}

function applySection() {
  if (!view3d) return;
  const axis = $('section-axis').value;
  const fraction = Number($('section-pos').value) / 1000;
  const k = { x: 0, y: 1, z: 2 }[axis];
  const planes = axis ? [section.plane] : [];
  section.axis = axis;
  if (axis) {
    const box = sectionBox();
    const lo = box.min.getComponent(k), hi = box.max.getComponent(k);
    section.position = lo + fraction * (hi - lo);
    const normal = new THREE.Vector3();
    normal.setComponent(k, -1);
    section.plane.set(normal, section.position);  // keeps points with coordinate <= position
    $('section-info').textContent = ` ${axis} ≤ ${fmt(section.position, 5)}${data.scene.units ? ' ' + data.scene.units : ''}`;
  } else {
    $('section-info').textContent = '';
  }
  for (const m of clippedMaterials()) { m.clippingPlanes = planes; m.clipShadows = false; m.needsUpdate = true; }
  requestRender();
}

function setSection(axis, fraction) {
  $('section-axis').value = axis || '';
  $('section-pos').value = String(Math.round(Math.min(1, Math.max(0, fraction)) * 1000));
  applySection();
  return sectionState();
}

function sectionState() {
  return { axis: section.axis, position: section.axis ? section.position : null,
    clippedMaterials: clippedMaterials().filter((m) => m.clippingPlanes && m.clippingPlanes.length).length,
    normal: section.plane.normal.toArray(), constant: section.plane.constant };
}

// ------------------------------------------------------------ measurement
// Measure mode: two clicks on S or D (the first surface hit, not in the
// part the section plane cuts away) give the straight distance between the
// two points, in scene units, drawn as a line.

const measure = { on: false, points: [], group: null };

function setMeasuring(on) {
  measure.on = !!on;
  $('measure').setAttribute('aria-pressed', String(measure.on));
  $('measure').textContent = measure.on ? 'Measuring: click two points' : 'Measure';
  if (measure.on) { measure.points = []; drawMeasurement(); }
}

function pickAt(clientX, clientY) {
  if (!view3d) return null;
  const rect = renderer.domElement.getBoundingClientRect();
  const ndc = new THREE.Vector2(((clientX - rect.left) / rect.width) * 2 - 1, -((clientY - rect.top) / rect.height) * 2 + 1);
  const raycaster = new THREE.Raycaster();
  raycaster.setFromCamera(ndc, camera);
  const targets = [dynamicMesh, staticMesh].filter((o) => o.visible);
  const hits = raycaster.intersectObjects(targets, false)
    .filter((h) => !section.axis || section.plane.distanceToPoint(h.point) >= 0);
  if (!hits.length) return null;
  const hit = hits[0];
  if (measure.points.length >= 2) measure.points = [];
  measure.points.push({ point: hit.point.clone(), on: hit.object === dynamicMesh ? 'D' : 'S' });
  drawMeasurement();
  return { point: hit.point.toArray(), on: hit.object === dynamicMesh ? 'D' : 'S' };
}

function drawMeasurement() {
  if (!view3d) return;
  if (measure.group) { scene3d.remove(measure.group); measure.group.traverse((o) => o.geometry && o.geometry.dispose()); }
  measure.group = new THREE.Group();
  const size = sectionBox().getSize(new THREE.Vector3()).length() || 1;
  const dot = new THREE.SphereGeometry(size * 0.004, 12, 8);
  const dotMaterial = new THREE.MeshBasicMaterial({ color: 0xd01f6b, depthTest: false });
  for (const p of measure.points) {
    const m = new THREE.Mesh(dot, dotMaterial);
    m.position.copy(p.point);
    m.renderOrder = 5;
    measure.group.add(m);
  }
  let text = measure.on ? 'Measure: click a point on S or D' : '';
  if (measure.points.length === 2) {
    const [a, b] = measure.points;
    const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints([a.point, b.point]),
      new THREE.LineBasicMaterial({ color: 0xd01f6b, depthTest: false }));
    line.renderOrder = 5;
    measure.group.add(line);
    text = `distance ${fmt(a.point.distanceTo(b.point), 6)}${data.scene.units ? ' ' + data.scene.units : ''}` +
      ` (${a.on} [${a.point.toArray().map((c) => fmt(c, 5)).join(', ')}] to ${b.on}` +
      ` [${b.point.toArray().map((c) => fmt(c, 5)).join(', ')}])`;
  } else if (measure.points.length === 1) {
    text = 'Measure: click the second point';
  }
  $('measureinfo').textContent = text;
  $('measureinfo').style.display = text ? 'block' : 'none';
  scene3d.add(measure.group);
  requestRender();
}

function measurement() {
  const pts = measure.points.map((p) => p.point.toArray());
  return { points: pts, on: measure.points.map((p) => p.on),
    distance: pts.length === 2 ? measure.points[0].point.distanceTo(measure.points[1].point) : null,
    text: $('measureinfo').textContent };
}

function project(p) {
  if (!view3d) return null;
  const v = new THREE.Vector3(...p).project(camera);
  const rect = renderer.domElement.getBoundingClientRect();
  return { x: rect.left + (v.x + 1) / 2 * rect.width, y: rect.top + (1 - v.y) / 2 * rect.height, depth: v.z };
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
  if (!view3d) return null;
  const shown = readPixels();
  // How many pixels change when `object` is hidden, and the middle one of
  // them (in reading order) as client coordinates: a pixel that shows it.
  const at = [];
  const differing = (object) => {
    const visible = object.visible;
    object.visible = false;
    const hidden = readPixels();
    object.visible = visible;
    let n = 0;
    const found = [];
    for (let i = 0; i < shown.length; i += 4) {
      if (Math.abs(shown[i] - hidden[i]) + Math.abs(shown[i + 1] - hidden[i + 1]) + Math.abs(shown[i + 2] - hidden[i + 2]) > 6) {
        ++n;
        found.push(i / 4);
      }
    }
    at.push(found.length ? found[Math.floor(found.length / 2)] : -1);
    return n;
  };
  const dPixels = differing(dynamicMesh), sPixels = differing(staticMesh);
  const rect = renderer.domElement.getBoundingClientRect(), width = renderer.domElement.width;
  const scale = rect.width / width;
  const client = (i) => (i < 0 ? null
    : { x: rect.left + ((i % width) + 0.5) * scale, y: rect.top + (Math.floor(i / width) + 0.5) * scale });
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
    nonBackground, dPixels, sPixels, hash, dPixel: client(at[0]), sPixel: client(at[1]) };
}

// ------------------------------------------------------------------ start

// The tables and plots first and on their own: whatever becomes of the 3D
// view, they are shown.
function start() {
  renderJsonTables();
  if (webglAvailable()) {
    try {
      setupScene();
      view3d = true;
    } catch (e) {
      // WebGL offered but unusable (a lost or refused context): the page
      // goes on without the 3D view and says why.
      fail('the 3D view could not start: ' + (e && e.message ? e.message : String(e)));
    }
  }
  hooks.webgl = view3d;
  if (!view3d) showWithoutWebGL();
  setupControls();
  new ResizeObserver(() => drawPlot()).observe($('plots'));
  const initial = data.paths.find((p) => p.key === 'smoothed' && p.waypoints.length) ||
    data.paths.find((p) => p.waypoints.length) || data.paths[0];
  selectPath(initial ? initial.key : '');
  if (view3d) {
    fitCamera();
    resize();
    renderer.render(scene3d, camera);
  }
  Object.assign(hooks, {
    setTime,
    time: () => state.u,
    poseOfD: () => ({ t: state.pose.t.slice(), q: state.pose.q.slice(), path: state.path ? state.path.key : null,
      segment: state.pose.segment, s: state.pose.s }),
    view: () => (view3d ? { up: camera.up.toArray(), target: controls.target.toArray(),
      position: camera.position.toArray() } : null),
    selectPath,
    paths: () => data.paths.map((p) => ({ key: p.key, waypoints: p.waypoints.length, times: p.times.slice(),
      reference_point: p.reference_point.slice(), dynamic_origin: p.dynamic_origin.slice() })),
    play: () => setPlaying(true),
    pause: () => setPlaying(false),
    pixelStats,
    labelsShown: () => view3d && !!data.labels && dynamicMesh.material.vertexColors === true &&
      $('legend').style.display === 'block',
    plots: () => Array.from($('plots').querySelectorAll('canvas.plot')).map((c) => {
      const series = state.path.series.find((s) => s.name === c.dataset.series);
      const values = series.y.concat(series.waypoints);
      return { name: series.name, label: series.label, unit: series.unit, width: c.width, height: c.height,
        points: values.length, finite: values.filter((v) => v !== null && Number.isFinite(v)).length,
        max: Math.max(...values.filter((v) => v !== null && Number.isFinite(v))) };
    }),
    waypointRows: () => { const t = $('waypoints'); return t ? t.tBodies[0].rows.length : 0; },
    setSection,
    section: sectionState,
    setMeasuring,
    pickAt,
    measurement,
    project,
  });
  hooks.loadMs = performance.now();
  hooks.ready = true;
  const tri = data.static.triangles + data.dynamic.triangles;
  if (view3d) status(`${tri.toLocaleString('en')} triangles; ready in ${(hooks.loadMs / 1000).toFixed(2)} s`);
}

try {
  start();
} catch (e) {
  fail(e && e.message ? e.message : String(e));
}
