// The animation page of a run (animation.html): the bodies in space with
// three.js, the energy and the coordinates against time beside them, one
// clock for both. The page's data is the JSON in <script id="lagrangian-data">
// written by lagrangian::write_animation (include/lagrangian/animation.hpp);
// its fields are documented there. window.lagrangian is the page's interface
// for tests and scripts (seek, state, pixel; README of tests/browser).

import {
  AmbientLight, BufferAttribute, BufferGeometry, Color, DirectionalLight, DoubleSide, Group,
  InstancedMesh, Line, LineBasicMaterial, LineSegments, Matrix4, Mesh, MeshBasicMaterial,
  MeshLambertMaterial, Object3D, PerspectiveCamera, Points, Quaternion,
  Scene, ShaderMaterial, SphereGeometry, Vector3, WebGLRenderer, BoxGeometry, EdgesGeometry,
  CircleGeometry,
} from 'three';

const errors = [];
window.addEventListener('error', (e) => errors.push(String(e.message || e)));
window.addEventListener('unhandledrejection', (e) => errors.push(String(e.reason)));

const PALETTE = [0xd62728, 0x1f77b4, 0x2ca02c, 0xff7f0e, 0x9467bd, 0x8c564b, 0xe377c2, 0x17becf, 0xbcbd22];
const BACKGROUND = 0xf4f4f0;
const MANY_BODIES = 400;  // above this, bodies are drawn as shaded point sprites
const TRAIL_BODIES = 12;  // trails for at most this many bodies

function decodeFloats(base64) {
  const bin = atob(base64);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
  return new Float32Array(bytes.buffer);
}

function v3(a) { return new Vector3(a[0], a[1], a[2]); }

function formatTime(t) {
  const a = Math.abs(t);
  if (a !== 0 && (a < 1e-3 || a >= 1e5)) return t.toExponential(3) + ' s';
  return t.toFixed(a < 1 ? 4 : 3) + ' s';
}

// -- the data --------------------------------------------------------------------

const data = JSON.parse(document.getElementById('lagrangian-data').textContent);
const nBodies = data.bodies.length;
const times = data.frames.t;
const nFrames = times.length;
const positions = nBodies > 0 ? decodeFloats(data.frames.positions) : new Float32Array(0);
if (positions.length !== nFrames * nBodies * 3) throw new Error('animation data: positions do not match frames x bodies');

// Extent of everything drawn: bodies over the whole run and the fixed parts.
const lo = new Vector3(Infinity, Infinity, Infinity), hi = new Vector3(-Infinity, -Infinity, -Infinity);
const grow = (x, y, z, r = 0) => {
  lo.min(new Vector3(x - r, y - r, z - r));
  hi.max(new Vector3(x + r, y + r, z + r));
};
for (let f = 0; f < nFrames; ++f)
  for (let b = 0; b < nBodies; ++b) {
    const k = 3 * (f * nBodies + b);
    grow(positions[k], positions[k + 1], positions[k + 2], data.bodies[b].radius);
  }
for (const p of data.pivots) grow(p[0], p[1], p[2]);
for (const s of data.rods.concat(data.springs)) if (s.b < 0) grow(s.anchor[0], s.anchor[1], s.anchor[2]);
for (const b of data.boxes) { grow(...b.min); grow(...b.max); }
for (const s of data.spheres) grow(s.centre[0], s.centre[1], s.centre[2], s.radius);
for (const c of data.circles) grow(c.centre[0], c.centre[1], c.centre[2], c.radius);
if (!isFinite(lo.x)) { lo.set(-1, -1, -1); hi.set(1, 1, 1); }
const centre = lo.clone().add(hi).multiplyScalar(0.5);
const span = Math.max(hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-9);
const pointRadius = 0.025 * span;  // bodies without a radius
const drawnRadius = (b) => (data.bodies[b].radius > 0 ? data.bodies[b].radius : pointRadius);

