//! The motion of each cycle: the reference and the drive requests it produces.
//!
//! Runs inside the cycle.

use super::Controller;
use super::exits::Exit;
use super::state::{CalPhase, Moving, PvtMotion, State, Stopping};
use super::{FRICTION_COMPENSATION, RELEASE_DAMPING};
use crate::canopen::DriveRequest;
use crate::pvt::StreamState;
use crate::trajectory::{JointSample, StopPlan};
use mcm_shared::NUM_AXES;

/// Deceleration of a stop after a safety trip, as a multiple of each axis's maximum
/// acceleration. The braking-distance check assumes only `safety.braking_efficiency` (0.8) of
/// the maximum; a trip at speed (an external torque, a hand) must stop well inside that, and
/// the drives have the torque for it (P-Rob2: 5 x 180 deg/s^2 on axis 1 takes about 15 Nm of
/// its 130).
pub const QUICK_STOP_FACTOR: f64 = 5.0;

/// How fast the torque feed-forward of a drive already in CSP may change [Nm/s]: the
/// gravity load changes at most about this fast in a move, and the loop's integral follows
/// such a ramp with a negligible error.
const FEED_FORWARD_RATE_NM_S: f64 = 200.0;

impl Controller {
    /// A controlled stop of whatever moves, at each axis's maximum deceleration, from the
    /// commanded state (position modes) or from the measured state (torque modes and
    /// calibration searches); `None` when already at rest. The caller sets the state.
    pub(super) fn stop_motion(&mut self) -> Option<Stopping> {
        self.stop(false)
    }

    /// The stop after a safety trip: from the measured state, whatever the mode (the command
    /// may be what went wrong), at [`QUICK_STOP_FACTOR`] times the maximum deceleration.
    pub(super) fn quick_stop(&mut self) -> Option<Stopping> {
        self.stop(true)
    }

    fn stop(&mut self, quick: bool) -> Option<Stopping> {
        let measured = quick
            || matches!(
                self.state,
                State::Release
                    | State::Torque { .. }
                    | State::Calibration {
                        phase: CalPhase::Search { .. },
                        ..
                    }
            );
        let from = if measured {
            JointSample {
                position: self.measured(),
                velocity: self.measured_velocity(),
                acceleration: [0.0; NUM_AXES],
            }
        } else {
            self.cmd
        };
        let factor = if quick {
            self.planted.quick_stop_factor()
        } else {
            1.0
        };
        let decel: [f64; NUM_AXES] =
            core::array::from_fn(|i| factor * self.p.limits[i].acceleration);
        let plan = StopPlan::plan(from.position, from.velocity, decel);
        self.cmd = from;
        self.current_limit = self.p.max_current;
        (plan.duration() > 0.0).then_some(Stopping { plan, t: 0.0 })
    }

    /// Advance a stop by `dt`; `None` once it ended (the axes at rest where it ended).
    pub(super) fn advance_stop(&mut self, stop: Option<Stopping>, dt: f64) -> Option<Stopping> {
        let Stopping { plan, t } = stop?;
        let t = t + dt;
        self.cmd = plan.sample(t);
        if t >= plan.duration() {
            self.cmd.velocity = [0.0; NUM_AXES];
            self.cmd.acceleration = [0.0; NUM_AXES];
            None
        } else {
            Some(Stopping { plan, t })
        }
    }

    /// Advance a move by `dt`; `None` once every axis arrived (the reference at its end).
    fn advance_move(&mut self, mut m: Moving, dt: f64) -> Option<Moving> {
        self.cmd = m.plan.advance(dt);
        (!m.plan.finished()).then_some(m)
    }

    /// Advance the motion by one period and set the drive requests.
    pub(super) fn advance_motion(&mut self) {
        let dt = self.p.period;
        self.current_limit = self.p.max_current;
        // OFF, and a mode with a motion of its own, end the relax of the axes whose
        // calibration search ended without success (`calibrate_relax.rs`).
        if !matches!(
            self.state,
            State::Enabling { .. } | State::Hold { .. } | State::Error { .. }
        ) {
            self.search_relax.end();
        }
        match self.state {
            State::Off => {}
            State::Enabling { .. } => self.relax_searched(false),
            State::Hold { stop } => {
                let stop = self.advance_stop(stop, dt);
                self.relax_searched(stop.is_some());
                self.state = State::Hold { stop };
            }
            State::Error { stop, mut relax } => {
                let stop = self.advance_stop(stop, dt);
                self.relax_tripped_axes(&mut relax);
                self.relax_searched(stop.is_some());
                self.state = State::Error { stop, relax };
            }
            State::Pvt { motion, starved } => self.advance_pvt(motion, starved, dt),
            State::Calibration {
                caller,
                phase: CalPhase::Search { .. },
            } => self.advance_calibration(caller, dt),
            State::Calibration {
                caller,
                phase: CalPhase::Return(m),
            } => match self.advance_move(m, dt) {
                Some(m) => {
                    self.state = State::Calibration {
                        caller,
                        phase: CalPhase::Return(m),
                    }
                }
                // Calibration done.
                None => self.arrive_in_hold(caller),
            },
            State::Identify { caller, run } => self.advance_identification(caller, run, dt),
            State::Release => {
                let q = self.measured();
                let qd = self.measured_velocity();
                let soft =
                    self.release
                        .torques(&self.model, &q, &qd, self.p.period, &self.p.peak_torque);
                let damping: [f64; NUM_AXES] = core::array::from_fn(|i| {
                    -RELEASE_DAMPING * self.p.viscous[i] * qd[i] + soft[i]
                });
                self.compensate(true, &damping);
                return;
            }
            State::Velocity { target, watchdog } => self.advance_velocity(target, watchdog),
            State::Torque {
                torques,
                gravity,
                watchdog,
            } => {
                if watchdog.is_some_and(|w| w.expired(self.now_ns)) {
                    // set_torques stopped arriving: the controlled stop to HOLD.
                    self.leave(Exit::Timeout);
                } else {
                    self.compensate(gravity, &torques);
                    // The torques about to be sent, judged where they would take each axis
                    // before a trip could stop it; on a trip they are not sent.
                    let Err(v) = self.check_commanded_torques() else {
                        return;
                    };
                    self.trip(v.reason());
                }
            }
        }
        self.position_requests();
    }

