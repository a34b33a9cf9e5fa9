//! What each command does, and in which modes it is accepted.
//!
//! Runs inside the cycle. Requests arrive typed ([`Request`], decoded once per sample) in the
//! user's units; positions and velocities become radians here, where the controller takes them
//! in, and refusals carry their figures in degrees.

use super::Controller;
use super::exits::Exit;
use super::state::{After, Caller, PvtMotion, State, Watchdog};
use crate::calibration::AxisSettings;
use crate::pvt::BatchError;
use crate::trajectory::PvtPoint;
use mcm_shared::NUM_AXES;
use mcm_shared::command::{
    Axis, Calibrate, Direction, Pvt, PvtChunk, Request, SetTorques, TorqueControl,
};
use mcm_shared::ranges::Arg;
use mcm_shared::reply::{Done, InfoReply, Reason};
use mcm_shared::sample::PVT_POINTS_PER_COMMAND;
use mcm_shared::units::{deg_to_rad, deg_to_rad6};

impl Controller {
    pub(super) fn wrong_mode(&mut self, c: Caller) {
        let mode = self.mode();
        self.refuse(c, Reason::WrongMode { mode });
    }

    pub(super) fn busy(&mut self, c: Caller) {
        let remaining_s = self.state.remaining().unwrap_or(0.0);
        self.refuse(c, Reason::Busy { remaining_s });
    }

    /// Refuse unless in HOLD and calibrated.
    fn check_motion_mode_entry(&mut self, c: Caller) -> bool {
        if !matches!(self.state, State::Hold { .. }) {
            self.wrong_mode(c);
            return false;
        }
        if let Some(axis) = self.offsets.iter().position(Option::is_none) {
            self.refuse(
                c,
                Reason::NotCalibrated {
                    axis: Axis::ALL[axis],
                },
            );
            return false;
        }
        true
    }

    pub(super) fn on_request(&mut self, c: Caller, req: Request) {
        // An identification runs: only a stop, the state and control change get through.
        if !matches!(
            req,
            Request::Status
                | Request::Info
                | Request::Hold
                | Request::Sim(_)
                | Request::TakeControl
                | Request::ReleaseControl
                | Request::ClientGone
        ) && self.busy_identifying(c)
        {
            return;
        }
        match req {
            Request::Status => self.done(c, Done::Ack),
            Request::Info => self.done(
                c,
                Done::Info(InfoReply {
                    num_axes: NUM_AXES as u32,
                    period_s: self.p.period,
                }),
            ),
            Request::Hold => self.on_hold(c),
            Request::Calibrate(cal) => self.on_calibrate(c, cal),
            Request::Pvt(pvt) => {
                // `dt` from one cycle period on: the range the gateway checks too.
                let dt = Arg::Dt;
                if let Err(e) = dt.check(pvt.dt_s, (self.p.period, Pvt::MAX_DT_S), None) {
                    return self.refuse(c, Reason::InvalidArgument { refusal: e });
                }
                if self.check_motion_mode_entry(c) {
                    self.stream.reset(pvt.dt_s);
                    // A stop under way in HOLD carries on in PVT.
                    let motion = match self.state {
                        State::Hold { stop: Some(s) } => PvtMotion::Stop(s),
                        _ => PvtMotion::Hold,
                    };
                    self.state = State::Pvt {
                        motion,
                        starved: false,
                    };
                    self.done(c, Done::Ack);
                }
            }
            Request::Release => {
                if self.check_motion_mode_entry(c) {
                    self.state = State::Release;
                    self.done(c, Done::Ack);
                }
            }
            Request::TorqueControl(t) => self.on_torque_control(c, t),
            Request::VelocityControl(v) => {
                if self.check_motion_mode_entry(c) {
                    self.enter_velocity_control(c, v);
                }
            }
            Request::SetVelocities(v) => self.on_set_velocities(c, v),
            Request::SetCartesianVelocity(v) => self.on_set_cartesian_velocity(c, v),
            Request::SetTool(t) => self.on_set_tool(c, t),
            Request::IdentifyPayload(i) => self.on_identify_payload(c, i),
            Request::SetTorques(t) => self.on_set_torques(c, t),
            Request::MoveAxis(m) => {
                let mut target = self.cmd.position;
                target[m.axis.index()] = deg_to_rad(m.target_deg);
                self.on_move(c, target, m.velocity_factor, Some(m.axis));
            }
            Request::MoveAll(m) => {
                self.on_move(c, deg_to_rad6(&m.targets_deg), m.velocity_factor, None)
            }
            Request::PvtPoints(chunk) => self.on_pvt_points(c, &chunk),
            Request::MoveLinear(m) => self.on_move_linear(c, m),
            // Fault injection is served by the simulator's edge (`crate::sim_edge`) before the
            // controller steps; reaching here means there is no simulated robot.
            Request::Sim(_) => self.refuse(c, Reason::NotSimulated),
            // The ownership gate (`ownership.rs`) answers these before the modes see them.
            Request::TakeControl | Request::ReleaseControl | Request::ClientGone => {
                self.done(c, Done::Ack)
            }
        }
    }

