//! What each command does, and in which modes it is accepted.
//!
//! Runs inside the cycle.

use super::{Controller, Motion, Waiting};
use crate::calibration::AxisSettings;
use crate::pvt::BatchError;
use crate::request::{self, AxisSet, Request};
use crate::trajectory::{MovePlan, PvtPoint};
use mcm_shared::NUM_AXES;
use mcm_shared::mode::{CommandKind, Mode, RejectCode, ReplyStatus};
use mcm_shared::sample::{CommandSample, PVT_POINTS_PER_COMMAND};

impl Controller {
    fn ok(&mut self, c: &CommandSample, values: &[f64]) {
        let kind = CommandKind::try_from(c.kind).unwrap_or(CommandKind::Status);
        self.reply(
            Waiting::of(c, kind),
            ReplyStatus::Ok,
            RejectCode::None,
            0,
            values,
        );
    }

    fn reject(&mut self, c: &CommandSample, code: RejectCode, axis: u32, values: &[f64]) {
        let kind = CommandKind::try_from(c.kind).unwrap_or(CommandKind::Status);
        self.reply(
            Waiting::of(c, kind),
            ReplyStatus::Rejected,
            code,
            axis,
            values,
        );
    }

    fn wrong_mode(&mut self, c: &CommandSample) {
        self.reject(
            c,
            RejectCode::WrongMode,
            0,
            &[f64::from(self.mode.to_wire())],
        );
    }

    /// Refuse unless in HOLD, calibrated, and with the drives able to run.
    fn check_motion_mode_entry(&mut self, c: &CommandSample) -> bool {
        if self.mode != Mode::Hold || self.enabling.is_some() {
            self.wrong_mode(c);
            return false;
        }
        if let Some(axis) = self.offsets.iter().position(Option::is_none) {
            self.reject(c, RejectCode::NotCalibrated, axis as u32 + 1, &[]);
            return false;
        }
        true
    }

    pub(super) fn on_command(&mut self, c: &CommandSample) {
        let req = match request::decode(c) {
            Ok(r) => r,
            Err(e) => return self.reject(c, e.code, e.axis, &e.values),
        };
        match req {
            Request::Status => self.ok(c, &[]),
            Request::Info => self.ok(c, &[NUM_AXES as f64, self.p.period]),
            Request::Hold => self.on_hold(c),
            Request::Calibrate {
                axes,
                elbow_direction,
                wrist_direction,
                force_mechanical_stop,
            } => self.on_calibrate(
                c,
                axes,
                elbow_direction,
                wrist_direction,
                force_mechanical_stop,
            ),
            Request::Pvt { dt } => {
                if self.check_motion_mode_entry(c) {
                    self.stream.reset(dt);
                    self.starved = false;
                    self.mode = Mode::Pvt;
                    self.ok(c, &[]);
                }
            }
            Request::Release => {
                if self.check_motion_mode_entry(c) {
                    self.mode = Mode::Release;
                    self.motion = Motion::Release;
                    self.ok(c, &[]);
                }
            }
            Request::TorqueControl {
                timeout,
                gravity_compensation,
            } => {
                if self.check_motion_mode_entry(c) {
                    let timeout_ns = timeout.map(|t| (t * 1e9) as u64);
                    self.mode = Mode::TorqueControl;
                    self.motion = Motion::Torque {
                        torques: [0.0; NUM_AXES],
                        gravity: gravity_compensation,
                        deadline_ns: timeout_ns.map(|t| self.now_ns + t),
                        timeout_ns,
                    };
                    self.ok(c, &[]);
                }
            }
            Request::SetTorques { torques } => self.on_set_torques(c, torques),
            Request::MoveAxis {
                axis,
                target_deg,
                velocity_factor,
            } => {
                let mut target = self.cmd.position;
                target[axis] = target_deg.to_radians();
                self.on_move(c, target, velocity_factor, Some(axis));
            }
            Request::MoveAll {
                target_deg,
                velocity_factor,
            } => self.on_move(c, target_deg.map(f64::to_radians), velocity_factor, None),
            Request::PvtPoints { count, last } => self.on_pvt_points(c, count, last),
            Request::Sim(_) => {
                // Fault injection is served by the simulator's edge (`crate::sim_edge`) before
                // the controller steps; reaching here means there is no simulated robot.
                self.reject(c, RejectCode::NotSimulated, 0, &[]);
            }
        }
    }

    fn on_hold(&mut self, c: &CommandSample) {
        let w = Waiting::of(c, CommandKind::Hold);
        match self.mode {
            Mode::Off | Mode::Error => {
                if let Some((code, axis)) = self.enable_blocker() {
                    return self.reject(c, code, axis, &[]);
                }
                self.begin_enabling(w, None);
            }
            Mode::Hold => self.ok(c, &[]),
            Mode::Calibration => {
                if let Some(waiting) = self.calibrating.take() {
                    self.reply(waiting, ReplyStatus::Failed, RejectCode::Aborted, 0, &[]);
                }
                self.stop_motion();
                self.mode = Mode::Hold;
                self.ok(c, &[]);
            }
            Mode::Pvt | Mode::Release | Mode::TorqueControl => {
                self.stop_motion();
                self.mode = Mode::Hold;
                self.ok(c, &[]);
            }
        }
    }