// Planar motion: every body centre and fixed point on one coordinate plane.
const flatAxis = (() => {
  const mn = [Infinity, Infinity, Infinity], mx = [-Infinity, -Infinity, -Infinity];
  const see = (p) => { for (let a = 0; a < 3; ++a) { mn[a] = Math.min(mn[a], p[a]); mx[a] = Math.max(mx[a], p[a]); } };
  for (let i = 0; i < positions.length; i += 3) see(positions.subarray(i, i + 3));
  for (const p of data.pivots) see(p);
  for (const s of data.rods.concat(data.springs)) if (s.b < 0) see(s.anchor);
  if (nBodies === 0) return -1;
  return [0, 1, 2].findIndex((a) => mx[a] - mn[a] <= 1e-9 * span);
})();
const up = v3(data.up);

// -- the scene ---------------------------------------------------------------------

const view = document.getElementById('view');
const renderer = new WebGLRenderer({ antialias: nBodies <= MANY_BODIES });
renderer.setPixelRatio(1);
renderer.setClearColor(BACKGROUND);
view.appendChild(renderer.domElement);
const scene = new Scene();
scene.add(new AmbientLight(0xffffff, 1.6));
const camera = new PerspectiveCamera(35, 1, span * 1e-3, span * 100);
const headlight = new DirectionalLight(0xffffff, 1.6);
camera.add(headlight);
headlight.position.set(0.3, 0.5, 1);
scene.add(camera);

const colorOf = (b) => new Color(data.bodies[b].color !== undefined ? data.bodies[b].color
                                                                    : PALETTE[b % PALETTE.length]);

// Bodies: meshes, instanced spheres, or point sprites for many bodies.
let bodyMeshes = [], instanced = null, sprites = null;
const bodyGroup = new Group();
scene.add(bodyGroup);
if (nBodies > 0 && nBodies <= 24) {
  for (let b = 0; b < nBodies; ++b) {
    const m = new Mesh(new SphereGeometry(drawnRadius(b), 32, 16), new MeshLambertMaterial({ color: colorOf(b) }));
    bodyMeshes.push(m);
    bodyGroup.add(m);
  }
} else if (nBodies > 24 && nBodies <= MANY_BODIES) {
  instanced = new InstancedMesh(new SphereGeometry(1, 16, 8), new MeshLambertMaterial(), nBodies);
  instanced.frustumCulled = false;  // its bounding sphere would be the first frame's
  for (let b = 0; b < nBodies; ++b) instanced.setColorAt(b, colorOf(b));
  bodyGroup.add(instanced);
} else if (nBodies > MANY_BODIES) {
  const g = new BufferGeometry();
  g.setAttribute('position', new BufferAttribute(new Float32Array(3 * nBodies), 3));
  const radii = new Float32Array(nBodies), colors = new Float32Array(3 * nBodies);
  for (let b = 0; b < nBodies; ++b) {
    radii[b] = drawnRadius(b);
    const c = colorOf(b);
    colors.set([c.r, c.g, c.b], 3 * b);
  }
  g.setAttribute('radius', new BufferAttribute(radii, 1));
  g.setAttribute('color', new BufferAttribute(colors, 3));
  sprites = new Points(g, new ShaderMaterial({
    uniforms: { scale: { value: 1 } },
    vertexShader: `attribute float radius; attribute vec3 color; uniform float scale; varying vec3 vColor;
      void main() { vec4 mv = modelViewMatrix * vec4(position, 1.0); gl_Position = projectionMatrix * mv;
        gl_PointSize = max(2.0, 2.0 * radius * scale / -mv.z); vColor = color; }`,
    fragmentShader: `varying vec3 vColor;
      void main() { vec2 d = 2.0 * gl_PointCoord - 1.0; float r2 = dot(d, d); if (r2 > 1.0) discard;
        gl_FragColor = vec4(vColor * (0.75 + 0.25 * sqrt(1.0 - r2)), 1.0);
        #include <colorspace_fragment>
      }`,
  }));
  sprites.frustumCulled = false;
  bodyGroup.add(sprites);
}

