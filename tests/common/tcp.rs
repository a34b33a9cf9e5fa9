//! The true TCP of the simulated arm for the Cartesian end-to-end tests: the simulation's
//! ground truth (`sim` `true_position`, `true_velocity`, in degrees) through the MCM's own
//! kinematics of the P-Rob2 with its configured TCP.

use mcm_kinematics::Kinematics;
use mcm_shared::config::RobotConfig;

/// A configuration [deg] away from the singularities (the wrist bent 50 deg, the elbow 60 deg),
/// within every axis's range, that the Cartesian tests start from.
pub const START: [f64; 6] = [20.0, 30.0, 60.0, -40.0, 50.0, 10.0];

/// The P-Rob2's kinematics with the TCP of the embedded configuration.
pub fn kinematics() -> Kinematics {
    Kinematics::from_config(&RobotConfig::prob2_default()).expect("the P-Rob2's kinematics")
}

/// The TCP at one instant: position [m], orientation `[x, y, z, w]`, its z axis in the base
/// frame, and the linear velocity of its origin [m/s].
#[derive(Debug, Clone, Copy)]
pub struct TrueTcp {
    pub position: [f64; 3],
    pub orientation: [f64; 4],
    pub z: [f64; 3],
    pub velocity: [f64; 3],
}

/// The TCP of the axes at `q_deg` moving at `v_deg_s`.
pub fn true_tcp(kin: &Kinematics, q_deg: &[f64; 6], v_deg_s: &[f64; 6]) -> TrueTcp {
    let q = q_deg.map(f64::to_radians);
    let qd = v_deg_s.map(f64::to_radians);
    let pose = kin.tcp_pose(&q);
    let j = kin.tcp_jacobian(&q);
    let r = pose.rotation.to_rotation_matrix();
    let (t, o) = (pose.translation.vector, pose.rotation.coords);
    TrueTcp {
        position: [t.x, t.y, t.z],
        orientation: [o.x, o.y, o.z, o.w],
        z: core::array::from_fn(|i| r[(i, 2)]),
        velocity: core::array::from_fn(|i| (0..6).map(|k| j[(i, k)] * qd[k]).sum()),
    }
}

/// `a - b`.
pub fn minus(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    core::array::from_fn(|i| a[i] - b[i])
}

/// The length of `a`.
pub fn norm(a: &[f64; 3]) -> f64 {
    a.iter().map(|x| x * x).sum::<f64>().sqrt()
}
