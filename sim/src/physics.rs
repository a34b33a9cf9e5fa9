//! The physics of the simulated arm: [`ArmSim`] holds the true joint state and integrates it.
//!
//! Runs inside the cycle thread (the simulated bus steps it): [`ArmSim::step`] and every
//! setter/getter is allocation-free and panic-free; only [`ArmSim::new`] runs at start-up.
//! The result is a pure function of the initial state, the inputs and `dt` (no clocks, no
//! randomness), so it does not depend on the machine's speed.
//!
//! Physics per step: rigid-body dynamics of [`ArmModel`] (inertia incl. armature and tool,
//! Coriolis/centrifugal, gravity), actuator and external torques, viscous friction, Coulomb
//! friction with true stiction ([`mcm_dynamics::solve_friction`]), holding brakes,
//! mechanical stops and blocking obstacles as stiff spring-dampers.
//!
//! Integrator: semi-implicit (symplectic) Euler, `q̇ₙ₊₁ = q̇ₙ + dt·q̈`, `qₙ₊₁ = qₙ + dt·q̇ₙ₊₁`,
//! with the stiff diagonal terms (stop/obstacle springs and dampers, viscous friction)
//! treated implicitly: `(M + dt·(c + k·dt)) q̈ = τ − b − k·Δq − (c + k·dt)·q̇ₙ`. This is
//! unconditionally stable for the stops (20000 Nm/rad, 200 Nm s/rad on a 0.03 kg m² wrist
//! axis would need dt < 0.3 ms explicitly), and lets the Coulomb torques be chosen at
//! velocity level so a joint at rest does not creep. A stop acts while the joint is beyond it
//! at the start of the step (spring plus damper, the damper also while leaving).
//!
//! ```
//! use mcm_dynamics::ArmModel;
//! use mcm_sim::physics::ArmSim;
//! let cfg = mcm_shared::config::RobotConfig::prob2_default();
//! let mut sim = ArmSim::new(ArmModel::from_config(&cfg), &cfg);
//! let q0 = sim.position();
//! let hold = sim.model().gravity_torques(&q0);
//! for _ in 0..2000 {
//!     sim.step(&hold, 500e-6); // one second held still
//! }
//! assert_eq!(sim.position(), q0);
//! ```

use mcm_dynamics::{ArmModel, DynamicsError, inverse_spd, solve_friction};
use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;
use nalgebra::Vector6;

const N: usize = NUM_AXES;

/// A holding brake holds up to this multiple of the axis's peak joint torque
/// (`max_current_a · torque_per_amp()`). Not in the configuration; a named constant here.
pub const BRAKE_HOLD_FACTOR: f64 = 2.0;

/// Numerical guard: joint speeds are clamped to ±this [rad/s] after each step. Far above
/// anything the arm can do (≈ 10 000 rpm joint side); it only keeps the state finite when
/// absurd inputs (e.g. 10⁶ Nm with a 0.1 s step) would otherwise blow the explicit
/// Coriolis terms up.
pub const MAX_JOINT_SPEED_RAD_S: f64 = 1000.0;

/// The true state and physics of the simulated arm.
#[derive(Debug, Clone)]
pub struct ArmSim {
    model: ArmModel,
    q: [f64; N],
    qd: [f64; N],
    stops: [(f64, f64); N],
    stop_stiffness: f64,
    stop_damping: f64,
    brake_fitted: [bool; N],
    brake_engaged: [bool; N],
    brake_hold: [f64; N],
    blocked_at: [Option<f64>; N],
    external: [f64; N],
    friction_on: bool,
    /// Coulomb torques of the last step (warm start of the friction solve).
    lambda: Vector6<f64>,
}

fn finite_or_zero(v: f64) -> f64 {
    if v.is_finite() { v } else { 0.0 }
}

impl ArmSim {
    /// The simulated arm at `cfg.sim.initial_position_deg`, at rest, friction on, no external
    /// torques, nothing blocked; holding brakes of axes with `brake = true` engaged (they are
    /// spring-applied: engaged until the drive releases them with [`ArmSim::set_brake`]).
    ///
    /// # Panics
    /// Only for a configuration `RobotConfig::validate` would refuse; see [`ArmSim::try_new`].
    pub fn new(model: ArmModel, cfg: &RobotConfig) -> ArmSim {
        match Self::try_new(model, cfg) {
            Ok(s) => s,
            Err(e) => panic!("arm simulation from an invalid configuration: {e}"),
        }
    }

