// The pendant in a real browser against one simulated MCM, in order (each step leaves the arm
// where the next one expects it): the page loads with six joints, calibrates from its button
// and shows the truth, jogs from the keyboard and stops on release, `hold` from a key during a
// jog and a move, the truth again at non-zero angles (and the 3D view's flange), the jog stops
// when the tab is closed, an injected fault appears with its words and its flight record
// plots, and the page reconnects after the gateway is killed and restarted. Claims about the
// arm are checked on the simulation's truth (`sim`), times on the robot's clock.
// Run by tests/end_to_end/web.rs; see lib.mjs for the environment it passes.

import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import {
  env, launchBrowser, JsonClient, openPendant, waitFrames, waitMode, jointTable, blur,
  setField, screenshot, flange, maxAbs, maxDiff, waitUntil, Sequence,
} from './lib.mjs';

/// How far the reported joint angles may be from the simulation's truth at rest [deg]: the
/// calibration's accuracy (docs/testing.md: within 0.05 deg of the truth).
const TRUTH_TOLERANCE_DEG = 0.05;
/// How far the page's 3-decimal angles may be from the state it shows [deg]: the rounding.
const DISPLAY_TOLERANCE_DEG = 0.0006;
/// How long the arm may take, on the robot's clock, from the key's release (or the tab's
/// closing, or Escape) to rest: the page's 50 ms between messages, the core's 0.2 s velocity
/// timeout for a closed tab, and the controlled stop from the jog speed.
const STOP_WITHIN_S = 1.0;
/// The page's default jog speed, a fraction of the axis's maximum velocity (docs/web.md).
const JOG_FRACTION = 0.2;

const url = env('MCM_WEB_URL');
const seq = new Sequence();
let browser;
let json;
let model;
let page;

before(async () => {
  browser = await launchBrowser();
  json = await JsonClient.connect(env('MCM_JSON'));
  const r = await fetch(new URL('/api/model', url));
  assert.equal(r.status, 200, '/api/model');
  model = await r.json();
});

after(async () => {
  json?.close();
  await browser?.close();
});

/// With the arm at rest: the page's joint table shows the MCM's reported angles (to its 3
/// decimals), and those are the simulation's true angles (within the calibration's accuracy);
/// the truth.
async function assertJointsShowTruth(p, what) {
  const rest = await json.waitAtRest(`the arm at rest (${what})`, 20000);
  let table;
  let reported;
  try {
    await waitUntil(`the joint table to show the reported angles (${what})`, 5000, async () => {
      reported = (await json.status()).axis_states.position;
      table = (await jointTable(p)).map((r) => r.pos);
      return maxDiff(table.map(Number), reported) <= DISPLAY_TOLERANCE_DEG;
    });
  } catch (e) {
    throw new Error(`${e.message}: table ${JSON.stringify(table)}, reported ${JSON.stringify(reported)}`);
  }
  for (const pos of table) assert.match(pos, /^-?\d+\.\d{3}$/, 'positions with 3 decimals');
  const off = maxDiff(table.map(Number), rest.truth.position);
  assert.ok(off <= TRUTH_TOLERANCE_DEG,
    `the page shows ${JSON.stringify(table)}, the truth is ${JSON.stringify(rest.truth.position)} (${off.toFixed(4)} deg apart)`);
  return rest.truth;
}

/// Jog axis `axis` from the keyboard in direction `key` until the truth shows it moving at
/// about the jog speed; the truth then.
async function startKeyJog(p, axis, key) {
  await blur(p);
  await p.keyboard.press(String(axis));
  await p.waitForFunction((a) => document.querySelector('#jog-axis')?.textContent.includes(String(a)),
    axis, { timeout: 3000 });
  const start = await json.truth();
  const sign = key === 'ArrowRight' || key === 'ArrowUp' ? 1 : -1;
  const jog = JOG_FRACTION * model.axes[axis - 1].max_velocity_deg_s;
  await p.keyboard.down(key);
  const moving = await json.waitTruth(`axis ${axis} jogging at about ${jog} deg/s`, 10000,
    (t) => sign * t.velocity[axis - 1] >= 0.9 * jog);
  assert.ok(sign * moving.velocity[axis - 1] <= 1.1 * jog,
    `the jog speed is ${JOG_FRACTION} of the axis's maximum: ${moving.velocity[axis - 1]} deg/s`);
  assert.ok(sign * (moving.position[axis - 1] - start.position[axis - 1]) > 0, 'moved the right way');
  // The other axes hold their positions; the motion of one joint disturbs the others a little
  // (the arm's dynamics, e.g. about 0.7 deg/s on axes 3 and 5 while axis 2 jogs).
  for (let a = 0; a < 6; a++) {
    if (a !== axis - 1) assert.ok(Math.abs(moving.velocity[a]) < 0.1 * jog, `only axis ${axis} jogs: ${moving.velocity}`);
  }
  return moving;
}

