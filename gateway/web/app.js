// The browser pendant of the MCM: state, commands, jogging, errors, flight records and the 3D
// view of the arm, over the gateway's WebSocket `/ws` (docs: the JSON protocol,
// docs/protocol.md). Everything is local: no external resource of any kind.

import { Connection } from './socket.js';
import { Jogger } from './jog.js';
import { fkOrigins, View3d, webglAvailable } from './view3d.js';
import { loadRecords as loadRecordList } from './records.js';
import { addError, clearCurrent } from './errors.js';
import { renderCartesian, setupCartesian } from './cartesian.js';
import {
  fillModel, jointColours, percentile, renderClients, renderConnections, renderJoints, renderTiming,
  fmt, setText,
} from './panels.js';

const $ = (sel) => document.querySelector(sel);
const POLL_MS = 1000;

const page = {
  model: null,
  state: null, // last state frame
  frames: 0,
  latencies: [],
  detail: null, // detail of our last `status` with detail (access, control)
  lastError: null, // last safety error result
  slowRenderedAt: -Infinity, // when the timing figures were last drawn
  view: null,
  names: [],
  cycleTime: null, // the core's cycle period [s] (`info`), asked once per connection
};

// ---- the connection ---------------------------------------------------------------------

const conn = new Connection({
  onConnected(up) {
    const el = $('#conn');
    el.textContent = up ? 'connected' : 'disconnected';
    el.dataset.state = el.textContent;
    document.body.dataset.conn = el.textContent; // dims the last state shown while it is stale
    if (up) {
      poll();
      loadRecords();
    }
    else {
      jog.stop('lost');
      jog.sessionEnded();
      page.detail = null;
      page.cycleTime = null;
      showAccess();
    }
  },
  onFrame(frame) {
    page.state = frame;
    page.frames++;
    if (typeof frame.cycle_unix_ms === 'number') {
      page.latencies.push(Date.now() - frame.cycle_unix_ms);
      if (page.latencies.length > 1000) page.latencies.splice(0, page.latencies.length - 1000);
    }
    scheduleRender();
  },
  onSpontaneous(kind, msg) {
    if (kind === 'safety') {
      page.lastError = msg;
      jog.sessionEnded();
      addError(msg);
      // The flight recorder writes its file some milliseconds after the trip.
      for (const ms of [300, 1500, 4000]) setTimeout(loadRecords, ms);
    } else if (kind === 'status') {
      if (msg.operating_mode !== 'VELOCITY_CONTROL') jog.sessionEnded();
    } else {
      // A set_velocities refusal names its `command`; notices of the core or the gateway
      // stopping name none.
      addError(msg, msg.command);
      if (kind === 'set_velocities' || kind === 'set_cartesian_velocity') jog.stop('refused');
    }
  },
  onReply(cmd, msg) {
    if (cmd.command === 'status' && msg.detail) {
      page.detail = msg.detail;
      showAccess();
      renderConnections($('#connections'), msg.detail, page.state?.owner);
      const a = msg.detail.access || {};
      $('#auth').hidden = !(a.secret_required && !a.authenticated && a.motion_allowed_here !== false);
      return;
    }
    showResult(cmd, msg);
  },
});

let pollTimer = null;
function poll() {
  clearTimeout(pollTimer);
  pollTimer = setTimeout(poll, POLL_MS);
  if (!conn.connected || conn.has('status')) return;
  conn.request({ command: 'status', arguments: { detail: true } }).catch(() => {});
  loadClients();
}

async function loadClients() {
  try {
    const r = await fetch('/api/connections', { cache: 'no-store' });
    if (r.ok) renderClients($('#clients'), await r.json(), page.detail?.access?.peer);
  } catch (e) {
    // The socket's state says the gateway is gone; the list waits for it.
  }
}

$('#auth').addEventListener('submit', async (e) => {
  e.preventDefault();
  const secret = $('#secret').value;
  $('#secret').value = '';
  const r = await run({ command: 'authenticate', arguments: { secret } });
  if (r && r.error_status === 'OK') $('#last-result').textContent = 'authenticated: this page may take control';
  poll();
});

