// Shared by the browser tests of the pendant (run by tests/end_to_end/web.rs): Chromium through
// playwright-core, a JSON-protocol client for the simulation's truth, bounded waits, the
// screenshots for docs/web.md, the arm's forward kinematics and the angle between two
// orientations.
//
// What the Rust side passes in the environment:
//   MCM_WEB_URL          the pendant's page, e.g. http://127.0.0.1:40123/
//   MCM_JSON             the JSON port, host:port
//   MCM_GATEWAY_PID      the gateway's pid (the reconnect test kills it; the launcher restarts it)
//   MCM_CHROMIUM         the Chromium binary
//   MCM_SCREENSHOT_DIR   where to write the PNGs of docs/web.md (unset: none are written)

import { chromium } from 'playwright-core';
import { after } from 'node:test';
import net from 'node:net';
import path from 'node:path';
import { setTimeout as delay } from 'node:timers/promises';

export function env(name) {
  const v = process.env[name];
  if (!v) throw new Error(`${name} is not set: run these scripts through tests/end_to_end/web.rs (cargo test --test end_to_end web::)`);
  return v;
}

/// Chromium as root on a closed network: no sandbox, no GPU, none of the background
/// connections it would otherwise open (docs/web.md, "Tests"); `extraArgs` added.
export async function launchBrowser(extraArgs = []) {
  return chromium.launch({
    executablePath: env('MCM_CHROMIUM'),
    headless: true,
    args: [
      '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      ...extraArgs,
    ],
  });
}

/// For a file of tests, awaited at its top: Chromium (with `extraArgs`) and a JSON client of the
/// MCM, both closed by `after` hooks once the file's tests have run.
export async function browserAndJson(extraArgs = []) {
  const browser = await launchBrowser(extraArgs);
  after(() => browser.close());
  const json = await JsonClient.connect(env('MCM_JSON'));
  after(() => json.close());
  return { browser, json };
}

/// Poll `probe()` (async) until it returns a truthy value, at most `ms`; that value. The poll
/// interval only paces the polling: every wait is bounded and says what it waited for.
export async function waitUntil(what, ms, probe, every = 10) {
  const deadline = Date.now() + ms;
  let last;
  for (;;) {
    last = await probe();
    if (last) return last;
    if (Date.now() > deadline) throw new Error(`timed out after ${ms} ms waiting for ${what}`);
    await delay(every);
  }
}

/// A JSON-protocol client over TCP (docs/protocol.md): one command at a time; spontaneous
/// safety errors (they carry `check`) are kept apart in `events`.
export class JsonClient {
  static connect(addr) {
    const [host, port] = [addr.slice(0, addr.lastIndexOf(':')), Number(addr.slice(addr.lastIndexOf(':') + 1))];
    return new Promise((resolve, reject) => {
      const sock = net.connect({ host, port }, () => resolve(new JsonClient(sock)));
      sock.once('error', reject);
    });
  }

  constructor(sock) {
    this.sock = sock;
    this.buf = '';
    this.results = [];
    this.events = [];
    this.waiter = null;
    this.closed = false;
    sock.setNoDelay(true);
    sock.setEncoding('utf8');
    sock.on('data', (d) => {
      this.buf += d;
      let i;
      while ((i = this.buf.indexOf('\n')) >= 0) {
        const v = JSON.parse(this.buf.slice(0, i));
        this.buf = this.buf.slice(i + 1);
        (v.check !== undefined ? this.events : this.results).push(v);
      }
      this.wake();
    });
    sock.on('close', () => { this.closed = true; this.wake(); });
    sock.on('error', () => {});
  }

  wake() {
    const w = this.waiter;
    this.waiter = null;
    if (w) w();
  }

  /// Wait (at most `ms`) until `ready()` holds, woken by each line.
  async until(what, ms, ready) {
    const deadline = Date.now() + ms;
    while (!ready()) {
      if (this.closed) throw new Error(`the JSON connection closed while waiting for ${what}`);
      const left = deadline - Date.now();
      if (left <= 0) throw new Error(`no ${what} within ${ms} ms`);
      await new Promise((resolve) => {
        const t = setTimeout(resolve, left);
        this.waiter = () => { clearTimeout(t); resolve(); };
      });
    }
  }