test('the page loads and shows six joints of the configured arm', { timeout: 60000 }, seq.wrap('load', async () => {
  page = await openPendant(browser);
  assert.equal(await page.textContent('#conn'), 'connected');
  assert.equal(await page.getAttribute('#conn', 'data-state'), 'connected');
  const table = await jointTable(page);
  assert.deepEqual(table.map((r) => r.name), model.axes.map((a) => a.name));
  assert.equal(model.axes.length, 6);
  const s = await json.status();
  assert.equal(s.operating_mode, 'OFF', 'a fresh MCM starts in OFF');
  await waitMode(page, 'OFF', 3000);
  assert.deepEqual(table.map((r) => r.cal), Array(6).fill('no'));
  assert.ok(await page.isVisible('canvas#view3d'), 'the 3D view');
  assert.equal(await page.isVisible('#readonly'), false, 'motion is allowed from loopback');
}));

test('calibrating from the page\'s button: HOLD, every axis calibrated, the joints show the truth',
  { timeout: 120000 }, seq.wrap('calibrate', async () => {
    await setField(page, '#cal-which', 'ALL');
    await page.click('#calibrate');
    await waitMode(page, 'HOLD', 90000);
    await page.waitForFunction(
      () => [...document.querySelectorAll('#joints tbody tr .cal')].every((c) => c.textContent.trim() === 'yes'),
      null, { timeout: 5000 });
    const s = await json.status();
    assert.equal(s.detail.all_calibrated, true);
    assert.ok(s.detail.control.owner, 'the page took control by calibrating');
    await page.waitForFunction(() => document.querySelector('#owner')?.textContent.includes('this page'),
      null, { timeout: 5000 });
    await assertJointsShowTruth(page, 'after calibration');
    await screenshot(page, 'overview');
  }));

test('a held arrow key jogs the selected axis; released, the arm stops', { timeout: 60000 }, seq.wrap('jog', async () => {
  await startKeyJog(page, 1, 'ArrowRight');
  await waitMode(page, 'VELOCITY_CONTROL', 3000);
  await page.keyboard.up('ArrowRight');
  const released = await json.robotTime();
  const rest = await json.waitAtRest('the arm at rest after the key was released', 10000);
  const took = rest.time - released;
  assert.ok(took < STOP_WITHIN_S, `at rest ${took.toFixed(3)} s (robot time) after the release`);
  assert.ok(rest.truth.position[0] > 1, `axis 1 moved: ${rest.truth.position}`);
  await waitMode(page, 'HOLD', 3000);
}));

test('Escape during a jog holds the arm', { timeout: 60000 }, seq.wrap('escape-jog', async () => {
  await startKeyJog(page, 2, 'ArrowLeft');
  // Far enough for the 3D view to show the arm leaning (and the screenshot of docs/web.md).
  await json.waitTruth('axis 2 jogged past -15 deg', 10000, (t) => t.position[1] < -15);
  await screenshot(page, 'jogging');
  await page.keyboard.press('Escape');
  const pressed = await json.robotTime();
  await waitMode(page, 'HOLD', 3000);
  const rest = await json.waitAtRest('the arm at rest after Escape', 10000);
  assert.ok(rest.time - pressed < STOP_WITHIN_S, `at rest ${(rest.time - pressed).toFixed(3)} s after Escape`);
  await page.keyboard.up('ArrowLeft');
  assert.equal((await json.status()).operating_mode, 'HOLD');
  assert.ok(rest.truth.position[1] < -15, `axis 2 moved: ${rest.truth.position}`);
}));

test('Escape during a move holds the arm, also with the focus in a form field', { timeout: 60000 }, seq.wrap('escape-move', async () => {
  await page.click('#pvt');
  await waitMode(page, 'PVT', 3000);
  const target = 40;
  await setField(page, '#move-axis', 3);
  await setField(page, '#move-target', target);
  await setField(page, '#move-vf', 0.2);
  await page.click('#move-go');
  await json.waitTruth('axis 3 moving towards its target', 10000, (t) => t.position[2] > 2 && t.velocity[2] > 1);
  await page.focus('#move-target');
  await page.keyboard.press('Escape');
  const pressed = await json.robotTime();
  await waitMode(page, 'HOLD', 3000);
  const rest = await json.waitAtRest('the arm at rest after Escape', 10000);
  assert.ok(rest.time - pressed < STOP_WITHIN_S, `at rest ${(rest.time - pressed).toFixed(3)} s after Escape`);
  assert.ok(rest.truth.position[2] < target - 1, `held before the target: ${rest.truth.position}`);
}));

