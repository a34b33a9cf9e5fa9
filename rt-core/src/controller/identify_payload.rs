//! `identify_payload`: the load on the flange, from what the drives hold at a few poses.
//!
//! Runs inside the cycle: plain `Copy` data, fixed-size arrays, no allocation.
//!
//! A procedure of HOLD (the wire mode stays HOLD; `State::Identify`): from the commanded
//! pose at rest it visits [`POSES`] poses, each the start pose plus one row of
//! [`POSE_OFFSETS_DEG`] (the elbow bent either way and the wrist turned, so that the load's
//! lever about the shoulder and the elbow changes apart from its orientation: moving the
//! wrist alone, the upright arm's wrist centre stays above both, and the mass could not be
//! told from its distance along the flange's axis; an offset that would leave the reachable
//! range is taken the other way). At each pose it measures twice, once arriving from
//! [`APPROACH_DEG`] above on every axis and once from as far below: after each arrival it
//! waits [`SETTLE_S`] for the drives' loops to settle and averages the joint torques the
//! drives report (their currents) over [`WINDOW_S`]. A joint at rest holds with its gravity
//! torque plus whatever static friction is left in it, and after a move that friction is
//! the Coulomb friction of the last motion's direction: arriving from both sides and taking
//! the mean cancels it, as the averaging cancels the loop's ripple. The poses' means go to
//! the least-squares estimator (`mcm_dynamics::PayloadEstimator`); then the arm moves back
//! to where it started and the reply is `payload` (mass, centre of mass, residual). With
//! `apply` the estimate becomes the active tool's mass and centre of mass (its TCP and
//! inertia kept), through the path `set_tool` takes.
//!
//! Every move is planned from rest to rest with the joint planner (jerk-limited, at
//! [`VELOCITY_FACTOR`]); the whole sequence is planned, and the poses judged
//! ([`mcm_dynamics::MAX_CONDITION`]), before anything moves: a pose outside the reachable
//! range is refused `unreachable`, poses that cannot tell the load apart `not_identifiable`.
//! The safety checks watch it as they watch PVT's planned moves (`Situation::procedure`). A
//! `hold`, a gone owner or a shutdown aborts it (its caller is answered `aborted` or
//! `shutting_down`, the arm stops with `hold`'s controlled stop), a trip fails it with the
//! trip's reason; any other command meanwhile is refused `busy`.

use super::Controller;
use super::state::{Caller, Moving, State};
use crate::trajectory::{JointPlan, MovePlan};
use mcm_dynamics::{MAX_CONDITION, PayloadError, PayloadEstimator};
use mcm_shared::NUM_AXES;
use mcm_shared::command::{Axis, IdentifyPayload};
use mcm_shared::reply::{Done, PayloadReply, Reason};
use mcm_shared::tool::Tool;

const N: usize = NUM_AXES;

/// How many poses are measured.
pub const POSES: usize = 4;

/// Each pose as the start pose plus these offsets [deg], axes 1 to 6.
pub const POSE_OFFSETS_DEG: [[f64; N]; POSES] = [
    [0.0, 0.0, 25.0, 0.0, 35.0, 0.0],
    [0.0, 0.0, 25.0, 90.0, -35.0, 90.0],
    [0.0, 0.0, -25.0, 90.0, 35.0, 0.0],
    [0.0, 0.0, -25.0, 0.0, -35.0, -90.0],
];

/// Each pose is approached from this far above and below on every axis [deg].
pub const APPROACH_DEG: f64 = 1.5;

/// Time after an arrival before the torques are averaged [s].
pub const SETTLE_S: f64 = 0.4;

/// Time over which the torques of one arrival are averaged [s].
pub const WINDOW_S: f64 = 0.5;

/// Velocity factor of the moves between the poses.
pub const VELOCITY_FACTOR: f64 = 0.5;

/// Moves of the sequence: to above, to the pose, to below, to the pose, for each pose; then
/// back to the start.
const LEGS: usize = 4 * POSES + 1;

/// Move `leg` ends at a pose, where the torques are measured (not at a point of approach, nor
/// back at the start).
fn measures_after(leg: usize) -> bool {
    !leg.is_multiple_of(2) && leg < 4 * POSES
}

/// Move `leg` belongs to the first of its pose's two measurements: the one from above.
fn from_above(leg: usize) -> bool {
    (leg / 2).is_multiple_of(2)
}

/// Means of the torques and positions of one arrival.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Mean {
    torque: [f64; N],
    position: [f64; N],
    n: u32,
}

impl Mean {
    fn add(&mut self, torque: &[f64; N], position: &[f64; N]) {
        for i in 0..N {
            self.torque[i] += torque[i];
            self.position[i] += position[i];
        }
        self.n += 1;
    }

