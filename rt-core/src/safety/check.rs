//! The interface every per-cycle safety check implements ([`CycleCheck`]): when it runs
//! ([`Situation`]), what it reads ([`CycleInputs`]), when it trips and what it names
//! ([`Violation`]). [`super::CycleChecks`] lists the checks in the order the controller runs
//! them.
//!
//! Runs inside the cycle: plain `Copy` data; a check is a pure function of its parameters and
//! inputs, allocation-free, lock-free and panic-free.

use super::{Check, SafetyParams, Violation};
use mcm_shared::NUM_AXES;
use mcm_shared::mode::Mode;

/// Where a calibration is, for the checks (outside CALIBRATION: [`Calibrating::No`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Calibrating {
    No,
    /// Its searches: positions are raw encoder angles; the axes it does not cover hold where
    /// they are (their following error is checked), the searching axes are watched by their
    /// searches (`calibration::lead`).
    Searching,
    /// Its move back to zero: a planned move whose axes are all calibrated by then.
    Returning,
}

/// What the arm is doing this cycle, as far as the checks care.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Situation {
    /// The operating mode (OFF or ERROR while the drives are being enabled).
    pub mode: Mode,
    pub calibrating: Calibrating,
    /// A planned move or controlled stop runs (validated when planned: its whole path lies in
    /// the reachable range).
    pub planned_motion: bool,
    /// A procedure of HOLD moves the arm (`identify_payload`): its moves and its holds between
    /// them are watched as PVT's are.
    pub procedure: bool,
    /// A check the simulation tester planted off (`controller/planted.rs`); `None` in `mcm-rt`.
    pub disabled: Option<Check>,
}

impl Situation {
    /// A mode in which a motion other than a planned one can run (RELEASE, TORQUE_CONTROL,
    /// PVT, VELOCITY_CONTROL), or a procedure of HOLD that moves the arm: the position,
    /// velocity and braking checks watch it.
    pub fn free_motion_mode(&self) -> bool {
        self.procedure
            || matches!(
                self.mode,
                Mode::Release | Mode::TorqueControl | Mode::Pvt | Mode::VelocityControl
            )
    }
}

/// What the checks read, all SI, in the joint frame.
#[derive(Clone, Copy, Debug)]
pub struct CycleInputs<'a> {
    /// Measured joint positions [rad].
    pub position: &'a [f64; NUM_AXES],
    /// Measured joint velocities [rad/s].
    pub velocity: &'a [f64; NUM_AXES],
    /// The position each axis is to be at now [rad]: the command of two cycles back (the
    /// measured position was sampled while the drives were reaching it). During a calibration's
    /// searches a searching axis's own measured position (its search watches it).
    pub commanded: &'a [f64; NUM_AXES],
}

/// One safety check the controller runs every cycle.
pub trait CycleCheck {
    /// The check its violations name.
    const ID: Check;

    /// Whether it runs in `now` (the manual's table of checks per mode, `docs/safety.md`).
    fn runs(&self, now: &Situation) -> bool;

    /// Its verdict on this cycle: `Err` for the first axis that breaks it. Non-finite inputs
    /// it reads always trip. Called only in the cycles it [`runs`](Self::runs) and no check
    /// before it tripped; a check that judges over several cycles (a debounce) keeps its count
    /// in its own fields.
    fn verdict(&mut self, params: &SafetyParams, inputs: &CycleInputs<'_>)
    -> Result<(), Violation>;
}

/// Run `check` if it runs in `now` and is not planted off.
pub(super) fn run_one<C: CycleCheck>(
    check: &mut C,
    params: &SafetyParams,
    now: &Situation,
    inputs: &CycleInputs<'_>,
) -> Result<(), Violation> {
    if now.disabled == Some(C::ID) || !check.runs(now) {
        return Ok(());
    }
    check.verdict(params, inputs)
}
