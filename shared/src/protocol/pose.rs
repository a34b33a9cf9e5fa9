//! A Cartesian pose as the commands take it (`inverse_kinematics`, `move_to_pose`): the TCP's
//! `position` [m] and `orientation` (a unit quaternion `[x, y, z, w]`) in the base frame
//! (`docs/cartesian.md`). A quaternion whose norm is within
//! [`crate::units::UNIT_QUATERNION_TOLERANCE`] of 1 is normalised; any other is refused, naming its norm. Not used inside the real-time cycle.

use super::args::numbers;
use super::spec::{ArgDef, Kind, arg};
use super::{Args, CommandError};
use crate::units::{UNIT_QUATERNION_TOLERANCE, unit_quaternion};
use serde_json::{Map, Value};

/// The `position` argument.
pub(crate) const POSITION: ArgDef = arg(
    "position",
    "pos",
    Kind::Position,
    true,
    "",
    "the TCP's position in the base frame: x, y, z [m]",
);

/// The `orientation` argument.
pub(crate) const ORIENTATION: ArgDef = arg(
    "orientation",
    "orient",
    Kind::Orientation,
    true,
    "",
    "the TCP's orientation in the base frame: a unit quaternion x, y, z, w (normalised when \
     its norm is within 0.001 of 1)",
);

/// A TCP pose in the base frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// [m]
    pub position: [f64; 3],
    /// A unit quaternion `[x, y, z, w]`.
    pub orientation: [f64; 4],
}

impl Pose {
    /// The pose of a command's `position` and `orientation` arguments (both required).
    pub fn parse(args: &Args<'_>) -> Result<Pose, CommandError> {
        let position = Pose::position(args)?;
        let orientation = Pose::orientation(args)?.ok_or_else(|| {
            args.missing(
                ORIENTATION.name,
                "an array of 4 quaternion components x, y, z, w",
            )
        })?;
        Ok(Pose {
            position,
            orientation,
        })
    }

    /// The required `position` argument [m].
    pub fn position(args: &Args<'_>) -> Result<[f64; 3], CommandError> {
        Ok(required::<3>(args, POSITION.name, "coordinates x, y, z [m]")?.1)
    }

    /// The `orientation` argument, normalised; `None` when absent.
    pub fn orientation(args: &Args<'_>) -> Result<Option<[f64; 4]>, CommandError> {
        if args.raw(ORIENTATION.name).is_none() {
            return Ok(None);
        }
        let (raw, q) = required::<4>(args, ORIENTATION.name, "quaternion components x, y, z, w")?;
        unit_quaternion(q).map(Some).map_err(|norm| {
            args.invalid(
                ORIENTATION.name,
                raw,
                format!(
                    "a unit quaternion [x, y, z, w]: its norm is {}, not within \
                     {UNIT_QUATERNION_TOLERANCE} of 1",
                    crate::ranges::Num(norm)
                ),
            )
        })
    }

    /// Its `position` and `orientation` into a command's `arguments`.
    pub fn insert_into(&self, m: &mut Map<String, Value>) {
        m.insert(POSITION.name.into(), self.position.to_vec().into());
        m.insert(ORIENTATION.name.into(), self.orientation.to_vec().into());
    }
}

/// The required argument `name` of `N` numbers (`what` they are), as given and as read.
fn required<'a, const N: usize>(
    args: &Args<'a>,
    name: &'static str,
    what: &str,
) -> Result<(&'a Value, [f64; N]), CommandError> {
    let raw = args
        .raw(name)
        .ok_or_else(|| args.missing(name, &format!("an array of {N} {what}")))?;
    Ok((raw, numbers(args, name, raw, what)?))
}

#[cfg(test)]
mod tests;