// Rods (links) and springs: segments between bodies or to a fixed anchor.
function segmentSet(list, color) {
  if (list.length === 0) return null;
  const g = new BufferGeometry();
  g.setAttribute('position', new BufferAttribute(new Float32Array(6 * list.length), 3));
  const lines = new LineSegments(g, new LineBasicMaterial({ color }));
  lines.frustumCulled = false;
  scene.add(lines);
  return lines;
}
const rodLines = segmentSet(data.rods, 0x333333);
// A spring is drawn as a zig-zag along its axis.
const COILS = 12;
const springLines = data.springs.map(() => {
  const g = new BufferGeometry();
  g.setAttribute('position', new BufferAttribute(new Float32Array(3 * (2 * COILS + 3)), 3));
  const l = new Line(g, new LineBasicMaterial({ color: 0x7a5c00 }));
  l.frustumCulled = false;
  scene.add(l);
  return l;
});

// Fixed parts: pivots, planes (drawn as a square patch), the box, spheres.
for (const p of data.pivots) {
  const m = new Mesh(new SphereGeometry(0.4 * pointRadius, 16, 8), new MeshBasicMaterial({ color: 0x222222 }));
  m.position.copy(v3(p));
  scene.add(m);
}
for (const pl of data.planes) {
  // A square patch under the motion; in a planar scene, a plane seen edge-on
  // is a thin strip across the view instead of a floor in perspective.
  const n = v3(pl.normal).normalize();
  const p0 = v3(pl.point);
  const c = centre.clone().sub(n.clone().multiplyScalar(centre.clone().sub(p0).dot(n)));
  let u = new Vector3(Math.abs(n.x) < 0.9 ? 1 : 0, Math.abs(n.x) < 0.9 ? 0 : 1, 0).cross(n).normalize();
  let hu = 0.6 * span;
  if (flatAxis >= 0) {
    const e = new Vector3().setComponent(flatAxis, 1);
    const along = e.clone().sub(n.clone().multiplyScalar(e.dot(n)));
    if (along.length() > 0.9) { u = along.normalize(); hu = 0.04 * span; }
  }
  const w = new Vector3().crossVectors(n, u).normalize();
  const hw = 0.6 * span;
  const corners = [[-1, -1], [1, -1], [1, 1], [-1, 1]].map(([a, b]) =>
    c.clone().add(u.clone().multiplyScalar(a * hu)).add(w.clone().multiplyScalar(b * hw)));
  const g = new BufferGeometry();
  g.setAttribute('position', new BufferAttribute(new Float32Array(corners.flatMap((p) => [p.x, p.y, p.z])), 3));
  g.setIndex([0, 1, 2, 0, 2, 3]);
  g.computeVertexNormals();
  scene.add(new Mesh(g, new MeshLambertMaterial({ color: 0xb9b4a6, side: DoubleSide, transparent: true, opacity: 0.55 })));
  const eg = new BufferGeometry();
  eg.setAttribute('position', new BufferAttribute(new Float32Array([0, 1, 1, 2, 2, 3, 3, 0].flatMap((i) => [corners[i].x, corners[i].y, corners[i].z])), 3));
  scene.add(new LineSegments(eg, new LineBasicMaterial({ color: 0x6b665a })));
}
for (const bx of data.boxes) {
  const a = v3(bx.min), b = v3(bx.max);
  const geom = new EdgesGeometry(new BoxGeometry(b.x - a.x, b.y - a.y, b.z - a.z));
  const box = new LineSegments(geom, new LineBasicMaterial({ color: 0x444444 }));
  box.position.copy(a.clone().add(b).multiplyScalar(0.5));
  scene.add(box);
}
for (const s of data.spheres) {
  const m = new Mesh(new SphereGeometry(s.radius, 48, 24),
                     new MeshLambertMaterial({ color: 0x9fb4c7, transparent: true, opacity: 0.25, depthWrite: false }));
  m.position.copy(v3(s.centre));
  scene.add(m);
}
for (const c of data.circles) {
  const ring = new LineSegments(new EdgesGeometry(new CircleGeometry(c.radius, 96)),
                                new LineBasicMaterial({ color: 0x666666 }));
  ring.position.copy(v3(c.centre));
  ring.quaternion.copy(new Quaternion().setFromUnitVectors(new Vector3(0, 0, 1), v3(c.normal).normalize()));
  scene.add(ring);
}