    /// Refuse a command that would enable the drives, for `reason` (from `enable_blocker`). A
    /// lost drive the master gave up configuring is reset and tried again: the drive may be
    /// back (its cable, its power), and a user who repeats the command once it is must not
    /// find it refused for good.
    fn refuse_enabling(&mut self, c: Caller, reason: Reason) {
        for axis in 0..NUM_AXES {
            if self.lost[axis] && self.master.gave_up(axis) {
                self.master.reset_node(axis);
            }
        }
        self.refuse(c, reason);
    }

    fn on_hold(&mut self, c: Caller) {
        match self.state {
            State::Off | State::Error { .. } | State::Enabling { .. } => {
                if let Some(reason) = self.enable_blocker() {
                    return self.refuse_enabling(c, reason);
                }
                self.begin_enabling(c, After::Hold);
            }
            State::Hold { .. }
            | State::Identify { .. }
            | State::Calibration { .. }
            | State::Pvt { .. }
            | State::Release
            | State::Torque { .. }
            | State::Velocity { .. } => {
                self.leave(Exit::Hold);
                self.done(c, Done::Ack);
            }
        }
    }

    fn on_calibrate(&mut self, c: Caller, cal: Calibrate) {
        if !matches!(self.state, State::Off | State::Hold { .. }) {
            return self.wrong_mode(c);
        }
        if self.state.planned_motion() {
            return self.busy(c);
        }
        let settings: [Option<AxisSettings>; NUM_AXES] = core::array::from_fn(|i| {
            cal.which.contains(Axis::ALL[i]).then(|| {
                let reverse = match i {
                    2 => cal.elbow_direction == Direction::Negative,
                    3..=5 => cal.wrist_direction == Direction::Negative,
                    _ => false,
                };
                self.cal_settings[i][usize::from(reverse)][usize::from(cal.force_mechanical_stop)]
            })
        });
        if matches!(self.state, State::Off) {
            if let Some(reason) = self.enable_blocker() {
                return self.refuse_enabling(c, reason);
            }
            self.begin_enabling(c, After::Calibrate(settings));
        } else {
            self.start_calibration(c, settings);
        }
    }

    fn on_torque_control(&mut self, c: Caller, t: TorqueControl) {
        if self.check_motion_mode_entry(c) {
            self.state = State::Torque {
                torques: [0.0; NUM_AXES],
                gravity: t.gravity_compensation,
                watchdog: Watchdog::start(t.timeout_s, self.now_ns),
            };
            self.done(c, Done::Ack);
        }
    }

    /// New torques, each within its axis's peak torque; refused whole (nothing changes) when
    /// one is not.
    fn on_set_torques(&mut self, c: Caller, t: SetTorques) {
        let State::Torque {
            gravity, watchdog, ..
        } = self.state
        else {
            return self.wrong_mode(c);
        };
        for (i, tau) in t.torques_nm.iter().copied().enumerate() {
            let peak = self.p.peak_torque[i];
            if let Err(e) = Arg::Torques.check(tau, (-peak, peak), Some(Axis::ALL[i])) {
                return self.refuse(c, Reason::InvalidArgument { refusal: e });
            }
        }
        self.state = State::Torque {
            torques: t.torques_nm,
            gravity,
            watchdog: watchdog.map(|w| w.fed(self.now_ns)),
        };
        self.done(c, Done::Ack);
    }

    /// Every sample of a batch is answered (so senders can pace themselves); the answer to the
    /// last one says whether the batch was queued.
    fn on_pvt_points(&mut self, c: Caller, chunk: &PvtChunk) {
        let State::Pvt { motion, .. } = self.state else {
            return self.wrong_mode(c);
        };
        let mut points = [PvtPoint::default(); PVT_POINTS_PER_COMMAND];
        let n = chunk.points().len();
        for (dst, src) in points.iter_mut().zip(chunk.points()) {
            dst.position = deg_to_rad6(&src.position_deg);
            dst.velocity = deg_to_rad6(&src.velocity_deg_s);
        }
        let staged = self.stream.stage(c.client_id, &points[..n]);
        if !chunk.last {
            return match staged {
                Ok(()) => self.done(c, Done::Ack),
                Err(e) => self.refuse_batch(c, e),
            };
        }
        if staged.is_err() {
            // The batch was poisoned; commit reports why and clears it.
            let start = self.cmd;
            if let Err(e) = self.stream.commit(c.client_id, &start, &self.p) {
                return self.refuse_batch(c, e);
            }
        }
        if !matches!(motion, PvtMotion::Hold | PvtMotion::Stream) {
            return self.busy(c);
        }
        let start = self.cmd;
        match self.stream.commit(c.client_id, &start, &self.p) {
            Ok(()) => {
                self.state = State::Pvt {
                    motion: PvtMotion::Stream,
                    starved: false,
                };
                self.done(c, Done::Ack);
            }
            Err(e) => self.refuse_batch(c, e),
        }
    }

    fn refuse_batch(&mut self, c: Caller, e: BatchError) {
        self.refuse(c, e.reason());
    }
}

// Scenario tests on the whole simulated robot.
#[cfg(all(test, feature = "sim"))]
mod tests;
