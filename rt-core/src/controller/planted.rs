//! Bugs planted on purpose, to show that the deterministic simulation tester (`mcm-dst`)
//! catches what its invariants claim to catch (`docs/testing.md`, "Deterministic simulation
//! testing"). Compiled only with the feature `planted-bugs`, which only `mcm-dst` enables;
//! nothing in `mcm-rt` calls [`Controller::plant`], so a build that has the feature (cargo
//! unifies features when the whole workspace is built together) behaves as one without it.
//!
//! [`Controller::plant`] runs before a run, outside the cycle; the cycle reads a flag.

use super::Controller;

/// A bug that [`Controller::plant`] puts into the controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlantedBug {
    /// The braking-distance check (`docs/safety.md`, "Braking distance") never trips: an axis
    /// driven by torques or pushed towards a limit is stopped by the position-limit check
    /// alone, when it already passes the limit less the margin.
    BrakingCheckOff,
    /// The stop after a safety trip brakes at a tenth of each axis's maximum deceleration
    /// instead of [`super::QUICK_STOP_FACTOR`] times it (a wrong factor): the arm
    /// stops far beyond the braking distance the braking check counts on.
    QuickStopSoft,
}

/// The bugs planted in a controller.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Planted {
    pub(super) braking_check_off: bool,
    pub(super) quick_stop_soft: bool,
}

impl Controller {
    /// Plant `bug`. For the simulation tester only.
    pub fn plant(&mut self, bug: PlantedBug) {
        match bug {
            PlantedBug::BrakingCheckOff => self.planted.braking_check_off = true,
            PlantedBug::QuickStopSoft => self.planted.quick_stop_soft = true,
        }
    }
}
