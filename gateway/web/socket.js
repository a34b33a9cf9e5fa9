// The page's WebSocket to the gateway (`/ws`): reconnects every second, sends one command at a
// time and matches each reply to it (the protocol has no request ids: replies come in the
// order of the commands), and tells spontaneous results and state frames apart.

import { ERROR_CODES } from './codes.js';

const RECONNECT_MS = 1000;

export function wsUrl(path) {
  const proto = location.protocol === 'https:' ? 'wss:' : 'ws:';
  return `${proto}//${location.host}${path}`;
}

/** A result no command of ours asked for, or `null` when it answers `inFlight`. */
export function spontaneousKind(msg, inFlight) {
  if (msg.check !== undefined) return 'safety';
  if (msg.result_type === 'generic' && msg.error_status === 'ERROR') {
    // `set_velocities` answers nothing on success: its refusal names it in `command`.
    if (msg.command === 'set_velocities') return 'set_velocities';
    // Generic ERROR results that no command asked for: the core or the gateway stopping, a
    // timeout or an eviction of this connection.
    if (ERROR_CODES[msg.error_code]?.spontaneous) return 'notice';
  }
  if (msg.result_type === 'status') {
    if (!inFlight) return 'status';
    // Our status commands ask for the detail; a session's status carries none.
    if (inFlight.cmd.command === 'status' && msg.detail === undefined) return 'status';
  }
  if (!inFlight) return msg.result_type === 'generic' ? 'notice' : 'status';
  return null;
}

export class Connection {
  /**
   * handlers: onFrame(frame), onSpontaneous(kind, msg), onReply(cmd, msg),
   * onConnected(bool).
   */
  constructor(handlers) {
    this.h = handlers;
    this.ws = null;
    this.connected = false;
    this.queue = []; // {cmd, resolve, reject} not yet sent
    this.inFlight = null; // {cmd, resolve, reject, sentAt}
    this.timer = null;
    this.open();
  }

  open() {
    clearTimeout(this.timer);
    let ws;
    try {
      ws = new WebSocket(wsUrl('/ws'));
    } catch (e) {
      this.timer = setTimeout(() => this.open(), RECONNECT_MS);
      return;
    }
    this.ws = ws;
    ws.onopen = () => {
      this.connected = true;
      this.h.onConnected(true);
      this.pump();
    };
    ws.onmessage = (ev) => this.receive(ev.data);
    ws.onclose = () => this.closed(ws);
    ws.onerror = () => {}; // onclose follows and reconnects
  }

  closed(ws) {
    if (ws !== this.ws) return;
    this.ws = null;
    const was = this.connected;
    this.connected = false;
    const lost = new Error('the connection to the robot was lost');
    if (this.inFlight) this.inFlight.reject(lost);
    this.inFlight = null;
    for (const q of this.queue.splice(0)) q.reject(lost);
    if (was) this.h.onConnected(false);
    this.timer = setTimeout(() => this.open(), RECONNECT_MS);
  }

  receive(text) {
    let msg;
    try {
      msg = JSON.parse(text);
    } catch (e) {
      console.warn('not JSON from /ws:', text.slice(0, 200));
      return;
    }
    if (msg.stream === 'state') {
      this.h.onFrame(msg);
      return;
    }
    const kind = spontaneousKind(msg, this.inFlight);
    if (kind) {
      this.h.onSpontaneous(kind, msg);
      return;
    }
    const done = this.inFlight;
    this.inFlight = null;
    this.h.onReply(done.cmd, msg);
    done.resolve(msg);
    this.pump();
  }

  rawSend(cmd) {
    if (!this.ws || this.ws.readyState !== WebSocket.OPEN) return false;
    this.ws.send(JSON.stringify(cmd));
    return true;
  }

  pump() {
    if (this.inFlight || !this.connected) return;
    const next = this.queue.shift();
    if (!next) return;
    if (!this.rawSend(next.cmd)) {
      next.reject(new Error('not connected to the robot'));
      this.pump();
      return;
    }
    next.sentAt = performance.now();
    this.inFlight = next;
  }

  /** Send a command that gets one reply; resolves with it. */
  request(cmd, { front = false } = {}) {
    return new Promise((resolve, reject) => {
      if (!this.connected) {
        reject(new Error('not connected to the robot'));
        return;
      }
      const item = { cmd, resolve, reject };
      if (front) this.queue.unshift(item);
      else this.queue.push(item);
      this.pump();
    });
  }

  /** Send a command that gets no reply on success (`set_velocities`). */
  fire(cmd) {
    return this.rawSend(cmd);
  }

  /** Whether a command of `name` is queued or in flight. */
  has(name) {
    return (
      (this.inFlight && this.inFlight.cmd.command === name) ||
      this.queue.some((q) => q.cmd.command === name)
    );
  }

  /** Drop the queued (unsent) commands other than `status`: `hold` overrides them. */
  dropQueuedMotion(why) {
    const keep = [];
    for (const q of this.queue) {
      if (q.cmd.command === 'status') keep.push(q);
      else q.reject(new Error(why));
    }
    this.queue = keep;
  }

  /**
   * `hold`, ahead of everything queued. The gateway runs a connection's commands one after
   * the other, so while a command of ours is still running (a `calibrate` takes about 12 s)
   * a `hold` on this socket would wait behind it: then it goes out on a second, short-lived
   * socket at once (`hold` is open to every client).
   */
  hold() {
    this.dropQueuedMotion('cancelled by hold');
    const busy = this.inFlight && this.inFlight.cmd.command !== 'status';
    if (this.connected && !busy) {
      return this.request({ command: 'hold' }, { front: true });
    }
    return sendOnce({ command: 'hold' });
  }
}

/** One command on a socket of its own; resolves with its reply, then closes the socket. */
export function sendOnce(cmd, timeoutMs = 5000) {
  return new Promise((resolve, reject) => {
    let ws;
    try {
      ws = new WebSocket(wsUrl('/ws'));
    } catch (e) {
      reject(e);
      return;
    }
    const timer = setTimeout(() => {
      ws.close();
      reject(new Error(`no reply to ${cmd.command} within ${timeoutMs / 1000} s`));
    }, timeoutMs);
    ws.onopen = () => ws.send(JSON.stringify(cmd));
    ws.onmessage = (ev) => {
      let msg;
      try {
        msg = JSON.parse(ev.data);
      } catch (e) {
        return;
      }
      if (msg.stream === 'state' || msg.check !== undefined) return;
      clearTimeout(timer);
      ws.close();
      resolve(msg);
    };
    ws.onerror = () => {
      clearTimeout(timer);
      reject(new Error(`could not open a connection for ${cmd.command}`));
    };
  });
}