    /// The mean of this window and `other`, each averaged over its own samples.
    fn both(&self, other: &Mean) -> ([f64; N], [f64; N]) {
        let (a, b) = (f64::from(self.n.max(1)), f64::from(other.n.max(1)));
        let mean =
            |x: &[f64; N], y: &[f64; N]| core::array::from_fn(|i| (x[i] / a + y[i] / b) / 2.0);
        (
            mean(&self.position, &other.position),
            mean(&self.torque, &other.torque),
        )
    }
}

/// What the procedure does this cycle.
// A joint plan is large; boxing it would allocate inside the cycle.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy)]
enum Phase {
    Move(Moving),
    /// After an arrival: time waited [s].
    Settle(f64),
    Average(Mean),
}

/// A running `identify_payload`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Identification {
    apply: bool,
    start: [f64; N],
    poses: [[f64; N]; POSES],
    /// Duration of each move [s], planned before the first.
    legs: [f64; LEGS],
    /// The move under way or last made (its index in the sequence).
    leg: usize,
    phase: Phase,
    /// The first arrival's means at the pose being measured.
    first: Mean,
    estimator: PayloadEstimator,
}

impl Identification {
    /// The move under way.
    pub fn moving(&self) -> Option<&Moving> {
        match &self.phase {
            Phase::Move(m) => Some(m),
            _ => None,
        }
    }

    /// Where move `leg` goes.
    fn target(&self, leg: usize) -> [f64; N] {
        if leg >= 4 * POSES {
            return self.start;
        }
        let pose = self.poses[leg / 4];
        let side = if from_above(leg) { 1.0 } else { -1.0 };
        if leg.is_multiple_of(2) {
            pose.map(|q| q + side * APPROACH_DEG.to_radians())
        } else {
            pose
        }
    }

    /// Robot time left until the reply [s].
    fn remaining_s(&self) -> f64 {
        let later: f64 = self.legs[self.leg + 1..].iter().sum();
        let later_measures = (self.leg + 1..LEGS).filter(|l| measures_after(*l)).count() as f64;
        let now = match &self.phase {
            Phase::Move(m) => {
                let measure = if measures_after(self.leg) {
                    SETTLE_S + WINDOW_S
                } else {
                    0.0
                };
                m.plan.remaining() + measure
            }
            Phase::Settle(t) => SETTLE_S - t + WINDOW_S,
            Phase::Average(_) => WINDOW_S,
        };
        now.max(0.0) + later + later_measures * (SETTLE_S + WINDOW_S)
    }

    /// Robot time the whole procedure takes [s].
    #[cfg(test)]
    pub fn duration_s(&self) -> f64 {
        self.legs.iter().sum::<f64>() + (2 * POSES) as f64 * (SETTLE_S + WINDOW_S)
    }
}

/// The refusal (or failure) of poses that do not tell the load apart.
fn not_identifiable(e: PayloadError) -> Reason {
    let condition = match e {
        PayloadError::IllConditioned { condition, .. } => condition,
        // Only a non-finite measurement: nothing can be told from it.
        PayloadError::NotFinite => f64::INFINITY,
    };
    Reason::NotIdentifiable {
        // The wire carries finite figures.
        condition: condition.min(f64::MAX),
        limit: MAX_CONDITION,
    }
}

/// A move from rest at `from` to rest at `to`.
fn plan(
    from: [f64; N],
    to: [f64; N],
    limits: &[crate::trajectory::AxisLimits; N],
) -> Option<JointPlan> {
    MovePlan::plan(from, to, limits, VELOCITY_FACTOR)
        .and_then(|p| JointPlan::from_move(&p))
        .ok()
}

impl Controller {
    /// `identify_payload`: in HOLD at rest, every axis calibrated.
    pub(super) fn on_identify_payload(&mut self, c: Caller, req: IdentifyPayload) {
        match self.state {
            State::Hold { stop: None } => {}
            State::Hold { stop: Some(_) } => return self.busy(c),
            _ => return self.wrong_mode(c),
        }
        if let Some(axis) = self.offsets.iter().position(Option::is_none) {
            return self.refuse(
                c,
                Reason::NotCalibrated {
                    axis: Axis::ALL[axis],
                },
            );
        }
        match self.plan_identification(req.apply) {
            Ok(run) => self.state = State::Identify { caller: c, run },
            Err(reason) => self.refuse(c, reason),
        }
    }

