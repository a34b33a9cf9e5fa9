//! The tool the arm carries, as `set_tool` takes it and `[arm.tool]` configures it: the TCP
//! (tool centre point) as a transform of the flange frame, and the load (mass, centre of mass,
//! inertia). [`Tool::new`] is the one place its values are checked; every sender (the
//! configuration, the gateway's parser, the core's decoding of a sample) builds it there.
//!
//! Units: metres, kilograms, kg·m²; the orientation is a unit quaternion `[x, y, z, w]`, the
//! centre of mass and the TCP position are in the flange frame (DH frame 6), the inertia
//! `[ixx, iyy, izz, ixy, ixz, iyz]` is about the centre of mass, flange-frame axes (the
//! tensor's own elements, as a URDF writes them).
//!
//! Allocation-free and panic-free: the core checks a tool in the cycle.
//!
//! ```
//! use mcm_shared::tool::{Tcp, Tool};
//! let tool = Tool::new(Tcp::FLANGE, 2.0, [0.0, 0.0, 0.06], None).unwrap();
//! assert_eq!(tool.inertia, [0.0; 6]); // a point mass
//! assert!(Tool::new(Tcp::FLANGE, 9.0, [0.0; 3], None).is_err()); // above the rating
//! ```

use crate::ranges::Num;
use crate::units::{UNIT_QUATERNION_TOLERANCE, unit_quaternion};
use core::fmt;

/// The heaviest tool [kg]: the P-Rob2's rated payload (3 kg) plus a gripper of up to 2 kg.
pub const MAX_MASS_KG: f64 = 5.0;
/// The farthest the centre of mass or the TCP may lie from the flange's origin [m]: a tool
/// longer than this would be a second arm (the P-Rob2 reaches 0.775 m).
pub const MAX_REACH_M: f64 = 0.5;

/// The TCP: the tool frame as a transform of the flange frame.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Tcp {
    /// [m], flange frame.
    pub position: [f64; 3],
    /// Unit quaternion `[x, y, z, w]`.
    pub orientation: [f64; 4],
}

impl Tcp {
    /// The TCP on the flange: no offset, no rotation.
    pub const FLANGE: Tcp = Tcp {
        position: [0.0; 3],
        orientation: [0.0, 0.0, 0.0, 1.0],
    };
}

/// A tool, checked ([`Tool::new`]). Its JSON is what `set_tool` takes and `status`
/// `detail.tool` shows.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Tool {
    pub tcp: Tcp,
    /// [kg], from 0 to [`MAX_MASS_KG`].
    pub mass: f64,
    /// [m], flange frame.
    pub center_of_mass: [f64; 3],
    /// `[ixx, iyy, izz, ixy, ixz, iyz]` about the centre of mass [kg·m²]; zeros: a point mass.
    pub inertia: [f64; 6],
}

/// A value of a tool, named as `set_tool` names it; `index` is the element of an array.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ToolField {
    pub name: &'static str,
    pub index: Option<u8>,
}

impl ToolField {
    pub const TCP_POSITION: &'static str = "tcp.position";
    pub const TCP_ORIENTATION: &'static str = "tcp.orientation";
    pub const MASS: &'static str = "mass";
    pub const CENTER_OF_MASS: &'static str = "center_of_mass";
    pub const INERTIA: &'static str = "inertia";

    const fn at(name: &'static str, index: usize) -> ToolField {
        ToolField {
            name,
            index: Some(index as u8),
        }
    }

    const fn whole(name: &'static str) -> ToolField {
        ToolField { name, index: None }
    }
}

impl fmt::Display for ToolField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.index {
            Some(i) => write!(f, "{}[{i}]", self.name),
            None => f.write_str(self.name),
        }
    }
}

/// Why a tool is not accepted: the value, and what is allowed.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum ToolError {
    #[error("{field} = {} is not allowed; expected a finite number", Num(*value))]
    NotFinite { field: ToolField, value: f64 },
    #[error(
        "mass = {} kg is not allowed; expected a number from 0 to {} kg (the rated payload plus the gripper)",
        Num(*value),
        Num(MAX_MASS_KG)
    )]
    Mass { value: f64 },
    #[error(
        "tcp.orientation has the norm {}; expected a unit quaternion [x, y, z, w] (norm 1 within {})",
        Num(*norm),
        Num(UNIT_QUATERNION_TOLERANCE)
    )]
    Orientation { norm: f64 },
    #[error(
        "{field} lies {} m from the flange; expected at most {} m",
        Num(*distance),
        Num(MAX_REACH_M)
    )]
    TooFar { field: ToolField, distance: f64 },
    /// Not the inertia of a body: `value` is the first of the checked quantities found
    /// negative (a principal moment of the body's mass distribution, see [`Tool::new`]).
    #[error(
        "inertia is not the inertia of a body ({} < 0); expected [ixx, iyy, izz, ixy, ixz, iyz] [kg m^2] positive semi-definite, each of ixx, iyy, izz at most the sum of the other two",
        Num(*value)
    )]
    Inertia { value: f64 },
}

impl ToolError {
    /// The value it names.
    pub fn field(&self) -> ToolField {
        match *self {
            ToolError::NotFinite { field, .. } | ToolError::TooFar { field, .. } => field,
            ToolError::Mass { .. } => ToolField::whole(ToolField::MASS),
            ToolError::Orientation { .. } => ToolField::whole(ToolField::TCP_ORIENTATION),
            ToolError::Inertia { .. } => ToolField::whole(ToolField::INERTIA),
        }
    }