// Trails: each body's path up to the current frame.
const trailCount = Math.min(nBodies, TRAIL_BODIES);
document.getElementById('trails').checked = nBodies <= 24;  // many bodies: off at first
const trails = [];
for (let b = 0; b < trailCount; ++b) {
  const pts = new Float32Array(3 * nFrames);
  for (let f = 0; f < nFrames; ++f) pts.set(positions.subarray(3 * (f * nBodies + b), 3 * (f * nBodies + b) + 3), 3 * f);
  const g = new BufferGeometry();
  g.setAttribute('position', new BufferAttribute(pts, 3));
  const c = colorOf(b).lerp(new Color(BACKGROUND), 0.35);
  const l = new Line(g, new LineBasicMaterial({ color: c }));
  l.frustumCulled = false;
  scene.add(l);
  trails.push(l);
}

// -- the camera: orbit about the scene's centre -----------------------------------

const orbit = { target: centre.clone(), distance: 1, dir: new Vector3() };
function homeView() {
  orbit.target.copy(centre);
  orbit.distance = (flatAxis >= 0 ? 1.25 : 1.7) * span / (2 * Math.tan((35 * Math.PI) / 360));
  if (flatAxis >= 0) {
    // look along the normal of the plane of motion, `up` (or the next axis) upwards
    orbit.dir.set(0, 0, 0).setComponent(flatAxis, 1);
    camera.up.copy(Math.abs(up.getComponent(flatAxis)) > 0.9 ? new Vector3(0, 0, 0).setComponent((flatAxis + 2) % 3, 1) : up);
    // from the side that shows the plane's other axes increasing rightwards
    const right = new Vector3().crossVectors(camera.up, orbit.dir);
    if (right.x + right.y + right.z < 0) orbit.dir.negate();
  } else {
    camera.up.copy(up);
    const side = new Vector3(1, 0, 0);
    if (Math.abs(up.dot(side)) > 0.9) side.set(0, 1, 0);
    const across = new Vector3().crossVectors(up, side).normalize();
    orbit.dir.copy(side).multiplyScalar(0.45).add(across.multiplyScalar(-1)).add(up.clone().multiplyScalar(0.45)).normalize();
  }
  placeCamera();
}
function placeCamera() {
  camera.position.copy(orbit.target).add(orbit.dir.clone().multiplyScalar(orbit.distance));
  camera.lookAt(orbit.target);
  camera.updateMatrixWorld();
  requestDraw();
}
{
  let drag = null;
  const el = renderer.domElement;
  el.addEventListener('pointerdown', (e) => { drag = { x: e.clientX, y: e.clientY, pan: e.button !== 0 || e.shiftKey }; el.setPointerCapture(e.pointerId); });
  el.addEventListener('pointerup', () => { drag = null; });
  el.addEventListener('contextmenu', (e) => e.preventDefault());
  el.addEventListener('pointermove', (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX; drag.y = e.clientY;
    const right = new Vector3().crossVectors(camera.up, orbit.dir).normalize();
    if (drag.pan) {
      const k = orbit.distance / el.clientHeight;
      const camUp = new Vector3().crossVectors(orbit.dir, right).normalize();
      orbit.target.add(right.multiplyScalar(-dx * k)).add(camUp.multiplyScalar(dy * k));
    } else {
      orbit.dir.applyAxisAngle(camera.up, -dx * 0.008);
      const next = orbit.dir.clone().applyAxisAngle(right, -dy * 0.008);
      if (Math.abs(next.dot(camera.up)) < 0.995) orbit.dir.copy(next);
      orbit.dir.normalize();
    }
    placeCamera();
  });
  el.addEventListener('wheel', (e) => { e.preventDefault(); orbit.distance *= Math.exp(e.deltaY * 0.001); placeCamera(); }, { passive: false });
}