    /// The poses from the commanded pose, judged and every move planned; the first move
    /// under way.
    fn plan_identification(&self, apply: bool) -> Result<Identification, Reason> {
        let start = self.cmd.position;
        let approach = APPROACH_DEG.to_radians();
        let fits = |i: usize, q: f64| {
            self.p.reachable(i, q - approach) && self.p.reachable(i, q + approach)
        };
        let mut poses = [start; POSES];
        let mut judged = PayloadEstimator::new();
        for (pose, offsets) in poses.iter_mut().zip(&POSE_OFFSETS_DEG) {
            for i in 0..N {
                let d = offsets[i].to_radians();
                let (up, down) = (start[i] + d, start[i] - d);
                pose[i] = if fits(i, up) {
                    up
                } else if fits(i, down) {
                    down
                } else {
                    // The first place the measurement would take the axis that is not
                    // reachable.
                    let bad = [up, up - approach, up + approach]
                        .into_iter()
                        .find(|q| !self.p.reachable(i, *q))
                        .unwrap_or(up);
                    return Err(self.unreachable(i, bad));
                };
            }
            judged.add_pose(&self.model, pose);
        }
        judged.judge().map_err(not_identifiable)?;
        let mut run = Identification {
            apply,
            start,
            poses,
            legs: [0.0; LEGS],
            leg: 0,
            phase: Phase::Settle(0.0),
            first: Mean::default(),
            estimator: PayloadEstimator::new(),
        };
        let mut from = start;
        let mut first = None;
        for leg in 0..LEGS {
            let to = run.target(leg);
            let Some(p) = plan(from, to, &self.p.limits) else {
                return Err(self.unreachable(0, to[0]));
            };
            run.legs[leg] = p.remaining();
            first.get_or_insert(p);
            from = to;
        }
        run.phase = Phase::Move(Moving {
            plan: first.unwrap_or_else(|| JointPlan::hold(start)),
        });
        Ok(run)
    }

    /// A `busy` refusal while an identification runs, with the time it has left.
    pub(super) fn busy_identifying(&mut self, c: Caller) -> bool {
        let State::Identify { run, .. } = self.state else {
            return false;
        };
        self.refuse(
            c,
            Reason::Busy {
                remaining_s: run.remaining_s(),
            },
        );
        true
    }

    /// One cycle of the procedure.
    pub(super) fn advance_identification(
        &mut self,
        caller: Caller,
        mut run: Identification,
        dt: f64,
    ) {
        match run.phase {
            Phase::Move(mut m) => {
                self.cmd = m.plan.advance(dt);
                if !m.plan.finished() {
                    run.phase = Phase::Move(m);
                } else if run.leg == LEGS - 1 {
                    return self.finish_identification(caller, &run);
                } else if measures_after(run.leg) {
                    run.phase = Phase::Settle(0.0);
                } else {
                    self.next_leg(&mut run);
                }
            }
            Phase::Settle(t) => {
                let t = t + dt;
                run.phase = if t >= SETTLE_S {
                    Phase::Average(Mean::default())
                } else {
                    Phase::Settle(t)
                };
            }
            Phase::Average(mut mean) => {
                let fb = self.master.feedback();
                let torque: [f64; N] = core::array::from_fn(|i| fb[i].torque_nm);
                mean.add(&torque, &self.measured());
                if f64::from(mean.n) * dt < WINDOW_S {
                    run.phase = Phase::Average(mean);
                } else {
                    if from_above(run.leg) {
                        run.first = mean;
                    } else {
                        let (q, tau) = run.first.both(&mean);
                        run.estimator.add(&self.model, &q, &tau);
                    }
                    self.next_leg(&mut run);
                }
            }
        }
        self.state = State::Identify { caller, run };
    }

    /// The next move of the sequence, from the commanded pose at rest.
    fn next_leg(&self, run: &mut Identification) {
        run.leg += 1;
        let to = run.target(run.leg);
        run.phase = Phase::Move(Moving {
            plan: plan(self.cmd.position, to, &self.p.limits)
                .unwrap_or_else(|| JointPlan::hold(self.cmd.position)),
        });
    }

    /// Back at the start: the estimate, applied if asked, and the reply.
    fn finish_identification(&mut self, caller: Caller, run: &Identification) {
        self.state = State::Hold { stop: None };
        let estimate = match run.estimator.estimate() {
            Ok(e) => e,
            Err(e) => return self.fail(caller, not_identifiable(e)),
        };
        if run.apply {
            let tool = *self.model.tool();
            match Tool::new(
                tool.tcp,
                estimate.mass,
                estimate.center_of_mass,
                Some(tool.inertia),
            ) {
                Ok(t) => self.use_tool(&t),
                Err(e) => {
                    let (min, max) = e.bounds();
                    return self.fail(
                        caller,
                        Reason::OutOfRange {
                            axis: None,
                            value: e.value(),
                            min,
                            max,
                        },
                    );
                }
            }
        }
        self.done(
            caller,
            Done::Payload(PayloadReply {
                mass_kg: estimate.mass,
                center_of_mass_m: estimate.center_of_mass,
                residual_nm: estimate.residual_nm,
            }),
        );
    }
}

#[cfg(all(test, feature = "sim"))]
mod tests;