    /// The figure it reports (the value, a norm, a distance).
    pub fn value(&self) -> f64 {
        match *self {
            ToolError::NotFinite { value, .. }
            | ToolError::Mass { value }
            | ToolError::Inertia { value } => value,
            ToolError::Orientation { norm } => norm,
            ToolError::TooFar { distance, .. } => distance,
        }
    }

    /// What is allowed, in words (for a refusal that carries the field and the value apart).
    pub fn allowed(&self) -> &'static str {
        match self {
            ToolError::NotFinite { .. } => "a finite number",
            ToolError::Mass { .. } => "a mass from 0 to 5 kg",
            ToolError::Orientation { .. } => "a unit quaternion [x, y, z, w] (norm 1 within 0.001)",
            ToolError::TooFar { .. } => "at most 0.5 m from the flange",
            ToolError::Inertia { .. } => {
                "a physical inertia (positive semi-definite, triangle inequality)"
            }
        }
    }

    /// The bounds a refusal on the wire carries (`out_of_range`'s min and max).
    pub fn bounds(&self) -> (f64, f64) {
        match self {
            ToolError::Mass { .. } => (0.0, MAX_MASS_KG),
            ToolError::Orientation { .. } => (
                1.0 - UNIT_QUATERNION_TOLERANCE,
                1.0 + UNIT_QUATERNION_TOLERANCE,
            ),
            ToolError::TooFar { .. } => (0.0, MAX_REACH_M),
            ToolError::Inertia { .. } => (0.0, f64::MAX),
            ToolError::NotFinite { .. } => (f64::MIN, f64::MAX),
        }
    }
}

fn finite<const K: usize>(name: &'static str, v: &[f64; K]) -> Result<(), ToolError> {
    match v.iter().position(|x| !x.is_finite()) {
        Some(i) => Err(ToolError::NotFinite {
            field: ToolField::at(name, i),
            value: v[i],
        }),
        None => Ok(()),
    }
}

fn within_reach(name: &'static str, p: &[f64; 3]) -> Result<(), ToolError> {
    let distance = p.iter().map(|x| x * x).sum::<f64>().sqrt();
    if distance <= MAX_REACH_M {
        Ok(())
    } else {
        Err(ToolError::TooFar {
            field: ToolField::whole(name),
            distance,
        })
    }
}

/// Whether `[ixx, iyy, izz, ixy, ixz, iyz]` is the inertia of a body: its mass distribution's
/// second moment `S = tr(I)/2 · 1 − I` (`∫ r rᵀ dm`) must be positive semi-definite, which
/// holds exactly when every principal minor of `S` is non-negative. The first one found
/// negative (beyond rounding) is the error's figure.
fn physical_inertia(i: &[f64; 6]) -> Result<(), ToolError> {
    let [ixx, iyy, izz, ixy, ixz, iyz] = *i;
    let half = (ixx + iyy + izz) / 2.0;
    let (sxx, syy, szz) = (half - ixx, half - iyy, half - izz);
    let (sxy, sxz, syz) = (-ixy, -ixz, -iyz);
    let scale = i.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let eps = 1e-9 * scale;
    let minors = [
        (ixx, eps),
        (iyy, eps),
        (izz, eps),
        (sxx, eps),
        (syy, eps),
        (szz, eps),
        (sxx * syy - sxy * sxy, eps * scale),
        (sxx * szz - sxz * sxz, eps * scale),
        (syy * szz - syz * syz, eps * scale),
        (
            sxx * (syy * szz - syz * syz) - sxy * (sxy * szz - syz * sxz)
                + sxz * (sxy * syz - syy * sxz),
            eps * scale * scale,
        ),
    ];
    match minors.iter().find(|(m, tol)| *m < -tol) {
        Some(&(value, _)) => Err(ToolError::Inertia { value }),
        None => Ok(()),
    }
}

impl Default for Tool {
    /// [`Tool::NONE`].
    fn default() -> Tool {
        Tool::NONE
    }
}

impl Tool {
    /// No tool: nothing on the flange, the TCP on it.
    pub const NONE: Tool = Tool {
        tcp: Tcp::FLANGE,
        mass: 0.0,
        center_of_mass: [0.0; 3],
        inertia: [0.0; 6],
    };

    /// The tool, every value checked: all finite; `mass` from 0 to [`MAX_MASS_KG`]; the
    /// orientation of norm 1 within [`UNIT_QUATERNION_TOLERANCE`] (then normalised); the centre
    /// of mass and the TCP within [`MAX_REACH_M`] of the flange; `inertia` (`None`: a point
    /// mass) the inertia of a body.
    pub fn new(
        tcp: Tcp,
        mass: f64,
        center_of_mass: [f64; 3],
        inertia: Option<[f64; 6]>,
    ) -> Result<Tool, ToolError> {
        let inertia = inertia.unwrap_or([0.0; 6]);
        finite(ToolField::TCP_POSITION, &tcp.position)?;
        finite(ToolField::TCP_ORIENTATION, &tcp.orientation)?;
        finite(ToolField::MASS, &[mass])?;
        finite(ToolField::CENTER_OF_MASS, &center_of_mass)?;
        finite(ToolField::INERTIA, &inertia)?;
        if !(0.0..=MAX_MASS_KG).contains(&mass) {
            return Err(ToolError::Mass { value: mass });
        }
        let orientation =
            unit_quaternion(tcp.orientation).map_err(|norm| ToolError::Orientation { norm })?;
        within_reach(ToolField::TCP_POSITION, &tcp.position)?;
        within_reach(ToolField::CENTER_OF_MASS, &center_of_mass)?;
        physical_inertia(&inertia)?;
        Ok(Tool {
            tcp: Tcp {
                position: tcp.position,
                orientation,
            },
            mass,
            center_of_mass,
            inertia,
        })
    }
}

#[cfg(test)]
mod tests;
