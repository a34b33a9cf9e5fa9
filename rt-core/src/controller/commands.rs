//! What each command does, and in which modes it is accepted.
//!
//! Runs inside the cycle. Requests arrive typed ([`Request`], decoded once per sample) in the
//! user's units; positions and velocities become radians here, where the controller takes them
//! in, and refusals carry their figures in degrees.

use super::Controller;
use super::state::{After, CalPhase, Caller, Moving, PvtMotion, State};
use crate::calibration::AxisSettings;
use crate::pvt::BatchError;
use crate::trajectory::{MovePlan, PvtPoint};
use mcm_shared::NUM_AXES;
use mcm_shared::command::{
    Axis, Calibrate, Direction, Pvt, PvtChunk, Request, SetTorques, TorqueControl,
};
use mcm_shared::ranges::{Arg, ArgRefusal};
use mcm_shared::reply::{Done, InfoReply, MoveAllPlan, Reason};
use mcm_shared::sample::PVT_POINTS_PER_COMMAND;
use mcm_shared::units::{deg_to_rad, deg_to_rad6, rad_to_deg, rad_to_deg6};

/// Targets closer than this to the commanded position are taken as the commanded position
/// [rad] (a nanoradian: far below one encoder count).
pub const TARGET_RESOLUTION_RAD: f64 = 1e-9;

impl Controller {
    fn wrong_mode(&mut self, c: Caller) {
        let mode = self.mode();
        self.refuse(c, Reason::WrongMode { mode });
    }

    fn busy(&mut self, c: Caller) {
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
                    return self.refuse(c, Reason::InvalidArgument(e));
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
            // Fault injection is served by the simulator's edge (`crate::sim_edge`) before the
            // controller steps; reaching here means there is no simulated robot.
            Request::Sim(_) => self.refuse(c, Reason::NotSimulated),
            // The ownership gate (`ownership.rs`) answers these before the modes see them.
            Request::TakeControl | Request::ReleaseControl | Request::ClientGone => {
                self.done(c, Done::Ack)
            }
        }
    }

    fn on_hold(&mut self, c: Caller) {
        match self.state {
            State::Off | State::Error { .. } | State::Enabling { .. } => {
                if let Some(reason) = self.enable_blocker() {
                    return self.refuse(c, reason);
                }
                self.begin_enabling(c, After::Hold);
            }
            State::Hold { .. } => self.done(c, Done::Ack),
            State::Calibration { caller, .. } => {
                self.fail(caller, Reason::Aborted);
                self.state = State::Hold {
                    stop: self.stop_motion(),
                };
                self.done(c, Done::Ack);
            }
            State::Pvt { .. } | State::Release | State::Torque { .. } => {
                self.state = State::Hold {
                    stop: self.stop_motion(),
                };
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
                return self.refuse(c, reason);
            }
            self.begin_enabling(c, After::Calibrate(settings));
        } else {
            self.start_calibration(c, settings);
        }
    }

    fn on_torque_control(&mut self, c: Caller, t: TorqueControl) {
        if self.check_motion_mode_entry(c) {
            let timeout_ns = t.timeout_s.map(|t| (t * 1e9) as u64);
            self.state = State::Torque {
                torques: [0.0; NUM_AXES],
                gravity: t.gravity_compensation,
                deadline_ns: timeout_ns.map(|t| self.now_ns + t),
                timeout_ns,
            };
            self.done(c, Done::Ack);
        }
    }

    /// New torques, each within its axis's peak torque; refused whole (nothing changes) when
    /// one is not.
    fn on_set_torques(&mut self, c: Caller, t: SetTorques) {
        let State::Torque {
            gravity,
            timeout_ns,
            ..
        } = self.state
        else {
            return self.wrong_mode(c);
        };
        for (i, tau) in t.torques_nm.iter().copied().enumerate() {
            let peak = self.p.peak_torque[i];
            if let Err(e) = Arg::Torques.check(tau, (-peak, peak), Some(Axis::ALL[i])) {
                return self.refuse(c, Reason::InvalidArgument(e));
            }
        }
        self.state = State::Torque {
            torques: t.torques_nm,
            gravity,
            deadline_ns: timeout_ns.map(|to| self.now_ns + to),
            timeout_ns,
        };
        self.done(c, Done::Ack);
    }

    /// A move to `target` [rad] (of axis `only`, or of all axes), planned from the commanded
    /// state. `move_all` answers with the plan; `move_axis` with a plain acknowledgement.
    fn on_move(&mut self, c: Caller, mut target: [f64; NUM_AXES], factor: f64, only: Option<Axis>) {
        let State::Pvt { motion, .. } = self.state else {
            return self.wrong_mode(c);
        };
        if !matches!(motion, PvtMotion::Hold) {
            return self.busy(c);
        }
        for (i, q) in target.iter().copied().enumerate() {
            if only.is_some_and(|a| a.index() != i) {
                continue;
            }
            if !self.p.reachable(i, q) {
                let reason = Reason::Unreachable {
                    axis: Axis::ALL[i],
                    target_deg: rad_to_deg(q),
                    min_deg: rad_to_deg(self.p.reach_min[i]),
                    max_deg: rad_to_deg(self.p.reach_max[i]),
                };
                return self.refuse(c, reason);
            }
        }
        // A target within [`TARGET_RESOLUTION_RAD`] of the commanded position is that position:
        // a move of a tiny (even subnormal) distance is no move, not an unplannable one.
        for (q, at) in target.iter_mut().zip(self.cmd.position) {
            if (*q - at).abs() < TARGET_RESOLUTION_RAD {
                *q = at;
            }
        }
        let plan = match MovePlan::plan(self.cmd.position, target, &self.p.limits, factor) {
            Ok(p) => p,
            Err(_) => {
                // Decoding checked the factor's range; a plan that still fails names it.
                let (min, max) = Arg::VelocityFactor.fixed_bounds();
                let reason = Reason::InvalidArgument(ArgRefusal {
                    arg: Arg::VelocityFactor,
                    axis: None,
                    value: factor,
                    min,
                    max,
                });
                return self.refuse(c, reason);
            }
        };
        self.state = State::Pvt {
            motion: PvtMotion::Move(Moving { plan, t: 0.0 }),
            starved: false,
        };
        if only.is_some() {
            return self.done(c, Done::Ack);
        }
        let plan = MoveAllPlan {
            velocities_deg_s: rad_to_deg6(&plan.velocities()),
            longest: Axis::ALL[plan.longest_axis().min(NUM_AXES - 1)],
            duration_s: plan.duration(),
        };
        self.done(c, Done::MoveAll(plan));
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
        if matches!(motion, PvtMotion::Move(_) | PvtMotion::Stop(_)) {
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

    /// Start the calibration searches of the axes that have settings.
    pub(super) fn start_calibration(
        &mut self,
        caller: Caller,
        settings: [Option<AxisSettings>; NUM_AXES],
    ) {
        let fb = *self.master.feedback();
        let mut axes = [None; NUM_AXES];
        let mut selected = 0u8;
        for (i, s) in settings.iter().enumerate() {
            if let Some(s) = s {
                selected |= 1 << i;
                self.offsets[i] = None;
                axes[i] = Some(crate::calibration::AxisCalibration::start(
                    *s,
                    crate::calibration::AxisInput {
                        position: fb[i].position_rad,
                        current: fb[i].current_a,
                        light_barrier: fb[i].light_barrier,
                    },
                ));
            }
        }
        self.hold_here();
        self.state = State::Calibration {
            caller,
            phase: CalPhase::Search { axes, selected },
        };
    }
}