// -- the charts: energy and coordinates against time --------------------------------

const charts = [];
function addChart(title, series, unit, floor = 0) {
  const box = document.createElement('div');
  box.className = 'chart';
  const label = document.createElement('div');
  label.className = 'chart-title';
  label.textContent = title;
  const canvas = document.createElement('canvas');
  box.append(label, canvas);
  document.getElementById('charts').appendChild(box);
  const chart = { canvas, series, unit, floor, title };
  canvas.addEventListener('pointerdown', (e) => {
    const r = canvas.getBoundingClientRect();
    const u = (e.clientX - r.left - chart.x0) / chart.w;
    seek(times[0] + Math.min(1, Math.max(0, u)) * (times[nFrames - 1] - times[0]));
  });
  charts.push(chart);
}
// The energy chart: the relative change (E − E0)/|E0| computed by the writer, on an axis at least ±floor wide,
// so that round-off draws as the flat line it is; the title says how constant the energy was.
if (data.energy) {
  const e = data.energy, sig = (v) => Number(v.toPrecision(10)).toString();
  const title = e.span <= e.floor
    ? `${e.name}: ${sig(e.e0)} ${e.unit}, constant to ${e.span.toPrecision(2)} of ${e.relative_to}`
    : `${e.name}: (E − E0) / ${e.relative_to}, E0 = ${sig(e.e0)} ${e.unit}`;
  addChart(title, [{ name: e.name, unit: '', values: e.values }], '', e.floor);
}
{
  const byUnit = new Map();
  for (const s of data.coordinates) {
    if (!byUnit.has(s.unit)) byUnit.set(s.unit, []);
    byUnit.get(s.unit).push(s);
  }
  for (const [unit, list] of byUnit) addChart('coordinates (' + unit + ')', list, unit);
}
if (data.coordinates_note) {
  const n = document.createElement('div');
  n.className = 'note';
  n.textContent = data.coordinates_note;
  document.getElementById('charts').appendChild(n);
}

function drawChart(chart, t) {
  const c = chart.canvas, ctx = c.getContext('2d');
  const W = c.clientWidth, H = c.clientHeight;
  if (c.width !== W || c.height !== H) { c.width = W; c.height = H; }
  ctx.clearRect(0, 0, W, H);
  let ymin = Infinity, ymax = -Infinity;
  for (const s of chart.series) for (const v of s.values) if (Number.isFinite(v)) { ymin = Math.min(ymin, v); ymax = Math.max(ymax, v); }
  if (!isFinite(ymin)) { ymin = 0; ymax = 1; }
  if (chart.floor > 0) { ymin = Math.min(ymin, -chart.floor); ymax = Math.max(ymax, chart.floor); }
  if (!(ymax - ymin > 1e-12 * Math.max(Math.abs(ymin), Math.abs(ymax)))) {
    const m = ymax !== 0 ? Math.abs(ymax) * 1e-3 : 1;  // a constant: centred in a band of ±0.1 %
    ymin -= m; ymax += m;
  }
  const x0 = 58, w = W - x0 - 8, y0 = 6, h = H - y0 - 18;
  chart.x0 = x0; chart.w = w; chart.ymin = ymin; chart.ymax = ymax;
  const t0 = times[0], t1 = times[nFrames - 1] > t0 ? times[nFrames - 1] : t0 + 1;
  const X = (tt) => x0 + ((tt - t0) / (t1 - t0)) * w, Y = (v) => y0 + (1 - (v - ymin) / (ymax - ymin)) * h;
  ctx.strokeStyle = '#999'; ctx.lineWidth = 1; ctx.strokeRect(x0, y0, w, h);
  ctx.fillStyle = '#444'; ctx.font = '10px sans-serif'; ctx.textAlign = 'right';
  ctx.fillText(ymax.toPrecision(4), x0 - 3, y0 + 8); ctx.fillText(ymin.toPrecision(4), x0 - 3, y0 + h);
  ctx.textAlign = 'left'; ctx.fillText(formatTime(t0), x0, H - 4);
  ctx.textAlign = 'right'; ctx.fillText(formatTime(t1), x0 + w, H - 4);
  // events: ticks along the time axis
  ctx.strokeStyle = data.events.length > 300 ? 'rgba(200,60,40,0.08)' : 'rgba(200,60,40,0.55)';
  for (const e of data.events) { const x = X(e.t); ctx.beginPath(); ctx.moveTo(x, y0 + h); ctx.lineTo(x, y0 + h - 6); ctx.stroke(); }
  chart.series.forEach((s, i) => {
    ctx.strokeStyle = '#' + PALETTE[i % PALETTE.length].toString(16).padStart(6, '0');
    ctx.beginPath();
    const step = Math.max(1, Math.floor(s.values.length / (2 * w)));
    let pen = false;  // a missing value (null in the data) leaves a gap
    for (let k = 0; k < s.values.length; k += step) {
      if (!Number.isFinite(s.values[k])) { pen = false; continue; }
      const x = X(times[k]), y = Y(s.values[k]);
      if (pen) ctx.lineTo(x, y); else ctx.moveTo(x, y);
      pen = true;
    }
    ctx.stroke();
    ctx.fillStyle = ctx.strokeStyle; ctx.textAlign = 'left';
    if (chart.series.length > 1) ctx.fillText(s.name, x0 + 4 + 60 * i, y0 + 11);
  });
  // the cursor
  ctx.strokeStyle = '#000'; ctx.beginPath(); ctx.moveTo(X(t), y0); ctx.lineTo(X(t), y0 + h); ctx.stroke();
}

