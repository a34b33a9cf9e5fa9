//! The motion of each cycle: the reference and the drive requests it produces.
//!
//! Runs inside the cycle.

use super::{Controller, FRICTION_COMPENSATION, RELEASE_DAMPING, Waiting};
use crate::calibration::{AxisCalibration, AxisInput, AxisSettings, Outcome};
use crate::canopen::DriveRequest;
use crate::pvt::StreamState;
use crate::trajectory::{JointSample, MovePlan, StopPlan};
use mcm_shared::NUM_AXES;
use mcm_shared::mode::{Mode, RejectCode, ReplyStatus};

/// Deceleration of a stop after a safety trip, as a multiple of each axis's maximum
/// acceleration. The braking-distance check assumes only `safety.braking_efficiency` (0.8) of
/// the maximum; a trip at speed (an external torque, a hand) must stop well inside that, and
/// the drives have the torque for it (P-Rob2: 5 x 180 deg/s^2 on axis 1 takes about 15 Nm of
/// its 130).
pub const QUICK_STOP_FACTOR: f64 = 5.0;

/// Velocity factor of the move back to zero after calibration.
const RETURN_VELOCITY_FACTOR: f64 = 0.5;

/// What the axes do.
// The calibration variant is large; boxing it would allocate inside the cycle.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy)]
pub enum Motion {
    /// Keep the commanded position.
    Hold,
    /// A planned move (`move_axis`, `move_all`, the return after calibration); `t` since start.
    Move { plan: MovePlan, t: f64 },
    /// A controlled stop, then hold.
    Stop { plan: StopPlan, t: f64 },
    /// Follow the PVT stream.
    Stream,
    /// Calibration searches (raw frame, per axis; `None`: the axis holds or is done);
    /// `selected` has bit `i` set for every axis this calibration covers.
    Calibrate {
        axes: [Option<AxisCalibration>; NUM_AXES],
        selected: u8,
    },
    /// Gravity and friction compensation (RELEASE).
    Release,
    /// External torques (TORQUE_CONTROL).
    Torque {
        torques: [f64; NUM_AXES],
        gravity: bool,
        /// Controller time by which the next `set_torques` must arrive (`None`: no timeout).
        deadline_ns: Option<u64>,
        timeout_ns: Option<u64>,
    },
}

impl Motion {
    /// Seconds until a planned motion ends (0 when none runs).
    pub fn remaining(&self) -> f64 {
        match self {
            Motion::Move { plan, t } => (plan.duration() - t).max(0.0),
            Motion::Stop { plan, t } => (plan.duration() - t).max(0.0),
            _ => 0.0,
        }
    }
}

impl Controller {
    /// Stop whatever moves, with a controlled stop at each axis's maximum deceleration, from
    /// the commanded state (position modes) or from the measured state (torque modes).
    pub(super) fn stop_motion(&mut self) {
        self.stop(false);
    }

    /// Stop after a safety trip: from the measured state, whatever the mode (the command may
    /// be what went wrong), at [`QUICK_STOP_FACTOR`] times the maximum deceleration.
    pub(super) fn quick_stop(&mut self) {
        self.stop(true);
    }

