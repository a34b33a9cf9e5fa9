// The pendant's Cartesian panel: the TCP's pose live (millimetres, roll/pitch/yaw degrees),
// the active tool and a form that sets it (`set_tool`), a move-to-pose form that shows the
// inverse kinematics' solutions (`inverse_kinematics`; the first is the one `move_to_pose`
// takes) and moves there (`move_to_pose`), and a straight-line form (`move_linear`, speed in
// mm/s). The protocol speaks metres and unit quaternions [x, y, z, w] (docs/cartesian.md); the
// page converts for people here, in one place.
//
// Roll, pitch and yaw are the URDF's rpy: fixed axes x, then y, then z, R = Rz(yaw) Ry(pitch)
// Rx(roll), as the HMI shows them.
//
// The panel's jog buttons (X/Y/Z/Rx/Ry/Rz in the base or the tool frame) are driven by jog.js's
// Jogger, under the joint jog's dead-man rule (app.js).

const DEG = Math.PI / 180;
const MM = 1000;

/** Roll, pitch, yaw [deg] of the unit quaternion [x, y, z, w] (fixed axes X, Y, Z). */
export function rpyFromQuaternion([x, y, z, w]) {
  const roll = Math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y));
  const pitch = Math.asin(Math.max(-1, Math.min(1, 2 * (w * y - z * x))));
  const yaw = Math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
  return [roll / DEG, pitch / DEG, yaw / DEG];
}

/** The unit quaternion [x, y, z, w] (w >= 0) of roll, pitch, yaw [deg] (fixed axes X, Y, Z). */
export function quaternionFromRpy([roll, pitch, yaw]) {
  const [cr, sr] = [Math.cos(roll * DEG / 2), Math.sin(roll * DEG / 2)];
  const [cp, sp] = [Math.cos(pitch * DEG / 2), Math.sin(pitch * DEG / 2)];
  const [cy, sy] = [Math.cos(yaw * DEG / 2), Math.sin(yaw * DEG / 2)];
  const q = [
    sr * cp * cy - cr * sp * sy,
    cr * sp * cy + sr * cp * sy,
    cr * cp * sy - sr * sp * cy,
    cr * cp * cy + sr * sp * sy,
  ];
  return q[3] < 0 ? q.map((v) => -v) : q;
}

/** A pose for people: {mm: [x, y, z], rpy: [roll, pitch, yaw]} of a protocol pose. */
export function poseForPeople(position, orientation) {
  return { mm: position.map((v) => v * MM), rpy: rpyFromQuaternion(orientation) };
}

/** The protocol's pose {position [m], orientation [x, y, z, w]} of millimetres and degrees. */
export function poseOfPeople(mm, rpy) {
  return { position: mm.map((v) => v / MM), orientation: quaternionFromRpy(rpy) };
}

const fixed = (v, d) => (typeof v === 'number' && Number.isFinite(v) ? (v + 0).toFixed(d) : '-');

/** Read six number fields `ids` (x, y, z, roll, pitch, yaw): {mm, rpy}, or {error: the id of
 * the first field that is not a number}. */
function sixFields($, ids) {
  const raw = ids.map((id) => $(`#${id}`).value.trim());
  const bad = raw.findIndex((t) => t === '' || !Number.isFinite(Number(t)));
  if (bad >= 0) return { error: ids[bad] };
  const v = raw.map(Number);
  return { mm: v.slice(0, 3), rpy: v.slice(3) };
}

const POSE_FIELDS = ['pose-x', 'pose-y', 'pose-z', 'pose-roll', 'pose-pitch', 'pose-yaw'];
const LINE_FIELDS = ['line-x', 'line-y', 'line-z', 'line-roll', 'line-pitch', 'line-yaw'];
const TOOL_FIELDS = ['tool-x', 'tool-y', 'tool-z', 'tool-roll', 'tool-pitch', 'tool-yaw'];

/**
 * Wire the panel. `run(cmd)`: send a command, show its outcome, resolve with the reply (null
 * when it failed); `enterPvtFromHold()`: enter PVT when in HOLD, resolve false when that
 * failed; `state()`: the newest state frame; `onError(text)`: show a mistake of the form.
 */
