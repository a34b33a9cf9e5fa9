//! One link's standard Denavit–Hartenberg parameters and its transform.

use nalgebra::{Matrix3, Vector3};

/// A link in standard DH form: frame i = frame i−1 · Rz(θ) · Tz(d) · Tx(a) · Rx(α), with the
/// joint angle θ = q + offset. Read-only once made (it keeps sin α and cos α).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dh {
    /// Offset along z of frame i−1 [m].
    pub(crate) d: f64,
    /// Length along x of frame i [m].
    pub(crate) a: f64,
    /// Twist about x of frame i [rad].
    pub(crate) alpha: f64,
    /// Joint offset: θ = q + offset [rad].
    pub(crate) offset: f64,
    /// sin α and cos α, kept: the kinematics run several times a cycle.
    sin_alpha: f64,
    cos_alpha: f64,
}

impl Dh {
    /// A link from its parameters (lengths in metres, angles in radians).
    pub fn new(d: f64, a: f64, alpha: f64, offset: f64) -> Dh {
        let (sin_alpha, cos_alpha) = alpha.sin_cos();
        Dh {
            d,
            a,
            alpha,
            offset,
            sin_alpha,
            cos_alpha,
        }
    }

    /// Rotation and origin of frame i in frame i−1 for the joint value `q` (θ = q + offset).
    #[inline]
    pub fn transform(&self, q: f64) -> (Matrix3<f64>, Vector3<f64>) {
        let (st, ct) = (q + self.offset).sin_cos();
        (
            self.rotation_theta(st, ct),
            Vector3::new(self.a * ct, self.a * st, self.d),
        )
    }

    /// Rotation of frame i in frame i−1, Rz(θ) Rx(α), for the joint angle θ (offset included).
    #[inline]
    pub fn rotation_at_theta(&self, theta: f64) -> Matrix3<f64> {
        let (st, ct) = theta.sin_cos();
        self.rotation_theta(st, ct)
    }

    fn rotation_theta(&self, st: f64, ct: f64) -> Matrix3<f64> {
        let (sa, ca) = (self.sin_alpha, self.cos_alpha);
        #[rustfmt::skip]
        let r = Matrix3::new(
            ct, -st * ca,  st * sa,
            st,  ct * ca, -ct * sa,
            0.0,      sa,       ca,
        );
        r
    }

    /// Offset along z of frame i−1 [m].
    pub fn d(&self) -> f64 {
        self.d
    }

    /// Length along x of frame i [m].
    pub fn a(&self) -> f64 {
        self.a
    }

    /// Twist about x of frame i [rad].
    pub fn alpha(&self) -> f64 {
        self.alpha
    }

    /// Joint offset: θ = q + offset [rad].
    pub fn offset(&self) -> f64 {
        self.offset
    }

    /// sin α.
    pub fn sin_alpha(&self) -> f64 {
        self.sin_alpha
    }

    /// cos α.
    pub fn cos_alpha(&self) -> f64 {
        self.cos_alpha
    }
}