    fn advance_pvt(&mut self, motion: PvtMotion, mut starved: bool, dt: f64) {
        let motion = match motion {
            PvtMotion::Hold => PvtMotion::Hold,
            PvtMotion::Move(m) => self
                .advance_move(m, dt)
                .map_or(PvtMotion::Hold, PvtMotion::Move),
            PvtMotion::Stop(s) => self
                .advance_stop(Some(s), dt)
                .map_or(PvtMotion::Hold, PvtMotion::Stop),
            PvtMotion::Stream => match self.stream.advance(dt) {
                (StreamState::Running, s) => {
                    self.cmd = s;
                    PvtMotion::Stream
                }
                (StreamState::Finished(at), _) => {
                    self.cmd = JointSample {
                        position: at,
                        ..JointSample::default()
                    };
                    PvtMotion::Hold
                }
                (StreamState::Starved(at), _) => {
                    starved = true;
                    self.cmd = at;
                    self.stop_motion().map_or(PvtMotion::Hold, PvtMotion::Stop)
                }
                (StreamState::Idle, _) => PvtMotion::Hold,
            },
            PvtMotion::LinePending(p) => self.advance_pending_line(p, dt),
            PvtMotion::Line(run) => self.advance_line(run, dt),
        };
        self.state = State::Pvt { motion, starved };
    }

    fn position_requests(&mut self) {
        let off = matches!(self.state, State::Off);
        // The gravity load at the commanded pose as the drives' torque feed-forward (once the
        // pose is known: every axis calibrated).
        let gravity = if self.offsets.iter().all(Option::is_some) {
            self.model.gravity_torques(&self.cmd.position)
        } else {
            [0.0; NUM_AXES]
        };
        for (i, &load) in gravity.iter().enumerate() {
            let raw = self.cmd.position[i] + self.offsets[i].unwrap_or(0.0);
            let was_position = matches!(self.requests[i], DriveRequest::Position { .. });
            self.requests[i] = match self.state {
                State::Off => DriveRequest::Disable,
                State::Error { .. }
                    if !self.master.feedback()[i].enabled
                        || self.overload_power_off(i)
                        || self.lost_power_off(i) =>
                {
                    DriveRequest::Disable
                }
                _ => DriveRequest::Position { position_rad: raw },
            };
            // Entering CSP (from RELEASE, TORQUE_CONTROL, or enabling): the loop starts with
            // no integral, so the feed-forward is there at once. In CSP it follows the load
            // at a bounded rate, which the loop's integral tracks without a bump.
            let step = FEED_FORWARD_RATE_NM_S * self.p.period;
            self.feed_forward[i] = if was_position && self.master.feedback()[i].enabled {
                self.feed_forward[i] + (load - self.feed_forward[i]).clamp(-step, step)
            } else {
                load
            };
            self.master.set_torque_offset(i, self.feed_forward[i]);
        }
        if off {
            self.cmd = JointSample {
                position: self.measured(),
                ..JointSample::default()
            };
        }
    }

    /// The braking check with the accelerations the commanded torques produce, from the
    /// measured state (`safety::check_braking_accelerating`); skipped when the braking check
    /// is planted off.
    fn check_commanded_torques(&self) -> Result<(), crate::safety::Violation> {
        if self.planted.braking_check_off {
            return Ok(());
        }
        let q = self.measured();
        let qd = self.measured_velocity();
        let qdd = self.model.forward_dynamics(&q, &qd, &self.cmd_torque);
        crate::safety::check_braking_accelerating(&self.safety, &q, &qd, &qdd)
    }

    /// Torque requests: the model's gravity (optionally) and part of its friction, plus `extra`.
    fn compensate(&mut self, gravity: bool, extra: &[f64; NUM_AXES]) {
        let q = self.measured();
        let qd = self.measured_velocity();
        let g = if gravity {
            self.model.gravity_torques(&q)
        } else {
            [0.0; NUM_AXES]
        };
        let f = if gravity {
            self.model.friction_compensation(&qd)
        } else {
            [0.0; NUM_AXES]
        };
        for i in 0..NUM_AXES {
            let peak = self.p.peak_torque[i];
            let tau = (g[i] + FRICTION_COMPENSATION * f[i] + extra[i]).clamp(-peak, peak);
            self.cmd_torque[i] = tau;
            self.requests[i] = DriveRequest::Torque { torque_nm: tau };
        }
        self.cmd = JointSample {
            position: q,
            velocity: qd,
            acceleration: [0.0; NUM_AXES],
        };
    }
}