    fn on_calibrate(
        &mut self,
        c: &CommandSample,
        axes: AxisSet,
        elbow: f64,
        wrist: f64,
        force: bool,
    ) {
        if !matches!(self.mode, Mode::Off | Mode::Hold) || self.enabling.is_some() {
            return self.wrong_mode(c);
        }
        if matches!(self.motion, Motion::Move { .. } | Motion::Stop { .. }) {
            return self.reject(c, RejectCode::Busy, 0, &[self.motion.remaining()]);
        }
        let settings: [Option<AxisSettings>; NUM_AXES] = core::array::from_fn(|i| {
            axes.contains(i).then(|| {
                let reverse = match i {
                    2 => elbow < 0.0,
                    3..=5 => wrist < 0.0,
                    _ => false,
                };
                self.cal_settings[i][usize::from(reverse)][usize::from(force)]
            })
        });
        let w = Waiting::of(c, CommandKind::Calibrate);
        if self.mode == Mode::Off {
            if let Some((code, axis)) = self.enable_blocker() {
                return self.reject(c, code, axis, &[]);
            }
            self.begin_enabling(w, Some(settings));
        } else {
            self.start_calibration(w, settings);
        }
    }

    fn on_set_torques(&mut self, c: &CommandSample, torques: [f64; NUM_AXES]) {
        if let Motion::Torque {
            torques: t,
            deadline_ns,
            timeout_ns,
            ..
        } = &mut self.motion
            && self.mode == Mode::TorqueControl
        {
            for (i, (dst, src)) in t.iter_mut().zip(torques).enumerate() {
                let peak = self.p.peak_torque[i];
                if src.abs() > peak {
                    let values = [src, -peak, peak];
                    return self.reject(c, RejectCode::OutOfRange, i as u32 + 1, &values);
                }
                *dst = src;
            }
            *deadline_ns = timeout_ns.map(|to| self.now_ns + to);
            self.ok(c, &[]);
        } else {
            self.wrong_mode(c);
        }
    }

    fn on_move(
        &mut self,
        c: &CommandSample,
        target: [f64; NUM_AXES],
        factor: f64,
        only: Option<usize>,
    ) {
        if self.mode != Mode::Pvt {
            return self.wrong_mode(c);
        }
        if !matches!(self.motion, Motion::Hold) || self.stream.running() {
            let left = self.motion.remaining();
            return self.reject(c, RejectCode::Busy, 0, &[left]);
        }
        for (axis, q) in target.iter().copied().enumerate() {
            if only.is_some_and(|a| a != axis) {
                continue;
            }
            if !self.p.reachable(axis, q) {
                let values = [
                    q.to_degrees(),
                    self.p.reach_min[axis].to_degrees(),
                    self.p.reach_max[axis].to_degrees(),
                ];
                return self.reject(c, RejectCode::Unreachable, axis as u32 + 1, &values);
            }
        }
        let plan = match MovePlan::plan(self.cmd.position, target, &self.p.limits, factor) {
            Ok(p) => p,
            Err(_) => return self.reject(c, RejectCode::OutOfRange, 0, &[factor, 0.0, 1.0]),
        };
        self.starved = false;
        self.motion = Motion::Move { plan, t: 0.0 };
        let v = plan.velocities().map(f64::to_degrees);
        let longest = (plan.longest_axis() + 1) as f64;
        self.ok(
            c,
            &[v[0], v[1], v[2], v[3], v[4], v[5], longest, plan.duration()],
        );
    }

    /// Every sample of a batch is answered (so senders can pace themselves); the answer to the
    /// last one says whether the batch was queued.
    fn on_pvt_points(&mut self, c: &CommandSample, count: usize, last: bool) {
        if self.mode != Mode::Pvt {
            return self.wrong_mode(c);
        }
        let mut points = [PvtPoint::default(); PVT_POINTS_PER_COMMAND];
        for (j, pt) in points.iter_mut().enumerate().take(count) {
            for i in 0..NUM_AXES {
                pt.position[i] = c.args[j * 12 + i].to_radians();
                pt.velocity[i] = c.args[j * 12 + 6 + i].to_radians();
            }
        }
        let staged = self.stream.stage(c.client_id, &points[..count]);
        if !last {
            return match staged {
                Ok(()) => self.ok(c, &[]),
                Err(e) => self.reject_batch(c, e),
            };
        }
        if staged.is_err() {
            // The batch was poisoned; commit reports why and clears it.
            let start = self.cmd;
            if let Err(e) = self.stream.commit(c.client_id, &start, &self.p) {
                return self.reject_batch(c, e);
            }
        }
        if matches!(self.motion, Motion::Move { .. } | Motion::Stop { .. }) {
            let left = self.motion.remaining();
            return self.reject(c, RejectCode::Busy, 0, &[left]);
        }
        let start = self.cmd;
        match self.stream.commit(c.client_id, &start, &self.p) {
            Ok(()) => {
                self.starved = false;
                self.motion = Motion::Stream;
                self.ok(c, &[]);
            }
            Err(e) => self.reject_batch(c, e),
        }
    }

    fn reject_batch(&mut self, c: &CommandSample, e: BatchError) {
        match e {
            BatchError::QueueFull { offered, free } => {
                self.reject(c, RejectCode::QueueFull, 0, &[offered as f64, free as f64])
            }
            BatchError::TooLong { limit } => self.reject(
                c,
                RejectCode::QueueFull,
                0,
                &[limit as f64 + 1.0, limit as f64],
            ),
            BatchError::Point {
                index,
                axis,
                what,
                value,
                limit,
            } => self.reject(
                c,
                RejectCode::PvtPoint,
                axis as u32 + 1,
                &[
                    (index + 1) as f64,
                    f64::from(what),
                    value.to_degrees(),
                    limit.to_degrees(),
                ],
            ),
        }
    }
}
