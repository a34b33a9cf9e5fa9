//! Drive events from the CANopen master, the emergency stop's press, the per-cycle safety
//! checks (`safety::CycleChecks`, run in their order on the cycle's measured state), and what a
//! trip does: ERROR, the quick stop, the power off of a lost drive, the failure of a calibration
//! or enabling under way, and one error record per incident.
//!
//! Runs inside the cycle.

use super::Controller;
use super::exits::Exit;
use super::state::{CalPhase, State};
use crate::canopen::MasterEvent;
use crate::safety::{Calibrating, Check, CycleInputs, Situation};
use mcm_shared::NUM_AXES;
use mcm_shared::command::Axis;
use mcm_shared::mode::Mode;
use mcm_shared::reply::{Reason, SafetyError};

/// Cycles an axis that tripped its following error follows its measured position (0.1 s at
/// 200 Hz: a joint pressed into an obstacle springs back within a few cycles).
pub(super) const RELAX_CYCLES: u8 = 20;

/// The axes that relax in the ERROR a trip for `reason` leads to: after a following error, the
/// drive's loop wound up against whatever held the axis; the axis relaxes and holds where it
/// comes to rest, so that it stops pressing. Not an axis whose motor is `derated`: what held
/// it back is more likely its own load, more than its derated current carries, and restarting
/// its loop would clear the integral that carries what it can, and it would fall; the overload
/// check powers such an arm off onto its brakes instead (`overload.rs`).
pub(super) fn relax_after(reason: Reason, derated: &[bool; NUM_AXES]) -> [u8; NUM_AXES] {
    let mut relax = [0; NUM_AXES];
    if let Reason::FollowingError { axis, .. } = reason
        && !derated[axis.index()]
    {
        relax[axis.index()] = RELAX_CYCLES;
    }
    relax
}

impl Controller {
    pub(super) fn on_event(&mut self, ev: MasterEvent) {
        match ev {
            MasterEvent::Lost { axis, .. }
            | MasterEvent::Missing { axis, .. }
            | MasterEvent::ConfigFailed { axis, .. } => {
                self.lost[axis] = true;
                self.trip(Reason::DriveDisconnected {
                    axis: Axis::ALL[axis],
                    also: 0,
                });
            }
            MasterEvent::Recovered { axis, .. } | MasterEvent::Configured { axis } => {
                self.lost[axis] = false;
            }
            MasterEvent::Emcy { axis, emcy } => {
                if emcy.code != 0 {
                    self.drive_fault(axis, emcy.code);
                }
            }
            MasterEvent::Fault { axis, code } => self.drive_fault(axis, code),
            MasterEvent::Booted { axis } => {
                // Calibration is gone unless the drive still holds it (below): a drive that
                // boots after a power cycle lost its encoder reference; a calibration under way
                // no longer keeps its previous offset either.
                self.forget_previous_calibration(axis);
                self.offsets[axis] = None;
                if self.mode() != Mode::Off {
                    self.trip(Reason::DriveDisconnected {
                        axis: Axis::ALL[axis],
                        also: 0,
                    });
                }
            }
            // Comes after `Booted` (and `Configured`) of the same boot: the calibration the
            // drive kept (0x2100) while the MCM restarted.
            MasterEvent::Calibration {
                axis,
                offset_counts,
            } => {
                self.offsets[axis] =
                    offset_counts.map(|c| f64::from(c) / self.p.counts_per_rad[axis]);
            }
            // Storing failed: the calibration holds until the MCM restarts (nothing to stop).
            MasterEvent::CalibrationStored { .. } | MasterEvent::CalibrationStoreFailed { .. } => {}
        }
    }

    /// Whether ERROR powers off the drive of `axis` because the master lost it: the axis has a
    /// holding brake, and its drive sends no TPDOs (or no heartbeat), so nothing tells whether it
    /// holds. The master delivers the power off by NMT stop where SYNC and PDOs no longer reach
    /// the drive (`Master::cut_off`); the brake holds the axis whatever its drive could still do
    /// (a derated axis would otherwise sink until its drive's own SYNC watchdog acts, if it has
    /// one). Axes without a brake stay enabled: their drives hold the last setpoint until their
    /// own watchdog acts, which beats letting them fall.
    pub(super) fn lost_power_off(&self, axis: usize) -> bool {
        self.lost[axis] && self.p.brake[axis] && matches!(self.state, State::Error { .. })
    }

