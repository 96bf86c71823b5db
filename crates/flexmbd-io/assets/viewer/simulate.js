// flexmbd view --analysis simulate: the time history of a simulation in the viewer.
//
// This file is appended to viewer.js in the same module script, so it shares DATA, state and
// the helpers there; viewer.js calls the functions below only when DATA.simulation is present
// (see crates/flexmbd-io/src/html_view/simulate.rs for the data).
//
// The frames are the output times of the run. Playback runs a clock in simulated time at
// `speed` simulated seconds per second of wall time and shows the last frame at or before it
// (looping at the end); the time slider picks a frame and pauses. The default speed plays the
// frames in about 5 s. The energy plot shows the kinetic energy T, the strain energy U, the
// net work put in W = W_ext + W_prescribed − W_dissipated and the energy balance error over
// time, with a cursor at the shown time; a click on the plot jumps to that time.
//
// Status attributes for tests: data-time (t of the shown frame), data-tip (drawn position of
// the node DATA.simulation.tip).

// key in DATA.simulation, label, colour, dash pattern (W is dashed: it equals T + U when the
// balance holds, and would hide them)
const SIM_SERIES = [
  ['kinetic', 'kinetic T', '#d6452f', []],
  ['strain', 'strain U', '#2f6fd6', []],
  ['work', 'work in W', '#3a9a4a', [5, 4]],
  ['balance_error', 'balance error', '#8a4fb8', []],
];
const SIM_PLAY_SECONDS = 5;

function simTimes() { return DATA.simulation.times; }

/** Index of the last frame at or before time t. */
function simFrameAt(t) {
  const T = simTimes();
  const eps = 1e-9 * Math.max(Math.abs(T[T.length - 1]), Math.abs(T[0]), 1e-300);
  if (t >= T[T.length - 1] - eps) return T.length - 1;
  let lo = 0, hi = T.length - 1;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (T[mid] <= t + eps) lo = mid; else hi = mid - 1;
  }
  return lo;
}

/** log10 of the default speed: the frames (of a stopped run too) in SIM_PLAY_SECONDS. */
function simDefaultSpeed() {
  const T = simTimes();
  let span = T[T.length - 1] - T[0];
  if (!(span > 0)) span = DATA.simulation.t_end;
  return span > 0 ? Math.log10(span / SIM_PLAY_SECONDS) : 0;
}

function simInit() {
  if (state.simT !== undefined) return;
  state.simT = simTimes()[state.frame] || 0;
  state.simSpeed = Math.round(10 * simDefaultSpeed()) / 10;
}

function simHeading() {
  const S = DATA.simulation;
  const t = simTimes()[state.frame];
  return 't = ' + fmt(t) + ' s of ' + fmt(S.t_end) + ' s' + (S.stopped ? ' (the run stopped at ' + fmt(simTimes()[simTimes().length - 1]) + ' s)' : '');
}

function simControlsHtml() {
  simInit();
  const S = DATA.simulation;
  const n = S.times.length;
  const d = Math.round(10 * simDefaultSpeed()) / 10;
  let h = '<h2>Time</h2>';
  h += '<div class="row"><button id="btn-play"></button><input type="range" id="rng-time" min="0" max="' + (n - 1) + '" step="1"></div>';
  h += '<div id="time-val" class="mono"></div>';
  h += '<div class="row"><label for="rng-speed">speed</label><input type="range" id="rng-speed" min="' + (d - 2) + '" max="' + (d + 2) + '" step="0.1"><span id="speed-val" class="mono"></span></div>';
  h += '<div class="row"><input type="checkbox" id="chk-ghost"><label for="chk-ghost">show the configuration at t = ' + esc(fmt(S.times[0])) + ' s</label></div>';
  h += '<div class="note">' + n + ' output times' + (S.stride > 1 ? ' (every ' + S.stride + 'th of the run)' : '') + '; speed in simulated seconds per second</div>';
  if (S.stopped) h += '<p class="warn">' + esc(S.stopped) + '</p>';
  h += '<h2>Energy</h2><canvas id="sim-energy" width="330" height="180" style="width:100%;cursor:crosshair"></canvas>';
  h += '<div id="sim-energy-legend" class="mono"></div>';
  return h;
}

function simBind(hooks) {
  const jump = (k) => {
    state.frame = Math.min(simTimes().length - 1, Math.max(0, k));
    state.simT = simTimes()[state.frame];
    state.playing = false;
    hooks.onChange({ geometry: true, color: true });
    hooks.flush();
  };
  const r = document.getElementById('rng-time');
  if (r) r.addEventListener('input', (e) => jump(Number(e.target.value)));
  const sp = document.getElementById('rng-speed');
  if (sp) sp.addEventListener('input', (e) => { state.simSpeed = Number(e.target.value); hooks.onChange({}); });
  const cv = document.getElementById('sim-energy');
  if (cv) {
    cv.addEventListener('click', (e) => {
      const b = cv.getBoundingClientRect();
      const box = simPlotBox(cv);
      const x = ((e.clientX - b.left) / Math.max(b.width, 1)) * cv.width;
      const t = box.t0 + ((x - box.left) / (box.right - box.left)) * (box.t1 - box.t0);
      jump(simFrameAt(t));
    });
  }
}

/** Advance the playback clock by dt seconds of wall time; the frame to show. */
function simAdvance(dt) {
  simInit();
  const T = simTimes();
  state.simT += dt * Math.pow(10, state.simSpeed);
  if (state.simT > T[T.length - 1]) state.simT = T[0];
  return simFrameAt(state.simT);
}

