//! The node's PVT stream: where the points it queued end, and when the stream began.
//!
//! The core runs a stream of points spaced `dt`: it starts at the commanded position when its
//! first batch is queued, point k is reached (k + 1)·dt later, and later batches append. The node
//! queues only a short lead ahead of the arm, so that a new trajectory can join the stream where
//! the queued points end, with their position and velocity: the arm goes on without a jump.

use mcm_shared::NUM_AXES;

/// The stream as the node has fed it.
#[derive(Debug, Clone, Default)]
pub struct Stream {
    /// Core time (`StateSample::t_ns`) of the stream's start: the cycle that queued its first
    /// batch. `None` before the first batch's reply (or with no stream).
    origin_ns: Option<u64>,
    /// Whether a stream exists (its first batch was sent).
    alive: bool,
    /// Time from the start to the last point sent [s].
    sent_s: f64,
    /// Position [rad] and velocity [rad/s] of the last point sent.
    last: ([f64; NUM_AXES], [f64; NUM_AXES]),
}

impl Stream {
    /// No stream (after a stop, or when the core left PVT).
    pub fn end(&mut self) {
        *self = Stream::default();
    }

    pub fn is_alive(&self) -> bool {
        self.alive
    }

    pub fn origin_ns(&self) -> Option<u64> {
        self.origin_ns
    }

    /// The first batch was queued in the cycle that started at `t_ns`, of period `period_ns`
    /// (called once per stream). That cycle already steps the reference one period along the
    /// stream: its commanded state is the stream's at one period, so the stream's time 0 is
    /// one period before the cycle.
    pub fn started(&mut self, t_ns: u64, period_ns: u64) {
        if self.alive && self.origin_ns.is_none() {
            self.origin_ns = Some(t_ns.saturating_sub(period_ns));
        }
    }

    /// Time since the stream's start at core time `now_ns` [s]; 0 before the start is known.
    pub fn elapsed_s(&self, now_ns: u64) -> f64 {
        self.origin_ns
            .map_or(0.0, |o| now_ns.saturating_sub(o) as f64 * 1e-9)
    }

    /// How far the points sent reach ahead of the arm at `now_ns` [s].
    pub fn ahead_s(&self, now_ns: u64) -> f64 {
        self.sent_s - self.elapsed_s(now_ns)
    }

    /// Where a new trajectory joins at `now_ns`: (its begin on the stream's time [s], position
    /// [rad], velocity [rad/s]), when points sent are still ahead of the arm.
    pub fn join(&self, now_ns: u64) -> Option<(f64, [f64; NUM_AXES], [f64; NUM_AXES])> {
        (self.alive && self.ahead_s(now_ns) > 0.0).then_some((
            self.sent_s,
            self.last.0,
            self.last.1,
        ))
    }

    /// `n` points were sent, spaced `dt`, the last at `position` with `velocity`.
    pub fn sent(
        &mut self,
        n: usize,
        dt: f64,
        position: [f64; NUM_AXES],
        velocity: [f64; NUM_AXES],
    ) {
        self.alive = true;
        self.sent_s += n as f64 * dt;
        self.last = (position, velocity);
    }
}

#[cfg(test)]
mod tests;
