// N WebSockets that only take the pendant's state frames, in a process of their own without a
// browser (for `bench-pendant.mjs --sockets`): node's own WebSocket client, an implementation
// other than the gateway's. Prints one JSON line of figures when it gets SIGTERM.
//   node --experimental-websocket bench-sockets.mjs HOST:PORT N

const [addr, n] = [process.argv[2], Number(process.argv[3])];
const t0 = Date.now();
let frames = 0;
const latencies = [];
const sockets = [];
for (let i = 0; i < n; i++) {
  // A browser's page sends its origin; the gateway accepts its own.
  const ws = new WebSocket(`ws://${addr}/ws`, { headers: { origin: `http://${addr}` } });
  ws.onmessage = (e) => {
    const m = JSON.parse(e.data);
    if (m.stream !== 'state') return;
    frames++;
    latencies.push(Date.now() - m.cycle_unix_ms);
  };
  sockets.push(ws);
}
process.stdout.write('open\n');
process.on('SIGTERM', () => {
  const s = latencies.sort((a, b) => a - b);
  const q = (x) => s[Math.min(s.length - 1, Math.floor(x * s.length))];
  const seconds = (Date.now() - t0) / 1000;
  process.stdout.write(`${JSON.stringify({ frames_per_socket_s: frames / n / seconds, p50: q(0.5), p99: q(0.99), max: s[s.length - 1], n: s.length })}\n`);
  process.exit(0);
});
