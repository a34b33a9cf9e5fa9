//! VELOCITY_CONTROL: joint velocities from `set_velocities`, or the TCP's velocity from
//! `set_cartesian_velocity` turned into joint velocities every cycle ([`twist`]), ramped within
//! each axis's velocity, acceleration and jerk limits ([`ramp`]) and braked before the joint
//! limits, under position control (the drives follow the integrated reference, as in PVT),
//! with every safety check of a motion mode active. Either command replaces the target of the
//! other; the ramp goes on from the commanded state. Neither within the timeout: the
//! controlled stop to HOLD, as `hold` does.
//!
//! Runs inside the cycle: no allocation, plain `Copy` data.

pub mod ramp;
pub mod twist;

use super::Controller;
use super::exits::Exit;
use super::state::{Caller, State, Watchdog};
use crate::params::JointParams;
use crate::safety::SafetyParams;
use mcm_shared::NUM_AXES;
use mcm_shared::command::{Axis, SetCartesianVelocity, SetVelocities, VelocityControl};
use mcm_shared::ranges::Arg;
use mcm_shared::reply::{Done, Reason};
use mcm_shared::units::deg_to_rad;
use ramp::{AxisRamp, RampLimits};
use twist::Twist;

/// What VELOCITY_CONTROL drives the axes towards.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum VelocityTarget {
    /// Each axis's velocity [rad/s] (`set_velocities`).
    Joint([f64; NUM_AXES]),
    /// The TCP's velocity (`set_cartesian_velocity`), turned into joint velocities each cycle.
    Cartesian(Twist),
}

/// Share of the braking-distance check's deceleration (`safety.braking_efficiency` x the
/// maximum acceleration) that velocity control plans to brake with before a limit: the
/// measured state, which lags the command, then stays well inside the check.
pub const BRAKE_SHARE: f64 = 0.5;
/// Distance kept between where a joint driven into a limit comes to rest and the limit less
/// the safety margin [rad] (0.25 deg), for the following error.
pub const STOP_CLEARANCE_RAD: f64 = 0.25 * core::f64::consts::PI / 180.0;

/// The ramp limits of axis `i` (0-based) from the joint and safety parameters.
pub fn ramp_limits(p: &JointParams, s: &SafetyParams, i: usize) -> RampLimits {
    let l = p.limits[i];
    let brake = (BRAKE_SHARE * s.brake_decel[i]).min(l.acceleration);
    let jerk = l.jerk.unwrap_or(f64::INFINITY);
    // The jerk ramp from full acceleration to the braking deceleration, one cycle of the ramp
    // itself, and the reaction latency the braking check counts.
    let lookahead_s = (l.acceleration + brake) / jerk + p.period + s.cycle_s + s.reaction_s;
    RampLimits {
        velocity: l.velocity,
        acceleration: l.acceleration,
        jerk,
        brake,
        lookahead_s,
        stop_min: s.q_min[i] + s.margin + STOP_CLEARANCE_RAD,
        stop_max: s.q_max[i] - s.margin - STOP_CLEARANCE_RAD,
    }
}

impl Controller {
    /// Enter VELOCITY_CONTROL (the caller checked HOLD and calibration): every axis's target is
    /// 0, the ramp starts from the commanded state (a stop under way in HOLD carries on
    /// smoothly).
    pub(super) fn enter_velocity_control(&mut self, c: Caller, v: VelocityControl) {
        self.state = State::Velocity {
            target: VelocityTarget::Joint([0.0; NUM_AXES]),
            watchdog: Watchdog::start(v.timeout_s, self.now_ns),
        };
        self.done(c, Done::Ack);
    }

    /// New target velocities, each within its axis's maximum velocity ([`Arg::Velocities`],
    /// the range and words the gateway uses); refused whole (the last targets stay) when one
    /// is not.
    pub(super) fn on_set_velocities(&mut self, c: Caller, v: SetVelocities) {
        let State::Velocity { watchdog, .. } = self.state else {
            return self.wrong_mode(c);
        };
        let mut target = [0.0; NUM_AXES];
        for (i, deg_s) in v.velocities_deg_s.iter().copied().enumerate() {
            let max_deg_s = self.p.max_velocity_deg_s[i];
            let bounds = (-max_deg_s, max_deg_s);
            if let Err(e) = Arg::Velocities.check(deg_s, bounds, Some(Axis::ALL[i])) {
                return self.refuse(c, Reason::InvalidArgument { refusal: e });
            }
            let max = self.p.limits[i].velocity;
            target[i] = deg_to_rad(deg_s).clamp(-max, max);
        }
        self.set_velocity_target(c, VelocityTarget::Joint(target), watchdog);
    }

    /// A new TCP velocity (its ranges checked when its sample was decoded: [`Arg::Linear`],
    /// [`Arg::Angular`]).
    pub(super) fn on_set_cartesian_velocity(&mut self, c: Caller, v: SetCartesianVelocity) {
        let State::Velocity { watchdog, .. } = self.state else {
            return self.wrong_mode(c);
        };
        let twist = Twist {
            linear: v.linear_m_s,
            angular: v.angular_deg_s.map(deg_to_rad),
            frame: v.frame,
        };
        self.set_velocity_target(c, VelocityTarget::Cartesian(twist), watchdog);
    }

    /// The new target of VELOCITY_CONTROL, the timeout fed.
    fn set_velocity_target(
        &mut self,
        c: Caller,
        target: VelocityTarget,
        watchdog: Option<Watchdog>,
    ) {
        self.state = State::Velocity {
            target,
            watchdog: watchdog.map(|w| w.fed(self.now_ns)),
        };
        self.done(c, Done::Ack);
    }

    /// One cycle of VELOCITY_CONTROL: the ramp towards the targets, or, once the timeout
    /// passed without `set_velocities` or `set_cartesian_velocity`, the controlled stop to
    /// HOLD.
    pub(super) fn advance_velocity(&mut self, target: VelocityTarget, watchdog: Option<Watchdog>) {
        if watchdog.is_some_and(|w| w.expired(self.now_ns)) {
            return self.leave(Exit::Timeout);
        }
        let dt = self.p.period;
        let limits: [RampLimits; NUM_AXES] =
            core::array::from_fn(|i| ramp_limits(&self.p, &self.safety, i));
        let target = match target {
            VelocityTarget::Joint(t) => t,
            VelocityTarget::Cartesian(twist) => {
                twist::joint_target(self.kinematics(), &self.cmd.position, &twist, &limits)
            }
        };
        for (i, (t, l)) in target.iter().copied().zip(&limits).enumerate() {
            let s = ramp::step(
                AxisRamp {
                    position: self.cmd.position[i],
                    velocity: self.cmd.velocity[i],
                    acceleration: self.cmd.acceleration[i],
                },
                t,
                l,
                dt,
            );
            self.cmd.position[i] = s.position;
            self.cmd.velocity[i] = s.velocity;
            self.cmd.acceleration[i] = s.acceleration;
        }
    }
}

// Scenario tests on the whole simulated robot.
#[cfg(all(test, feature = "sim"))]
mod tests;