// -- playback ---------------------------------------------------------------------------

const ui = {
  play: document.getElementById('play'), speed: document.getElementById('speed'),
  slider: document.getElementById('time'), clock: document.getElementById('clock'),
  trails: document.getElementById('trails'), status: document.getElementById('status'),
  flash: document.getElementById('flash'), home: document.getElementById('home'),
};
ui.slider.max = String(Math.max(0, nFrames - 1));
let frame = 0, playing = false, simTime = times[0], lastWall = null, drawQueued = false;
const duration = times[nFrames - 1] - times[0];
// Default speed: the whole run in about 10 s of playback, in a round ratio.
{
  const wanted = duration > 0 ? duration / 10 : 1;
  const options = [1e-4, 1e-3, 0.01, 0.1, 0.25, 0.5, 1, 2, 5, 10, 100, 1000, 1e4, 1e5];
  for (const o of options) {
    const opt = document.createElement('option');
    opt.value = String(o);
    opt.textContent = o + '×';
    ui.speed.appendChild(opt);
  }
  let best = options[0];
  for (const o of options) if (Math.abs(Math.log(o / wanted)) < Math.abs(Math.log(best / wanted))) best = o;
  ui.speed.value = String(best);
}

function frameAt(t) {
  // the last frame at or before t
  let a = 0, b = nFrames - 1;
  if (t >= times[b]) return b;
  while (a < b) { const m = (a + b + 1) >> 1; if (times[m] <= t) a = m; else b = m - 1; }
  return a;
}

