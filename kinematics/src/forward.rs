//! Forward kinematics (flange and TCP) and the geometric Jacobian at the TCP.

use crate::{Kinematics, N};
use nalgebra::{Isometry3, Matrix3, Matrix6, Rotation3, Translation3, UnitQuaternion, Vector3};

/// The DH frames of one joint vector, in the base frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frames {
    /// Rotation of frame i (index i−1: frames 1..6).
    pub rot: [Matrix3<f64>; N],
    /// Origin of frame i (index i−1).
    pub origin: [Vector3<f64>; N],
}

impl Frames {
    /// Direction of joint i's axis (0-based `i`): z of frame i−1.
    pub fn axis(&self, i: usize) -> Vector3<f64> {
        match i.checked_sub(1) {
            Some(p) => self.rot[p].column(2).into_owned(),
            None => Vector3::z(),
        }
    }

    /// A point on joint i's axis (0-based `i`): the origin of frame i−1.
    pub fn axis_point(&self, i: usize) -> Vector3<f64> {
        match i.checked_sub(1) {
            Some(p) => self.origin[p],
            None => Vector3::zeros(),
        }
    }
}

impl Kinematics {
    pub(crate) fn frames(&self, q: &[f64; N]) -> Frames {
        let mut f = Frames {
            rot: [Matrix3::identity(); N],
            origin: [Vector3::zeros(); N],
        };
        let mut r = Matrix3::identity();
        let mut o = Vector3::zeros();
        for (i, (link, qi)) in self.links.iter().zip(q).enumerate() {
            let (rl, ol) = link.transform(*qi);
            o += r * ol;
            r *= rl;
            f.rot[i] = r;
            f.origin[i] = o;
        }
        f
    }

    /// The flange (DH frame 6) in the base frame (DH frame 0) for the joint values `q` [rad].
    pub fn flange_pose(&self, q: &[f64; N]) -> Isometry3<f64> {
        let f = self.frames(q);
        iso(&f.rot[N - 1], &f.origin[N - 1])
    }

    /// The TCP in the base frame: the flange times the TCP transform ([`Kinematics::tcp`]).
    pub fn tcp_pose(&self, q: &[f64; N]) -> Isometry3<f64> {
        self.flange_pose(q) * self.tcp
    }

    /// The geometric Jacobian of the TCP for the joint values `q` [rad]: column i is the TCP's
    /// velocity for a unit velocity of joint i (1 rad/s); rows 0..3 the linear velocity of the
    /// TCP's origin [m/s], rows 3..6 the angular velocity [rad/s], both in base-frame axes
    /// (what Pinocchio calls `LOCAL_WORLD_ALIGNED`; `mcm_dynamics::ArmModel::flange_jacobian`'s
    /// convention, at the TCP instead of the flange).
    pub fn tcp_jacobian(&self, q: &[f64; N]) -> Matrix6<f64> {
        let f = self.frames(q);
        let p = f.origin[N - 1] + f.rot[N - 1] * self.tcp.translation.vector;
        let mut j = Matrix6::zeros();
        for i in 0..N {
            let z = f.axis(i);
            let lin = z.cross(&(p - f.axis_point(i)));
            j.fixed_view_mut::<3, 1>(0, i).copy_from(&lin);
            j.fixed_view_mut::<3, 1>(3, i).copy_from(&z);
        }
        j
    }
}

/// An isometry from a rotation matrix (proper, orthonormal up to rounding) and an origin.
pub(crate) fn iso(r: &Matrix3<f64>, o: &Vector3<f64>) -> Isometry3<f64> {
    let rot = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*r));
    Isometry3::from_parts(Translation3::from(*o), rot)
}

#[cfg(test)]
mod tests;
