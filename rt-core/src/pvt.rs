//! PVT streaming: staging of `pvt_points` batches, their validation, the queue, and the
//! reference that passes through every point at its time.
//!
//! Runs inside the cycle; all storage is preallocated (the queue holds
//! [`DEFAULT_PVT_CAPACITY`] points, the staging area one whole batch).
//!
//! Timing: a stream starts at the commanded state when its first batch is queued; the first
//! point is reached `dt` later, the next one `dt` after that, and so on. Between points the
//! reference is the cubic Hermite spline through (position, velocity). When the queue runs dry
//! on a point with zero velocity the stream ends there; with a non-zero velocity the axes stop
//! with a controlled stop at their maximum deceleration (not an error; `starved` is set).

use crate::params::JointParams;
use crate::trajectory::{
    DEFAULT_PVT_CAPACITY, JointSample, PvtPoint, PvtQueue, PvtSegment, SegmentError,
};
use mcm_shared::NUM_AXES;
use mcm_shared::command::Axis;
use mcm_shared::pvt::{PointLimits, check_point as check_point_limits};
use mcm_shared::reply::{PvtQuantity, Reason};
use mcm_shared::units::rad_to_deg;

/// Most points in one batch.
pub const MAX_BATCH: usize = 1000;
/// A point whose speed is below this counts as at rest [rad/s].
const REST_SPEED: f64 = 1e-6;

/// Why a batch was refused; nothing of it was queued.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BatchError {
    /// The batch does not fit: points offered, places free.
    QueueFull { offered: usize, free: usize },
    /// A point breaks a limit: point index (0-based), axis (0-based), which quantity, value
    /// and limit (SI units).
    Point {
        index: usize,
        axis: usize,
        what: PvtQuantity,
        value: f64,
        limit: f64,
    },
    /// More points than one batch may hold.
    TooLong { limit: usize },
}

impl BatchError {
    /// The refusal it stands for (figures in the user's degrees; a batch longer than one may
    /// be is a full queue: one point more offered than fits).
    pub fn reason(&self) -> Reason {
        match *self {
            BatchError::QueueFull { offered, free } => Reason::QueueFull {
                offered: u32::try_from(offered).unwrap_or(u32::MAX),
                free: u32::try_from(free).unwrap_or(u32::MAX),
            },
            BatchError::TooLong { limit } => {
                let limit = u32::try_from(limit).unwrap_or(u32::MAX - 1);
                Reason::QueueFull {
                    offered: limit + 1,
                    free: limit,
                }
            }
            BatchError::Point {
                index,
                axis,
                what,
                value,
                limit,
            } => Reason::PvtPoint {
                axis: Axis::ALL[axis],
                point: u32::try_from(index + 1).unwrap_or(u32::MAX),
                quantity: what,
                value: rad_to_deg(value),
                limit: rad_to_deg(limit),
            },
        }
    }
}

/// What the stream does this cycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StreamState {
    /// No stream.
    Idle,
    /// Following the points.
    Running,
    /// Ran dry while moving: the caller must stop from this state.
    Starved(JointSample),
    /// Reached its last point at rest.
    Finished([f64; NUM_AXES]),
}

/// The PVT stream of the controller.
pub struct PvtStream {
    dt: f64,
    queue: PvtQueue<DEFAULT_PVT_CAPACITY>,
    staging: [PvtPoint; MAX_BATCH],
    staged: usize,
    staging_client: u64,
    /// The first error of the batch being staged: the whole batch will be refused.
    poisoned: Option<BatchError>,
    running: bool,
    /// The point the current segment starts from, and the time since it.
    from: PvtPoint,
    tau: f64,
}

impl Default for PvtStream {
    fn default() -> Self {
        Self::new()
    }
}

impl PvtStream {
    pub fn new() -> Self {
        Self {
            dt: 0.01,
            queue: PvtQueue::new(),
            staging: [PvtPoint::default(); MAX_BATCH],
            staged: 0,
            staging_client: 0,
            poisoned: None,
            running: false,
            from: PvtPoint::default(),
            tau: 0.0,
        }
    }

    /// Set the point spacing (on entering PVT) and forget everything queued.
    pub fn reset(&mut self, dt: f64) {
        self.dt = dt;
        self.queue.clear();
        self.staged = 0;
        self.running = false;
        self.tau = 0.0;
    }

    pub fn dt(&self) -> f64 {
        self.dt
    }

    pub fn queued(&self) -> usize {
        self.queue.len()
    }

    pub fn capacity(&self) -> usize {
        self.queue.capacity()
    }

    pub fn running(&self) -> bool {
        self.running
    }

    /// Add points of a batch sent by `client`. A new client's points discard another client's
    /// unfinished batch. After an error, the rest of the batch is ignored and the batch will be
    /// refused whole by [`PvtStream::commit`].
    pub fn stage(&mut self, client: u64, points: &[PvtPoint]) -> Result<(), BatchError> {
        if client != self.staging_client {
            self.staged = 0;
            self.poisoned = None;
            self.staging_client = client;
        }
        if let Some(e) = self.poisoned {
            return Err(e);
        }
        if self.staged + points.len() > MAX_BATCH {
            self.staged = 0;
            let e = BatchError::TooLong { limit: MAX_BATCH };
            self.poisoned = Some(e);
            return Err(e);
        }
        self.staging[self.staged..self.staged + points.len()].copy_from_slice(points);
        self.staged += points.len();
        Ok(())
    }