  async request(command, args, ms = 10000) {
    const line = JSON.stringify(args === undefined ? { command } : { command, arguments: args });
    this.sock.write(line + '\n');
    await this.until(`a result for ${line}`, ms, () => this.results.length > 0);
    return this.results.shift();
  }

  /// The simulation's ground truth: true joint angles [deg] and velocities [deg/s].
  async truth() {
    const r = await this.request('sim');
    if (r.result_type !== 'sim') throw new Error(`sim: ${JSON.stringify(r)}`);
    return { position: r.true_position, velocity: r.true_velocity };
  }

  async status() {
    const s = await this.request('status', { detail: true });
    if (s.result_type !== 'status') throw new Error(`status: ${JSON.stringify(s)}`);
    return s;
  }

  /// The robot's clock of the newest state [s].
  async robotTime() {
    return (await this.status()).axis_states.time[0];
  }

  /// The next spontaneous safety error not taken yet, at most `ms`.
  async event(ms = 10000) {
    await this.until('a spontaneous safety error', ms, () => this.events.length > 0);
    return this.events.shift();
  }

  /// Poll the truth until `done(truth)`; the truth then.
  async waitTruth(what, ms, done) {
    let last;
    try {
      return await waitUntil(what, ms, async () => {
        last = await this.truth();
        return done(last) ? last : null;
      });
    } catch (e) {
      throw new Error(`${e.message}; last truth ${JSON.stringify(last)}`);
    }
  }

  /// Wait until the arm is at rest on the truth (every true velocity below `eps` deg/s); the
  /// robot's time when that was seen.
  async waitAtRest(what, ms, eps = 0.01) {
    const t = await this.waitTruth(what, ms, (t) => maxAbs(t.velocity) < eps);
    return { truth: t, time: await this.robotTime() };
  }

  close() {
    this.sock.destroy();
  }
}

export const maxAbs = (v) => v.reduce((m, x) => Math.max(m, Math.abs(x)), 0);
export const maxDiff = (a, b) => a.reduce((m, x, i) => Math.max(m, Math.abs(x - b[i])), 0);

/// A new tab on the pendant, connected and receiving state frames.
export async function openPendant(browser, url = env('MCM_WEB_URL')) {
  const page = await browser.newPage({ viewport: { width: 1400, height: 1000 } });
  const log = [];
  page.on('console', (m) => log.push(`${m.type()}: ${m.text()}`));
  page.on('pageerror', (e) => log.push(`pageerror: ${e.message}`));
  page.pendantLog = log;
  await page.goto(url);
  await waitFrames(page, 'the page connected and receiving state frames', 30000);
  return page;
}

/// Wait until the page is connected and has received frames (more than it had when asked,
/// by at least `more`).
export async function waitFrames(page, what, ms, more = 3) {
  const before = await page.evaluate(() => window.mcmPendant?.frames ?? 0);
  try {
    await page.waitForFunction(
      ([n]) => window.mcmPendant?.connected === true && window.mcmPendant.frames >= n,
      [before + more], { timeout: ms, polling: 20 });
  } catch (e) {
    throw new Error(`${what}: ${e.message}\npage log:\n${page.pendantLog?.join('\n')}`);
  }
}

/// Wait until `#mode` reads `mode`.
export async function waitMode(page, mode, ms) {
  try {
    await page.waitForFunction(
      (m) => document.querySelector('#mode')?.textContent.trim() === m, mode,
      { timeout: ms, polling: 20 });
  } catch (e) {
    const now = await page.evaluate(() => document.querySelector('#mode')?.textContent);
    throw new Error(`#mode did not become ${mode} within ${ms} ms (it reads ${JSON.stringify(now)}): ${e.message}`);
  }
}

/// The joint table: per axis 1..6 the cells' texts.
export async function jointTable(page) {
  return page.evaluate(() => [1, 2, 3, 4, 5, 6].map((a) => {
    const row = document.querySelector(`#joints tbody tr[data-axis="${a}"]`);
    const cell = (c) => row?.querySelector(`.${c}`)?.textContent.trim() ?? null;
    return { name: cell('name'), pos: cell('pos'), vel: cell('vel'), cur: cell('cur'), cal: cell('cal') };
  }));
}

/// Take the keyboard focus away from form fields and buttons (as a click on the page's
/// background would), so that digits and arrows reach the jog keys.
export async function blur(page) {
  await page.evaluate(() => document.activeElement?.blur?.());
}