const tmp = new Object3D();
let flashUntil = -Infinity, flashBodies = new Set();
function applyFrame() {
  const P = (b) => positions.subarray(3 * (frame * nBodies + b), 3 * (frame * nBodies + b) + 3);
  const flashing = performance.now() < flashUntil;
  bodyMeshes.forEach((m, b) => {
    m.position.fromArray(P(b));
    m.material.emissive.setHex(flashing && flashBodies.has(b) ? 0x884400 : 0x000000);
  });
  if (instanced) {
    for (let b = 0; b < nBodies; ++b) {
      tmp.position.fromArray(P(b));
      tmp.scale.setScalar(drawnRadius(b));
      tmp.updateMatrix();
      instanced.setMatrixAt(b, tmp.matrix);
    }
    instanced.instanceMatrix.needsUpdate = true;
  }
  if (sprites) {
    sprites.geometry.attributes.position.array.set(positions.subarray(3 * frame * nBodies, 3 * (frame + 1) * nBodies));
    sprites.geometry.attributes.position.needsUpdate = true;
    sprites.material.uniforms.scale.value = renderer.domElement.height / (2 * Math.tan((camera.fov * Math.PI) / 360));
  }
  const end = (s) => (s.b >= 0 ? P(s.b) : s.anchor);
  if (rodLines) {
    const a = rodLines.geometry.attributes.position.array;
    data.rods.forEach((s, i) => { a.set(P(s.a), 6 * i); a.set(end(s), 6 * i + 3); });
    rodLines.geometry.attributes.position.needsUpdate = true;
  }
  data.springs.forEach((s, i) => {
    const A = v3(P(s.a)), B = v3(end(s));
    const axis = B.clone().sub(A), len = axis.length();
    const side = new Vector3(0, 0, 1).cross(axis);
    if (side.lengthSq() < 1e-12 * len * len) side.set(1, 0, 0).cross(axis);
    side.normalize().multiplyScalar(0.15 * pointRadius * 4);
    const arr = springLines[i].geometry.attributes.position.array;
    let k = 0;
    const put = (p) => { arr[k++] = p.x; arr[k++] = p.y; arr[k++] = p.z; };
    put(A);
    for (let j = 0; j <= 2 * COILS; ++j) {
      const u = 0.1 + (0.8 * j) / (2 * COILS);
      const p = A.clone().add(axis.clone().multiplyScalar(u));
      if (j > 0 && j < 2 * COILS) p.add(side.clone().multiplyScalar(j % 2 ? 1 : -1));
      put(p);
    }
    put(B);
    springLines[i].geometry.attributes.position.needsUpdate = true;
  });
  for (const l of trails) { l.visible = ui.trails.checked; l.geometry.setDrawRange(0, frame + 1); }
}

function requestDraw() {
  if (drawQueued) return;
  drawQueued = true;
  requestAnimationFrame(tick);
}

function resize() {
  const w = view.clientWidth, h = view.clientHeight;
  if (renderer.domElement.width !== w || renderer.domElement.height !== h) {
    renderer.setSize(w, h, true);
    camera.aspect = w / Math.max(1, h);
    camera.updateProjectionMatrix();
  }
}

function drawNow() {
  resize();
  applyFrame();
  renderer.render(scene, camera);
  const t = times[frame];
  for (const c of charts) drawChart(c, t);
  ui.clock.textContent = 't = ' + formatTime(t);
  ui.slider.value = String(frame);
}

// Frames drawn per second of wall time, over the last second.
const fps = { count: 0, since: performance.now(), value: 0 };
function tick(now) {
  drawQueued = false;
  if (playing) {
    if (lastWall !== null) simTime += ((now - lastWall) / 1000) * Number(ui.speed.value);
    lastWall = now;
    if (simTime >= times[nFrames - 1]) { simTime = times[nFrames - 1]; setPlaying(false); }
    const next = frameAt(simTime);
    for (const e of data.events) if ((e.t > times[frame] || (frame === 0 && e.t === times[0])) && e.t <= times[next]) flashEvent(e);
    frame = next;
  }
  drawNow();
  ++fps.count;
  if (now - fps.since >= 1000) {
    fps.value = (1000 * fps.count) / (now - fps.since);
    fps.count = 0; fps.since = now;
    showStatus();
  }
  if (playing || performance.now() < flashUntil) requestDraw();
}

function flashEvent(e) {
  flashUntil = performance.now() + 250;
  flashBodies = new Set(e.bodies.length ? e.bodies : [...Array(nBodies).keys()]);
  ui.flash.textContent = e.kind + (e.label ? ' ' + e.label : '') + ' at ' + formatTime(e.t);
  ui.flash.classList.add('on');
  clearTimeout(flashEvent.timer);
  flashEvent.timer = setTimeout(() => ui.flash.classList.remove('on'), 700);
}