    /// Validate the staged batch of `client` and queue it whole, or refuse it whole. `start`
    /// is the commanded state the stream starts from if it is not running.
    pub fn commit(
        &mut self,
        client: u64,
        start: &JointSample,
        p: &JointParams,
    ) -> Result<(), BatchError> {
        if client != self.staging_client {
            self.staged = 0;
            self.poisoned = None;
        }
        let n = self.staged;
        self.staged = 0;
        if let Some(e) = self.poisoned.take() {
            return Err(e);
        }
        if n > self.queue.free() {
            return Err(BatchError::QueueFull {
                offered: n,
                free: self.queue.free(),
            });
        }
        let mut prev = if self.running {
            self.queue.last().copied().unwrap_or(self.from)
        } else {
            PvtPoint {
                position: start.position,
                velocity: start.velocity,
            }
        };
        for (index, point) in self.staging[..n].iter().enumerate() {
            check_point(index, point, p)?;
            let seg = PvtSegment::new(&prev, point, self.dt);
            if let Err(e) = seg.check(&p.reach_min, &p.reach_max, &p.limits) {
                let (what, value, limit) = match e.error {
                    SegmentError::Position {
                        position, min, max, ..
                    } => (
                        PvtQuantity::Position,
                        position,
                        if position > max { max } else { min },
                    ),
                    SegmentError::Velocity {
                        velocity, limit, ..
                    } => (PvtQuantity::Velocity, velocity, limit),
                    SegmentError::Acceleration {
                        acceleration,
                        limit,
                        ..
                    } => (PvtQuantity::Acceleration, acceleration, limit),
                    _ => (PvtQuantity::Position, f64::NAN, f64::NAN),
                };
                return Err(BatchError::Point {
                    index,
                    axis: e.axis,
                    what,
                    value,
                    limit,
                });
            }
            prev = *point;
        }
        self.queue
            .push_batch(&self.staging[..n])
            .map_err(|e| BatchError::QueueFull {
                offered: e.offered,
                free: e.free,
            })?;
        if !self.running && n > 0 {
            self.running = true;
            self.from = PvtPoint {
                position: start.position,
                velocity: start.velocity,
            };
            self.tau = 0.0;
        }
        Ok(())
    }

    /// Advance by `period` and give the reference. Call only while in PVT mode.
    pub fn advance(&mut self, period: f64) -> (StreamState, JointSample) {
        if !self.running {
            return (StreamState::Idle, JointSample::default());
        }
        self.tau += period;
        while self.tau >= self.dt {
            match self.queue.pop() {
                Some(next) => {
                    self.from = next;
                    self.tau -= self.dt;
                }
                None => break,
            }
        }
        match self.queue.peek() {
            Some(next) => {
                let s = PvtSegment::new(&self.from, next, self.dt).sample(self.tau.min(self.dt));
                (StreamState::Running, s)
            }
            None => {
                self.running = false;
                let at = JointSample {
                    position: self.from.position,
                    velocity: self.from.velocity,
                    acceleration: [0.0; NUM_AXES],
                };
                if self.from.velocity.iter().all(|v| v.abs() < REST_SPEED) {
                    (StreamState::Finished(self.from.position), at)
                } else {
                    (StreamState::Starved(at), at)
                }
            }
        }
    }
}

