// DNS rebinding against the pendant (docs/security.md, "DNS rebinding"): Chromium, in a network
// namespace whose hosts file maps `evil.example` to the robot, loads a page from
// `http://evil.example:PORT/` (the attacker's page; after the rebinding the name resolves to the
// robot). Its own script then opens `ws://evil.example:PORT/ws` and sends `hold` and
// `calibrate`, and reads `/api/model`: all of it reaches the robot with `evil.example` in `Host`
// and `Origin`. Nothing may run: the WebSocket is refused, `/api` answers 421 naming the host,
// and the arm's mode, calibration and true position over the JSON port are as before. The
// pendant's own page (by its address) still connects.
// Run by tests/end_to_end/web.rs inside the namespace; see lib.mjs for the environment, and
// MCM_OWN_URL: the pendant by the robot's address.

import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { env, launchBrowser, JsonClient, openPendant, maxDiff } from './lib.mjs';

let browser;
let json;

/// Chromium's own check (Private / Local Network Access) stops a page of a public site from
/// reaching a private or loopback address when the page is not served over HTTPS; other
/// browsers and older ones have none, and the robot must not rely on it: switched off here, so
/// that every request of the attacker's page reaches the robot.
const NO_BROWSER_CHECK = [
  '--disable-features=LocalNetworkAccessChecks,BlockInsecurePrivateNetworkRequests,'
    + 'PrivateNetworkAccessSendPreflights,PrivateNetworkAccessRespectPreflightResults',
];

before(async () => {
  browser = await launchBrowser(NO_BROWSER_CHECK);
  json = await JsonClient.connect(env('MCM_JSON'));
});

after(async () => {
  json?.close();
  await browser?.close();
});

/// The attacker's page: everything it tries, reported in `window.attack`.
const ATTACKER_PAGE = `<!doctype html><title>not the robot</title><script>
window.attack = (async () => {
  const api = await fetch('/api/model').then(
    async (r) => ({ status: r.status, body: await r.text() }),
    (e) => ({ error: String(e) }));
  const ws = await new Promise((resolve) => {
    const events = [];
    const done = () => resolve(events);
    const socket = new WebSocket('ws://' + location.host + '/ws');
    socket.onopen = () => {
      events.push('open');
      socket.send(JSON.stringify({ command: 'hold' }));
      socket.send(JSON.stringify({ command: 'calibrate' }));
    };
    socket.onmessage = (m) => events.push('message ' + String(m.data).slice(0, 200));
    socket.onerror = () => events.push('error');
    socket.onclose = (c) => { events.push('close ' + c.code); done(); };
    // An open socket never closes by itself: the page reports what it got by then.
    setTimeout(done, 10000);
  });
  return { api, ws };
})();
</script>`;

/// Mode, calibration and true position over the JSON port.
async function armState() {
  const s = await json.status();
  const truth = await json.truth();
  return { mode: s.operating_mode, calibrated: s.detail.calibrated, position: truth.position };
}

test('a page of a rebound name runs nothing on the robot', { timeout: 60000 }, async () => {
  const attackUrl = env('MCM_WEB_URL');
  const before = await armState();
  const context = await browser.newContext();
  const page = await context.newPage();
  await page.route(attackUrl, (route) =>
    route.fulfill({ status: 200, contentType: 'text/html', body: ATTACKER_PAGE }));
  await page.goto(attackUrl);
  const attack = await page.evaluate(() => window.attack);

  // The name reached the robot (else this test would prove nothing) and was refused.
  const host = new URL(attackUrl).host;
  assert.equal(attack.api.status, 421, `/api/model: ${JSON.stringify(attack.api)}`);
  assert.ok(attack.api.body.includes(host) && attack.api.body.includes('allowed_hosts'), attack.api.body);
  assert.ok(!attack.ws.includes('open'), `the WebSocket opened: ${JSON.stringify(attack.ws)}`);
  assert.ok(attack.ws.includes('error'), `the WebSocket was refused: ${JSON.stringify(attack.ws)}`);
  await context.close();

  const after = await armState();
  assert.equal(after.mode, before.mode, 'the mode is unchanged');
  assert.deepEqual(after.calibrated, before.calibrated, 'the calibration is unchanged');
  assert.ok(maxDiff(after.position, before.position) < 0.01,
    `the arm moved from ${before.position} to ${after.position}`);
});

test("the pendant's own page still connects by the robot's address", { timeout: 60000 }, async () => {
  const page = await openPendant(browser, env('MCM_OWN_URL'));
  await page.close();
});
