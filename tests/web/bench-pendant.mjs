// Benchmark of the browser pendant (docs/performance.md, "Browser pendant"); not a test, not
// run in CI. It starts the MCM (simulated arm) itself and measures, first without pages, then
// with N pages open in headless Chromium:
//   - the gateway's CPU over S seconds (utime + stime of /proc/<gateway pid>/stat),
//   - the JSON `status` round trip (10000 requests one after the other on one connection),
//   - with pages: each page's display latency (`window.mcmPendant.latencies`: Date.now() minus
//     the cycle's `cycle_unix_ms` when a frame is shown), p50/p99/max over all pages.
//
// From the repository's root, after `cargo test --test end_to_end web::` has installed the node
// packages beside a copy of these scripts in target/tmp/web-node:
//   cargo build --release
//   cp tests/web/*.mjs target/tmp/web-node/
// node target/tmp/web-node/bench-pendant.mjs [--mcm target/release/mcm] [--pages 10] [--seconds 60]
// [--moving] --moving: the arm is calibrated first and axis 1 sweeps back and forth (velocity
// control, 30 deg/s) through every measurement, so that the pages draw a moving arm.

import { spawn, execFileSync } from 'node:child_process';
import { readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { createServer } from 'node:net';
import path from 'node:path';
import { chromium } from 'playwright-core';
import { JsonClient, waitUntil } from './lib.mjs';

const opt = (name, dflt) => {
  const i = process.argv.indexOf(`--${name}`);
  return i > 0 ? process.argv[i + 1] : dflt;
};
const mcmBinary = path.resolve(opt('mcm', 'target/release/mcm'));
const pages = Number(opt('pages', 10));
const seconds = Number(opt('seconds', 60));
const chromiumPath = opt('chromium', process.env.MCM_CHROMIUM ?? '/usr/bin/chromium');
const rttSamples = 10000;
const moving = process.argv.includes('--moving');
// --sockets: instead of N pendant pages in Chromium, N WebSockets that only take the frames, in
// a node process of their own (bench-sockets.mjs): the gateway's cost of N pages without N
// browsers rendering on the same two CPUs (on a robot the browsers run on other machines).
const socketsOnly = process.argv.includes('--sockets');

/// Calibrate, then sweep axis 1 at +-30 deg/s (velocity control, a new direction every 2 s)
/// until `stop()`; over its own JSON connection.
async function sweep(addr) {
  const c = await JsonClient.connect(addr);
  const cal = await c.request('calibrate', undefined, 120000);
  if (cal.error_status !== 'OK') throw new Error(`calibrate: ${JSON.stringify(cal)}`);
  const vc = await c.request('velocity_control', { timeout: 0.5, dt_status: 0 });
  if (vc.operating_mode !== 'VELOCITY_CONTROL') throw new Error(`velocity_control: ${JSON.stringify(vc)}`);
  let running = true;
  const t0 = Date.now();
  const timer = setInterval(() => {
    if (!running) return;
    const dir = Math.floor((Date.now() - t0) / 2000) % 2 === 0 ? 1 : -1;
    c.sock.write(`${JSON.stringify({ command: 'set_velocities', arguments: { velocities: [30 * dir, 0, 0, 0, 0, 0] } })}\n`);
  }, 50);
  return async () => {
    running = false;
    clearInterval(timer);
    await c.request('hold');
    c.close();
  };
}

const freePort = () => new Promise((resolve) => {
  const s = createServer().listen(0, '127.0.0.1', () => {
    const { port } = s.address();
    s.close(() => resolve(port));
  });
});

const quantile = (xs, q) => {
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.min(s.length - 1, Math.floor(q * s.length))];
};
const fmt = (ms) => (ms < 1 ? `${(ms * 1000).toFixed(0)} µs` : `${ms.toFixed(2)} ms`);
const summary = (xs) => `p50 ${fmt(quantile(xs, 0.5))}, p99 ${fmt(quantile(xs, 0.99))}, max ${fmt(Math.max(...xs))} (n=${xs.length})`;

