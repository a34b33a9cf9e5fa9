//! Bugs planted on purpose, to show that the deterministic simulation tester (`mcm-dst`)
//! catches what its invariants claim to catch (`docs/testing.md`, "Deterministic simulation
//! testing"). The flags ([`Planted`]) are always there and always off; only the feature
//! `planted-bugs`, which only `mcm-dst` enables, adds `Controller::plant` to set them, and
//! nothing in `mcm-rt` calls it, so a build that has the feature (cargo unifies features when
//! the whole workspace is built together) behaves as one without it.
//!
//! `Controller::plant` runs before a run, outside the cycle; the cycle reads the flags.

use super::QUICK_STOP_FACTOR;

/// The quick stop's share of the maximum deceleration with [`PlantedBug::QuickStopSoft`].
pub const SOFT_QUICK_STOP_FACTOR: f64 = 0.1;

/// A bug that `Controller::plant` puts into the controller.
#[cfg(feature = "planted-bugs")]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlantedBug {
    /// The braking-distance check (`docs/safety.md`, "Braking distance") never trips: an axis
    /// driven by torques or pushed towards a limit is stopped by the position-limit check
    /// alone, when it already passes the limit less the margin.
    BrakingCheckOff,
    /// The stop after a safety trip brakes at [`SOFT_QUICK_STOP_FACTOR`] of each axis's maximum
    /// deceleration instead of [`QUICK_STOP_FACTOR`] times it (a wrong factor): the arm
    /// stops far beyond the braking distance the braking check counts on.
    QuickStopSoft,
}

/// The bugs planted in a controller (none but through `Controller::plant`).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Planted {
    pub(super) braking_check_off: bool,
    quick_stop_soft: bool,
}

impl Planted {
    /// The quick stop's deceleration as a multiple of the maximum.
    pub(super) fn quick_stop_factor(&self) -> f64 {
        if self.quick_stop_soft {
            SOFT_QUICK_STOP_FACTOR
        } else {
            QUICK_STOP_FACTOR
        }
    }
}

#[cfg(feature = "planted-bugs")]
impl super::Controller {
    /// Plant `bug`. For the simulation tester only.
    pub fn plant(&mut self, bug: PlantedBug) {
        match bug {
            PlantedBug::BrakingCheckOff => self.planted.braking_check_off = true,
            PlantedBug::QuickStopSoft => self.planted.quick_stop_soft = true,
        }
    }
}