/** Send a command and show its outcome; resolves with the reply (or null when it failed). */
async function run(cmd) {
  $('#last-result').textContent = `${cmd.command} ...`;
  try {
    return await conn.request(cmd);
  } catch (e) {
    $('#last-result').textContent = `${cmd.command}: ${e.message}`;
    return null;
  }
}

function showResult(cmd, msg) {
  const el = $('#last-result');
  if (msg.error_status === 'ERROR') {
    el.textContent = '';
    addError(msg, cmd.command);
    return;
  }
  const what = msg.result_type === 'status' ? `mode ${msg.operating_mode}` : 'OK';
  el.textContent = `${cmd.command}: ${what}`;
  if (['take_control', 'release_control'].includes(cmd.command)) poll();
}

// ---- hold, control, commands -------------------------------------------------------------

function hold() {
  jog.stop('hold');
  conn.hold().then((r) => {
    if (r && r.error_status === 'ERROR') addError(r, 'hold');
    else $('#last-result').textContent = `hold: mode ${r?.operating_mode ?? '?'}`;
  }).catch((e) => addError({ error_message: `hold could not be sent: ${e.message}` }, 'hold'));
}

$('#hold').addEventListener('click', hold);
$('#take-control').addEventListener('click', () => run({ command: 'take_control' }));
$('#release-control').addEventListener('click', () => run({ command: 'release_control' }));
$('#release').addEventListener('click', () => run({ command: 'release' }));
$('#pvt').addEventListener('click', enterPvt);
$('#calibrate').addEventListener('click', () => {
  const w = $('#cal-which').value;
  run({
    command: 'calibrate',
    arguments: {
      which: /^[1-6]$/.test(w) ? Number(w) : w,
      elbow_direction: Number($('#cal-elbow-dir').value),
      wrist_direction: Number($('#cal-wrist-dir').value),
      force_mechanical_stop: $('#cal-force-stop').checked,
    },
  });
  $('#last-result').textContent = 'calibrating (about 12 s); Hold aborts it';
});
$('#move-go').addEventListener('click', async () => {
  const args = {
    axis_index: Number($('#move-axis').value),
    target_position: Number($('#move-target').value),
    velocity_factor: Number($('#move-vf').value),
  };
  if (await enterPvtFromHold()) run({ command: 'move_axis', arguments: args });
});

setupCartesian($, {
  run,
  enterPvtFromHold,
  state: () => page.state,
  onError: (text) => addError({ error_message: text }),
});

function currentMode() {
  return page.state?.status?.operating_mode;
}

/** Enter PVT with the `dt` every core accepts: 0.01 s, or one cycle (`info`'s `cycle_time`)
 * when the cycle is longer (`pvt` refuses a `dt` under one cycle). Resolves whether the arm is
 * in PVT now. */
async function enterPvt() {
  if (page.cycleTime === null) {
    const info = await run({ command: 'info' });
    if (info?.result_type !== 'initialization') return false;
    page.cycleTime = info.cycle_time;
  }
  const r = await run({ command: 'pvt', arguments: { dt: Math.max(0.01, page.cycleTime) } });
  return r?.operating_mode === 'PVT';
}

/** Before a move: enter PVT when in HOLD (a move needs PVT). Resolves false when that failed. */
async function enterPvtFromHold() {
  return currentMode() !== 'HOLD' || enterPvt();
}

// ---- jogging -----------------------------------------------------------------------------

const jog = new Jogger(conn, {
  maxVelocity: (axis) => page.model?.axes?.[axis - 1]?.max_velocity_deg_s ?? 0,
  speed: () => Number($('#jog-speed').value) || 0.2,
  tcp: () => ({
    linearMmS: Number($('#cjog-linear').value) || 0,
    angularDegS: Number($('#cjog-angular').value) || 0,
    frame: $('#cjog-frame').value,
  }),
  onError: (text) => addError({ error_message: text }, 'jog'),
  onChange: (a) => {
    document.querySelectorAll('button.jog.active').forEach((b) => b.classList.remove('active'));
    const s = $('#jog-state');
    if (a) {
      $(`button.jog[data-axis="${a.axis}"][data-dir="${a.dir > 0 ? '+' : '-'}"]`)?.classList.add('active');
      s.textContent = typeof a.axis === 'number'
        ? `jogging axis ${a.axis} ${a.dir > 0 ? '+' : '-'}`
        : `jogging the TCP ${a.axis} ${a.dir > 0 ? '+' : '-'} (${$('#cjog-frame').value} frame)`;
      s.className = 'jogging';
    } else {
      s.textContent = 'idle';
      s.className = 'muted';
    }
  },
});