    /// A drive reports a fault: the emergency stop (which cuts the drives' power) when its
    /// input is active, a drive fault otherwise.
    fn drive_fault(&mut self, axis: usize, code: u16) {
        // The emergency switch: by the statusword's bit 14 or by the drive's own EMCY for it,
        // whichever the bus brought first.
        let sto = code == crate::canopen::emcy::SAFE_TORQUE_OFF;
        if sto || self.master.feedback().iter().any(|f| f.estop) {
            self.estop_seen = true;
            self.trip(Reason::EmergencyStop);
        } else {
            self.trip(Reason::DriveFault {
                axis: Some(Axis::ALL[axis]),
                code,
            });
        }
    }

    /// The checks of the manual's "Safety checks" evaluated every cycle: the emergency stop's
    /// press, then the per-cycle checks (`safety::CycleChecks`) on the measured state (drive
    /// connections and faults come as master events).
    pub(super) fn check_safety(&mut self) {
        let estop = self.master.feedback().iter().any(|f| f.estop);
        if estop && !self.estop_seen {
            self.estop_seen = true;
            self.trip(Reason::EmergencyStop);
        }
        self.estop_seen = estop;
        let searches = self.searches();
        let calibrating = match self.state {
            State::Calibration {
                phase: CalPhase::Search { .. },
                ..
            } => Calibrating::Searching,
            State::Calibration {
                phase: CalPhase::Return(_),
                ..
            } => Calibrating::Returning,
            _ => Calibrating::No,
        };
        let now = Situation {
            mode: self.mode(),
            calibrating,
            planned_motion: self.state.planned_motion(),
            procedure: matches!(self.state, State::Identify { .. }),
            disabled: self
                .planted
                .braking_check_off
                .then_some(Check::BrakingDistance),
        };
        let q = self.measured();
        let qd = self.measured_velocity();
        // The axes a calibration's searches cover are watched by their searches: their own
        // measured position stands for their command.
        let commanded: [f64; NUM_AXES] = core::array::from_fn(|i| {
            if searches.as_ref().is_some_and(|axes| axes[i].is_some()) {
                q[i]
            } else {
                self.cmd_hist[1][i]
            }
        });
        let inputs = CycleInputs {
            position: &q,
            velocity: &qd,
            commanded: &commanded,
        };
        if let Err(v) = self.checks.run(&now, &inputs) {
            self.trip(v.reason());
        }
    }

    /// A safety check or drive error: mode ERROR (from any mode but OFF, where nothing moves
    /// and the error is only reported), axes stopped, a calibration or enabling under way
    /// failed, and one spontaneous error record per incident (until a `hold` succeeds).
    pub(super) fn trip(&mut self, reason: Reason) {
        self.leave(Exit::Trip(reason));
        self.report_incident(reason);
    }

    /// One spontaneous error record per incident: `reason` is recorded unless an error was
    /// already reported and not yet cleared by a successful `hold`.
    pub(super) fn report_incident(&mut self, reason: Reason) {
        if self.incident_reported {
            self.merge_lost_drive(reason);
            return;
        }
        self.incident_reported = true;
        self.view.last_error = Some(SafetyError {
            seq: self.view.last_error.map_or(0, |e| e.seq) + 1,
            cycle: self.cycle,
            unix_ns: 0,
            reason,
        });
    }

    /// Drives lost in the cycle the incident was reported in belong to it: the error names
    /// every one (a power cycle reboots all six at once), not only the first.
    fn merge_lost_drive(&mut self, reason: Reason) {
        let Some(e) = self.view.last_error.as_mut() else {
            return;
        };
        if let (
            Reason::DriveDisconnected { axis, also },
            Reason::DriveDisconnected {
                axis: lost,
                also: more,
            },
        ) = (&mut e.reason, reason)
            && e.cycle == self.cycle
            && lost != *axis
        {
            *also |= more | 1 << lost.index();
        }
    }

    /// In ERROR, an axis that tripped its following error follows its measured position for
    /// [`RELAX_CYCLES`], its drive's loop restarted at the start: a loop wound up against an
    /// obstacle stops pressing, and the axis holds where it came to rest. Not restarted again
    /// at the end: that would drop what the integral carries against the obstacle's spring,
    /// and the loop would creep the axis back to its reference later.
    pub(super) fn relax_tripped_axes(&mut self, relax: &mut [u8; NUM_AXES]) {
        let measured = self.measured();
        for (i, &at) in measured.iter().enumerate() {
            let left = relax[i];
            if left == 0 {
                continue;
            }
            self.cmd.position[i] = at;
            self.cmd.velocity[i] = 0.0;
            self.cmd.acceleration[i] = 0.0;
            if left == RELAX_CYCLES {
                self.master.restart_position_loop(i);
            }
            relax[i] = left - 1;
        }
    }
}
