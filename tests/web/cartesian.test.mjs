// The pendant's Cartesian panel in a real browser against one simulated MCM, in order: the TCP
// table shows the status's `cartesian_state` in millimetres and roll/pitch/yaw degrees, the
// 3D view draws the TCP's triad there; the tool form sets the tool `detail.tool` then reports
// (the convention checked on a pose where fixed and moving axes differ); the move-to-pose form
// shows the inverse kinematics' solutions, the first being the JSON port's first, and its Go
// moves the true arm there (the simulation's truth, then the status's TCP), entering PVT from
// HOLD with a `dt` the core takes (it runs at 50 Hz here, where 0.01 s is under one cycle); the
// Cartesian jog buttons move the true TCP along the base's x and against the tool's z while
// held and stop when let go; the straight-line form moves the true TCP on a line to its target
// and shows a refusal. Run by tests/end_to_end/web.rs; see lib.mjs for the environment it
// passes.

import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  browserAndJson, openPendant, waitMode, setField, screenshot, maxDiff, maxAbs, waitUntil, Sequence,
  orientationAngleDeg, tcpOf, env,
} from './lib.mjs';

const seq = new Sequence();
const { browser, json } = await browserAndJson();
let page;

/// Roll, pitch, yaw [deg] of a unit quaternion [x, y, z, w] through its rotation matrix
/// (fixed axes x, y, z: R = Rz(yaw) Ry(pitch) Rx(roll)), independently of the page's formula.
function rpyOfMatrix([x, y, z, w]) {
  const r = [
    [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
    [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
    [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
  ];
  const d = 180 / Math.PI;
  return [Math.atan2(r[2][1], r[2][2]) * d, -Math.asin(r[2][0]) * d, Math.atan2(r[1][0], r[0][0]) * d];
}

const TCP_CELLS = ['x', 'y', 'z', 'roll', 'pitch', 'yaw'];
const tcpTable = (p) => p.evaluate((cells) => cells.map((c) => document.querySelector(`#tcp-${c}`).textContent), TCP_CELLS);

test('the TCP table and the 3D triad show the status\'s TCP', { timeout: 90000 }, seq.wrap('tcp', async () => {
  page = await openPendant(browser);
  assert.ok((await page.textContent('#tcp-note')).includes('not every axis is calibrated'));
  await page.click('#take-control');
  await page.click('#calibrate');
  await waitUntil('every axis calibrated, in HOLD', 60000, async () => {
    const s = await json.status();
    return s.detail.all_calibrated && s.operating_mode === 'HOLD';
  }, 50);
  let shown;
  let expected;
  await waitUntil('the TCP table to show the status\'s TCP', 5000, async () => {
    const c = (await json.status()).cartesian_state;
    expected = [...c.position.map((v) => v * 1000), ...rpyOfMatrix(c.orientation)];
    shown = (await tcpTable(page)).map(Number);
    return maxDiff(shown.slice(0, 3), expected.slice(0, 3)) < 0.006 && maxDiff(shown.slice(3), expected.slice(3)) < 0.002;
  }).catch((e) => { throw new Error(`${e.message}: shown ${shown}, expected ${expected}`); });
  const triad = await page.evaluate(() => {
    const a = window.mcmPendant.view?.tcpAxes;
    return a && { visible: a.visible, p: a.position.toArray(), q: a.quaternion.toArray() };
  });
  assert.ok(triad, 'the 3D view runs (WebGL) and has the TCP triad');
  const c = (await json.status()).cartesian_state;
  assert.ok(triad.visible, 'the triad shows once calibrated');
  assert.ok(maxDiff(triad.p, c.position) < 1e-4, `triad at ${triad.p}, TCP at ${c.position}`);
  assert.ok(orientationAngleDeg(triad.q, c.orientation) < 0.01, `triad turned ${triad.q}, TCP ${c.orientation}`);
}));

test('the tool form sets the tool in millimetres and degrees', { timeout: 30000 }, seq.wrap('tool', async () => {
  // Roll 90 and yaw 90 about the fixed axes: [0.5, 0.5, 0.5, 0.5] (about moving axes it would
  // be [0.5, -0.5, 0.5, 0.5]).
  const form = { '#tool-x': 20, '#tool-y': 0, '#tool-z': 150, '#tool-roll': 90, '#tool-pitch': 0, '#tool-yaw': 90,
    '#tool-mass': 1.2, '#tool-com-x': 0, '#tool-com-y': 0, '#tool-com-z': 60 };
  for (const [sel, v] of Object.entries(form)) await setField(page, sel, v);
  await page.click('#tool-set');
  const tool = await waitUntil('detail.tool to be the one set', 5000, async () => {
    const t = (await json.status()).detail.tool;
    return t.mass === 1.2 ? t : null;
  });
  assert.deepEqual(tool.tcp.position, [0.02, 0, 0.15]);
  assert.ok(maxDiff(tool.tcp.orientation, [0.5, 0.5, 0.5, 0.5]) < 1e-6, `${tool.tcp.orientation}`);
  assert.deepEqual(tool.center_of_mass, [0, 0, 0.06]);
  await page.waitForFunction(() => document.querySelector('#tool-now').textContent
    .includes('TCP at [20.00, 0.00, 150.00] mm, rpy [90.000, 0.000, 90.000] deg'), null, { timeout: 3000 });
}));

test('the move-to-pose form shows the solutions and moves the TCP there', { timeout: 60000 }, seq.wrap('pose', async () => {
  await page.click('#pose-here');
  const here = (await json.status()).cartesian_state;
  // 80 mm lower, 100 mm further out along x, the same orientation.
  const z = Number(await page.inputValue('#pose-z'));
  const x = Number(await page.inputValue('#pose-x'));
  await setField(page, '#pose-z', (z - 80).toFixed(2));
  await setField(page, '#pose-x', (x + 100).toFixed(2));
  const goal = [here.position[0] + 0.1, here.position[1], here.position[2] - 0.08];
  await page.click('#pose-solve');
  await page.waitForSelector('#pose-solutions tr.chosen', { timeout: 5000 });
  const first = await page.$$eval('#pose-solutions tr.chosen td.num', (tds) => tds.map((td) => Number(td.textContent)));
  const seed = (await json.status()).axis_states.position;
  const ik = await json.request('inverse_kinematics', { position: goal, orientation: here.orientation });
  assert.equal(ik.result_type, 'inverse_kinematics', JSON.stringify(ik));
  // The page's first is the JSON port's first, or one as near the present position: from the
  // calibration pose (the elbow at 0 deg) the two elbow branches need the same travel of axis 3,
  // and the page's inputs, rounded to 0.01 mm and 0.001 deg, may order such a tie the other way.
  const speeds = (await json.request('info')).axes.map((a) => a.max_velocity);
  const travel = (q) => Math.max(...q.map((v, i) => Math.abs(v - seed[i]) / speeds[i]));
  const chosen = ik.solutions.find((q) => maxDiff(first, q) < 0.01);
  assert.ok(chosen, `the page's first ${first} is not among the JSON port's solutions ${JSON.stringify(ik.solutions)}`);
  assert.ok(chosen === ik.solutions[0] || Math.abs(travel(chosen) - travel(ik.solutions[0])) < 1e-3,
    `the page's first ${first} (${travel(chosen)} s away), the JSON port's ${ik.solutions[0]} (${travel(ik.solutions[0])} s)`);

  await setField(page, '#pose-vf', 1);
  await page.click('#pose-go');
  await waitMode(page, 'PVT', 5000);
  await json.waitTruth('the true arm at the page\'s first solution, at rest', 30000,
    (t) => maxDiff(t.position, chosen) < 0.05 && t.velocity.every((v) => Math.abs(v) < 0.1));
  const c = await waitUntil('the commanded move to end', 10000, async () => {
    const s = await json.status();
    return s.axis_states.velocity.every((v) => v === 0) ? s.cartesian_state : null;
  });
  assert.ok(maxDiff(c.position, goal) < 1e-3, `the TCP ends at ${c.position}, asked ${goal}`);
  assert.ok(orientationAngleDeg(c.orientation, here.orientation) < 0.1, `turned ${c.orientation} from ${here.orientation}`);
  await screenshot(page, 'cartesian');
}));

/// The true TCP now (the simulation's truth through the DH links and the active tool's TCP).
async function trueTcp(links, tcp) {
  return tcpOf(links, (await json.truth()).position, tcp);
}

const minus = (a, b) => a.map((v, i) => v - b[i]);
const dot = (a, b) => a.reduce((s, v, i) => s + v * b[i], 0);
const norm = (a) => Math.hypot(...a);

/// Hold the pendant's jog button of `direction` ('x' .. 'rz', '+' or '-') down until the true
/// TCP has moved `metres` from where it was, then let go; wait for the arm at rest and in HOLD
/// (the jog's stop). The TCP before and after.
async function jogTcp(links, tcp, direction, sign, metres) {
  const start = await trueTcp(links, tcp);
  await page.hover(`button.jog[data-axis="${direction}"][data-dir="${sign}"]`);
  await page.mouse.down();
  try {
    await waitUntil(`the true TCP ${metres} m from where it was (${direction} ${sign})`, 10000,
      async () => norm(minus((await trueTcp(links, tcp)).position, start.position)) >= metres);
  } finally {
    await page.mouse.up();
  }
  await json.waitAtRest('the arm at rest once the button was let go', 5000, 0.05);
  await waitMode(page, 'HOLD', 5000);
  return { start, end: await trueTcp(links, tcp) };
}

test('the Cartesian jog buttons move the true TCP along the base\'s and the tool\'s axes while held', { timeout: 60000 }, seq.wrap('cartesian-jog', async () => {
  const model = await (await fetch(new URL('/api/model', env('MCM_WEB_URL')))).json();
  const { tcp } = (await json.status()).detail.tool;
  await page.click('#hold');
  await waitMode(page, 'HOLD', 5000);
  await setField(page, '#cjog-frame', 'base');
  await setField(page, '#cjog-linear', 40);
  // Base frame: along +x only.
  let { start, end } = await jogTcp(model.links, tcp, 'x', '+', 0.03);
  let d = minus(end.position, start.position);
  assert.ok(d[0] > 0.03 && Math.abs(d[1]) < 0.003 && Math.abs(d[2]) < 0.003, `along the base's x: ${d}`);
  // Stopped: nothing moves after the release.
  const rest = await trueTcp(model.links, tcp);
  assert.ok(norm(minus(rest.position, end.position)) < 1e-4, `still moving: ${rest.position} after ${end.position}`);

  // Tool frame: against the TCP's own z axis (not the base's).
  await setField(page, '#cjog-frame', 'tool');
  ({ start, end } = await jogTcp(model.links, tcp, 'z', '-', 0.03));
  const z = start.axes[2];
  assert.ok(Math.abs(z[2]) < 0.98, `the TCP's z ${z} differs from the base's`);
  d = minus(end.position, start.position);
  const along = -dot(d, z);
  const across = norm(d.map((v, i) => v + along * z[i]));
  assert.ok(along > 0.03 && across < 0.003, `against the TCP's z ${z}: ${d} (${along} along, ${across} across)`);
  assert.equal(await page.textContent('#jog-state'), 'idle');
}));

test('the straight-line form moves the true TCP to its target', { timeout: 60000 }, seq.wrap('line', async () => {
  const model = await (await fetch(new URL('/api/model', env('MCM_WEB_URL')))).json();
  const { tcp } = (await json.status()).detail.tool;
  await page.click('#line-here');
  const start = await trueTcp(model.links, tcp);
  const here = (await json.status()).cartesian_state;
  // 100 mm along y, the orientation as it is (roll, pitch, yaw left as filled in).
  const y = Number(await page.inputValue('#line-y'));
  await setField(page, '#line-y', (y + 100).toFixed(2));
  await setField(page, '#line-v', 150);
  const goal = [start.position[0], start.position[1] + 0.1, start.position[2]];
  await page.click('#line-go');
  await page.waitForFunction(() => document.querySelector('#line-result').textContent.includes('move_linear: OK, the TCP arrives in'),
    null, { timeout: 5000 });
  await waitMode(page, 'PVT', 5000);
  let worst = 0;
  await waitUntil('the true TCP at the line\'s target, at rest', 20000, async () => {
    const t = await json.truth();
    const now = tcpOf(model.links, t.position, tcp).position;
    worst = Math.max(worst, Math.hypot(now[0] - start.position[0], now[2] - start.position[2]));
    return norm(minus(now, goal)) < 1e-3 && maxAbs(t.velocity) < 0.05;
  });
  assert.ok(worst < 1e-3, `${worst} m off the line`);
  const c = await waitUntil('the commanded line to end', 10000, async () => {
    const s = await json.status();
    return s.axis_states.velocity.every((v) => v === 0) ? s.cartesian_state : null;
  });
  assert.ok(orientationAngleDeg(c.orientation, here.orientation) < 0.1, `turned ${c.orientation} from ${here.orientation}`);

  // An unreachable target is refused in the MCM's words; nothing moves.
  const before = (await json.waitAtRest('the arm settled at the line\'s end', 5000)).truth.position;
  await setField(page, '#line-x', 3000);
  await page.click('#line-go');
  await page.waitForFunction(() => document.querySelector('#line-result').textContent.includes('move_linear refused'),
    null, { timeout: 5000 });
  const after = await json.truth();
  assert.ok(maxDiff(after.position, before) < 0.01 && maxAbs(after.velocity) < 0.05, `moved: ${before} -> ${after.position}`);
}));
