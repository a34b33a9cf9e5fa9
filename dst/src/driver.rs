//! The driver: a client with one purpose, to get a calibrated arm into the motion modes and
//! move it hard towards its limits, where the safety checks have to stop it in time. Random
//! clients rarely get that far; a seed's swarm gives a run a driver or not
//! ([`Swarm::driver`](crate::swarm::Swarm)).
//!
//! It reads the published state as a real client does: `take_control` when nobody has it,
//! `hold` out of OFF and ERROR, `calibrate` all axes in HOLD unless they are, then one of
//! VELOCITY_CONTROL (one axis at 50 to 100 % of its speed limit towards a limit),
//! TORQUE_CONTROL (gravity compensated, one axis towards a limit: half the plans push with 30 to
//! 100 % of its motor's torque, which the overspeed check ends within a few cycles; the other
//! half regulate the axis's speed to 45 to 90 % of its limit with torques, as an integrator's
//! force or admittance controller would, so that the axis reaches its limit at speed and the
//! braking-distance check has to stop it) or PVT (`move_axis` to just inside a limit at full
//! speed) or RELEASE (the arm limp, moved only by a push), for a few seconds, then `hold` and
//! the next plan.

use crate::clients::Limits;
use crate::rate::Rate;
use crate::rng::Rng;
use crate::stamp::{Stamp, calibrate_all};
use mcm_dynamics::ArmModel;
use mcm_shared::NUM_AXES;
use mcm_shared::command::{
    Axis, MoveAxis, Pvt, Request, SetTorques, SetVelocities, TorqueControl, VelocityControl,
};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::Mode;
use mcm_shared::sample::{AXIS_CALIBRATED, CommandSample, StateSample};
use mcm_shared::units::deg_to_rad;

/// How long a plan runs before the driver sends `hold` [s].
const PLAN_S: f64 = 3.0;
/// How long it waits after `take_control` [s].
const AFTER_TAKE_CONTROL_S: f64 = 0.05;
/// How long it waits after `hold` out of OFF, ERROR or RELEASE, and after `calibrate` (the
/// drives' enabling takes a while) [s].
const AFTER_HOLD_S: f64 = 0.2;
/// How long it waits after the entry into a motion mode [s].
const AFTER_ENTRY_S: f64 = 0.025;
/// How long it waits after the `hold` that ends a plan [s].
const AFTER_PLAN_S: f64 = 0.1;
/// How often it sends `set_velocities` and `set_torques` [s].
const SETPOINT_PERIOD_S: f64 = 0.02;
/// Time constant of the torque plans' speed regulation [s]: ten setpoint periods, so that the
/// loop, closed over the published state once a period, is well damped.
const SPEED_LOOP_TAU_S: f64 = 0.2;
/// Share of the speed limit a speed-regulating torque plan aims at, times its factor: 45 to
/// 90 %, below the overspeed check (110 %).
const SPEED_LOOP_SHARE: f64 = 0.9;

/// What the driver does in the motion mode it entered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Motion {
    Velocity,
    /// A constant torque.
    Torque,
    /// Torques that regulate the speed.
    TorqueSpeed,
    Pvt,
    /// RELEASE: the arm limp (gravity compensated) for a pushed fault or nothing to move it.
    Release,
}

/// The driver client.
#[derive(Debug, Clone)]
pub struct Driver {
    stamp: Stamp,
    /// The arm's rigid-body model: the joint's inertia for the speed-regulating torques.
    model: ArmModel,
    rate: Rate,
    motion: Motion,
    axis: usize,
    /// +1 towards the upper limit, -1 towards the lower.
    direction: f64,
    /// Share of the axis's speed or torque limit.
    factor: f64,
    /// The state's `seq` before which it sends nothing.
    wait_until: u64,
    /// The state's `seq` at which the plan ends with `hold`.
    plan_until: u64,
    /// `move_axis` of the plan sent.
    moved: bool,
}

impl Driver {
    pub fn new(id: u64, cfg: &RobotConfig, rate: Rate, rng: &mut Rng) -> Driver {
        let mut d = Driver {
            stamp: Stamp::new(id),
            model: ArmModel::from_config(cfg),
            rate,
            motion: Motion::Velocity,
            axis: 0,
            direction: 1.0,
            factor: 1.0,
            wait_until: 0,
            plan_until: 0,
            moved: false,
        };
        d.plan(0, rng);
        d
    }