export function setupCartesian($, { run, enterPvtFromHold, state, onError }) {
  const setFields = (ids, mm, rpy) => {
    ids.forEach((id, i) => { $(`#${id}`).value = fixed(i < 3 ? mm[i] : rpy[i - 3], i < 3 ? 2 : 3); });
  };

  const fillWithTcp = (ids) => () => {
    const c = state()?.status?.cartesian_state;
    if (!c) return onError('no TCP pose yet: every axis must be calibrated');
    const p = poseForPeople(c.position, c.orientation);
    setFields(ids, p.mm, p.rpy);
  };
  $('#pose-here').addEventListener('click', fillWithTcp(POSE_FIELDS));
  $('#line-here').addEventListener('click', fillWithTcp(LINE_FIELDS));

  const poseArgs = () => {
    const f = sixFields($, POSE_FIELDS);
    if (f.error) {
      onError(`move to pose: ${f.error.replace('pose-', '')} is not a number`);
      return null;
    }
    return poseOfPeople(f.mm, f.rpy);
  };

  $('#pose-solve').addEventListener('click', async () => {
    const pose = poseArgs();
    if (!pose) return;
    const r = await run({ command: 'inverse_kinematics', arguments: pose });
    showSolutions($('#pose-solutions'), r);
  });

  $('#pose-go').addEventListener('click', async () => {
    const pose = poseArgs();
    if (!pose) return;
    if (!(await enterPvtFromHold())) return;
    const r = await run({
      command: 'move_to_pose',
      arguments: { ...pose, velocity_factor: Number($('#pose-vf').value) },
    });
    if (r && r.result_type === 'move_all') {
      $('#last-result').textContent =
        `move_to_pose: OK, arrives within ${fixed(r.max_time_to_target, 2)} s`;
    }
  });

  $('#line-go').addEventListener('click', async () => {
    const args = lineArgs($, onError);
    if (!args) return;
    $('#line-result').textContent = '';
    if (!(await enterPvtFromHold())) return;
    const r = await run({ command: 'move_linear', arguments: args });
    if (r && r.result_type === 'move_linear') {
      $('#line-result').textContent = `move_linear: OK, the TCP arrives in ${fixed(r.duration, 2)} s`;
    } else if (r && r.error_message) {
      $('#line-result').textContent = `move_linear refused: ${r.error_message}`;
    }
  });

  $('#tool-here').addEventListener('click', () => {
    const t = state()?.status?.detail?.tool;
    if (!t) return;
    const p = poseForPeople(t.tcp.position, t.tcp.orientation);
    setFields(TOOL_FIELDS, p.mm, p.rpy);
    $('#tool-mass').value = fixed(t.mass, 3);
    ['x', 'y', 'z'].forEach((k, i) => { $(`#tool-com-${k}`).value = fixed(t.center_of_mass[i] * MM, 2); });
  });

  $('#tool-set').addEventListener('click', () => {
    const f = sixFields($, TOOL_FIELDS);
    const mass = Number($('#tool-mass').value);
    const com = ['x', 'y', 'z'].map((k) => Number($(`#tool-com-${k}`).value) / MM);
    if (f.error) return onError(`tool: ${f.error.replace('tool-', '')} is not a number`);
    if (!Number.isFinite(mass) || !com.every(Number.isFinite)) {
      return onError('tool: the mass and the centre of mass need numbers');
    }
    const tcp = poseOfPeople(f.mm, f.rpy);
    run({ command: 'set_tool', arguments: { tcp, mass, center_of_mass: com } });
  });
}

/** The `move_linear` arguments of the straight-line form: the position [m]; the orientation
 * when roll, pitch and yaw are all given (all empty: kept); the speed [m/s]. Null, with the
 * mistake shown, when a field is not a number. */
function lineArgs($, onError) {
  const raw = LINE_FIELDS.map((id) => $(`#${id}`).value.trim());
  const keep = raw.slice(3).every((t) => t === '');
  const bad = raw.findIndex((t, i) => !(keep && i >= 3) && (t === '' || !Number.isFinite(Number(t))));
  if (bad >= 0) {
    onError(`straight line: ${LINE_FIELDS[bad].replace('line-', '')} is not a number`
      + (bad >= 3 ? ' (leave roll, pitch and yaw all empty to keep the orientation)' : ''));
    return null;
  }
  const v = Number($('#line-v').value);
  // Its range is the protocol's (move_linear's `velocity`), refused by the MCM in its words.
  if ($('#line-v').value.trim() === '' || !Number.isFinite(v)) {
    onError('straight line: the speed [mm/s] is not a number');
    return null;
  }
  const pose = poseOfPeople(raw.slice(0, 3).map(Number), keep ? [0, 0, 0] : raw.slice(3).map(Number));
  return keep
    ? { position: pose.position, velocity: v / MM }
    : { ...pose, velocity: v / MM };
}

/** The solutions of an `inverse_kinematics` reply (or its refusal) as a table. */
function showSolutions(el, r) {
  el.textContent = '';
  if (!r) return;
  if (r.result_type !== 'inverse_kinematics') {
    el.textContent = r.error_message ? `no solution: ${r.error_message}` : '';
    return;
  }
  const table = document.createElement('table');
  const head = table.createTHead().insertRow();
  for (const h of ['', '1', '2', '3', '4', '5', '6']) {
    const th = document.createElement('th');
    th.textContent = h ? `axis ${h}` : 'deg';
    head.appendChild(th);
  }
  const body = table.createTBody();
  r.solutions.forEach((q, k) => {
    const row = body.insertRow();
    row.className = k === 0 ? 'chosen' : '';
    row.insertCell().textContent = k === 0 ? 'taken' : String(k + 1);
    for (const v of q) {
      const td = row.insertCell();
      td.className = 'num';
      td.textContent = fixed(v, 3);
    }
  });
  const note = document.createElement('div');
  note.className = 'muted';
  note.textContent = `${r.solutions.length} solution${r.solutions.length === 1 ? '' : 's'} within the axis limits; `
    + 'move_to_pose takes the first, the nearest to the present position';
  el.append(table, note);
}

/** The live figures: the TCP (or why there is none) and the active tool. */
export function renderCartesian($, status, setText) {
  const c = status?.cartesian_state;
  const cells = ['x', 'y', 'z', 'roll', 'pitch', 'yaw'];
  if (c) {
    const p = poseForPeople(c.position, c.orientation);
    cells.forEach((k, i) => setText($(`#tcp-${k}`), fixed(i < 3 ? p.mm[i] : p.rpy[i - 3], i < 3 ? 2 : 3)));
    setText($('#tcp-note'), '');
  } else {
    cells.forEach((k) => setText($(`#tcp-${k}`), '-'));
    setText($('#tcp-note'), 'no TCP pose: not every axis is calibrated');
  }
  const t = status?.detail?.tool;
  if (t) {
    const p = poseForPeople(t.tcp.position, t.tcp.orientation);
    const three = (v, d) => v.map((x) => fixed(x, d)).join(', ');
    setText($('#tool-now'),
      `TCP at [${three(p.mm, 2)}] mm, rpy [${three(p.rpy, 3)}] deg (flange frame); `
      + `load ${fixed(t.mass, 3)} kg at [${three(t.center_of_mass.map((v) => v * MM), 2)}] mm`);
  }
}