function showStatus() {
  let s = data.frames.note;
  if (playing && fps.value > 0) {
    s += ' · drawing ' + fps.value.toFixed(0) + ' frames/s';
    const perFrame = (Number(ui.speed.value) / Math.max(fps.value, 1e-9)) / Math.max(data.frames.interval, 1e-300);
    if (fps.value < 30) s += ' (below 30: frames are thinned to keep the speed, about one sample in ' + Math.max(1, Math.round(perFrame)) + ' drawn)';
  }
  ui.status.textContent = s;
}

function setPlaying(on) {
  playing = on;
  ui.play.textContent = on ? '❚❚ pause' : '▶ play';
  lastWall = null;
  if (on) {
    if (frame >= nFrames - 1) { frame = 0; simTime = times[0]; }
    fps.count = 0; fps.since = performance.now();
    requestDraw();
  }
  showStatus();
}

function seek(t) {
  frame = frameAt(t);
  simTime = times[frame];
  drawNow();
}

ui.play.addEventListener('click', () => setPlaying(!playing));
ui.slider.addEventListener('input', () => { frame = Number(ui.slider.value); simTime = times[frame]; requestDraw(); });
ui.trails.addEventListener('change', requestDraw);
ui.home.addEventListener('click', homeView);
window.addEventListener('resize', requestDraw);
window.addEventListener('keydown', (e) => { if (e.code === 'Space') { e.preventDefault(); setPlaying(!playing); } });

homeView();
seek(times[0]);
showStatus();

// -- the page's interface for tests and scripts ------------------------------------------

const bodyWorld = (b) => v3(positions.subarray(3 * (frame * nBodies + b), 3 * (frame * nBodies + b) + 3));
window.lagrangian = {
  errors,
  data,
  /// Shows the last frame at or before t (s); returns that frame's time.
  seek(t) { seek(t); return times[frame]; },
  play(on = true) { setPlaying(on); },
  /// The drawn state: time, canvas size (CSS px), the camera's view-projection
  /// matrix (column-major) and each body's centre as drawn, in canvas pixels.
  state() {
    drawNow();
    const c = renderer.domElement;
    const vp = new Matrix4().multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse);
    const bodies = [];
    for (let b = 0; b < nBodies; ++b) {
      const p = bodyMeshes[b] ? bodyMeshes[b].position.clone() : bodyWorld(b);
      p.project(camera);
      bodies.push({ x: ((p.x + 1) / 2) * c.clientWidth, y: ((1 - p.y) / 2) * c.clientHeight });
    }
    const r = c.getBoundingClientRect();
    return { t: times[frame], frame, frames: nFrames, width: c.clientWidth, height: c.clientHeight, pointRadius,
             left: r.left, top: r.top, viewProjection: vp.elements.slice(), bodies, fps: fps.value,
             background: '#' + BACKGROUND.toString(16) };
  },
  /// The colour drawn at canvas pixel (x, y), [r, g, b] in 0..255.
  pixel(x, y) { return window.lagrangian.pixels([[x, y]])[0]; },
  /// The colours at several canvas pixels [[x, y], …], from one drawing.
  pixels(points) {
    drawNow();
    const gl = renderer.getContext(), px = new Uint8Array(4), h = renderer.domElement.height;
    return points.map(([x, y]) => {
      gl.readPixels(Math.round(x), h - 1 - Math.round(y), 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
      return [px[0], px[1], px[2]];
    });
  },
  /// The charts as drawn: each one's title and vertical axis range [ymin, ymax].
  charts() { drawNow(); return charts.map((c) => ({ title: c.title, ymin: c.ymin, ymax: c.ymax })); },
  /// A body's colour, [r, g, b] in 0..255 (sRGB).
  bodyColor(b) { const h = colorOf(b).getHex(); return [(h >> 16) & 255, (h >> 8) & 255, h & 255]; },
  ready: true,
};