/// Set a form field, whether it is a select or an input.
export async function setField(page, selector, value) {
  const tag = await page.$eval(selector, (e) => e.tagName);
  if (tag === 'SELECT') await page.selectOption(selector, String(value));
  else await page.fill(selector, String(value));
}

/// A screenshot for docs/web.md, when asked for (MCM_SCREENSHOT_DIR).
export async function screenshot(page, name) {
  const dir = process.env.MCM_SCREENSHOT_DIR;
  if (!dir) return;
  await page.screenshot({ path: path.join(dir, `${name}.png`) });
}

const mul4 = (a, b) => a.map((row) => b[0].map((_, j) => row.reduce((s, x, k) => s + x * b[k][j], 0)));

/// The flange's pose (a 4x4 matrix, metres) for joint angles `q_deg` and the standard DH links
/// of /api/model: frame i = frame i-1 * RotZ(q_i + offset_i) * TransZ(d_i) * TransX(a_i) * RotX(alpha_i).
export function flangeMatrix(links, qDeg) {
  let m = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]];
  links.forEach((l, i) => {
    const th = ((qDeg[i] + l.offset_deg) * Math.PI) / 180;
    const al = (l.alpha_deg * Math.PI) / 180;
    const [ct, st, ca, sa] = [Math.cos(th), Math.sin(th), Math.cos(al), Math.sin(al)];
    m = mul4(m, [
      [ct, -st * ca, st * sa, l.a * ct],
      [st, ct * ca, -ct * sa, l.a * st],
      [0, sa, ca, l.d],
      [0, 0, 0, 1],
    ]);
  });
  return m;
}

/// The flange's position [m] (of [`flangeMatrix`]).
export function flange(links, qDeg) {
  const m = flangeMatrix(links, qDeg);
  return [m[0][3], m[1][3], m[2][3]];
}

/// The TCP for joint angles `q_deg`, the tool's `tcp` ({position [m], orientation [x, y, z, w]}
/// in the flange frame, as `detail.tool.tcp`): its position [m] and the columns of its
/// rotation (its x, y and z axes in the base frame).
export function tcpOf(links, qDeg, tcp) {
  const [x, y, z, w] = tcp.orientation;
  const [px, py, pz] = tcp.position;
  const t = [
    [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w), px],
    [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w), py],
    [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y), pz],
    [0, 0, 0, 1],
  ];
  const m = mul4(flangeMatrix(links, qDeg), t);
  const column = (j) => [m[0][j], m[1][j], m[2][j]];
  return { position: column(3), axes: [column(0), column(1), column(2)] };
}

/// The angle [deg] between two orientations written as quaternions [x, y, z, w] (q and -q are
/// one rotation), as tests/common/mod.rs's `orientation_angle`: each is normalised first (the
/// protocol's figures are rounded, so their norm is 1 only to about 1e-6), and the angle is
/// taken with `atan2` of the relative rotation's vector and scalar parts: `acos` of a dot
/// product near 1 would turn that rounding into hundredths of a degree.
export function orientationAngleDeg(a, b) {
  const unit = (q) => {
    const n = Math.hypot(...q);
    return q.map((v) => v / n);
  };
  const [[ax, ay, az, aw], [bx, by, bz, bw]] = [unit(a), unit(b)];
  // conj(a) * b: the rotation from a to b.
  const w = aw * bw + ax * bx + ay * by + az * bz;
  const v = Math.hypot(
    aw * bx - bw * ax - (ay * bz - az * by),
    aw * by - bw * ay - (az * bx - ax * bz),
    aw * bz - bw * az - (ax * by - ay * bx),
  );
  return (2 * Math.atan2(v, Math.abs(w)) * 180) / Math.PI;
}

/// Steps that depend on the ones before: once one fails, the later ones fail at once, naming
/// it, instead of each waiting out its own timeout on an arm in an unknown state.
export class Sequence {
  constructor() { this.failed = null; }
  wrap(name, fn) {
    return async (t) => {
      if (this.failed) throw new Error(`not run: the earlier step "${this.failed}" failed`);
      try {
        await fn(t);
      } catch (e) {
        this.failed = name;
        throw e;
      }
    };
  }
}