    /// Like [`ArmSim::new`], returning a typed error naming the bad key.
    pub fn try_new(model: ArmModel, cfg: &RobotConfig) -> Result<ArmSim, DynamicsError> {
        if cfg.axes.len() != N {
            return Err(DynamicsError::WrongCount {
                key: "axis",
                found: cfg.axes.len(),
            });
        }
        let bad = |key: String, value: f64, allowed: &'static str| DynamicsError::Invalid {
            key,
            value,
            allowed,
        };
        let (k, c) = (cfg.sim.stop_stiffness_nm_rad, cfg.sim.stop_damping_nm_s_rad);
        if !(k.is_finite() && k > 0.0) {
            return Err(bad(
                "sim.stop_stiffness_nm_rad".into(),
                k,
                "a finite value > 0",
            ));
        }
        if !(c.is_finite() && c >= 0.0) {
            return Err(bad(
                "sim.stop_damping_nm_s_rad".into(),
                c,
                "a finite value >= 0",
            ));
        }
        let mut sim = ArmSim {
            model,
            q: [0.0; N],
            qd: [0.0; N],
            stops: [(0.0, 0.0); N],
            stop_stiffness: k,
            stop_damping: c,
            brake_fitted: [false; N],
            brake_engaged: [false; N],
            brake_hold: [0.0; N],
            blocked_at: [None; N],
            external: [0.0; N],
            friction_on: true,
            lambda: Vector6::zeros(),
        };
        for (i, a) in cfg.axes.iter().enumerate() {
            let (stop, lo, hi) = (a.calibration.stop_deg, a.min_deg, a.max_deg);
            let ok = stop.is_finite()
                && if a.calibration.direction > 0 {
                    stop > hi
                } else {
                    stop < lo
                };
            if !ok {
                let key = format!("axis[{}].calibration.stop_deg", i + 1);
                return Err(bad(
                    key,
                    stop,
                    "finite and beyond the software limit in the search direction",
                ));
            }
            // The opposite stop lies symmetrically beyond the other limit.
            let (s_lo, s_hi) = if a.calibration.direction > 0 {
                (lo - (stop - hi), stop)
            } else {
                (stop, hi + (lo - stop))
            };
            sim.stops[i] = (s_lo.to_radians(), s_hi.to_radians());
            sim.brake_fitted[i] = a.brake;
            sim.brake_engaged[i] = a.brake;
            sim.brake_hold[i] = BRAKE_HOLD_FACTOR * a.max_current_a * a.torque_per_amp();
            let q0 = cfg.sim.initial_position_deg[i];
            if !q0.is_finite() {
                return Err(bad(
                    format!("sim.initial_position_deg[{}]", i + 1),
                    q0,
                    "a finite angle",
                ));
            }
            sim.q[i] = q0.to_radians();
        }
        Ok(sim)
    }

    /// The (true) model the simulation uses.
    pub fn model(&self) -> &ArmModel {
        &self.model
    }

    /// Change the true model, e.g. the payload with `ArmModel::set_tool`.
    pub fn model_mut(&mut self) -> &mut ArmModel {
        &mut self.model
    }

    /// Integrate one physics step of `dt` seconds with joint-side motor torques
    /// `actuator_torque` [Nm]. Non-finite torques count as 0; a non-finite or non-positive `dt`
    /// does nothing. Meant for dt = `sim.physics_step_us` (500 µs); stable for larger steps,
    /// with less accuracy.
    pub fn step(&mut self, actuator_torque: &[f64; N], dt: f64) {
        if !(dt.is_finite() && dt > 0.0) {
            return;
        }
        let qd = Vector6::from(self.qd);
        let (mut a, bias) = self.model.mass_matrix_and_bias(&self.q, &self.qd);
        let friction = self.model.friction();
        let mut rhs = Vector6::zeros();
        let mut bound = Vector6::zeros();
        for i in 0..N {
            let (stiff, damp, spring) = self.spring_terms(i);
            let f = friction[i];
            let viscous = if self.friction_on { f.viscous } else { 0.0 };
            let s = damp + viscous + stiff * dt;
            let tau = finite_or_zero(actuator_torque[i]) + self.external[i];
            rhs[i] = tau - bias[i] + spring - s * qd[i];
            a[(i, i)] += dt * s;
            let coulomb = if self.friction_on { f.coulomb } else { 0.0 };
            let brake = if self.brake_fitted[i] && self.brake_engaged[i] {
                self.brake_hold[i]
            } else {
                0.0
            };
            bound[i] = coulomb + brake;
        }
        let w = inverse_spd(&a) * dt;
        let v_free = qd + w * rhs;
        let v = solve_friction(&w, &v_free, &bound, &mut self.lambda);
        if v.iter().all(|x| x.is_finite()) {
            for i in 0..N {
                let v = v[i].clamp(-MAX_JOINT_SPEED_RAD_S, MAX_JOINT_SPEED_RAD_S);
                self.qd[i] = v;
                self.q[i] += dt * v;
            }
        } else {
            self.lambda = Vector6::zeros();
        }
    }

    /// Stiffness, damping and spring torque at the current position from the mechanical stops
    /// and an obstacle blocking axis `i`.
    fn spring_terms(&self, i: usize) -> (f64, f64, f64) {
        let (k, c) = (self.stop_stiffness, self.stop_damping);
        let q = self.q[i];
        let (lo, hi) = self.stops[i];
        let mut out = if q < lo {
            (k, c, k * (lo - q))
        } else if q > hi {
            (k, c, -k * (q - hi))
        } else {
            (0.0, 0.0, 0.0)
        };
        if let Some(anchor) = self.blocked_at[i] {
            out = (out.0 + k, out.1 + c, out.2 - k * (q - anchor));
        }
        out
    }

    /// True joint angles [rad].
    pub fn position(&self) -> [f64; N] {
        self.q
    }

    /// True joint velocities [rad/s].
    pub fn velocity(&self) -> [f64; N] {
        self.qd
    }

    /// Put the arm at `q` [rad] moving with `qd` [rad/s] (tests, scenario set-up). Ignored if
    /// any value is not finite.
    pub fn set_state(&mut self, q: [f64; N], qd: [f64; N]) {
        if q.iter().chain(&qd).all(|v| v.is_finite()) {
            self.q = q;
            self.qd = qd;
            self.lambda = Vector6::zeros();
        }
    }

    /// External torques on the joints, e.g. a hand pushing the arm [Nm]; they act until
    /// replaced. Non-finite entries count as 0.
    pub fn set_external_torques(&mut self, tau: [f64; N]) {
        self.external = tau.map(finite_or_zero);
    }

    /// The external torques currently applied [Nm].
    pub fn external_torques(&self) -> [f64; N] {
        self.external
    }

    /// Block `axis` (0-based) by a rigid obstacle where it is now (a spring-damper with the stop
    /// stiffness and damping, anchored at the current angle, both directions), or remove the
    /// obstacle. Blocking an already blocked axis keeps the first anchor. Invalid axes are ignored.
    pub fn set_blocked(&mut self, axis: usize, blocked: bool) {
        if let (Some(b), Some(q)) = (self.blocked_at.get_mut(axis), self.q.get(axis)) {
            *b = match (blocked, *b) {
                (true, Some(anchor)) => Some(anchor),
                (true, None) => Some(*q),
                (false, _) => None,
            };
        }
    }

    /// Whether an obstacle blocks `axis`.
    pub fn is_blocked(&self, axis: usize) -> bool {
        matches!(self.blocked_at.get(axis), Some(Some(_)))
    }

    /// Engage or release the holding brake of `axis`. Only axes configured with `brake = true`
    /// have one; for the others (and invalid axes) this does nothing. An engaged brake holds
    /// like static friction up to [`BRAKE_HOLD_FACTOR`] × the axis's peak joint torque, and
    /// slips with that torque above it.
    pub fn set_brake(&mut self, axis: usize, engaged: bool) {
        if self.brake_fitted.get(axis) == Some(&true) {
            self.brake_engaged[axis] = engaged;
        }
    }

    /// Whether the holding brake of `axis` is fitted and engaged.
    pub fn brake_engaged(&self, axis: usize) -> bool {
        self.brake_fitted.get(axis) == Some(&true) && self.brake_engaged[axis]
    }

    /// Holding torque of the brake of `axis` [Nm] (0 without brake or for invalid axes).
    pub fn brake_holding_torque(&self, axis: usize) -> f64 {
        match self.brake_fitted.get(axis) {
            Some(true) => self.brake_hold[axis],
            _ => 0.0,
        }
    }

    /// Switch joint friction (Coulomb and viscous) on or off; brakes and stops are unaffected.
    pub fn set_friction_enabled(&mut self, on: bool) {
        self.friction_on = on;
        self.lambda = Vector6::zeros();
    }

    /// Angles of the mechanical stops of `axis` (lower, upper) [rad]; (−∞, +∞) for an invalid
    /// axis.
    pub fn mechanical_stops(&self, axis: usize) -> (f64, f64) {
        self.stops
            .get(axis)
            .copied()
            .unwrap_or((f64::NEG_INFINITY, f64::INFINITY))
    }

    /// Total mechanical energy [J]: kinetic (links and rotors) + gravitational potential +
    /// energy stored in compressed stops and obstacle springs.
    pub fn energy(&self) -> f64 {
        let mut e =
            self.model.kinetic_energy(&self.q, &self.qd) + self.model.potential_energy(&self.q);
        let k = self.stop_stiffness;
        for i in 0..N {
            let q = self.q[i];
            let (lo, hi) = self.stops[i];
            let pen = if q < lo {
                lo - q
            } else if q > hi {
                q - hi
            } else {
                0.0
            };
            e += 0.5 * k * pen * pen;
            if let Some(anchor) = self.blocked_at[i] {
                e += 0.5 * k * (q - anchor) * (q - anchor);
            }
        }
        e
    }
}

#[cfg(test)]
mod tests;