// The axes' buttons (data-axis 1..6) and the TCP's (data-axis x, y, z, rx, ry, rz).
for (const b of document.querySelectorAll('button.jog')) {
  const axis = /^[1-6]$/.test(b.dataset.axis) ? Number(b.dataset.axis) : b.dataset.axis;
  const dir = b.dataset.dir === '+' ? 1 : -1;
  b.addEventListener('pointerdown', (e) => {
    if (b.disabled || e.button !== 0) return;
    e.preventDefault();
    b.setPointerCapture(e.pointerId);
    if (typeof axis === 'number') selectJogAxis(axis);
    jog.start(axis, dir, 'pointer');
  });
  for (const ev of ['pointerup', 'pointercancel', 'lostpointercapture']) {
    b.addEventListener(ev, () => jog.release('pointer'));
  }
  b.addEventListener('contextmenu', (e) => e.preventDefault());
}
$('#jog-speed').addEventListener('input', () => {
  $('#jog-speed-text').textContent = `${Math.round(Number($('#jog-speed').value) * 100)} %`;
});
window.addEventListener('blur', () => jog.stop('blur'));
document.addEventListener('visibilitychange', () => {
  if (document.visibilityState === 'hidden') jog.stop('hidden');
});

let jogAxis = 1;
function selectJogAxis(a) {
  jogAxis = a;
  $('#jog-axis').textContent = String(a);
}

const JOG_KEYS = { ArrowRight: 1, ArrowUp: 1, ArrowLeft: -1, ArrowDown: -1 };
function inField(t) {
  return t && (t.tagName === 'INPUT' || t.tagName === 'SELECT' || t.tagName === 'TEXTAREA' || t.isContentEditable);
}
function typing(t) {
  return inField(t) && !(t.tagName === 'INPUT' && ['checkbox', 'range', 'button'].includes(t.type));
}

document.addEventListener('keydown', (e) => {
  if (e.key === 'Escape' || ((e.key === ' ' || e.code === 'Space') && !typing(e.target))) {
    e.preventDefault();
    if (!e.repeat) hold();
    return;
  }
  if (inField(e.target) || e.ctrlKey || e.altKey || e.metaKey) return;
  if (/^[1-6]$/.test(e.key)) {
    selectJogAxis(Number(e.key));
    return;
  }
  const dir = JOG_KEYS[e.key];
  if (dir) {
    e.preventDefault();
    // Only the first press: a refused jog must not be retried at the key's repeat rate.
    if (e.repeat || !motionAllowed()) return;
    jog.start(jogAxis, dir, `key:${e.key}`);
  }
});
document.addEventListener('keyup', (e) => {
  if (e.key === ' ' || e.code === 'Space') e.preventDefault();
  if (JOG_KEYS[e.key]) jog.release(`key:${e.key}`);
});

// ---- access and control ------------------------------------------------------------------

function motionAllowed() {
  return page.detail?.access?.motion_allowed_here !== false;
}

function thisPageControls() {
  const c = page.detail?.control;
  return !!(c && c.this_connection && (page.state ? page.state.owner === c.owner : true));
}

function showAccess() {
  const allowed = motionAllowed() && conn.connected;
  $('#readonly').hidden = page.detail?.access?.motion_allowed_here !== false;
  const motion = ['#take-control', '#calibrate', '#release', '#pvt', '#move-go', 'button.jog', '#pose-go', '#line-go', '#tool-set'];
  for (const sel of motion) {
    document.querySelectorAll(sel).forEach((b) => { b.disabled = !allowed; });
  }
}