/// The per-point checks shared with the gateway ([`mcm_shared::pvt::check_point`]).
fn check_point(index: usize, pt: &PvtPoint, p: &JointParams) -> Result<(), BatchError> {
    let limits = PointLimits {
        reach_min: p.reach_min,
        reach_max: p.reach_max,
        velocity: core::array::from_fn(|i| p.limits[i].velocity),
    };
    check_point_limits(&pt.position, &pt.velocity, &limits).map_err(|e| BatchError::Point {
        index,
        axis: e.axis,
        what: e.what,
        value: e.value,
        limit: e.limit,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use mcm_shared::config::RobotConfig;

    fn params() -> JointParams {
        JointParams::from_config(&RobotConfig::prob2_default())
    }

    fn point(q: f64, v: f64) -> PvtPoint {
        PvtPoint {
            position: [q; NUM_AXES],
            velocity: [v; NUM_AXES],
        }
    }

    #[test]
    fn passes_through_every_point_at_its_time() {
        let p = params();
        let mut s = PvtStream::new();
        s.reset(0.01);
        let pts: Vec<PvtPoint> = (1..=20)
            .map(|k| {
                let t = k as f64 * 0.01;
                // p = A (1 - cos wt): starts at rest, |a| <= A w^2 = 0.9 rad/s^2.
                point(0.1 * (1.0 - (t * 3.0).cos()), 0.3 * (t * 3.0).sin())
            })
            .collect();
        s.stage(7, &pts).unwrap();
        s.commit(7, &JointSample::default(), &p).unwrap();
        assert_eq!(s.queued(), 20);
        // Period 0.005: every second cycle lands on a point.
        for k in 1..=40 {
            let (state, r) = s.advance(0.005);
            if k % 2 == 0 && k < 40 {
                let expect = pts[k / 2 - 1].position[0];
                assert!(
                    (r.position[0] - expect).abs() < 1e-9,
                    "k {k}: {} vs {expect}",
                    r.position[0]
                );
                assert_eq!(state, StreamState::Running);
            }
        }
    }

    #[test]
    fn a_stream_ending_in_motion_starves_and_one_ending_at_rest_finishes() {
        let p = params();
        let mut s = PvtStream::new();
        s.reset(0.01);
        // Constant acceleration of 2 rad/s^2 from rest for 10 ms.
        s.stage(1, &[point(0.0001, 0.02)]).unwrap();
        s.commit(1, &JointSample::default(), &p).unwrap();
        let (st, _) = s.advance(0.005);
        assert_eq!(st, StreamState::Running);
        let (st, _) = s.advance(0.005);
        assert!(matches!(st, StreamState::Starved(_)), "{st:?}");
        assert!(!s.running());

        s.stage(1, &[point(0.00004, 0.0)]).unwrap();
        s.commit(1, &JointSample::default(), &p).unwrap();
        s.advance(0.005);
        let (st, _) = s.advance(0.005);
        assert_eq!(st, StreamState::Finished([0.00004; NUM_AXES]));
    }

    #[test]
    fn a_bad_point_refuses_the_whole_batch() {
        let p = params();
        let mut s = PvtStream::new();
        s.reset(0.01);
        // A jump of 1 rad in 10 ms breaks the velocity limit of the segment.
        s.stage(1, &[point(0.00004, 0.0), point(1.0, 0.0)]).unwrap();
        let e = s.commit(1, &JointSample::default(), &p).unwrap_err();
        assert!(
            matches!(
                e,
                BatchError::Point {
                    index: 1,
                    axis: 0,
                    ..
                }
            ),
            "{e:?}"
        );
        assert_eq!(s.queued(), 0);
        // Outside the reachable range.
        s.stage(1, &[point(3.0, 0.0)]).unwrap();
        let e = s.commit(1, &JointSample::default(), &p).unwrap_err();
        assert!(
            matches!(
                e,
                BatchError::Point {
                    index: 0,
                    what: PvtQuantity::Position,
                    ..
                }
            ),
            "{e:?}"
        );
    }

    #[test]
    fn overflow_queues_nothing() {
        let p = params();
        let mut s = PvtStream::new();
        s.reset(0.01);
        let pts = vec![point(0.0, 0.0); MAX_BATCH];
        s.stage(1, &pts).unwrap();
        s.commit(1, &JointSample::default(), &p).unwrap();
        s.stage(1, &pts[..100]).unwrap();
        let e = s.commit(1, &JointSample::default(), &p).unwrap_err();
        assert_eq!(
            e,
            BatchError::QueueFull {
                offered: 100,
                free: DEFAULT_PVT_CAPACITY - MAX_BATCH
            }
        );
        assert_eq!(s.queued(), MAX_BATCH);
    }

    #[test]
    fn a_batch_too_long_is_refused_whole() {
        let p = params();
        let mut s = PvtStream::new();
        s.reset(0.01);
        s.stage(1, &vec![point(0.0, 0.0); MAX_BATCH - 1]).unwrap();
        assert!(s.stage(1, &[point(0.0, 0.0); 2]).is_err());
        assert!(
            s.stage(1, &[point(0.0, 0.0); 1]).is_err(),
            "the rest is ignored"
        );
        let e = s.commit(1, &JointSample::default(), &p).unwrap_err();
        assert_eq!(e, BatchError::TooLong { limit: MAX_BATCH });
        assert_eq!(s.queued(), 0);
        // The next batch starts clean.
        s.stage(1, &[point(0.0, 0.0); 3]).unwrap();
        s.commit(1, &JointSample::default(), &p).unwrap();
        assert_eq!(s.queued(), 3);
    }

    #[test]
    fn the_gateway_computes_the_same_point_limits_as_the_core() {
        let cfg = RobotConfig::prob2_default();
        let p = JointParams::from_config(&cfg);
        let l = PointLimits::from_config(&cfg);
        assert_eq!((l.reach_min, l.reach_max), (p.reach_min, p.reach_max));
        assert_eq!(l.velocity, core::array::from_fn(|i| p.limits[i].velocity));
    }

    #[test]
    fn batches_of_two_clients_do_not_mix() {
        let p = params();
        let mut s = PvtStream::new();
        s.reset(0.01);
        s.stage(1, &[point(0.0, 0.0); 3]).unwrap();
        s.stage(2, &[point(0.0, 0.0); 2]).unwrap();
        s.commit(2, &JointSample::default(), &p).unwrap();
        assert_eq!(s.queued(), 2);
    }
}
