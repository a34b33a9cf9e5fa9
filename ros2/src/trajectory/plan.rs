//! A goal's trajectory as the stream executes it: a spline from the start state through the
//! goal's points, checked against the axis limits, cut into PVT points.

use super::error::GoalError;
use super::joints::{AxisLimits, Joints};
use super::knots::{self, Knot};
use super::order::ColumnOrder;
use super::points::goal_points;
use super::polynomial::{self, Polynomial};
use super::quantity::Quantity;
use super::{MAX_DURATION_S, Sample, StartState, limits, stream_check, velocities};
use crate::msgs::builtin::Time;
use crate::msgs::trajectory::JointTrajectory;
use mcm_shared::NUM_AXES;
use mcm_shared::command::PvtPoint;

/// A start velocity below this [rad/s] is rest (for a trajectory that is only its start).
const REST_RAD_S: f64 = 1e-9;

/// How far above a limit (relative for velocities, rad for positions) a PVT point may come by
/// round-off alone; such a point is written at the limit (see [`Plan::pvt_point`]).
pub(super) const ROUND_OFF: f64 = 1e-9;

/// A validated, limit-checked plan on the stream's clock: t = 0 is where the stream reaches
/// the start state (the first PVT point is reached at t = dt).
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// Knot times [s], the first 0.
    times: Vec<f64>,
    /// Knot states (position and velocity exact at the knots), as many as `times`.
    states: Vec<Sample>,
    /// `segments[i]` runs from knot i to knot i + 1, one polynomial per axis.
    segments: Vec<[Polynomial; NUM_AXES]>,
    /// Plan time of every goal point (`offset + time_from_start`; 0 or less for points
    /// dropped as past or merged into the start).
    point_times: Vec<f64>,
    offset: f64,
    dt: f64,
    count: usize,
    limits: [AxisLimits; NUM_AXES],
}