    fn plan(&mut self, seq: u64, rng: &mut Rng) {
        self.motion = rng.pick(&[
            Motion::Velocity,
            Motion::Torque,
            Motion::Pvt,
            Motion::Release,
        ]);
        if self.motion == Motion::Torque && rng.below(2) == 0 {
            self.motion = Motion::TorqueSpeed;
        }
        self.axis = rng.below(NUM_AXES as u64) as usize;
        self.direction = rng.pick(&[1.0, -1.0]);
        self.factor = rng.pick(&[0.5, 0.8, 1.0]);
        self.plan_until = seq + self.rate.cycles(PLAN_S);
        self.moved = false;
    }

    fn request(&mut self, r: Request) -> CommandSample {
        self.stamp.request(r)
    }

    /// Its `client_gone` (its connection closes).
    pub fn gone(&mut self) -> CommandSample {
        self.request(Request::ClientGone)
    }

    fn wait(&mut self, s: &StateSample, seconds: f64) {
        self.wait_until = s.seq + self.rate.cycles(seconds);
    }

    /// This cycle's command of the driver, if it sends one.
    pub fn act(&mut self, s: &StateSample, lim: &Limits, rng: &mut Rng) -> Option<CommandSample> {
        if s.seq < self.wait_until {
            return None;
        }
        if s.owner_client_id != self.stamp.client_id {
            if s.owner_client_id != 0 {
                return None; // someone else drives
            }
            self.wait(s, AFTER_TAKE_CONTROL_S);
            return Some(self.request(Request::TakeControl));
        }
        let mode = Mode::try_from(s.mode).unwrap_or(Mode::Off);
        let calibrated = s.axis_flags.iter().all(|f| f & AXIS_CALIBRATED != 0);
        let r = match mode {
            Mode::Off | Mode::Error | Mode::Release => {
                self.wait(s, AFTER_HOLD_S);
                Request::Hold
            }
            Mode::Calibration => return None,
            Mode::Hold if !calibrated => {
                self.wait(s, AFTER_HOLD_S);
                calibrate_all()
            }
            Mode::Hold => {
                self.plan(s.seq, rng);
                self.wait(s, AFTER_ENTRY_S);
                match self.motion {
                    Motion::Velocity => Request::VelocityControl(VelocityControl {
                        timeout_s: Some(0.5),
                    }),
                    Motion::Torque | Motion::TorqueSpeed => Request::TorqueControl(TorqueControl {
                        timeout_s: Some(0.5),
                        gravity_compensation: true,
                    }),
                    Motion::Pvt => Request::Pvt(Pvt { dt_s: 0.01 }),
                    Motion::Release => Request::Release,
                }
            }
            _ if s.seq >= self.plan_until => {
                self.wait(s, AFTER_PLAN_S);
                Request::Hold
            }
            Mode::VelocityControl => {
                let mut v = [0.0; NUM_AXES];
                v[self.axis] = self.direction * self.factor * lim.max_velocity[self.axis];
                self.wait(s, SETPOINT_PERIOD_S);
                Request::SetVelocities(SetVelocities {
                    velocities_deg_s: v,
                })
            }
            Mode::TorqueControl => {
                let mut t = [0.0; NUM_AXES];
                let i = self.axis;
                let most = (0.3 + 0.7 * (self.factor - 0.5) / 0.5) * lim.max_torque[i];
                t[i] = if self.motion == Motion::TorqueSpeed {
                    let target =
                        self.direction * self.factor * SPEED_LOOP_SHARE * lim.max_velocity[i];
                    let q = s.position.map(deg_to_rad);
                    let inertia = self.model.mass_matrix(&q)[(i, i)];
                    let nm = inertia * deg_to_rad(target - s.velocity[i]) / SPEED_LOOP_TAU_S;
                    nm.clamp(-most, most)
                } else {
                    self.direction * most
                };
                self.wait(s, SETPOINT_PERIOD_S);
                Request::SetTorques(SetTorques { torques_nm: t })
            }
            Mode::Pvt if !self.moved => {
                self.moved = true;
                let (lo, hi) = (lim.min_deg[self.axis], lim.max_deg[self.axis]);
                let target = if self.direction > 0.0 {
                    hi - 0.5
                } else {
                    lo + 0.5
                };
                Request::MoveAxis(MoveAxis {
                    axis: Axis::ALL[self.axis],
                    target_deg: target,
                    velocity_factor: self.factor,
                })
            }
            _ => return None,
        };
        Some(self.request(r))
    }
}
