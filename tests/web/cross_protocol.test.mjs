// HTTP from any web page to the JSON and telnet HMI ports (docs/security.md): a page served from
// another origin (a port of its own here) sends `fetch(port, {method: 'POST', mode: 'no-cors',
// body})` with `calibrate` and `release` lines in the body to each port; the arm, OFF and
// uncalibrated, stays so. A control first: the same fetch to a plain TCP listener of this script
// arrives there with its body, so the browser does send it.
// Run by tests/end_to_end/web.rs (web::cross_protocol_requests_from_a_page_in_chromium), which
// passes MCM_JSON, MCM_HMI (the ports, host:port) and MCM_CHROMIUM; see lib.mjs.

import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import http from 'node:http';
import net from 'node:net';
import { env, launchBrowser, JsonClient, waitUntil } from './lib.mjs';

let browser;
let json;
let site;
let page;

/// Listen on a free loopback port; its `host:port`.
function listen(server) {
  return new Promise((resolve) => {
    server.listen(0, '127.0.0.1', () => resolve(`127.0.0.1:${server.address().port}`));
  });
}

before(async () => {
  browser = await launchBrowser();
  json = await JsonClient.connect(env('MCM_JSON'));
  // The attacker's page: any origin other than the robot's ports.
  site = http.createServer((req, res) => {
    res.writeHead(200, { 'content-type': 'text/html' });
    res.end('<!doctype html><title>any page</title><p>any page</p>');
  });
  const origin = await listen(site);
  page = await browser.newPage();
  await page.goto(`http://${origin}/`);
});

after(async () => {
  json?.close();
  await browser?.close();
  site?.close();
});

/// From the page: the no-cors POST of `body` to `addr`, given up after 5 s when no answer
/// comes; how it ended, in words.
async function postFromPage(addr, body) {
  return page.evaluate(async ([url, text]) => {
    try {
      const r = await fetch(url, {
        method: 'POST', mode: 'no-cors', body: text, signal: AbortSignal.timeout(5000),
      });
      return `answered (${r.type})`;
    } catch (e) {
      return `failed: ${e}`;
    }
  }, [`http://${addr}/`, body]);
}

/// The arm is OFF and uncalibrated, and stays so for `seconds` of robot time.
async function assertUntouched(seconds, what) {
  const s0 = await json.status();
  const t0 = s0.axis_states.time[0];
  await waitUntil(`${seconds} s of robot time (${what})`, 10000 + seconds * 1000, async () => {
    const s = await json.status();
    assert.equal(s.operating_mode, 'OFF', `${what}: the mode is now ${s.operating_mode}`);
    assert.equal(s.detail.all_calibrated, false, `${what}: the arm was calibrated`);
    assert.ok(!s.detail.calibrated.some((c) => c), `${what}: an axis was calibrated: ${s.detail.calibrated}`);
    return s.axis_states.time[0] - t0 >= seconds;
  });
}

test('the arm starts OFF and uncalibrated', async () => {
  await assertUntouched(0, 'before any request');
});

test('control: the page can POST its body to any TCP port', async () => {
  let received = '';
  const sink = net.createServer((sock) => {
    sock.on('data', (d) => {
      received += d;
      if (received.includes('body-line')) sock.destroy();
    });
    sock.on('error', () => {});
  });
  const addr = await listen(sink);
  try {
    const outcome = await postFromPage(addr, '\nbody-line\n');
    await waitUntil('the body at the plain listener', 10000, async () => received.includes('body-line'));
    assert.match(received, /^POST \/ HTTP\/1\.1\r\n/, `received ${JSON.stringify(received)} (${outcome})`);
  } finally {
    sink.close();
  }
});

test('a POST from the page to the JSON port runs nothing', async () => {
  const outcome = await postFromPage(env('MCM_JSON'), '\n{"command":"calibrate"}\n{"command":"release"}\n');
  await assertUntouched(1, `after the POST to the JSON port (${outcome})`);
});

test('a POST from the page to the telnet port runs nothing', async () => {
  const outcome = await postFromPage(env('MCM_HMI'), '\ncalibrate\r\nrelease\r\n');
  await assertUntouched(1, `after the POST to the HMI port (${outcome})`);
});