impl Plan {
    /// The plan of `traj` for the arm `joints`, joining the stream at `start` (see
    /// [`StartState`]). `t0` is the ROS time (the clock of `header.stamp`) at which the stream
    /// reaches `start`, the plan's t = 0; `dt` is the stream's PVT spacing [s]. How the goal's
    /// points are placed on the plan's clock (zero, future and past stamps, a first point at
    /// time 0): see the `knots` module; velocities the goal leaves out: see `velocities`.
    pub fn new(
        traj: &JointTrajectory,
        joints: &Joints,
        start: StartState,
        t0: Time,
        dt: f64,
    ) -> Result<Plan, GoalError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(GoalError::Dt { dt });
        }
        check_start(&start, joints)?;
        let order = ColumnOrder::new(&traj.joint_names, joints)?;
        let points = goal_points(traj, &order, joints)?;
        let stamp = traj.header.stamp;
        let offset = if stamp == Time::default() {
            0.0
        } else {
            knots::seconds_between(stamp, t0)
        };
        let last = points[points.len() - 1].time;
        if stamp != Time::default() && offset + last <= 0.0 {
            return Err(GoalError::OldHeaderTimestamp {
                stamp: knots::seconds(stamp),
                last,
                late: -(offset + last),
            });
        }
        // Also refuses a NaN end.
        let end = offset + last;
        if end.is_nan() || end > MAX_DURATION_S {
            return Err(GoalError::TooLong {
                end,
                max: MAX_DURATION_S,
            });
        }
        let knots = knots::knots(&points, &start, offset, joints)?;
        if knots.len() == 1 {
            refuse_moving(&start, joints)?;
        }
        let plan = Plan::from_knots(
            &knots,
            points.iter().map(|p| offset + p.time).collect(),
            offset,
            dt,
            joints,
        );
        limits::check(&plan, joints)?;
        stream_check::check(&plan, &start, joints)?;
        Ok(plan)
    }

    fn from_knots(
        knots: &[Knot],
        point_times: Vec<f64>,
        offset: f64,
        dt: f64,
        joints: &Joints,
    ) -> Plan {
        let times: Vec<f64> = knots.iter().map(|k| k.time).collect();
        let positions: Vec<_> = knots.iter().map(|k| k.position).collect();
        let given: Vec<_> = knots.iter().map(|k| k.velocity).collect();
        let velocities = velocities::fill(&times, &positions, &given);
        let axis_knot = |k: usize, axis: usize| polynomial::Knot {
            p: positions[k][axis],
            v: velocities[k][axis],
            a: knots[k].acceleration.map(|a| a[axis]),
        };
        let segments: Vec<[Polynomial; NUM_AXES]> = (1..knots.len())
            .map(|k| {
                std::array::from_fn(|axis| {
                    Polynomial::hermite(
                        axis_knot(k - 1, axis),
                        axis_knot(k, axis),
                        times[k] - times[k - 1],
                    )
                })
            })
            .collect();
        let states = (0..knots.len())
            .map(|k| Sample {
                position: positions[k],
                velocity: velocities[k],
                acceleration: knots[k].acceleration.unwrap_or_default(),
            })
            .collect();
        let duration = times[times.len() - 1];
        // ceil(duration / dt), less a point that round-off alone would add.
        let count = (duration / dt - 1e-9).ceil().max(0.0) as usize;
        Plan {
            times,
            states,
            segments,
            point_times,
            offset,
            dt,
            count,
            limits: *joints.limits(),
        }
    }

    /// The plan's end time [s]: when the final state is reached.
    pub fn duration(&self) -> f64 {
        self.times[self.times.len() - 1]
    }

    /// The PVT spacing [s] the plan was made for.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// The plan time of the goal's `time_from_start` 0 (0 for a zero stamp; the delay of a
    /// future stamp; negative for a past one).
    pub fn offset(&self) -> f64 {
        self.offset
    }

    /// The state at plan time `t`: the start state for t <= 0 (its acceleration is the first
    /// segment's), the final state from [`Plan::duration`] on. At a knot's time position and
    /// velocity are the knot's exactly.
    pub fn sample(&self, t: f64) -> Sample {
        let last = self.times.len() - 1;
        if t.is_nan() || t <= 0.0 {
            return self.eval(0, 0.0).unwrap_or(self.states[0]);
        }
        // The last knot at or before t.
        let k = self.times.partition_point(|&x| x <= t) - 1;
        if k >= last {
            return self.states[last];
        }
        self.eval(k, t - self.times[k]).unwrap_or(self.states[k])
    }

    /// The final state: the goal's last point (its velocity or 0, its acceleration or 0).
    pub fn final_state(&self) -> Sample {
        self.states[self.states.len() - 1]
    }

    /// Segment `i` at τ seconds after its start knot.
    pub(super) fn eval(&self, i: usize, tau: f64) -> Option<Sample> {
        let seg = self.segments.get(i)?;
        let mut s = Sample::default();
        for (axis, poly) in seg.iter().enumerate() {
            (s.position[axis], s.velocity[axis], s.acceleration[axis]) = poly.eval(tau);
        }
        Some(s)
    }

    /// Knot times on the plan's clock.
    pub(super) fn knot_times(&self) -> &[f64] {
        &self.times
    }

    /// How many PVT points the plan takes: ceil(duration / dt) (0 for a plan that is only
    /// its start state).
    pub fn point_count(&self) -> usize {
        self.count
    }

    /// PVT point `k` (0-based; degrees, deg/s): the sample at t = (k + 1)·dt; the last one
    /// (and any beyond) is the final state exactly. A position or speed beyond its limit by
    /// round-off alone (at most 1e-9 rad, or 1e-9 of the speed limit) is written at the
    /// limit's configured value, so the core's exact point check passes.
    pub fn pvt_point(&self, k: usize) -> PvtPoint {
        let s = if k + 1 >= self.count {
            self.final_state()
        } else {
            self.sample((k + 1) as f64 * self.dt)
        };
        let mut out = PvtPoint::default();
        for (axis, l) in self.limits.iter().enumerate() {
            let (p, v) = (s.position[axis], s.velocity[axis]);
            out.position_deg[axis] = if p > l.max && p <= l.max + ROUND_OFF {
                l.max_deg
            } else if p < l.min && p >= l.min - ROUND_OFF {
                l.min_deg
            } else {
                p.to_degrees()
            };
            out.velocity_deg_s[axis] =
                if v.abs() > l.velocity && v.abs() <= l.velocity * (1.0 + ROUND_OFF) {
                    l.velocity_deg.copysign(v)
                } else {
                    v.to_degrees()
                };
        }
        out
    }

    /// The index in the goal's `points` of the point being executed at plan time `t`, for the
    /// feedback's `index`: the last point whose time has come (the start of the segment the
    /// arm is on), 0 before the first.
    pub fn index_at(&self, t: f64) -> usize {
        self.point_times
            .partition_point(|&x| x <= t)
            .saturating_sub(1)
    }

    /// Plan time `t` as the goal's `time_from_start`.
    pub fn time_from_start(&self, t: f64) -> f64 {
        t - self.offset
    }
}

/// Every value of the start state finite.
fn check_start(start: &StartState, joints: &Joints) -> Result<(), GoalError> {
    let vectors = [
        (Quantity::Position, &start.position),
        (Quantity::Velocity, &start.velocity),
    ];
    for (quantity, values) in vectors {
        if let Some(axis) = values.iter().position(|v| !v.is_finite()) {
            return Err(GoalError::Start {
                joint: joints.name(axis).to_string(),
                quantity,
                value: values[axis],
            });
        }
    }
    Ok(())
}

/// A trajectory that is only its start cannot be executed while the arm moves.
fn refuse_moving(start: &StartState, joints: &Joints) -> Result<(), GoalError> {
    match start.velocity.iter().position(|v| v.abs() > REST_RAD_S) {
        Some(axis) => Err(GoalError::CannotStop {
            joint: joints.name(axis).to_string(),
            velocity: start.velocity[axis],
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests;
