//! The kind of arm the analytic solver handles, checked once when the configuration is loaded,
//! and the constants of its closed-form solution.
//!
//! Supported: six revolute axes in standard DH form where
//! - axis 2 is perpendicular to axis 1 (link 1: α = ±90°; `d` and `a` free),
//! - axes 2 and 3 are parallel (link 2: α = 0°, `a` ≠ 0: the upper arm; `d` free),
//! - a forearm reaches from axis 3 to the wrist (link 3's `a` or link 4's `d` non-zero; link
//!   3's `d` and α free),
//! - the wrist is spherical: axes 4, 5 and 6 meet in one point, the wrist centre (link 4:
//!   `a` = 0, α = ±90°; link 5: `a` = 0, `d` = 0, α = ±90°),
//! - link 6 is free (its `d`, `a` and α place the flange relative to the wrist centre).
//!
//! The P-Rob2, the PUMA and most six-axis industrial arms are of this kind.

use crate::dh::Dh;
use mcm_shared::NUM_AXES;
use mcm_shared::config::LinkConfig;
use nalgebra::{Matrix3, Rotation3, Vector3};

/// How far an angle of the configuration may be from the value the solver needs [deg].
pub const ANGLE_TOLERANCE_DEG: f64 = 1e-9;

/// How far from zero a length of the configuration may be where the solver needs zero [m]
/// (well under the solver's accuracy of 1 µm).
pub const LENGTH_TOLERANCE_M: f64 = 1e-9;

/// Why a configuration gives no kinematics. Every message names the key, the value found and
/// what the solver needs.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KinematicsError {
    /// The configuration has the wrong number of `[[arm.link]]` or `[[axis]]` tables.
    #[error("config `{key}` has {found} entries; the kinematics need exactly {NUM_AXES}")]
    WrongCount { key: &'static str, found: usize },
    /// A value is not a finite number, or out of its range.
    #[error("config key `{key}` = {value} is not allowed: {allowed}")]
    Invalid {
        key: String,
        value: f64,
        allowed: &'static str,
    },
    /// The arm is of a kind the analytic inverse kinematics cannot solve.
    #[error(
        "config key `{key}` = {value}: the analytic inverse kinematics cannot solve this arm; \
         it needs {needed}"
    )]
    Unsupported {
        key: String,
        value: f64,
        needed: &'static str,
    },
}

/// Sign of a twist the solver needs to be ±90°: +1 or −1 (the twist exactly ±90° with that
/// sign is assumed in the closed form).
fn quarter_turn(alpha_deg: f64) -> Option<f64> {
    let r = alpha_deg.rem_euclid(360.0);
    if (r - 90.0).abs() <= ANGLE_TOLERANCE_DEG {
        Some(1.0)
    } else if (r - 270.0).abs() <= ANGLE_TOLERANCE_DEG {
        Some(-1.0)
    } else {
        None
    }
}

fn is_zero_turn(alpha_deg: f64) -> bool {
    let r = alpha_deg.rem_euclid(360.0);
    r <= ANGLE_TOLERANCE_DEG || 360.0 - r <= ANGLE_TOLERANCE_DEG
}

/// The constants of the closed-form solution, derived from the six links.
///
/// With θ1 turned out, the wrist centre seen from frame 1 lies in the plane of axes 2 and 3 at
/// a constant height `h` along axis 2; the upper arm (`a2`) and the forearm (length `forearm`,
/// at angle θ3 + `forearm_angle` from the upper arm) form a planar two-link arm in that plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Shape {
    /// sin α1 (±1).
    pub s1: f64,
    pub a1: f64,
    pub d1: f64,
    pub a2: f64,
    /// The wrist centre's lateral offset from axis 1 in the rotated base frame: −s1·h, with
    /// h = d2 + d3 + d4·cos α3 [m].
    pub lateral: f64,
    /// Distance from axis 3 to the wrist centre, perpendicular to axis 3 [m].
    pub forearm: f64,
    /// Angle from x of frame 2 to the line from axis 3 to the wrist centre when θ3 = 0 [rad]:
    /// that line is at θ3 + this in the plane of axes 2 and 3.
    pub forearm_angle: f64,
    /// sin α5 (±1).
    pub s5: f64,
    /// The wrist centre in the flange frame, negated: centre = flange − R6 · this [m].
    pub wrist_offset: Vector3<f64>,
    /// Axis 6's direction in the flange frame.
    pub axis6: Vector3<f64>,
    /// Rx(α6)ᵀ: from the flange frame to frame 5 turned by θ6.
    pub unturn6: Matrix3<f64>,
}