    fn stop(&mut self, quick: bool) {
        let measured = quick
            || matches!(
                self.motion,
                Motion::Release | Motion::Torque { .. } | Motion::Calibrate { .. }
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
        let factor = if quick { QUICK_STOP_FACTOR } else { 1.0 };
        let decel: [f64; NUM_AXES] =
            core::array::from_fn(|i| factor * self.p.limits[i].acceleration);
        let plan = StopPlan::plan(from.position, from.velocity, decel);
        self.cmd = from;
        self.motion = if plan.duration() > 0.0 {
            Motion::Stop { plan, t: 0.0 }
        } else {
            Motion::Hold
        };
        self.current_limit = self.p.max_current;
    }

    /// Start the calibration searches of the axes that have settings.
    pub(super) fn start_calibration(
        &mut self,
        waiting: Waiting,
        settings: [Option<AxisSettings>; NUM_AXES],
    ) {
        let fb = *self.master.feedback();
        let mut axes = [None; NUM_AXES];
        let mut selected = 0u8;
        for (i, s) in settings.iter().enumerate() {
            if let Some(s) = s {
                selected |= 1 << i;
                self.offsets[i] = None;
                axes[i] = Some(AxisCalibration::start(
                    *s,
                    AxisInput {
                        position: fb[i].position_rad,
                        current: fb[i].current_a,
                        light_barrier: fb[i].light_barrier,
                    },
                ));
            }
        }
        self.hold_here();
        self.mode = Mode::Calibration;
        self.calibrating = Some(waiting);
        self.motion = Motion::Calibrate { axes, selected };
    }

    /// Advance the motion by one period and set the drive requests.
    pub(super) fn advance_motion(&mut self) {
        let dt = self.p.period;
        self.current_limit = self.p.max_current;
        match self.motion {
            Motion::Hold => {}
            Motion::Move { plan, t } => {
                let t = t + dt;
                self.cmd = plan.sample(t);
                self.motion = if t >= plan.duration() {
                    self.cmd = plan.sample(plan.duration());
                    if self.mode == Mode::Calibration {
                        self.finish_calibration();
                    }
                    Motion::Hold
                } else {
                    Motion::Move { plan, t }
                };
            }
            Motion::Stop { plan, t } => {
                let t = t + dt;
                self.cmd = plan.sample(t);
                self.motion = if t >= plan.duration() {
                    self.cmd.velocity = [0.0; NUM_AXES];
                    self.cmd.acceleration = [0.0; NUM_AXES];
                    Motion::Hold
                } else {
                    Motion::Stop { plan, t }
                };
            }
            Motion::Stream => match self.stream.advance(dt) {
                (StreamState::Running, s) => self.cmd = s,
                (StreamState::Finished(at), _) => {
                    self.cmd = JointSample {
                        position: at,
                        ..JointSample::default()
                    };
                    self.motion = Motion::Hold;
                }
                (StreamState::Starved(at), _) => {
                    self.starved = true;
                    self.cmd = at;
                    self.stop_motion();
                }
                (StreamState::Idle, _) => self.motion = Motion::Hold,
            },
            Motion::Calibrate { axes, selected } => self.advance_calibration(axes, selected, dt),
            Motion::Release => {
                let qd = self.measured_velocity();
                let damping: [f64; NUM_AXES] =
                    core::array::from_fn(|i| -RELEASE_DAMPING * self.p.viscous[i] * qd[i]);
                self.compensate(true, &damping);
                return;
            }
            Motion::Torque {
                torques,
                gravity,
                deadline_ns,
                ..
            } => {
                if deadline_ns.is_some_and(|d| self.now_ns > d) {
                    // set_torques stopped arriving: fall back to HOLD.
                    self.stop_motion();
                    self.mode = Mode::Hold;
                } else {
                    self.compensate(gravity, &torques);
                    return;
                }
            }
        }
        self.position_requests();
    }

    fn position_requests(&mut self) {
        for i in 0..NUM_AXES {
            let raw = self.cmd.position[i] + self.offsets[i].unwrap_or(0.0);
            self.requests[i] = match self.mode {
                _ if self.enabling.is_some() => DriveRequest::Position { position_rad: raw },
                Mode::Off => DriveRequest::Disable,
                Mode::Error if !self.master.feedback()[i].enabled => DriveRequest::Disable,
                _ => DriveRequest::Position { position_rad: raw },
            };
        }
        if self.mode == Mode::Off && self.enabling.is_none() {
            self.cmd = JointSample {
                position: self.measured(),
                ..JointSample::default()
            };
        }
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

    fn advance_calibration(
        &mut self,
        mut axes: [Option<AxisCalibration>; NUM_AXES],
        selected: u8,
        dt: f64,
    ) {
        let fb = *self.master.feedback();
        let mut running = false;
        for (i, slot) in axes.iter_mut().enumerate() {
            let Some(cal) = slot else { continue };
            let out = cal.step(
                AxisInput {
                    position: fb[i].position_rad,
                    current: fb[i].current_a,
                    light_barrier: fb[i].light_barrier,
                },
                dt,
            );
            // The raw target, in the joint frame of an uncalibrated axis (offset 0).
            self.cmd.position[i] = cal.target();
            self.current_limit[i] = cal.current_limit();
            match out {
                Outcome::Running => running = true,
                Outcome::Found { offset } => {
                    self.offsets[i] = Some(offset);
                    // Kept by the drive until it loses power: survives a restart of the MCM.
                    let counts = (offset * self.p.counts_per_rad[i])
                        .round()
                        .clamp(f64::from(i32::MIN), f64::from(i32::MAX));
                    self.master.store_calibration(i, counts as i32);
                    self.cmd.position[i] = cal.target() - offset;
                    *slot = None;
                }
                Outcome::Failed { code, searched } => {
                    self.motion = Motion::Hold;
                    self.mode = Mode::Error;
                    if let Some(w) = self.calibrating.take() {
                        self.reply(
                            w,
                            ReplyStatus::Failed,
                            RejectCode::CalibrationFailed,
                            i as u32 + 1,
                            &[f64::from(code), searched.to_degrees()],
                        );
                    }
                    self.trip(
                        RejectCode::CalibrationFailed,
                        i,
                        [f64::from(code), searched.to_degrees(), 0.0, 0.0],
                    );
                    self.hold_here();
                    return;
                }
            }
        }
        if running {
            self.motion = Motion::Calibrate { axes, selected };
            return;
        }
        // Every axis found its zero: move the axes of this calibration back to zero (the
        // others stay where they are).
        let start = self.cmd.position;
        let target: [f64; NUM_AXES] = core::array::from_fn(|i| {
            if selected & (1 << i) != 0 {
                0.0
            } else {
                start[i]
            }
        });
        match MovePlan::plan(start, target, &self.p.limits, RETURN_VELOCITY_FACTOR) {
            Ok(plan) => self.motion = Motion::Move { plan, t: 0.0 },
            Err(_) => {
                self.motion = Motion::Hold;
                self.finish_calibration();
            }
        }
    }

    /// Calibration done: HOLD, and the reply.
    fn finish_calibration(&mut self) {
        self.mode = Mode::Hold;
        if let Some(w) = self.calibrating.take() {
            self.reply(w, ReplyStatus::Ok, RejectCode::None, 0, &[]);
        }
    }
}
