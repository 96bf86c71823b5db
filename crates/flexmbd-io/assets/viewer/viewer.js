// flexmbd view: the 3D viewer of a flexmbd HTML report (an ES module, inlined in the page).
//
// The page holds the data (JSON, see crates/flexmbd-io/src/html_view.rs) and the sources of
// three.js and its OrbitControls as text; both are imported from Blob URLs made here, so the
// page needs no network and works from a file:// URL.
//
// Geometry: every beam is its cross-section swept along the cubic Hermite curve through its end
// positions with the end tangents of the current node rotations; trusses, rigid-body bars and
// hinges are straight tubes. Node states are those of the selected frame (reference, load step,
// static state), displaced by the selected animation: x + s·u and R(s·w)·R with
// s = amplitude · scale · sin(2π·phase).
//
// URL hash parameters (for a fixed picture, e.g. in tests):
//   item=K (animation, 0-based; none: no animation)  phase=P (0..1)  paused=1  step=K (frame)
//   color=KEY (a field key, or type)  amp=A (amplitude factor)  view=iso|x|y|z
//
// A simulation (DATA.simulation) is played over its output times by simulate.js, appended to
// this file in the page: the functions sim* there are called below.

const DATA = JSON.parse(document.getElementById('flexmbd-data').textContent);
const NN = DATA.nodes.length;
const NE = DATA.elements.length;
const SIZE = DATA.size > 0 ? DATA.size : 1;

// ---------------------------------------------------------------------------------------------
// Small vector and quaternion helpers on plain arrays; quaternions are [λ0, λ1, λ2, λ3].