impl Shape {
    /// Check the links' shape and derive the constants; `links` are the configured ones.
    pub fn new(cfg: &[LinkConfig], links: &[Dh; NUM_AXES]) -> Result<Shape, KinematicsError> {
        let key = |i: usize, name: &str| format!("arm.link[{}].{name}", i + 1);
        let unsupported = |i: usize, name: &str, value: f64, needed: &'static str| {
            Err(KinematicsError::Unsupported {
                key: key(i, name),
                value,
                needed,
            })
        };
        let Some(s1) = quarter_turn(cfg[0].alpha_deg) else {
            return unsupported(
                0,
                "alpha_deg",
                cfg[0].alpha_deg,
                "alpha_deg = 90 or -90 (axis 2 perpendicular to axis 1)",
            );
        };
        if !is_zero_turn(cfg[1].alpha_deg) {
            return unsupported(
                1,
                "alpha_deg",
                cfg[1].alpha_deg,
                "alpha_deg = 0 (axes 2 and 3 parallel)",
            );
        }
        if cfg[1].a.abs() <= LENGTH_TOLERANCE_M {
            return unsupported(
                1,
                "a",
                cfg[1].a,
                "a != 0 (an upper arm from axis 2 to axis 3)",
            );
        }
        if cfg[3].a.abs() > LENGTH_TOLERANCE_M {
            return unsupported(
                3,
                "a",
                cfg[3].a,
                "a = 0 (a spherical wrist: axes 4, 5 and 6 meeting in one point)",
            );
        }
        let Some(_) = quarter_turn(cfg[3].alpha_deg) else {
            return unsupported(
                3,
                "alpha_deg",
                cfg[3].alpha_deg,
                "alpha_deg = 90 or -90 (axis 5 perpendicular to axis 4)",
            );
        };
        for (name, v) in [("a", cfg[4].a), ("d", cfg[4].d)] {
            if v.abs() > LENGTH_TOLERANCE_M {
                return unsupported(
                    4,
                    name,
                    v,
                    "a = 0 and d = 0 (a spherical wrist: axes 4, 5 and 6 meeting in one point)",
                );
            }
        }
        let Some(s5) = quarter_turn(cfg[4].alpha_deg) else {
            return unsupported(
                4,
                "alpha_deg",
                cfg[4].alpha_deg,
                "alpha_deg = 90 or -90 (axis 6 perpendicular to axis 5)",
            );
        };
        let (l2, l3, l4, l6) = (&links[1], &links[2], &links[3], &links[5]);
        let (sa3, ca3) = (l3.sin_alpha(), l3.cos_alpha());
        let forearm = l3.a.hypot(sa3 * l4.d);
        if forearm <= LENGTH_TOLERANCE_M {
            return unsupported(
                3,
                "d",
                cfg[3].d,
                "a forearm: link 3's a or link 4's d (across a twisted axis 3) non-zero",
            );
        }
        let h = l2.d + l3.d + ca3 * l4.d;
        let unturn6 = Rotation3::from_axis_angle(&Vector3::x_axis(), -l6.alpha).into_inner();
        Ok(Shape {
            s1,
            a1: links[0].a,
            d1: links[0].d,
            a2: l2.a,
            lateral: -s1 * h,
            forearm,
            forearm_angle: (-sa3 * l4.d).atan2(l3.a),
            s5,
            wrist_offset: unturn6 * Vector3::new(l6.a, 0.0, l6.d),
            axis6: unturn6 * Vector3::z(),
            unturn6,
        })
    }
}