function simSync() {
  simInit();
  const T = simTimes();
  // the frame may have been set elsewhere (keys, step buttons, the URL): the clock follows
  if (simFrameAt(state.simT) !== state.frame) state.simT = T[state.frame];
  const set = (id, prop, v) => { const e = document.getElementById(id); if (e) e[prop] = v; };
  set('rng-time', 'value', String(state.frame));
  set('time-val', 'textContent', 't = ' + fmt(T[state.frame]) + ' s (output ' + state.frame + ' of ' + (T.length - 1) + ')');
  set('rng-speed', 'value', String(state.simSpeed));
  set('speed-val', 'textContent', '×' + String(Number(Math.pow(10, state.simSpeed).toPrecision(2))));
  const field = DATA.fields.find((x) => x.key === state.color);
  if (field && field.per === 'frame') set('color-note', 'textContent', 'colour range over all output times');
  simDrawEnergy();
  const status = document.getElementById('status');
  if (status) {
    status.setAttribute('data-time', String(T[state.frame]));
    status.setAttribute('data-frame', String(state.frame));
  }
}

/** Record the drawn position of the tracked node (called with every new geometry). */
function simDrawn(S) {
  const status = document.getElementById('status');
  if (status) status.setAttribute('data-tip', S.pos(DATA.simulation.tip).map((v) => String(v)).join(','));
}

function simPlotBox(cv) {
  const S = DATA.simulation;
  const T = S.times;
  const t0 = T[0];
  let t1 = Math.max(T[T.length - 1], S.t_end);
  if (!(t1 > t0)) t1 = t0 + 1;
  return { left: 58, right: cv.width - 8, top: 8, bottom: cv.height - 22, t0, t1 };
}

function simDrawEnergy() {
  const cv = document.getElementById('sim-energy');
  if (!cv) return;
  const S = DATA.simulation;
  const T = S.times;
  const ctx = cv.getContext('2d');
  const box = simPlotBox(cv);
  let lo = 0, hi = 0;
  for (const [key] of SIM_SERIES) {
    for (const v of S[key]) {
      if (isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    }
  }
  if (!(hi > lo)) hi = lo + 1;
  const pad = 0.05 * (hi - lo);
  lo -= pad; hi += pad;
  const X = (t) => box.left + ((t - box.t0) / (box.t1 - box.t0)) * (box.right - box.left);
  const Y = (v) => box.bottom - ((v - lo) / (hi - lo)) * (box.bottom - box.top);
  ctx.clearRect(0, 0, cv.width, cv.height);
  ctx.fillStyle = '#ffffff';
  ctx.fillRect(0, 0, cv.width, cv.height);
  ctx.strokeStyle = '#9aa4b2';
  ctx.lineWidth = 1;
  ctx.strokeRect(box.left, box.top, box.right - box.left, box.bottom - box.top);
  ctx.strokeStyle = '#d5dae2';
  ctx.beginPath();
  ctx.moveTo(box.left, Y(0));
  ctx.lineTo(box.right, Y(0));
  ctx.stroke();
  ctx.fillStyle = '#42506a';
  ctx.font = '10px sans-serif';
  ctx.textAlign = 'right';
  ctx.textBaseline = 'middle';
  const ticks = [lo + pad, hi - pad];
  if (Math.abs(Y(0) - Y(lo + pad)) > 12 && Math.abs(Y(0) - Y(hi - pad)) > 12) ticks.push(0);
  for (const v of ticks) ctx.fillText(fmt(v), box.left - 3, Y(v));
  ctx.textAlign = 'center';
  ctx.textBaseline = 'top';
  ctx.fillText(fmt(box.t0), box.left, box.bottom + 3);
  ctx.fillText('t [s]', (box.left + box.right) / 2, box.bottom + 3);
  ctx.fillText(fmt(box.t1), box.right - 6, box.bottom + 3);
  ctx.save();
  ctx.translate(10, (box.top + box.bottom) / 2);
  ctx.rotate(-Math.PI / 2);
  ctx.fillText('energy [J]', 0, -6);
  ctx.restore();
  ctx.lineWidth = 1.5;
  for (const [key, , color, dash] of SIM_SERIES) {
    ctx.strokeStyle = color;
    ctx.setLineDash(dash);
    ctx.beginPath();
    let started = false;
    S[key].forEach((v, k) => {
      if (!isFinite(v)) { started = false; return; }
      if (started) ctx.lineTo(X(T[k]), Y(v)); else ctx.moveTo(X(T[k]), Y(v));
      started = true;
    });
    ctx.stroke();
  }
  ctx.setLineDash([]);
  const tc = T[state.frame];
  ctx.strokeStyle = '#1d2430';
  ctx.lineWidth = 1;
  ctx.beginPath();
  ctx.moveTo(X(tc), box.top);
  ctx.lineTo(X(tc), box.bottom);
  ctx.stroke();
  const legend = document.getElementById('sim-energy-legend');
  if (legend) {
    const maxErr = S.balance_error.reduce((m, v) => (isFinite(v) ? Math.max(m, Math.abs(v)) : m), 0);
    legend.innerHTML = SIM_SERIES.map(([key, label, color]) => '<span style="display:inline-block;width:10px;height:10px;margin-right:4px;background:' + color + '"></span>' + esc(label) + ': ' + esc(fmt(S[key][state.frame])) + ' J').join('<br>') + '<br>largest |balance error|: ' + esc(fmt(maxErr)) + ' J';
  }
}