/// The MCM, started with its page on a free port; its ready line's addresses and pids.
async function startMcm() {
  const httpPort = await freePort();
  const instance = `bench-web-${process.pid}`;
  const child = spawn(mcmBinary, ['--instance', instance, '--bind', '127.0.0.1', '--json-port', '0',
    '--hmi-port', '0', '--http-port', String(httpPort)], { stdio: ['ignore', 'pipe', 'inherit'] });
  let out = '';
  const ready = await new Promise((resolve, reject) => {
    const t = setTimeout(() => reject(new Error(`no ready line from ${mcmBinary} within 30 s`)), 30000);
    child.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/json=(\S+) .*web=(\S+) .*gateway_pid=(\d+)/);
      if (m) {
        clearTimeout(t);
        resolve({ json: m[1], web: `http://${m[2]}/`, gatewayPid: Number(m[3]) });
      }
    });
    child.on('exit', (c) => reject(new Error(`${mcmBinary} exited (${c}) before its ready line`)));
  });
  return { child, instance, ...ready };
}

/// The gateway's CPU time [s] so far.
function cpuSeconds(pid) {
  const stat = readFileSync(`/proc/${pid}/stat`, 'utf8');
  const f = stat.slice(stat.lastIndexOf(')') + 2).split(' ');
  const ticks = Number(execFileSync('getconf', ['CLK_TCK'], { encoding: 'utf8' }));
  return (Number(f[11]) + Number(f[12])) / ticks; // fields 14 and 15: utime, stime
}

async function gatewayCpu(pid) {
  const c0 = cpuSeconds(pid);
  const t0 = process.hrtime.bigint();
  await new Promise((r) => setTimeout(r, seconds * 1000));
  const wall = Number(process.hrtime.bigint() - t0) / 1e9;
  return (100 * (cpuSeconds(pid) - c0)) / wall;
}

async function statusRtt(json) {
  for (let i = 0; i < 50; i++) await json.request('status');
  const xs = [];
  for (let i = 0; i < rttSamples; i++) {
    const t0 = process.hrtime.bigint();
    await json.request('status');
    xs.push(Number(process.hrtime.bigint() - t0) / 1e6);
  }
  return xs;
}