function add3(a, b) { return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]; }
function sub3(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
function scale3(s, a) { return [s * a[0], s * a[1], s * a[2]]; }
function dot3(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
function cross3(a, b) {
  return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
}
function norm3(a) { return Math.sqrt(dot3(a, a)); }
function unit3(a, fallback) {
  const n = norm3(a);
  return n > 1e-300 ? scale3(1 / n, a) : (fallback || [1, 0, 0]);
}
/** A unit vector perpendicular to the unit vector t. */
function perpendicular(t) {
  const ax = Math.abs(t[0]), ay = Math.abs(t[1]), az = Math.abs(t[2]);
  const e = ax <= ay && ax <= az ? [1, 0, 0] : (ay <= az ? [0, 1, 0] : [0, 0, 1]);
  return unit3(sub3(e, scale3(dot3(e, t), t)));
}
function qmul(a, b) {
  return [
    a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
    a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
    a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
    a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
  ];
}
/** R(q) v, as flexmbd_core::math::rotate. */
function qrot(q, v) {
  const l = [q[1], q[2], q[3]];
  const n2 = q[0] * q[0] + dot3(l, l);
  const c0 = q[0] * q[0] - dot3(l, l);
  const c1 = 2 * dot3(l, v);
  const c2 = 2 * q[0];
  const lv = cross3(l, v);
  return [
    (c0 * v[0] + c1 * l[0] + c2 * lv[0]) / n2,
    (c0 * v[1] + c1 * l[1] + c2 * lv[1]) / n2,
    (c0 * v[2] + c1 * l[2] + c2 * lv[2]) / n2,
  ];
}
/** Euler parameters of the rotation vector w (axis × angle). */
function qFromRotvec(w) {
  const a = norm3(w);
  if (a < 1e-300) return [1, 0, 0, 0];
  const s = Math.sin(a / 2) / a;
  return [Math.cos(a / 2), s * w[0], s * w[1], s * w[2]];
}

// ---------------------------------------------------------------------------------------------
// Formatting and colour maps.

function fmt(v) {
  if (v === null || v === undefined || !isFinite(v)) return '–';
  const a = Math.abs(v);
  if (a === 0) return '0';
  if (a >= 1e-3 && a < 1e5) return String(Number(v.toPrecision(4)));
  return v.toExponential(3);
}
function esc(s) {
  return String(s).replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;')
    .replace(/"/g, '&quot;');
}
const DIVERGING = [
  [0.0, [0.09, 0.25, 0.60]], [0.25, [0.36, 0.58, 0.86]], [0.5, [0.80, 0.81, 0.83]],
  [0.75, [0.93, 0.50, 0.35]], [1.0, [0.70, 0.07, 0.10]],
];
const SEQUENTIAL = [
  [0.0, [0.27, 0.00, 0.33]], [0.2, [0.23, 0.32, 0.55]], [0.4, [0.13, 0.57, 0.55]],
  [0.6, [0.20, 0.72, 0.47]], [0.8, [0.56, 0.84, 0.26]], [1.0, [0.99, 0.91, 0.14]],
];
const UNDEFINED_COLOR = [0.78, 0.80, 0.83];
const SELECTED_COLOR = [1.0, 0.78, 0.05];
const TYPE_COLORS = {
  beam: [0.33, 0.50, 0.70],
  truss: [0.25, 0.33, 0.45],
  hinge: [0.85, 0.50, 0.12],
  rigid: [0.42, 0.45, 0.52],
};
function cmap(stops, t) {
  t = Math.min(1, Math.max(0, t));
  for (let i = 1; i < stops.length; i++) {
    if (t <= stops[i][0]) {
      const [t0, c0] = stops[i - 1], [t1, c1] = stops[i];
      const f = (t - t0) / (t1 - t0);
      return [c0[0] + f * (c1[0] - c0[0]), c0[1] + f * (c1[1] - c0[1]), c0[2] + f * (c1[2] - c0[2])];
    }
  }
  return stops[stops.length - 1][1];
}
function rgbCss(c) {
  return 'rgb(' + c.map((x) => Math.round(255 * x)).join(',') + ')';
}

// ---------------------------------------------------------------------------------------------
// State, from the URL hash.

function initialState() {
  const p = new URLSearchParams(location.hash.replace(/^#/, ''));
  const num = (k, d) => {
    const v = p.get(k);
    if (v === null || v === '') return d;
    const x = Number(v);
    return isFinite(x) ? x : d;
  };
  const nA = DATA.animations.length;
  let item = nA > 0 ? 0 : -1;
  if (p.has('item')) {
    const v = p.get('item');
    item = v === 'none' ? -1 : Math.round(num('item', item));
    if (item >= nA || item < -1) item = nA > 0 ? 0 : -1;
  }
  let frame = DATA.analysis === 'static' ? DATA.frames.length - 1 : 0;
  if (p.has('step')) frame = Math.min(DATA.frames.length - 1, Math.max(0, Math.round(num('step', 0))));
  let color = defaultColor();
  if (p.has('color')) {
    const c = p.get('color');
    if (c === 'type' || DATA.fields.some((f) => f.key === c)) color = c;
  }
  return {
    item,
    frame,
    phase: ((num('phase', 0.25) % 1) + 1) % 1,
    playing: p.get('paused') !== '1',
    amp: Math.max(0, num('amp', 1)),
    color,
    view: p.get('view') || 'iso',
    ghost: true,
    selected: -1,
    speed: 0.5,
  };
}
function defaultColor() {
  const keys = DATA.fields.map((f) => f.key);
  for (const k of ['self_stress_1', 'max_stress', 'sigma1', 'strain_energy']) {
    if (keys.includes(k)) return k;
  }
  return keys.length > 0 ? keys[0] : 'type';
}
const state = initialState();

// ---------------------------------------------------------------------------------------------
// Node states of the current frame and animation.

/** Positions (3 per node) and Euler parameters (4 per node) to draw. */
function nodeStates(frameIndex, item, phase, amp) {
  const f = DATA.frames[frameIndex];
  const x = new Float64Array(f.x);
  const q = new Float64Array(f.q);
  if (item >= 0) {
    const a = DATA.animations[item];
    const s = amp * a.scale * Math.sin(2 * Math.PI * phase);
    for (let i = 0; i < NN; i++) {
      for (let k = 0; k < 3; k++) x[3 * i + k] += s * a.u[3 * i + k];
      const w = [s * a.w[3 * i], s * a.w[3 * i + 1], s * a.w[3 * i + 2]];
      if (w[0] !== 0 || w[1] !== 0 || w[2] !== 0) {
        const r = qmul(qFromRotvec(w), [q[4 * i], q[4 * i + 1], q[4 * i + 2], q[4 * i + 3]]);
        const n = Math.hypot(r[0], r[1], r[2], r[3]);
        for (let k = 0; k < 4; k++) q[4 * i + k] = r[k] / n;
      }
    }
  }
  return {
    x,
    q,
    pos: (i) => [x[3 * i], x[3 * i + 1], x[3 * i + 2]],
    rot: (i) => [q[4 * i], q[4 * i + 1], q[4 * i + 2], q[4 * i + 3]],
  };
}

// ---------------------------------------------------------------------------------------------
// Swept geometry: a profile (points with normals in the local y-z plane) along stations
// (position, tangent t, section axes y and z).

const R_TRUSS = 0.006 * SIZE;
const R_BAR = 0.004 * SIZE;
const R_HINGE = 0.012 * SIZE;
const L_HINGE = 0.06 * SIZE;
const R_NODE = 0.009 * SIZE;
const SUPPORT = 0.035 * SIZE;
const SUPPORT_COLOR = 0x3b4048;
const INPUT_COLOR = 0x2e9d4a;

function roundProfile(d, sides) {
  const pts = [], edges = [], cap = [];
  for (let i = 0; i < sides; i++) {
    const a = (2 * Math.PI * i) / sides;
    const c = Math.cos(a), s = Math.sin(a);
    pts.push([0.5 * d * c, 0.5 * d * s, c, s]);
    edges.push([i, (i + 1) % sides]);
    cap.push([0.5 * d * c, 0.5 * d * s]);
  }
  return { pts, edges, cap };
}
function rectProfile(w, t) {
  const y = w / 2, z = t / 2;
  const c = [[y, z], [-y, z], [-y, -z], [y, -z]];
  const normals = [[0, 1], [-1, 0], [0, -1], [1, 0]];
  const pts = [], edges = [];
  for (let i = 0; i < 4; i++) {
    const a = c[i], b = c[(i + 1) % 4], n = normals[i];
    pts.push([a[0], a[1], n[0], n[1]], [b[0], b[1], n[0], n[1]]);
    edges.push([2 * i, 2 * i + 1]);
  }
  return { pts, edges, cap: c };
}

const beamSegments = NE > 3000 ? 2 : NE > 800 ? 4 : 10;

/** Drawable items: each a swept tube belonging to an element. */
function buildItems() {
  const items = [];
  DATA.elements.forEach((e, el) => {
    if (e.kind === 'beam') {
      const s = e.section;
      const profile = s && s.shape === 'rectangle'
        ? rectProfile(s.width, s.thickness)
        : roundProfile(s ? s.width : 2 * R_TRUSS, 12);
      items.push({ el, type: 'beam', a: e.nodes[0], b: e.nodes[1], profile, stations: beamSegments + 1 });
    } else if (e.kind === 'truss') {
      items.push({ el, type: 'line', a: e.nodes[0], b: e.nodes[1], profile: roundProfile(2 * R_TRUSS, 10), stations: 2 });
    } else if (e.kind === 'rigid') {
      for (let m = 1; m < e.nodes.length; m++) {
        items.push({ el, type: 'line', a: e.nodes[0], b: e.nodes[m], profile: roundProfile(2 * R_BAR, 8), stations: 2 });
      }
    } else if (e.kind === 'hinge') {
      items.push({ el, type: 'hinge', a: e.nodes[0], b: e.nodes[1], profile: roundProfile(2 * R_HINGE, 16), stations: 2 });
      items.push({ el, type: 'line', a: e.nodes[0], b: e.nodes[1], profile: roundProfile(2 * R_BAR, 8), stations: 2, optional: true });
    }
  });
  let v = 0;
  for (const it of items) {
    it.v0 = v;
    v += it.stations * it.profile.pts.length + 2 * it.profile.cap.length;
  }
  return { items, vertices: v };
}

/** Stations of an item in the node state S: arrays of {p, t, y, z}. */
function stations(it, S) {
  const out = [];
  const pa = S.pos(it.a), pb = S.pos(it.b);
  if (it.type === 'beam') {
    const F = DATA.elements[it.el].frame;
    const qa = S.rot(it.a), qb = S.rot(it.b);
    const ta = qrot(qa, F[0]), tb = qrot(qb, F[0]);
    const ya = qrot(qa, F[1]), yb = qrot(qb, F[1]);
    const chord = sub3(pb, pa);
    const L = norm3(chord);
    const n = it.stations - 1;
    for (let k = 0; k <= n; k++) {
      const s = k / n, s2 = s * s, s3 = s2 * s;
      const h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
      const d00 = 6 * s2 - 6 * s, d10 = 3 * s2 - 4 * s + 1, d01 = -6 * s2 + 6 * s, d11 = 3 * s2 - 2 * s;
      const p = [0, 1, 2].map((i) => h00 * pa[i] + h10 * L * ta[i] + h01 * pb[i] + h11 * L * tb[i]);
      const dp = [0, 1, 2].map((i) => d00 * pa[i] + d10 * L * ta[i] + d01 * pb[i] + d11 * L * tb[i]);
      const t = unit3(dp, unit3(chord, ta));
      let y = add3(scale3(1 - s, ya), scale3(s, yb));
      y = sub3(y, scale3(dot3(y, t), t));
      y = norm3(y) > 1e-9 ? unit3(y) : perpendicular(t);
      out.push({ p, t, y, z: cross3(t, y) });
    }
    return out;
  }
  let p0 = pa, p1 = pb;
  if (it.type === 'hinge') {
    const F = DATA.elements[it.el].frame;
    const axis = unit3(qrot(S.rot(it.a), F[0]));
    const c = scale3(0.5, add3(pa, pb));
    p0 = sub3(c, scale3(L_HINGE / 2, axis));
    p1 = add3(c, scale3(L_HINGE / 2, axis));
  }
  const t = unit3(sub3(p1, p0), [0, 0, 1]);
  const y = perpendicular(t);
  const z = cross3(t, y);
  out.push({ p: p0, t, y, z }, { p: p1, t, y, z });
  return out;
}

// ---------------------------------------------------------------------------------------------
// Convex hull of a rigid body's member positions (faces as index triples, outward), or a
// planar fan when the members lie in a plane; null when they lie on a line.

function hull(points) {
  const n = points.length;
  if (n < 3) return null;
  const eps = 1e-7 * SIZE;
  let i1 = 0, best = -1;
  for (let i = 1; i < n; i++) {
    const d = norm3(sub3(points[i], points[0]));
    if (d > best) { best = d; i1 = i; }
  }
  if (best < eps) return null;
  const axis = unit3(sub3(points[i1], points[0]));
  let i2 = -1; best = eps;
  for (let i = 0; i < n; i++) {
    const v = sub3(points[i], points[0]);
    const d = norm3(sub3(v, scale3(dot3(v, axis), axis)));
    if (d > best) { best = d; i2 = i; }
  }
  if (i2 < 0) return null;
  const normal = unit3(cross3(sub3(points[i1], points[0]), sub3(points[i2], points[0])));
  let i3 = -1; best = eps;
  for (let i = 0; i < n; i++) {
    const d = Math.abs(dot3(sub3(points[i], points[0]), normal));
    if (d > best) { best = d; i3 = i; }
  }
  if (i3 < 0) {
    // planar: 2D hull (monotone chain) in the plane, as a fan
    const u = axis, w = cross3(normal, u);
    const p2 = points.map((p, i) => [dot3(sub3(p, points[0]), u), dot3(sub3(p, points[0]), w), i]);
    p2.sort((a, b) => a[0] - b[0] || a[1] - b[1]);
    const turn = (o, a, b) => (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    const lower = [], upper = [];
    for (const p of p2) {
      while (lower.length >= 2 && turn(lower[lower.length - 2], lower[lower.length - 1], p) <= 0) lower.pop();
      lower.push(p);
    }
    for (let k = p2.length - 1; k >= 0; k--) {
      const p = p2[k];
      while (upper.length >= 2 && turn(upper[upper.length - 2], upper[upper.length - 1], p) <= 0) upper.pop();
      upper.push(p);
    }
    const ring = lower.slice(0, -1).concat(upper.slice(0, -1)).map((p) => p[2]);
    if (ring.length < 3) return null;
    const faces = [];
    for (let k = 1; k + 1 < ring.length; k++) faces.push([ring[0], ring[k], ring[k + 1]]);
    return faces;
  }
  // 3D: incremental hull
  const base = [0, i1, i2, i3];
  const centre = scale3(0.25, base.reduce((s, i) => add3(s, points[i]), [0, 0, 0]));
  let faces = [];
  const makeFace = (a, b, c) => {
    let f = [a, b, c];
    let nrm = cross3(sub3(points[b], points[a]), sub3(points[c], points[a]));
    if (dot3(nrm, sub3(points[a], centre)) < 0) { f = [a, c, b]; nrm = scale3(-1, nrm); }
    return { v: f, n: unit3(nrm), d: 0 };
  };
  const setD = (f) => { f.d = dot3(f.n, points[f.v[0]]); return f; };
  faces.push(setD(makeFace(0, i1, i2)), setD(makeFace(0, i1, i3)), setD(makeFace(0, i2, i3)), setD(makeFace(i1, i2, i3)));
  for (let p = 0; p < n; p++) {
    if (base.includes(p)) continue;
    const visible = faces.filter((f) => dot3(f.n, points[p]) - f.d > eps);
    if (visible.length === 0) continue;
    const edges = new Map();
    for (const f of visible) {
      for (let k = 0; k < 3; k++) {
        const a = f.v[k], b = f.v[(k + 1) % 3];
        const rev = b + ',' + a;
        if (edges.has(rev)) edges.delete(rev); else edges.set(a + ',' + b, [a, b]);
      }
    }
    faces = faces.filter((f) => !visible.includes(f));
    for (const [a, b] of edges.values()) {
      const nrm = unit3(cross3(sub3(points[b], points[a]), sub3(points[p], points[a])));
      faces.push({ v: [a, b, p], n: nrm, d: dot3(nrm, points[a]) });
    }
  }
  return faces.map((f) => f.v);
}

// ---------------------------------------------------------------------------------------------
// The page.

async function loadThree() {
  const src = document.getElementById('three-module').textContent;
  const threeUrl = URL.createObjectURL(new Blob([src], { type: 'text/javascript' }));
  const THREE = await import(threeUrl);
  const orbitSrc = document.getElementById('three-orbit').textContent;
  const parts = orbitSrc.split("from 'three'");
  if (parts.length !== 2) throw new Error('OrbitControls: cannot find its import of three');
  const orbitUrl = URL.createObjectURL(new Blob([parts.join("from '" + threeUrl + "'")], { type: 'text/javascript' }));
  const { OrbitControls } = await import(orbitUrl);
  return { THREE, OrbitControls };
}

function fieldSet(f) {
  if (f.per === 'frame') return f.values[state.frame];
  if (f.per === 'animation') return state.item >= 0 ? f.values[state.item] : null;
  return f.values[0];
}
function currentField() {
  return DATA.fields.find((f) => f.key === state.color) || null;
}
/** Colour of element el under the current colouring. */
function elementColor(el) {
  if (el === state.selected) return SELECTED_COLOR;
  const f = currentField();
  if (!f) return TYPE_COLORS[DATA.elements[el].kind];
  const set = fieldSet(f);
  const v = set ? set[el] : null;
  if (v === null || v === undefined) return UNDEFINED_COLOR;
  const [lo, hi] = f.range;
  return cmap(f.diverging ? DIVERGING : SEQUENTIAL, (v - lo) / (hi - lo));
}
function elementValue(el) {
  const f = currentField();
  if (!f) return null;
  const set = fieldSet(f);
  return set ? set[el] : null;
}

async function main() {
  const { THREE, OrbitControls } = await loadThree();
  const host = document.getElementById('canvas-host');
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  host.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f6f9);
  const camera = new THREE.PerspectiveCamera(35, 1, SIZE * 1e-3, SIZE * 100);
  camera.up.set(0, 0, 1);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x8090a0, 1.6));
  const sun = new THREE.DirectionalLight(0xffffff, 1.6);
  scene.add(sun);
  scene.add(camera);
  const headlight = new THREE.DirectionalLight(0xffffff, 0.8);
  headlight.position.set(0, 0, 1);
  camera.add(headlight);

  // --- swept tubes of all elements: one merged mesh with vertex colours
  const { items, vertices } = buildItems();
  const positions = new Float32Array(3 * vertices);
  const normals = new Float32Array(3 * vertices);
  const colors = new Float32Array(3 * vertices);
  const index = [];
  const triElement = [];
  for (const it of items) {
    const P = it.profile.pts.length, C = it.profile.cap.length;
    for (let k = 0; k + 1 < it.stations; k++) {
      for (const [a, b] of it.profile.edges) {
        const v00 = it.v0 + k * P + a, v01 = it.v0 + k * P + b;
        const v10 = it.v0 + (k + 1) * P + a, v11 = it.v0 + (k + 1) * P + b;
        index.push(v00, v01, v11, v00, v11, v10);
        triElement.push(it.el, it.el);
      }
    }
    const c0 = it.v0 + it.stations * P, c1 = c0 + C;
    for (let k = 1; k + 1 < C; k++) {
      index.push(c0, c0 + k + 1, c0 + k, c1, c1 + k, c1 + k + 1);
      triElement.push(it.el, it.el);
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute('normal', new THREE.BufferAttribute(normals, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
  geometry.setIndex(vertices > 65535 ? new THREE.Uint32BufferAttribute(index, 1) : new THREE.Uint16BufferAttribute(index, 1));
  const tubes = new THREE.Mesh(geometry, new THREE.MeshPhongMaterial({ vertexColors: true, shininess: 40, specular: 0x222222 }));
  scene.add(tubes);

  // --- rigid bodies: translucent hulls over the members
  const bodies = [];
  const frame0 = nodeStates(0, -1, 0, 0);
  DATA.elements.forEach((e, el) => {
    if (e.kind !== 'rigid') return;
    const members = [];
    for (const i of e.nodes) {
      const p = frame0.pos(i);
      if (!members.some((j) => norm3(sub3(frame0.pos(j), p)) < 1e-9 * SIZE)) members.push(i);
    }
    const faces = hull(members.map((i) => frame0.pos(i)));
    if (!faces) return;
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(9 * faces.length), 3));
    const mat = new THREE.MeshPhongMaterial({ color: 0x8892a0, transparent: true, opacity: 0.35, side: THREE.DoubleSide, depthWrite: false });
    const mesh = new THREE.Mesh(g, mat);
    mesh.userData.element = el;
    scene.add(mesh);
    bodies.push({ el, members, faces, mesh });
  });

  // --- nodes and supports; node spheres shrink below a third of the typical element length,
  // so that finely segmented beams do not disappear under their nodes
  const plainNodes = DATA.nodes.map((n, i) => i).filter((i) => DATA.nodes[i].host === null);
  const lengths = items.filter((it) => it.type !== 'hinge').map((it) => norm3(sub3(frame0.pos(it.a), frame0.pos(it.b)))).filter((l) => l > 0).sort((a, b) => a - b);
  const rNode = lengths.length > 0 ? Math.min(R_NODE, lengths[Math.floor(lengths.length / 2)] / 3) : R_NODE;
  const nodeMesh = new THREE.InstancedMesh(new THREE.SphereGeometry(rNode, 12, 8), new THREE.MeshPhongMaterial({ color: 0x2a3140 }), Math.max(1, plainNodes.length));
  nodeMesh.count = plainNodes.length;
  scene.add(nodeMesh);
  const markers = [];
  DATA.nodes.forEach((n, i) => {
    if (n.host !== null) return;
    const fixedPos = ['x', 'y', 'z'].filter((d) => n.fixed.includes(d)).length;
    const fixedRot = ['rx', 'ry', 'rz'].filter((d) => n.fixed.includes(d)).length;
    let mesh = null;
    if (fixedPos === 3 && (fixedRot === 3 || !n.rot)) {
      mesh = new THREE.Mesh(new THREE.BoxGeometry(SUPPORT, SUPPORT, SUPPORT), new THREE.MeshPhongMaterial({ color: SUPPORT_COLOR }));
    } else if (n.fixed.length > 0) {
      mesh = new THREE.Mesh(new THREE.ConeGeometry(0.6 * SUPPORT, 1.2 * SUPPORT, 16), new THREE.MeshPhongMaterial({ color: SUPPORT_COLOR }));
      mesh.rotation.x = Math.PI / 2;
      mesh.userData.offset = [0, 0, -0.6 * SUPPORT];
    }
    if (mesh) { scene.add(mesh); markers.push({ i, mesh }); }
    if (n.input.length > 0) {
      const m = new THREE.Mesh(new THREE.OctahedronGeometry(0.8 * SUPPORT), new THREE.MeshPhongMaterial({ color: INPUT_COLOR }));
      scene.add(m);
      markers.push({ i, mesh: m });
    }
  });

  // --- reference configuration (thin lines), shown while animating
  const ghostPts = [];
  for (const it of items) {
    if (it.type === 'hinge') continue;
    const st = stations(it, frame0);
    for (let k = 0; k + 1 < st.length; k++) ghostPts.push(...st[k].p, ...st[k + 1].p);
  }
  const ghostGeom = new THREE.BufferGeometry();
  ghostGeom.setAttribute('position', new THREE.BufferAttribute(new Float32Array(ghostPts), 3));
  const ghost = new THREE.LineSegments(ghostGeom, new THREE.LineBasicMaterial({ color: 0x6c7686, transparent: true, opacity: 0.55 }));
  scene.add(ghost);

  // --- bounding box, axes, camera
  const box = new THREE.Box3();
  for (const f of DATA.frames) {
    for (let i = 0; i < NN; i++) box.expandByPoint(new THREE.Vector3(f.x[3 * i], f.x[3 * i + 1], f.x[3 * i + 2]));
  }
  if (box.isEmpty()) box.expandByPoint(new THREE.Vector3(0, 0, 0));
  const centre = box.getCenter(new THREE.Vector3());
  const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 0.05 * SIZE);
  const axes = new THREE.AxesHelper(0.15 * SIZE);
  axes.position.copy(box.min).addScalar(-0.05 * SIZE);
  scene.add(axes);

  // --- the lines of the designer's language (check): the axis of every body's twist, drawn
  // with its motion, and the line of action of every wrench, drawn with its self-stress field
  // and the suggested wires that would remove the motion, each drawn as the wire itself
  const screwColors = { rotation: 0xe07b00, translation: 0x1f9e4a, force: 0xc62828, couple: 0x7b1fa2, wire: 0x1565c0 };
  const screwLines = (DATA.screw_lines || []).map((s) => {
    const wire = typeof s.length === 'number';
    const a = wire ? s.point : add3(s.point, scale3(-0.6 * SIZE, s.direction));
    const b = wire ? add3(s.point, scale3(s.length, s.direction)) : add3(s.point, scale3(0.6 * SIZE, s.direction));
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array([...a, ...b]), 3));
    const line = new THREE.Line(g, new THREE.LineBasicMaterial({ color: screwColors[s.kind] || 0x000000 }));
    line.visible = false;
    scene.add(line);
    return { s, line };
  });
  function updateScrewLines() {
    for (const { s, line } of screwLines) {
      line.visible = (s.item !== null && s.item !== undefined && s.item === state.item)
        || (s.field !== null && s.field !== undefined && s.field === state.color);
    }
    const shown = screwLines.filter((l) => l.line.visible);
    const el = document.getElementById('status');
    if (el) el.setAttribute('data-screw-lines', String(shown.length));
    // their labels, in their colours, below the heading
    let info = document.getElementById('screw-info');
    if (!info && screwLines.length > 0) {
      info = document.createElement('div');
      info.id = 'screw-info';
      info.style.cssText = 'position:absolute;left:10px;top:56px;font-size:12px;background:rgba(255,255,255,0.8);padding:2px 6px;pointer-events:none';
      renderer.domElement.parentElement.appendChild(info);
    }
    if (info) {
      info.innerHTML = shown
        .map((l) => '<div style="color:#' + (screwColors[l.s.kind] || 0).toString(16).padStart(6, '0') + '">' + esc(l.s.label) + '</div>')
        .join('');
    }
    requestRender();
  }
  sun.position.set(centre.x + radius, centre.y - 2 * radius, centre.z + 3 * radius);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.copy(centre);
  function setView(v) {
    const dirs = { iso: [1.0, -1.5, 0.9], x: [1, 0, 0], y: [0, -1, 0], z: [0, 0, 1] };
    const d = new THREE.Vector3(...(dirs[v] || dirs.iso)).normalize();
    const dist = (1.15 * radius) / Math.sin((camera.fov * Math.PI) / 360);
    camera.up.set(0, v === 'z' ? 1 : 0, v === 'z' ? 0 : 1);
    camera.position.copy(centre).addScaledVector(d, dist);
    controls.target.copy(centre);
    camera.lookAt(centre);
    controls.update();
    requestRender();
  }

  // --- updates
  let needGeometry = true, needColor = true, needRender = true;
  function requestRender() { needRender = true; }
  function updateGeometry() {
    const S = nodeStates(state.frame, state.item, state.phase, state.amp);
    for (const it of items) {
      const st = stations(it, S);
      const pr = it.profile, P = pr.pts.length, C = pr.cap.length;
      const hidden = it.optional && norm3(sub3(S.pos(it.a), S.pos(it.b))) < 1e-9 * SIZE;
      for (let k = 0; k < st.length; k++) {
        const { p, y, z } = st[k];
        for (let j = 0; j < P; j++) {
          const [py, pz, ny, nz] = pr.pts[j];
          const v = 3 * (it.v0 + k * P + j);
          for (let c = 0; c < 3; c++) {
            positions[v + c] = hidden ? p[c] : p[c] + py * y[c] + pz * z[c];
            normals[v + c] = ny * y[c] + nz * z[c];
          }
        }
      }
      for (let e = 0; e < 2; e++) {
        const { p, t, y, z } = st[e === 0 ? 0 : st.length - 1];
        const sign = e === 0 ? -1 : 1;
        for (let j = 0; j < C; j++) {
          const [py, pz] = pr.cap[j];
          const v = 3 * (it.v0 + st.length * P + e * C + j);
          for (let c = 0; c < 3; c++) {
            positions[v + c] = hidden ? p[c] : p[c] + py * y[c] + pz * z[c];
            normals[v + c] = sign * t[c];
          }
        }
      }
    }
    geometry.attributes.position.needsUpdate = true;
    geometry.attributes.normal.needsUpdate = true;
    geometry.computeBoundingSphere();
    for (const b of bodies) {
      const arr = b.mesh.geometry.attributes.position.array;
      b.faces.forEach((f, k) => {
        for (let j = 0; j < 3; j++) {
          const p = S.pos(b.members[f[j]]);
          arr.set(p, 9 * k + 3 * j);
        }
      });
      b.mesh.geometry.attributes.position.needsUpdate = true;
      b.mesh.geometry.computeVertexNormals();
      b.mesh.geometry.computeBoundingSphere();
    }
    const m = new THREE.Matrix4();
    plainNodes.forEach((i, k) => {
      m.makeTranslation(...S.pos(i));
      nodeMesh.setMatrixAt(k, m);
    });
    nodeMesh.instanceMatrix.needsUpdate = true;
    nodeMesh.computeBoundingSphere();
    for (const mk of markers) {
      const p = S.pos(mk.i);
      const o = mk.mesh.userData.offset || [0, 0, 0];
      mk.mesh.position.set(p[0] + o[0], p[1] + o[1], p[2] + o[2]);
    }
    ghost.visible = state.ghost && (state.item >= 0 || state.frame > 0);
    if (DATA.simulation) simDrawn(S);
    needGeometry = false;
    needRender = true;
  }
  function updateColors() {
    for (const it of items) {
      const c = elementColor(it.el);
      const n = it.stations * it.profile.pts.length + 2 * it.profile.cap.length;
      for (let j = 0; j < n; j++) colors.set(c, 3 * (it.v0 + j));
    }
    geometry.attributes.color.needsUpdate = true;
    for (const b of bodies) b.mesh.material.color.setRGB(...elementColor(b.el));
    drawColorbar();
    needColor = false;
    needRender = true;
  }

  function resize() {
    const w = host.clientWidth || 1, h = host.clientHeight || 1;
    renderer.setSize(w, h, false);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    const r = host.getBoundingClientRect();
    document.getElementById('status').setAttribute('data-canvas', [r.left, r.top, r.width, r.height].map(Math.round).join(','));
    needRender = true;
  }
  window.addEventListener('resize', resize);
  controls.addEventListener('change', requestRender);

  // --- panel, colour bar, heading
  buildPanel({ setView, onChange, flush });
  function onChange(what) {
    if (what.geometry) needGeometry = true;
    if (what.color) needColor = true;
    updateScrewLines();
    updateHeading();
    syncPanel();
  }
  /** Rebuild what changed now, not at the next animation frame (the time slider). */
  function flush() {
    if (needGeometry) updateGeometry();
    if (needColor) updateColors();
  }

  // --- picking
  const raycaster = new THREE.Raycaster();
  const pointer = new THREE.Vector2();
  let down = null;
  renderer.domElement.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
  renderer.domElement.addEventListener('click', (e) => {
    // a click, not the end of an orbit drag
    if (down && Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
    down = null;
    const r = renderer.domElement.getBoundingClientRect();
    pointer.set(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
    camera.updateMatrixWorld();
    raycaster.setFromCamera(pointer, camera);
    const hits = raycaster.intersectObjects([tubes, ...bodies.map((b) => b.mesh)], false);
    let el = -1;
    if (hits.length > 0) {
      const h = hits[0];
      el = h.object === tubes ? triElement[h.faceIndex] : h.object.userData.element;
    }
    state.selected = el;
    showSelection(el);
    const tip = document.getElementById('tooltip');
    if (el >= 0) {
      const e2 = DATA.elements[el];
      const v = elementValue(el);
      tip.textContent = e2.name + ' (' + e2.kind + ')' + (v !== null && v !== undefined ? '\n' + fmt(v) + ' ' + (currentField() ? currentField().unit : '') : '');
      tip.style.left = (e.clientX - r.left + 12) + 'px';
      tip.style.top = (e.clientY - r.top + 12) + 'px';
      tip.hidden = false;
    } else {
      tip.hidden = true;
    }
    needColor = true;
  });

  window.addEventListener('keydown', (e) => {
    if (e.target && (e.target.tagName === 'INPUT' || e.target.tagName === 'SELECT')) return;
    if (e.key === ' ') { state.playing = !state.playing; onChange({}); e.preventDefault(); }
    if (e.key === 'ArrowRight' || e.key === 'ArrowLeft') {
      const d = e.key === 'ArrowRight' ? 1 : -1;
      state.frame = Math.min(DATA.frames.length - 1, Math.max(0, state.frame + d));
      onChange({ geometry: true, color: true });
    }
  });

  // --- first picture, synchronously; then the loop
  resize();
  setView(state.view);
  updateHeading();
  updateGeometry();
  updateColors();
  updateScrewLines();
  renderer.render(scene, camera);
  needRender = false;
  const status = document.getElementById('status');
  status.setAttribute('data-animations', String(DATA.animations.length));
  status.setAttribute('data-fields', DATA.fields.map((f) => f.key).join(' '));
  status.setAttribute('data-elements', String(NE));
  status.setAttribute('data-frames', String(DATA.frames.length));
  status.setAttribute('data-triangles', String(index.length / 3));
  status.setAttribute('data-item', String(state.item));
  status.setAttribute('data-color', state.color);
  if (DATA.summary) status.setAttribute('data-table1-row', String(DATA.summary.table1_row));
  if (status.getAttribute('data-state') !== 'error') {
    status.setAttribute('data-state', 'ready');
    status.textContent = 'ready';
  }

  let last = performance.now();
  let stepClock = 0;
  function tick(now) {
    requestAnimationFrame(tick);
    const dt = Math.min(0.1, Math.max(0, (now - last) / 1000));
    last = now;
    if (state.playing) {
      if (state.item >= 0) {
        state.phase = (state.phase + dt * state.speed) % 1;
        needGeometry = true;
        syncPhase();
      } else if (DATA.simulation) {
        const k = simAdvance(dt);
        if (k !== state.frame) {
          state.frame = k;
          needGeometry = true;
          if (currentField() && currentField().per === 'frame') needColor = true;
          updateHeading();
          syncPanel();
        }
      } else if (DATA.frames.length > 1) {
        stepClock += dt;
        if (stepClock > 0.25) {
          stepClock = 0;
          state.frame = (state.frame + 1) % DATA.frames.length;
          needGeometry = true;
          if (currentField() && currentField().per === 'frame') needColor = true;
          updateHeading();
          syncPanel();
        }
      }
    }
    if (needGeometry) updateGeometry();
    if (needColor) updateColors();
    if (needRender) {
      renderer.render(scene, camera);
      needRender = false;
    }
  }
  requestAnimationFrame(tick);
}

// ---------------------------------------------------------------------------------------------
// Panel.

function updateHeading() {
  const parts = [];
  if (DATA.simulation) {
    parts.push(simHeading());
  } else if (DATA.frames.length > 1) {
    const f = DATA.frames[state.frame];
    parts.push(f.label + ' of ' + (DATA.frames.length - 1) + (f.load_factor !== null ? ', load factor ' + fmt(f.load_factor) : ''));
  }
  if (state.item >= 0) {
    const a = DATA.animations[state.item];
    // the class's name here (the selector shows its fractions too)
    parts.push(a.label + ' (' + a.detail + (a.class ? ', ' + a.class.replace(/ β.*$/, '') : '') + ')');
  }
  const f = DATA.fields.find((x) => x.key === state.color);
  parts.push('colour: ' + (f ? f.label : 'element type'));
  document.getElementById('heading').textContent = parts.join(' · ');
}

function drawColorbar() {
  const f = DATA.fields.find((x) => x.key === state.color);
  const bar = document.getElementById('colorbar');
  if (!f) { bar.hidden = true; return; }
  bar.hidden = false;
  document.getElementById('colorbar-label').textContent = f.label + (f.unit ? ' [' + f.unit + ']' : '') + (f.diverging ? '  (− blue, + red)' : '');
  const cv = document.getElementById('colorbar-canvas');
  const ctx = cv.getContext('2d');
  for (let x = 0; x < cv.width; x++) {
    ctx.fillStyle = rgbCss(cmap(f.diverging ? DIVERGING : SEQUENTIAL, x / (cv.width - 1)));
    ctx.fillRect(x, 0, 1, cv.height);
  }
  const [lo, hi] = f.range;
  document.getElementById('colorbar-ticks').innerHTML = [lo, (lo + hi) / 2, hi].map((v) => '<span>' + esc(fmt(v)) + '</span>').join('');
}

function modeNames(kind) {
  const m = DATA.mode_names.find((x) => x[0] === kind);
  return m ? m[1] : [];
}

function showSelection(el) {
  const box = document.getElementById('selection');
  if (!box) return;
  if (el < 0) { box.innerHTML = '<span class="note">click an element</span>'; return; }
  const e = DATA.elements[el];
  const names = modeNames(e.kind);
  const letters = { r: 'rigid', f: 'free', i: 'input' };
  const modes = e.partition.split('').map((c, k) => (names[k] ? names[k] : 'e' + (k + 1)) + ': ' + letters[c]);
  let h = '<b>' + esc(e.name) + '</b> (' + esc(e.kind) + ')<br>nodes: ' + esc(e.nodes.map((i) => DATA.nodes[i].name).join(', '));
  if (e.section) {
    const s = e.section;
    h += '<br>section: ' + esc(s.shape) + (s.actual ? ' ' + fmt(s.actual[0]) + ' × ' + fmt(s.actual[1]) + ' m' : ' (' + esc(s.source) + '; drawn ' + fmt(s.width) + ' × ' + fmt(s.thickness) + ' m)');
  }
  if (e.kind !== 'rigid' || e.partition.length <= 12) h += '<br><span class="mono">' + esc(modes.join('; ')) + '</span>';
  const v = elementValue(el);
  const f = DATA.fields.find((x) => x.key === state.color);
  if (f && v !== null && v !== undefined) h += '<br>' + esc(f.label) + ': <b>' + esc(fmt(v)) + '</b> ' + esc(f.unit);
  box.innerHTML = h;
}

function row(k, v) { return '<tr><td class="k">' + esc(k) + '</td><td>' + v + '</td></tr>'; }

function controlsHtml() {
  let h = '';
  if (DATA.animations.length > 0) {
    const kind = DATA.animations[0].kind === 'mode' ? 'Modes' : 'Motions';
    h += '<h2>' + kind + '</h2>';
    h += '<select id="sel-item"><option value="-1">none</option>' + DATA.animations.map((a, k) => '<option value="' + k + '">' + esc(a.label + ' — ' + a.detail + (a.class ? ', ' + a.class : '')) + '</option>').join('') + '</select>';
    h += '<div class="row"><button id="btn-play"></button><label for="rng-phase">phase</label><input type="range" id="rng-phase" min="0" max="1" step="0.01"></div>';
    h += '<div class="row"><label for="rng-amp">amplitude</label><input type="range" id="rng-amp" min="0" max="3" step="0.05"><span id="amp-val" class="mono"></span></div>';
    h += '<div class="row"><input type="checkbox" id="chk-ghost"><label for="chk-ghost">show the ' + (DATA.analysis === 'check' ? 'reference' : 'static') + ' configuration</label></div>';
    h += '<div class="note">amplitude 1: largest translation 10 % of the model size, or largest rotation 0.35 rad if that comes first</div>';
  }
  if (DATA.simulation) {
    h += simControlsHtml();
  } else if (DATA.frames.length > 1) {
    h += '<h2>Load steps</h2>';
    h += '<div class="row"><button id="btn-prev">◀</button><input type="range" id="rng-step" min="0" max="' + (DATA.frames.length - 1) + '" step="1"><button id="btn-next">▶</button></div>';
    h += '<div id="step-label" class="mono"></div>';
    if (DATA.animations.length === 0) h += '<div class="row"><button id="btn-play"></button><span class="note">play the steps</span></div>';
  }
  h += '<h2>Colour</h2><select id="sel-color"><option value="type">element type</option>' + DATA.fields.map((f) => '<option value="' + esc(f.key) + '">' + esc(f.label + (f.unit ? ' [' + f.unit + ']' : '')) + '</option>').join('') + '</select>';
  h += '<div class="note" id="color-note"></div>';
  return h;
}

function buildPanel(hooks) {
  const P = document.getElementById('panel-content');
  let h = '<h1>' + esc(DATA.title || DATA.file) + '</h1>';
  h += '<div class="sub">' + esc(DATA.file) + ' · ' + esc(DATA.analysis) + ' · ' + esc(DATA.generator) + '</div>';
  const S = DATA.summary;
  if (S) {
    h += '<h2>Classification</h2>';
    h += S.exactly_constrained ? '<span class="badge ok">exactly constrained</span>' : '<span class="badge warn">not exactly constrained</span>';
    h += '<div class="case">Table 1, row ' + S.table1_row + ': ' + esc(S.classification) + '</div>';
    h += '<table>';
    h += row('Dcc', S.rows + ' × ' + S.cols + ', rank ' + S.rank);
    h += row('motions (n − r)', '<b>' + S.n_motions + '</b>');
    h += row('self-stresses (m − r)', '<b>' + S.n_self_stresses + '</b>');
    h += row('rank threshold', esc(fmt(S.rank_threshold)) + ' (' + esc(fmt(S.rank_tol)) + ' · s1)');
    if (S.rank_gap !== null) h += row('gap s_r / s_r+1', esc(fmt(S.rank_gap)));
    h += row('generalised coordinates', S.generalised.length ? esc(S.generalised.join(', ')) : 'none');
    h += '</table>';
  }
  h += controlsHtml();
  if (S) {
    h += '<h2>Details of the classification</h2>';
    const sv = S.singular_values.map((v, i) => '<span' + (v <= S.rank_threshold ? ' class="zero"' : '') + '>s' + (i + 1) + ' = ' + esc(fmt(v)) + '</span>');
    h += '<details' + (sv.length <= 8 ? ' open' : '') + '><summary>singular values (' + sv.length + ')</summary><div class="sv">' + sv.join('<br>') + '</div></details>';
    S.self_stresses.forEach((lines, k) => {
      h += '<details><summary>self-stress state ' + (k + 1) + '</summary><div class="mono">' + lines.map(esc).join('<br>') + '</div></details>';
    });
    if (S.advice.length > 0) {
      h += '<h2>Repair advice (verified)</h2>';
      const open = S.advice.length <= 3 ? ' open' : '';
      for (const a of S.advice) {
        h += '<details' + open + '><summary>' + (a.kind === 'motion' ? 'motion ' : 'self-stress state ') + (a.state + 1) + ': any one of</summary><ul>';
        h += a.suggestions.length ? a.suggestions.map((s) => '<li>' + esc(s) + '</li>').join('') : '<li class="note">no single change removes it</li>';
        h += '</ul></details>';
      }
    }
  }
  h += '<h2>View</h2><div class="row"><button data-view="iso">iso</button><button data-view="x">along x</button><button data-view="y">along y</button><button data-view="z">from top</button></div>';
  h += '<h2>Selection</h2><div id="selection"></div>';
  if (DATA.info.length > 0 || DATA.notes.length > 0) {
    h += '<h2>Analysis</h2><table>' + DATA.info.map(([k, v]) => row(k, esc(v))).join('') + '</table>';
    h += DATA.notes.map((n) => '<p class="note">' + esc(n) + '</p>').join('');
  }
  const lic = document.getElementById('three-license');
  h += '<h2>About</h2><div class="note">Drawn with three.js (MIT licence), inlined in this file; no network is used.</div>';
  if (lic) h += '<details><summary>three.js licence</summary><pre class="mono" style="white-space:pre-wrap">' + esc(lic.textContent.trim()) + '</pre></details>';
  P.innerHTML = h;

  const bind = (id, ev, fn) => { const e = document.getElementById(id); if (e) e.addEventListener(ev, fn); };
  bind('sel-item', 'change', (e) => {
    state.item = Number(e.target.value);
    hooks.onChange({ geometry: true, color: true });
  });
  bind('btn-play', 'click', () => { state.playing = !state.playing; hooks.onChange({}); });
  bind('rng-phase', 'input', (e) => { state.phase = Number(e.target.value); state.playing = false; hooks.onChange({ geometry: true }); });
  bind('rng-amp', 'input', (e) => { state.amp = Number(e.target.value); hooks.onChange({ geometry: true }); });
  bind('chk-ghost', 'change', (e) => { state.ghost = e.target.checked; hooks.onChange({ geometry: true }); });
  bind('rng-step', 'input', (e) => { state.frame = Number(e.target.value); hooks.onChange({ geometry: true, color: true }); });
  bind('btn-prev', 'click', () => { state.frame = Math.max(0, state.frame - 1); hooks.onChange({ geometry: true, color: true }); });
  bind('btn-next', 'click', () => { state.frame = Math.min(DATA.frames.length - 1, state.frame + 1); hooks.onChange({ geometry: true, color: true }); });
  bind('sel-color', 'change', (e) => { state.color = e.target.value; hooks.onChange({ color: true }); });
  for (const b of P.querySelectorAll('button[data-view]')) b.addEventListener('click', () => hooks.setView(b.getAttribute('data-view')));
  if (DATA.simulation) simBind(hooks);
  const tb = document.getElementById('toolbar');
  tb.innerHTML = '<button data-view="iso">iso</button><button data-view="x">x</button><button data-view="y">y</button><button data-view="z">z</button>';
  for (const b of tb.querySelectorAll('button')) b.addEventListener('click', () => hooks.setView(b.getAttribute('data-view')));
  buildLegend();
  syncPanel();
  showSelection(-1);
}

function syncPhase() {
  const r = document.getElementById('rng-phase');
  if (r) r.value = String(state.phase);
}

function syncPanel() {
  const set = (id, prop, v) => { const e = document.getElementById(id); if (e) e[prop] = v; };
  set('sel-item', 'value', String(state.item));
  set('btn-play', 'textContent', state.playing ? 'pause' : 'play');
  syncPhase();
  set('rng-amp', 'value', String(state.amp));
  set('amp-val', 'textContent', state.amp.toFixed(2));
  set('chk-ghost', 'checked', state.ghost);
  set('rng-step', 'value', String(state.frame));
  set('sel-color', 'value', state.color);
  const f = DATA.frames[state.frame];
  set('step-label', 'textContent', f.label + (f.load_factor !== null ? ', load factor ' + fmt(f.load_factor) : ''));
  const field = DATA.fields.find((x) => x.key === state.color);
  let note = '';
  if (field && field.per === 'animation' && state.item < 0) note = 'select a mode to see this colouring';
  else if (field && field.key.startsWith('self_stress')) note = 'largest entry of each element in the state (unit length, sign of the stress resultant); grey: the element carries none of it';
  else if (field && field.per === 'frame') note = 'colour range over all load steps';
  set('color-note', 'textContent', note);
  if (DATA.simulation) simSync();
  if (state.selected >= 0) showSelection(state.selected);
}

function buildLegend() {
  const kinds = new Set(DATA.elements.map((e) => e.kind));
  const sheets = DATA.elements.some((e) => e.section && e.section.shape === 'rectangle');
  const parts = [];
  const sw = (c) => '<span class="sw" style="background:' + rgbCss(c) + '"></span>';
  if (kinds.has('beam')) parts.push(sw(TYPE_COLORS.beam) + 'beam' + (sheets ? ' (sheets drawn with their section)' : ''));
  if (kinds.has('truss')) parts.push(sw(TYPE_COLORS.truss) + 'truss');
  if (kinds.has('hinge')) parts.push(sw(TYPE_COLORS.hinge) + 'hinge (along its axis)');
  if (kinds.has('rigid')) parts.push(sw(TYPE_COLORS.rigid) + 'rigid body (bars and hull)');
  parts.push(sw([0.23, 0.25, 0.28]) + 'support: cube fixed, cone partly fixed');
  if (DATA.nodes.some((n) => n.input.length > 0)) parts.push(sw([0.18, 0.62, 0.29]) + 'input (generalised coordinate)');
  parts.push('axes: <span style="color:#c00">x</span> <span style="color:#080">y</span> <span style="color:#00c">z</span>');
  document.getElementById('legend').innerHTML = parts.join('<br>');
}

main().catch((e) => {
  if (window.__flexmbdRecord) window.__flexmbdRecord('viewer: ' + (e && e.stack ? e.stack : e));
  else throw e;
});