test('the joint table and the 3D view show the truth at non-zero angles', { timeout: 30000 }, seq.wrap('truth', async () => {
  const truth = await assertJointsShowTruth(page, 'after the jogs and the move');
  assert.ok(maxAbs(truth.position.slice(0, 3)) > 1, `the arm is away from zero: ${truth.position}`);
  // The view's flange against the arm's kinematics at the angles the page shows.
  const links = model.links;
  assert.ok(Math.abs(flange(links, [0, 0, 0, 0, 0, 0])[2] - 1.035) < 1e-3, 'the DH links put the flange at z = 1.035 m at zero');
  const seen = await page.evaluate(() => ({
    flange: window.mcmPendant.flange(),
    q: window.mcmPendant.state.status.axis_states.position,
  }));
  const want = flange(links, seen.q);
  assert.ok(maxDiff(seen.flange, want) < 0.002, `flange ${seen.flange} vs the kinematics ${want}`);
}));

test('closing the tab while jogging stops the arm', { timeout: 60000 }, seq.wrap('tab-close', async () => {
  await startKeyJog(page, 1, 'ArrowRight');
  await page.close();
  page = null;
  const closed = await json.robotTime();
  const rest = await json.waitAtRest('the arm at rest after the tab closed', 10000);
  const took = rest.time - closed;
  assert.ok(took < STOP_WITHIN_S, `at rest ${took.toFixed(3)} s (robot time) after the tab closed`);
  const s = await waitUntil('the closed page\'s control released', 5000, async () => {
    const s = await json.status();
    return s.detail.control.owner === null ? s : null;
  });
  assert.equal(s.operating_mode, 'HOLD');
  page = await openPendant(browser);
  await waitMode(page, 'HOLD', 3000);
}));

test('an injected fault shows with its words; its flight record is listed and plots', { timeout: 60000 }, seq.wrap('fault', async () => {
  await json.request('sim', { disconnect_axis: 3 });
  const e = await json.event(10000);
  assert.equal(e.check, 'drive_disconnected', JSON.stringify(e));
  const words = 'the drive of axis 3 does not answer on the bus';
  assert.ok(e.error_message.includes(words), e.error_message);
  const li = `#errors li.error[data-check="drive_disconnected"]`;
  await page.waitForSelector(li, { timeout: 5000 });
  const text = await page.textContent(li);
  assert.ok(text.includes(words), `the page's error says ${JSON.stringify(text)}`);
  await waitMode(page, 'ERROR', 3000);

  const name = e.flight_recorder.split('/').pop();
  const item = `#records li[data-name="${name}"]`;
  await page.waitForSelector(item, { timeout: 15000 });
  const href = await page.getAttribute(`${item} a.download`, 'href');
  assert.ok(href?.endsWith(`/api/flight-records/${name}`), `download link ${href}`);
  const csv = await fetch(new URL(href, url));
  assert.equal(csv.status, 200);
  assert.match(csv.headers.get('content-type'), /^text\/csv/);
  assert.match((await csv.text()).split('\n')[0], /(^|,)cycle(,|$)/);
  await page.click(item);
  await page.waitForSelector('#record-plot canvas', { timeout: 10000 });
  await page.waitForFunction(() => document.querySelector('#record-plot')?.textContent.includes('drive_disconnected'),
    null, { timeout: 5000 });
  await screenshot(page, 'error-record');

  // Recovery: the drive back, then `hold` from the key until it is accepted (it is refused
  // while the drive is still silent).
  await json.request('sim', { reconnect_axis: 3 });
  await waitUntil('hold from Escape accepted once the drive answers', 20000, async () => {
    await blur(page);
    await page.keyboard.press('Escape');
    try {
      await waitMode(page, 'HOLD', 1000);
      return true;
    } catch {
      return false;
    }
  });
}));

test('the page reconnects after the gateway is killed and restarted', { timeout: 60000 }, seq.wrap('reconnect', async () => {
  await waitFrames(page, 'frames before the restart', 5000);
  process.kill(Number(env('MCM_GATEWAY_PID')), 'SIGKILL');
  await page.waitForFunction(() => document.querySelector('#conn')?.dataset.state === 'disconnected',
    null, { timeout: 5000, polling: 10 });
  assert.equal(await page.textContent('#conn'), 'disconnected');
  await page.waitForFunction(() => document.querySelector('#conn')?.dataset.state === 'connected',
    null, { timeout: 30000, polling: 20 });
  await waitFrames(page, 'frames after the restart', 10000, 10);
  await waitMode(page, 'HOLD', 3000);
}));
