// The pendant from a network that may not move the arm (`[gateway.access] motion_networks`
// without loopback): the page says it is read-only and disables its motion controls, a held
// jog key and the protocol's motion commands sent over the page's own WebSocket move nothing
// on the simulation's truth, and `hold` from a key still works. The arm is calibrated (the
// MCM was restarted with the calibration its drives kept), so only the access rule stops it.
// Run by tests/end_to_end/web.rs; see lib.mjs for the environment it passes.

import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  browserAndJson, openPendant, waitMode, blur, screenshot, maxDiff, waitUntil, Sequence,
} from './lib.mjs';

const seq = new Sequence();
const { browser, json } = await browserAndJson();
let page;

/// Poll the truth for `seconds` of robot time; every sample within 0.01 deg of `from`.
async function assertStill(from, seconds, what) {
  const t0 = await json.robotTime();
  await waitUntil(`${seconds} s of robot time (${what})`, 10000 + seconds * 1000, async () => {
    const t = await json.truth();
    assert.ok(maxDiff(t.position, from) < 0.01, `${what}: the arm moved from ${from} to ${t.position}`);
    return (await json.robotTime()) - t0 >= seconds;
  });
}

/// Send one protocol command over a new WebSocket of the page's own origin; its result
/// (state frames skipped).
function overPagesSocket(p, command) {
  return p.evaluate((cmd) => new Promise((resolve, reject) => {
    const ws = new WebSocket(new URL('/ws', location.href).href.replace(/^http/, 'ws'));
    const timer = setTimeout(() => { ws.close(); reject(new Error(`no result for ${JSON.stringify(cmd)} within 5 s`)); }, 5000);
    ws.onopen = () => ws.send(JSON.stringify(cmd));
    ws.onerror = () => reject(new Error('the WebSocket failed'));
    ws.onmessage = (m) => {
      const v = JSON.parse(m.data);
      if (v.result_type === undefined) return;
      clearTimeout(timer);
      ws.close();
      resolve(v);
    };
  }), command);
}

test('the page says it is read-only and disables its motion controls', { timeout: 60000 }, seq.wrap('banner', async () => {
  const s = await json.status();
  assert.equal(s.detail.access.motion_allowed_here, false, 'loopback is outside motion_networks');
  assert.equal(s.detail.all_calibrated, true, 'the restarted MCM kept the calibration');
  assert.equal(s.operating_mode, 'OFF', 'a restarted MCM starts in OFF');
  page = await openPendant(browser);
  await page.waitForSelector('#readonly', { state: 'visible', timeout: 5000 });
  const banner = await page.textContent('#readonly');
  assert.ok(banner.includes('Read-only') && banner.includes('motion_networks'), banner);
  for (const sel of ['button.jog', '#calibrate', '#move-go', '#pvt', '#release', '#take-control', '#pose-go', '#line-go', '#tool-set']) {
    const enabled = await page.$$eval(sel, (els) => els.filter((e) => !e.disabled).map((e) => e.outerHTML));
    assert.deepEqual(enabled, [], `${sel} disabled when read-only`);
  }
  assert.equal(await page.isEnabled('#hold'), true, '#hold stays enabled');
  // Solving a pose moves nothing: open to a read-only page as the protocol's command is.
  assert.equal(await page.isEnabled('#pose-solve'), true, '#pose-solve stays enabled');
}));

test('hold from a key works when read-only', { timeout: 30000 }, seq.wrap('hold', async () => {
  await waitMode(page, 'OFF', 3000);
  await blur(page);
  await page.keyboard.press('Escape');
  await waitMode(page, 'HOLD', 5000);
  assert.equal((await json.status()).operating_mode, 'HOLD');
  await screenshot(page, 'readonly');
}));

test('a held jog key moves nothing when read-only', { timeout: 30000 }, seq.wrap('jog', async () => {
  const start = await json.waitAtRest('the arm at rest in HOLD', 10000);
  await blur(page);
  await page.keyboard.press('1');
  await page.keyboard.down('ArrowRight');
  await assertStill(start.truth.position, 1.0, 'jog key held');
  await page.keyboard.up('ArrowRight');
  assert.equal((await json.status()).operating_mode, 'HOLD');
}));

test('motion commands over the page\'s WebSocket are refused, naming the rule; hold is not', { timeout: 30000 }, seq.wrap('ws', async () => {
  const start = (await json.truth()).position;
  for (const cmd of [
    { command: 'velocity_control', arguments: { timeout: 0.2, dt_status: 0 } },
    { command: 'pvt' },
    { command: 'take_control' },
  ]) {
    const r = await overPagesSocket(page, cmd);
    assert.equal(r.error_status, 'ERROR', `${JSON.stringify(cmd)}: ${JSON.stringify(r)}`);
    assert.ok(r.error_message.includes('refused') && r.error_message.includes('motion_networks'), r.error_message);
  }
  const held = await overPagesSocket(page, { command: 'hold' });
  assert.equal(held.result_type, 'status', JSON.stringify(held));
  assert.equal(held.operating_mode, 'HOLD');
  await assertStill(start, 0.5, 'after the refused commands');
  const s = await json.status();
  assert.ok(s.detail.access.refused.network >= 3, `refusals counted: ${JSON.stringify(s.detail.access.refused)}`);
}));
