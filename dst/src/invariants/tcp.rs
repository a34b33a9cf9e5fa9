//! The invariant of the TCP's state (`cartesian_state`, the sample's `cartesian`): with every
//! axis calibrated it is present and equals the forward kinematics of the axis positions the
//! same sample reports (position within [`POSITION_M`], orientation within
//! [`ORIENTATION_RAD`]) and, for its velocity, the geometric Jacobian there times the axis
//! velocities the sample reports (within [`LINEAR_M_S`] and [`ANGULAR_DEG_S`]); before, it is
//! absent (`STATE_CARTESIAN` clear, every value zero). The tester computes it with
//! `mcm-kinematics` from the configuration and the TCP of the tool the sample reports, not
//! with the core's own code.

use mcm_kinematics::{Kinematics, KinematicsError, tcp_transform};
use mcm_shared::config::RobotConfig;
use mcm_shared::sample::{STATE_ALL_CALIBRATED, STATE_CARTESIAN, StateSample, TcpState};
use mcm_shared::tool::Tool;
use nalgebra::{Vector3, Vector6};

/// How far the reported TCP position may be from the forward kinematics [m].
pub const POSITION_M: f64 = 1e-9;
/// How far the reported orientation may be turned from the forward kinematics' [rad].
pub const ORIENTATION_RAD: f64 = 1e-9;
/// How far the reported linear velocity may be from the Jacobian's [m/s].
pub const LINEAR_M_S: f64 = 1e-9;
/// How far the reported angular velocity may be from the Jacobian's [deg/s].
pub const ANGULAR_DEG_S: f64 = 1e-9;

/// The kinematics the TCP's state is checked against.
pub struct TcpCheck {
    kin: Result<Kinematics, KinematicsError>,
}

impl TcpCheck {
    /// The check of a run under `cfg` (the TCP: the one each sample reports in its `tool`).
    pub fn new(cfg: &RobotConfig) -> TcpCheck {
        TcpCheck {
            kin: Kinematics::from_config(cfg),
        }
    }

    /// The TCP's state of `s` against the kinematics of its own axis values; `Err` names what
    /// differs, by how much, and the axis values.
    pub fn check(&self, s: &StateSample) -> Result<(), String> {
        let present = s.flags & STATE_CARTESIAN != 0;
        if s.flags & STATE_ALL_CALIBRATED == 0 {
            if present || s.cartesian != TcpState::default() {
                return Err(format!(
                    "cartesian_state present (flag {present}, {:?}) while not every axis is calibrated",
                    s.cartesian
                ));
            }
            return Ok(());
        }
        if !present {
            return Err(format!(
                "cartesian_state absent with every axis calibrated (position {:?} deg)",
                s.position
            ));
        }
        let mut kin = *self.kin.as_ref().map_err(|e| {
            format!("cartesian_state published for an arm the kinematics refuse: {e}")
        })?;
        // The TCP of the tool the same sample reports (`set_tool`'s, or the configuration's).
        kin.set_tcp(tcp_transform(&Tool::from(&s.tool).tcp))
            .map_err(|e| format!("the sample's tool {:?}: {e}", s.tool))?;
        let q = s.position.map(f64::to_radians);
        let pose = kin.tcp_pose(&q);
        let twist = kin.tcp_jacobian(&q) * Vector6::from(s.velocity.map(f64::to_radians));
        let t = &s.cartesian;
        let reported = mcm_kinematics::rotation(t.orientation);
        let differences = [
            (
                "position",
                (Vector3::from(t.position) - pose.translation.vector).norm(),
                POSITION_M,
                "m",
            ),
            (
                "orientation",
                reported.angle_to(&pose.rotation),
                ORIENTATION_RAD,
                "rad",
            ),
            (
                "orientation's norm",
                (t.orientation.iter().map(|c| c * c).sum::<f64>().sqrt() - 1.0).abs(),
                ORIENTATION_RAD,
                "",
            ),
            (
                "linear_velocity",
                (Vector3::from(t.linear_velocity) - twist.fixed_rows::<3>(0)).norm(),
                LINEAR_M_S,
                "m/s",
            ),
            (
                "angular_velocity",
                (Vector3::from(t.angular_velocity) - twist.fixed_rows::<3>(3).map(f64::to_degrees))
                    .norm(),
                ANGULAR_DEG_S,
                "deg/s",
            ),
        ];
        match differences.iter().find(|d| d.1.is_nan() || d.1 > d.2) {
            Some((what, off, allowed, unit)) => Err(format!(
                "cartesian_state {what} is {off:e} {unit} off the kinematics of the reported axes (allowed {allowed:e}): {t:?}, position {:?} deg, velocity {:?} deg/s",
                s.position, s.velocity
            )),
            None => Ok(()),
        }
    }
}
