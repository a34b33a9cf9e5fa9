// Jogging under the dead-man rule: the arm moves only while a jog button is held down (or an
// arrow key, after choosing the axis with 1..6). `velocity_control` (timeout 0.2 s) once, then
// every 50 ms `set_velocities` (an axis) or `set_cartesian_velocity` (the TCP along or about
// x, y or z of the base or the tool frame); on release, blur, a hidden page or a lost socket:
// zeros, then `hold`. If the messages stop for any reason the core's 0.2 s timeout stops the
// arm itself.

export const JOG_PERIOD_MS = 50;
export const JOG_TIMEOUT_S = 0.2;

/** The TCP's jog directions: along x, y, z (linear) and about them (angular). */
export const TCP_DIRECTIONS = ['x', 'y', 'z', 'rx', 'ry', 'rz'];

/** The `set_cartesian_velocity` arguments of a TCP jog of `target` (one of TCP_DIRECTIONS) in
 * `dir` (+1/-1, 0 for none): `linearMmS` [mm/s] along, `angularDegS` [deg/s] about, in `frame`. */
export function cartesianVelocity(target, dir, { linearMmS, angularDegS, frame }) {
  const linear = [0, 0, 0];
  const angular = [0, 0, 0];
  const i = TCP_DIRECTIONS.indexOf(target);
  if (i >= 0 && i < 3) linear[i] = Math.round(dir * linearMmS * 1000) / 1e6;
  else if (i >= 3) angular[i - 3] = Math.round(dir * angularDegS * 1000) / 1000;
  return { linear, angular, frame };
}

export class Jogger {
  /**
   * conn: the Connection; maxVelocity(axis) -> deg/s; speed() -> fraction 0.05..1;
   * tcp() -> {linearMmS, angularDegS, frame} of a TCP jog; onError(text); onChange(active|null).
   */
  constructor(conn, { maxVelocity, speed, tcp, onError, onChange }) {
    this.conn = conn;
    this.maxVelocity = maxVelocity;
    this.speed = speed;
    this.tcp = tcp;
    this.onError = onError;
    this.onChange = onChange;
    this.active = null; // {axis, dir, source}: axis 1..6, or a TCP direction ('x' .. 'rz')
    this.session = false; // our VELOCITY_CONTROL is running
    this.entering = false; // velocity_control sent, no reply yet
    this.timer = null;
  }

  /** Start jogging `axis` (1..6, or a TCP direction of TCP_DIRECTIONS) in `dir` (+1/-1);
   * `source` says who holds it (pointer, key). */
  start(axis, dir, source) {
    if (this.active && this.active.axis === axis && this.active.dir === dir) return;
    this.active = { axis, dir, source };
    this.onChange(this.active);
    if (this.session) {
      this.beat();
      return;
    }
    if (this.entering) return;
    this.entering = true;
    this.conn
      .request({ command: 'velocity_control', arguments: { timeout: JOG_TIMEOUT_S, dt_status: 0 } })
      .then((r) => {
        this.entering = false;
        if (r.result_type === 'status' && r.operating_mode === 'VELOCITY_CONTROL') {
          this.session = true;
          if (this.active) this.run();
          else this.finish();
        } else {
          this.onError(r.error_message || `jog refused: mode ${r.operating_mode}`);
          this.stop('refused');
        }
      })
      .catch((e) => {
        this.entering = false;
        this.session = false;
        if (this.active) this.onError(`jog: ${e.message}`);
        this.stop('lost');
      });
  }

  run() {
    clearInterval(this.timer);
    this.beat();
    this.timer = setInterval(() => this.beat(), JOG_PERIOD_MS);
  }

  velocities() {
    const v = [0, 0, 0, 0, 0, 0];
    if (this.active && !TCP_DIRECTIONS.includes(this.active.axis)) {
      const a = this.active.axis;
      const raw = this.active.dir * this.speed() * this.maxVelocity(a);
      v[a - 1] = Math.round(raw * 1000) / 1000;
    }
    return v;
  }

  /** The command of one beat: the axis's velocities, or the TCP's. */
  message() {
    const a = this.active;
    if (a && TCP_DIRECTIONS.includes(a.axis)) {
      return { command: 'set_cartesian_velocity', arguments: cartesianVelocity(a.axis, a.dir, this.tcp()) };
    }
    return { command: 'set_velocities', arguments: { velocities: this.velocities() } };
  }

  beat() {
    if (!this.session) return;
    if (!this.conn.fire(this.message())) {
      this.stop('lost');
    }
  }

  /** Stop whatever `source` started (any jog when `source` is omitted). */
  release(source) {
    if (!this.active) return;
    if (source && this.active.source !== source) return;
    this.stop('released');
  }

  stop(why) {
    const was = this.active;
    this.active = null;
    clearInterval(this.timer);
    this.timer = null;
    if (was) this.onChange(null);
    if (this.entering) return; // finished when velocity_control answers
    if (this.session) this.finish();
    return why;
  }

  finish() {
    this.session = false;
    if (!this.conn.connected) return;
    this.conn.fire({ command: 'set_velocities', arguments: { velocities: [0, 0, 0, 0, 0, 0] } });
    this.conn.hold().catch(() => {});
  }

  /** The mode was left from elsewhere (timeout, a safety trip, someone's `hold`). */
  sessionEnded() {
    if (!this.session) return;
    this.session = false;
    clearInterval(this.timer);
    this.timer = null;
    if (this.active) {
      this.active = null;
      this.onChange(null);
    }
  }
}
