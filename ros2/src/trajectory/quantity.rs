//! The quantities limits and tolerances apply to, and how a value of one is written in a
//! message: in the SI unit ROS speaks and in degrees, which the MCM speaks.

use mcm_shared::ranges::Num;
use std::fmt;

/// Position, velocity or acceleration of a joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    Position,
    Velocity,
    Acceleration,
}

impl Quantity {
    /// The word for messages.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Position => "position",
            Quantity::Velocity => "velocity",
            Quantity::Acceleration => "acceleration",
        }
    }

    fn units(self) -> (&'static str, &'static str) {
        match self {
            Quantity::Position => ("rad", "deg"),
            Quantity::Velocity => ("rad/s", "deg/s"),
            Quantity::Acceleration => ("rad/s^2", "deg/s^2"),
        }
    }

    /// `value` (SI) written as "0.5 rad/s (28.6478897565 deg/s)".
    pub fn show(self, value: f64) -> Shown {
        Shown {
            quantity: self,
            value,
        }
    }
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A value with its unit, in SI and in degrees (see [`Quantity::show`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shown {
    quantity: Quantity,
    value: f64,
}

impl fmt::Display for Shown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (si, deg) = self.quantity.units();
        let v = self.value;
        write!(f, "{} {si} ({} {deg})", Num(v), Num(v.to_degrees()))
    }
}
