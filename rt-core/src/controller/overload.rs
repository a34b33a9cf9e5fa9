//! Overload: an axis that cannot hold its load with the current its hot motor is allowed.
//!
//! Runs inside the cycle.
//!
//! The i2t protection (`safety/i2t.rs`) derates a hot motor to its derated current. An axis
//! whose load at rest needs more than that (the shoulder holding the stretched arm and its
//! payload) can then no longer hold: its current stands at the derated limit and it sags. In
//! HOLD the following error would trip only once it had sagged by its band, and in ERROR
//! nothing would react at all. So an axis at rest in HOLD (no stop under way), or in ERROR (its
//! stop or a relax under way too), whose motor is derated and whose current has stood at the
//! derated limit for [`OVERLOAD_S`] trips [`Reason::Overload`]: ERROR, with the drives of every
//! axis that has a holding brake powered off, so that the brakes hold the arm and the motors
//! cool. Axes without a brake stay enabled and hold as ERROR does. The time at the limit is
//! counted also where the drive follows a reference without the check (HOLD's stop, a move,
//! VELOCITY_CONTROL), so that an axis that stood at its limit before a trip is overloaded in
//! the next cycle (the trip's own record goes out first). The same power off follows any trip once ERROR's stop (and every
//! relax) has ended while a motor is derated: in ERROR the arm does no work, and a derated
//! motor holding a load near its rated current never cools (it stays above the release level,
//! and a calibration's search cannot get the current it needs). A `hold` enables the drives
//! again (`begin_enabling` ends the power off); a motor still hot trips again within
//! [`OVERLOAD_S`] if the pose still needs more.

use super::Controller;
use super::state::State;
use mcm_shared::NUM_AXES;
use mcm_shared::command::Axis;
use mcm_shared::reply::Reason;

/// How long a derated axis's current stands at its limit before the overload trips [s]: a few
/// cycles, so that one reading at the limit is not taken for a load; short, because the axis
/// sags from the first cycle at the limit and faster every cycle (the P-Rob2's stretched
/// shoulder: 0.06 deg in 25 ms, 0.6 deg in 0.1 s).
pub const OVERLOAD_S: f64 = 0.025;

/// The share of the derated limit at which the current counts as standing at it (the drive's
/// current loop and its measurement stay a little below the clamp).
pub const AT_LIMIT: f64 = 0.98;

/// The overload check's state: cycles each axis's current has stood at its derated limit, and
/// whether the drives are powered off for an overload.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Overload {
    at_limit: [u32; NUM_AXES],
    /// The drives of the axes with a brake are powered off (until an enabling starts).
    pub powered_off: bool,
}

/// Cycles of `period_s` the current must stand at the derated limit: [`OVERLOAD_S`], and at
/// least one.
fn overload_cycles(period_s: f64) -> u32 {
    (OVERLOAD_S / period_s).ceil().max(1.0) as u32
}

impl Controller {
    /// The overload check, once per cycle before the references are made.
    pub(super) fn check_overload(&mut self) {
        // In ERROR also while its stop or a relax runs: a derated axis whose current stands at
        // its limit there is falling, not braking, and the power off after a trip waits for
        // the stop and the relaxes.
        let at_rest = matches!(self.state, State::Hold { stop: None } | State::Error { .. });
        // Where the drive follows a moving position reference (HOLD's stop, a move, VELOCITY
        // CONTROL), a derated axis whose current stands at its limit cannot follow it: its time
        // at the limit is counted there too, and carried into ERROR or a HOLD at rest, where it
        // trips. An axis that stood at its limit through HOLD's stop or a move before a trip is
        // overloaded the cycle after, in ERROR, before ERROR's stop can drive it: that stop
        // starts from the measured position, which for a sagging axis lies below the drive's
        // target, and reaches the drive as a move towards it at up to the axis's top speed.
        // Not in CALIBRATION: a search presses at its limit on purpose (the axes it does not
        // cover are `held`).
        let follows = matches!(
            self.state,
            State::Hold { stop: Some(_) }
                | State::Identify { .. }
                | State::Pvt { .. }
                | State::Velocity { .. }
        );
        // During a calibration's searches, the axes it does not cover hold where they are, and
        // one whose derated current cannot hold it is overloaded as it would be in HOLD.
        let searches = self.searches();
        let held = |i: usize| searches.is_some_and(|s| s[i].is_none());
        let derated = self.i2t.derated();
        let limit = self.i2t.max_current();
        let fb = *self.master.feedback();
        let need = overload_cycles(self.p.period);
        let mut tripped = None;
        for i in 0..NUM_AXES {
            let watched = at_rest || held(i);
            let at_limit = (watched || follows)
                && derated[i]
                && fb[i].enabled
                && fb[i].current_a.abs() >= AT_LIMIT * limit[i];
            let n = &mut self.overload.at_limit[i];
            *n = if at_limit { n.saturating_add(1) } else { 0 };
            if tripped.is_none() && watched && *n >= need {
                tripped = Some(Reason::Overload {
                    axis: Axis::ALL[i],
                    current_a: fb[i].current_a,
                    limit_a: limit[i],
                });
            }
        }
        let Some(reason) = tripped else {
            let settled = matches!(
                self.state,
                State::Error { stop: None, relax } if relax == [0; NUM_AXES]
            ) && !self.search_relax.any();
            if settled && derated.iter().any(|d| *d) {
                self.overload.powered_off = true;
            }
            return;
        };
        // One error record a cycle (the state carries the newest): a trip reported in this very
        // cycle, such as the following error of an axis that sank behind its reference, goes
        // out first, and the overload, its count kept, trips in the next cycle.
        if self.view.last_error.is_some_and(|e| e.cycle == self.cycle) {
            return;
        }
        self.overload.at_limit = [0; NUM_AXES];
        // Its own incident even in an ERROR already reported: the arm is now powered off.
        self.incident_reported = false;
        self.trip(reason);
        if matches!(self.state, State::Error { .. }) {
            self.overload.powered_off = true;
        }
    }

    /// Why the drives may not be enabled yet: the arm is powered off onto its brakes (after an
    /// overload, or a trip while a motor was derated) and the motor of an axis with a brake is
    /// still derated. Enabled again, that axis could hold no more than before: it would sag
    /// from its brake again until a check trips, a little further each time a client repeats
    /// `hold`, until it passes its limit. The derating ends once the motor has cooled below
    /// the i2t release level.
    pub(super) fn overload_blocker(&self) -> Option<Reason> {
        if !self.overload.powered_off || !matches!(self.state, State::Error { .. }) {
            return None;
        }
        let derated = self.i2t.derated();
        let limit = self.i2t.max_current();
        (0..NUM_AXES)
            .find(|&i| self.p.brake[i] && derated[i])
            .map(|i| Reason::Overload {
                axis: Axis::ALL[i],
                current_a: limit[i],
                limit_a: limit[i],
            })
    }

    /// Whether the drive of `axis` is to be powered off for an overload.
    pub(super) fn overload_power_off(&self, axis: usize) -> bool {
        self.overload.powered_off && self.p.brake[axis] && matches!(self.state, State::Error { .. })
    }
}

// Scenario tests on the whole simulated robot.
#[cfg(all(test, feature = "sim"))]
mod tests;