const mcm = await startMcm();
let browser;
try {
  const json = await JsonClient.connect(mcm.json);
  const stopSweep = moving ? await sweep(mcm.json) : null;
  if (moving) console.log('the arm is calibrated; axis 1 sweeps at 30 deg/s through the measurements');
  console.log(`MCM ${mcm.instance}: page ${mcm.web}, JSON ${mcm.json}, gateway pid ${mcm.gatewayPid}; ${pages} pages, ${seconds} s windows`);
  const idleCpu = await gatewayCpu(mcm.gatewayPid);
  console.log(`without pages: gateway CPU ${idleCpu.toFixed(1)} % of one core over ${seconds} s`);
  const rttAlone = await statusRtt(json);
  console.log(`without pages: status round trip ${summary(rttAlone)}`);

  if (socketsOnly) {
    // At the lowest priority (nice 19): they stand in for browsers on other machines, so
    // their own CPU time must not delay the measuring client on these two CPUs.
    const child = spawn('nice', ['-n', '19', process.execPath, '--experimental-websocket', path.join(path.dirname(new URL(import.meta.url).pathname), 'bench-sockets.mjs'),
      new URL(mcm.web).host, String(pages)], { stdio: ['ignore', 'pipe', 'ignore'] });
    let out = '';
    child.stdout.on('data', (d) => { out += d; });
    await waitUntil('the sockets to open', 10000, async () => out.includes('open'), 20);
    await new Promise((r) => setTimeout(r, 2000));
    const cpu = await gatewayCpu(mcm.gatewayPid);
    const rtt = await statusRtt(json);
    child.kill('SIGTERM');
    await waitUntil('the sockets\' figures', 10000, async () => out.trim().split('\n').length > 1, 20);
    const f = JSON.parse(out.trim().split('\n').pop());
    console.log(`with ${pages} sockets: gateway CPU ${cpu.toFixed(1)} % of one core over ${seconds} s; frames per socket ${f.frames_per_socket_s.toFixed(1)} /s`);
    console.log(`with ${pages} sockets: status round trip ${summary(rtt)}`);
    console.log(`with ${pages} sockets: frame age when taken p50 ${f.p50.toFixed(2)} ms, p99 ${f.p99.toFixed(2)} ms, max ${f.max.toFixed(2)} ms (n=${f.n})`);
  }
  if (!socketsOnly) {
    browser = await chromium.launch({
      executablePath: chromiumPath,
      args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
        '--disable-background-networking', '--disable-component-update', '--disable-sync'],
    });
    const open = [];
    for (let i = 0; i < pages; i++) {
      // One context each: every page is a foreground tab of its own window.
      const p = await (await browser.newContext({ viewport: { width: 1280, height: 900 } })).newPage();
      await p.goto(mcm.web);
      open.push(p);
    }
    for (const p of open) {
      await p.waitForFunction(() => window.mcmPendant?.connected && window.mcmPendant.frames > 10, null, { timeout: 30000 });
    }
    // The first page's weight on the wire (compressed, headers included: the browser's
    // `transferSize` of the page and every resource it loaded) and its first contentful paint.
    const first = await open[0].evaluate(() => {
      const nav = performance.getEntriesByType('navigation')[0];
      const res = performance.getEntriesByType('resource');
      const fcp = performance.getEntriesByName('first-contentful-paint')[0];
      return {
        bytes: nav.transferSize + res.reduce((a, r) => a + r.transferSize, 0),
        decoded: nav.decodedBodySize + res.reduce((a, r) => a + r.decodedBodySize, 0),
        files: res.length + 1,
        fcp: fcp ? fcp.startTime : null,
      };
    });
    console.log(`first page: ${first.files} files, ${(first.bytes / 1024).toFixed(0)} KiB on the wire (${(first.decoded / 1024).toFixed(0)} KiB decoded), first contentful paint ${first.fcp?.toFixed(0)} ms after navigation`);
    // Only the window's frames count: not those of the pages' start (loading, compiling the 3D
    // view's shaders).
    await Promise.all(open.map((p) => p.evaluate(() => { window.mcmPendant.latencies.length = 0; })));
    const framesBefore = await Promise.all(open.map((p) => p.evaluate(() => window.mcmPendant.frames)));
    const pagesCpu = await gatewayCpu(mcm.gatewayPid);
    const framesAfter = await Promise.all(open.map((p) => p.evaluate(() => window.mcmPendant.frames)));
    const rate = framesAfter.map((f, i) => (f - framesBefore[i]) / seconds);
    console.log(`with ${pages} pages: gateway CPU ${pagesCpu.toFixed(1)} % of one core over ${seconds} s; frames per page ${Math.min(...rate).toFixed(1)}..${Math.max(...rate).toFixed(1)} /s`);
    const rttPages = await statusRtt(json);
    console.log(`with ${pages} pages: status round trip ${summary(rttPages)}`);
    const lat = (await Promise.all(open.map((p) => p.evaluate(() => window.mcmPendant.latencies)))).flat();
    console.log(`with ${pages} pages: display latency ${summary(lat)}`);
  }
  const load = readFileSync('/proc/loadavg', 'utf8').split(' ').slice(0, 3).join(' ');
  console.log(`load average at the end: ${load}`);
  if (stopSweep) await stopSweep();
  json.close();
} finally {
  await browser?.close();
  mcm.child.kill('SIGTERM');
  await waitUntil('the MCM to stop', 30000, async () => mcm.child.exitCode !== null || mcm.child.signalCode !== null, 50);
  rmSync(path.join(tmpdir(), `mcm-sim-${mcm.instance}.state`), { force: true });
}