// ---- rendering the state -----------------------------------------------------------------

let renderPending = false;
function scheduleRender() {
  if (renderPending) return;
  renderPending = true;
  requestAnimationFrame(() => {
    renderPending = false;
    render();
  });
}
// A hidden page gets no animation frames; render at least every 250 ms anyway.
setInterval(() => { if (renderPending) { renderPending = false; render(); } }, 250);

function render() {
  const f = page.state;
  if (!f || !f.status) return;
  const st = f.status;
  const mode = $('#mode');
  setText(mode, st.operating_mode ?? '-');
  if (mode.dataset.mode !== mode.textContent) mode.dataset.mode = mode.textContent;
  if (document.body.dataset.mode !== mode.textContent) document.body.dataset.mode = mode.textContent;
  setText($('#hw'), st.hardware_status ?? '');
  const mine = thisPageControls();
  setText($('#owner'), mine ? 'this page' : (f.owner ?? 'nobody'));
  const ownerKind = mine ? 'this-page' : f.owner ? 'other' : 'nobody';
  if ($('#owner').dataset.owner !== ownerKind) $('#owner').dataset.owner = ownerKind;
  if (st.operating_mode !== 'ERROR') {
    clearCurrent();
  }
  renderJoints($('#joints'), st, page.model);
  // Figures for reading, not for watching: four times a second is enough.
  const now = performance.now();
  if (!(now - page.slowRenderedAt < 250)) {
    page.slowRenderedAt = now;
    renderTiming($('#timing'), st.detail?.timing, page.model?.bus, st.detail?.bus);
    const l = page.latencies;
    setText($('#latency'), l.length
      ? `p50 ${fmt(percentile(l, 50), 1)} ms, p99 ${fmt(percentile(l, 99), 1)} ms (last ${l.length} frames)`
      : '-');
  }
  if (page.view && page.model) {
    const pts = fkOrigins(page.model.links, st.axis_states?.position || []);
    page.view.update(pts, jointColours(st, page.model, page.lastError?.axis), st.cartesian_state ?? null);
  }
  renderCartesian($, st, setText);
}

// ---- the model, the 3D view, the records -------------------------------------------------

async function loadModel() {
  try {
    const r = await fetch('/api/model', { cache: 'no-store' });
    if (!r.ok) throw new Error(`HTTP ${r.status}`);
    page.model = await r.json();
  } catch (e) {
    $('#notice').hidden = false;
    $('#notice').textContent = `Could not read the robot's model (/api/model: ${e.message}); retrying.`;
    setTimeout(loadModel, 2000);
    return;
  }
  $('#notice').hidden = true;
  page.names = page.model.axes.map((a) => a.name);
  $('#robot').textContent = `${page.model.robot} (${page.model.instance})`;
  document.title = `MCM pendant - ${page.model.robot}`;
  fillModel($('#joints'), page.model);
  setupView();
  scheduleRender();
}

function setupView() {
  const canvas = $('#view3d');
  const msg = $('#view-msg');
  if (!webglAvailable()) {
    canvas.hidden = true;
    msg.hidden = false;
    msg.textContent = 'The 3D view needs WebGL, which this browser does not offer; everything else works.';
    return;
  }
  try {
    page.view = new View3d(canvas, page.model.links);
  } catch (e) {
    canvas.hidden = true;
    msg.hidden = false;
    msg.textContent = `The 3D view could not start (${e.message}); everything else works.`;
  }
}



const loadRecords = () => loadRecordList(() => page.names);
$('#records-refresh').addEventListener('click', loadRecords);

// ---- for the tests -----------------------------------------------------------------------

window.mcmPendant = {
  get state() { return page.state; },
  get frames() { return page.frames; },
  get latencies() { return page.latencies; },
  get connected() { return conn.connected; },
  get model() { return page.model; },
  get view() { return page.view; },
  flange() {
    if (!page.model || !page.state) return null;
    const pts = fkOrigins(page.model.links, page.state.status?.axis_states?.position || []);
    return pts[pts.length - 1];
  },
};

showAccess();
loadModel();
loadRecords();
