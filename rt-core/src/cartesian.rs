//! The TCP's state in the published sample ([`TcpState`], `cartesian_state` of the protocol):
//! the TCP's pose in the base frame from the forward kinematics of the axis positions the
//! sample reports, and its velocity from the geometric Jacobian times the axis velocities the
//! sample reports (commanded in PVT and HOLD, measured otherwise: the same values a `status`
//! result shows beside it). Present once every axis is calibrated ([`STATE_CARTESIAN`]); all
//! zeros before, since an uncalibrated angle says nothing about where the arm is.
//!
//! Runs inside the cycle, after [`crate::publish::compose`] has written the axis values: one
//! forward kinematics and one Jacobian of `mcm-kinematics`, fixed-size, no allocation, no lock.
//! The kinematics are built once at start ([`Cartesian::from_config`], which refuses an arm the
//! kinematics cannot handle).
//!
//! ```
//! use mcm_rt_core::cartesian::Cartesian;
//! use mcm_shared::config::RobotConfig;
//! use mcm_shared::sample::{STATE_ALL_CALIBRATED, STATE_CARTESIAN, StateSample};
//! let cartesian = Cartesian::from_config(&RobotConfig::prob2_default()).unwrap();
//! let mut s = StateSample { flags: STATE_ALL_CALIBRATED, ..StateSample::default() };
//! cartesian.compose(&mut s);
//! assert_ne!(s.flags & STATE_CARTESIAN, 0);
//! let w = s.cartesian.orientation[3];
//! assert!(w >= 0.0);
//! ```

use mcm_kinematics::{Kinematics, KinematicsError, TcpError, tcp_transform};
use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;
use mcm_shared::sample::{STATE_ALL_CALIBRATED, STATE_CARTESIAN, StateSample, TcpState};
use mcm_shared::tool::Tcp;
use mcm_shared::units::{deg_to_rad6, rad_to_deg};
use nalgebra::Vector6;

/// Why the core cannot compute the TCP's state for this configuration.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CartesianSetupError {
    /// An arm the kinematics cannot handle.
    #[error(transparent)]
    Arm(#[from] KinematicsError),
    /// The configured tool's TCP transform.
    #[error("the configured tool's TCP: {0}")]
    Tcp(#[from] TcpError),
}

/// The arm's kinematics with the active tool's TCP, as the cycle uses them for the state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cartesian {
    kin: Kinematics,
    /// The TCP `kin` has, as the tool gives it (to see when the active tool's changes).
    tcp: Tcp,
}

impl Cartesian {
    /// The kinematics of the configured arm with the configured tool's TCP. Refuses a
    /// configuration whose arm the kinematics cannot handle ([`KinematicsError`], naming the
    /// link, the key and what is needed) or whose tool's TCP is not a transform.
    pub fn from_config(cfg: &RobotConfig) -> Result<Cartesian, CartesianSetupError> {
        let mut c = Cartesian {
            kin: Kinematics::from_config(cfg)?,
            tcp: Tcp::FLANGE,
        };
        c.follow_tool(&cfg.arm.tool.active().tcp)?;
        Ok(c)
    }

    /// The one place the core's TCP is set: make the active tool's `tcp` the TCP of every
    /// following sample, if it is not already (the controller calls this when `set_tool`
    /// changes its tool, in the cycle the tool changes, so a sample's `cartesian` is computed
    /// with the tool the same sample reports). Refused, the
    /// TCP unchanged, when not a transform; the controller's tools are checked when they are
    /// taken (`mcm_shared::tool::Tool::new`), so it is not. Allocation-free.
    pub fn follow_tool(&mut self, tcp: &Tcp) -> Result<(), TcpError> {
        if *tcp != self.tcp {
            self.kin.set_tcp(tcp_transform(tcp))?;
            self.tcp = *tcp;
        }
        Ok(())
    }

    /// The kinematics in use.
    pub fn kinematics(&self) -> &Kinematics {
        &self.kin
    }

    /// Write the TCP's state of `s` from its `position` and `velocity` and set
    /// [`STATE_CARTESIAN`] when `s` has [`STATE_ALL_CALIBRATED`]; otherwise zero it and clear
    /// the flag.
    pub fn compose(&self, s: &mut StateSample) {
        if s.flags & STATE_ALL_CALIBRATED == 0 {
            s.flags &= !STATE_CARTESIAN;
            s.cartesian = TcpState::default();
            return;
        }
        s.cartesian = self.tcp_state(&s.position, &s.velocity);
        s.flags |= STATE_CARTESIAN;
    }

    /// The TCP's state at axis positions `position_deg` [deg] moving at `velocity_deg_s`
    /// [deg/s].
    pub fn tcp_state(
        &self,
        position_deg: &[f64; NUM_AXES],
        velocity_deg_s: &[f64; NUM_AXES],
    ) -> TcpState {
        let q = deg_to_rad6(position_deg);
        let pose = self.kin.tcp_pose(&q);
        let twist = self.kin.tcp_jacobian(&q) * Vector6::from(deg_to_rad6(velocity_deg_s));
        let t = pose.translation.vector;
        let r = pose.rotation.quaternion().coords;
        // q and -q are the same rotation: the one with w >= 0, so that readers see one form.
        let sign = if r.w < 0.0 { -1.0 } else { 1.0 };
        TcpState {
            position: [t.x, t.y, t.z],
            orientation: [sign * r.x, sign * r.y, sign * r.z, sign * r.w],
            linear_velocity: [twist[0], twist[1], twist[2]],
            angular_velocity: [
                rad_to_deg(twist[3]),
                rad_to_deg(twist[4]),
                rad_to_deg(twist[5]),
            ],
        }
    }
}

#[cfg(test)]
mod tests;
