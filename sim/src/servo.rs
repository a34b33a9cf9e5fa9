//! The position controller of the simulated drive in CSP: linear interpolation of the cyclic
//! target over one SYNC period, a PID position loop with velocity feed-forward and
//! anti-windup producing a joint torque, and the quick-stop ramp.
//!
//! Runs inside the cycle: plain `f64` arithmetic, no allocation. Positions are in the drive's
//! encoder frame expressed in joint radians (counts / counts_per_rad: the encoder offset is
//! included), velocities in rad/s, torques joint-side in Nm.
//!
//! # Gains and how they were chosen
//! The drive does not know the arm's inertia; its gains are proportional to the reflected
//! motor inertia `armature_kg_m2` of the axis (0.15 kg m^2 on axes 1-3, 0.03 on axes 4-6 of
//! the P-Rob2), which is the floor of the joint inertia and scales like the axis's torque
//! capacity: `kp = KP_PER_INERTIA * J`, `ki = KI_PER_INERTIA * J`, `kd = KD_PER_INERTIA * J`
//! (axes 1-3: kp = 15000 Nm/rad, ki = 150000 Nm/(rad s), kd = 150 Nm s/rad; axes 4-6: 1/5 of that).
//! - `kd / J = 1000 1/s`: on the bare armature (the smallest inertia an axis can see) the
//!   velocity term gives `kd * dt / J = 0.5` at the 0.5 ms physics step, well inside the
//!   explicit-step stability bound 2; more inertia only makes it smaller.
//! - `kp / J = 1e5 1/s^2`: position bandwidth sqrt(kp / J) = 316 rad/s on the bare armature
//!   (omega * dt = 0.16), about 60 rad/s on the shoulder with the stretched arm and the full
//!   3.8 kg tool (J ~ 4 kg m^2). The gravity sag before the integrator catches up is about
//!   tau_g / kp = 66 Nm / 15000 Nm/rad = 0.25 deg on a horizontal shoulder.
//! - `ki = 10 kp` (integral corner 10 rad/s, below every position bandwidth): removes the
//!   gravity and Coulomb-friction steady error. Anti-windup: the integral is clamped to the
//!   torque limit and frozen while the output saturates in the direction it would push.
//!
//! Checked with the real arm model (`sim::bus::tests`, through the whole bus with the full
//! tool): at five poses across the workspace the steady error after 1 s is below 0.001 deg
//! (required: 0.05 deg), the largest sag right after enabling is 0.29 deg (shoulder
//! horizontal), and a 30 deg/s ramp is followed with at most 0.11 deg lag behind the
//! set-point (less than the 0.15 deg the ramp moves in one 5 ms cycle).

/// Proportional gain per unit of reflected motor inertia [Nm/rad per kg m^2].
pub const KP_PER_INERTIA: f64 = 1.0e5;
/// Integral gain per unit of reflected motor inertia [Nm/(rad s) per kg m^2].
pub const KI_PER_INERTIA: f64 = 1.0e6;
/// Derivative (velocity) gain per unit of reflected motor inertia [Nm s/rad per kg m^2].
pub const KD_PER_INERTIA: f64 = 1.0e3;

/// PID gains of one axis, joint side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoGains {
    /// [Nm/rad]
    pub kp: f64,
    /// [Nm/(rad s)]
    pub ki: f64,
    /// [Nm s/rad]
    pub kd: f64,
}

impl ServoGains {
    /// The sim's tuning for an axis with this reflected motor inertia [kg m^2].
    pub fn for_armature(j: f64) -> ServoGains {
        ServoGains {
            kp: KP_PER_INERTIA * j,
            ki: KI_PER_INERTIA * j,
            kd: KD_PER_INERTIA * j,
        }
    }
}

/// Interpolator, PID state and quick-stop ramp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Servo {
    gains: ServoGains,
    seg_start: f64,
    seg_end: f64,
    seg_velocity: f64,
    integral: f64,
    ramp_position: f64,
    ramp_velocity: f64,
}

impl Servo {
    pub fn new(gains: ServoGains) -> Servo {
        Servo {
            gains,
            seg_start: 0.0,
            seg_end: 0.0,
            seg_velocity: 0.0,
            integral: 0.0,
            ramp_position: 0.0,
            ramp_velocity: 0.0,
        }
    }

    /// Hold `position` (no motion, integral cleared): used when the drive is enabled.
    pub fn hold(&mut self, position: f64) {
        self.seg_start = position;
        self.seg_end = position;
        self.seg_velocity = 0.0;
        self.integral = 0.0;
    }

    /// Start the next interpolation segment at SYNC: from the end of the previous one to
    /// `target`, over `period_s`.
    pub fn new_segment(&mut self, target: f64, period_s: f64) {
        self.seg_start = self.seg_end;
        self.seg_end = target;
        self.seg_velocity = (self.seg_end - self.seg_start) / period_s;
    }

    /// Interpolated set-point (position, velocity) at `fraction` (0..=1) of the period.
    pub fn setpoint(&self, fraction: f64) -> (f64, f64) {
        (
            self.seg_start + fraction * (self.seg_end - self.seg_start),
            self.seg_velocity,
        )
    }

    /// Start the quick-stop ramp from this set-point.
    pub fn start_quick_stop(&mut self, position: f64, velocity: f64) {
        self.ramp_position = position;
        self.ramp_velocity = velocity;
    }

    /// Advance the quick-stop ramp by `dt` at `deceleration`: the new set-point, and whether
    /// the ramp has come to rest.
    pub fn quick_stop_step(&mut self, deceleration: f64, dt: f64) -> (f64, f64, bool) {
        let dv = deceleration * dt;
        let v = self.ramp_velocity;
        self.ramp_velocity = if v.abs() <= dv {
            0.0
        } else {
            v - dv * v.signum()
        };
        self.ramp_position += 0.5 * (v + self.ramp_velocity) * dt;
        (
            self.ramp_position,
            self.ramp_velocity,
            self.ramp_velocity == 0.0,
        )
    }

    /// Clear the integral (entering a mode that does not use it).
    pub fn reset_integral(&mut self) {
        self.integral = 0.0;
    }

    /// One PID step: joint torque toward (`p_ref`, `v_ref`) from the measured (`p`, `v`),
    /// limited to +-`tau_max`.
    pub fn torque(&mut self, p_ref: f64, v_ref: f64, p: f64, v: f64, dt: f64, tau_max: f64) -> f64 {
        let g = self.gains;
        let e = p_ref - p;
        let pd = g.kp * e + g.kd * (v_ref - v);
        let integral = (self.integral + g.ki * e * dt).clamp(-tau_max, tau_max);
        let u = pd + integral;
        if u.abs() > tau_max {
            // anti-windup: keep the integral unless it moves the output out of saturation
            if (integral - self.integral) * u < 0.0 {
                self.integral = integral;
            }
            return tau_max.copysign(u);
        }
        self.integral = integral;
        u
    }
}

#[cfg(test)]
mod tests;
