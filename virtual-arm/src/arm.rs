//! [`VirtualArm`]: the simulated P-Rob2 (`mcm_sim::SimBus`: six CiA 402 drives, the arm's
//! physics, the emergency switch) answering a CANopen master over a real bus.
//!
//! Every frame from the wire goes to the simulated drives as the in-process bus hands it over
//! (`Bus::send` of the `SimBus`): SDOs, NMT and RPDOs are answered at once, and a SYNC runs one
//! period of the drives and the physics. Every frame the drives transmit goes back to the
//! wire. [`crate::pace::Pace`] runs periods without SYNC when the master is silent, so the
//! arm's time follows the wall clock. Fault injections ([`VirtualArm::apply`]) and the ground
//! truth are those of the `sim` command.

use crate::pace::Pace;
use mcm_bus::{Bus, BusError, Frame};
use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;
use mcm_sim::bus::SYNC_ID;
use mcm_sim::drive::DriveCounters;
use mcm_sim::{SimBus, SimCommand, SimCommandError, SimControl, SimTruth};

/// What the virtual arm has seen and done since it started.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counters {
    /// Frames received from the wire.
    pub frames_in: u64,
    /// Frames the drives sent to the wire.
    pub frames_out: u64,
    /// SYNCs received (periods run with SYNC).
    pub syncs: u64,
    /// Periods run without SYNC because the master was silent.
    pub periods_without_sync: u64,
    /// Frames of the drives the wire refused (transmit queue full): lost.
    pub tx_dropped: u64,
    /// Receive or transmit errors of the wire other than a full queue.
    pub wire_errors: u64,
    /// Fault injections applied.
    pub faults: u64,
}

/// Something worth a line in the log, returned by [`VirtualArm::poll`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Event {
    /// The first SYNC arrived.
    FirstSync,
    /// No SYNC for more than the grace: the arm runs on without one.
    SyncLost { periods: u64 },
    /// SYNCs arrive again after `periods` periods without one.
    SyncBack { periods: u64 },
    /// The wire failed.
    WireError(BusError),
}

/// The simulated arm on a bus `W`.
pub struct VirtualArm<W: Bus> {
    sim: SimBus,
    wire: W,
    pace: Pace,
    counters: Counters,
    /// Periods without SYNC in a row.
    silent: u64,
}

impl<W: Bus> VirtualArm<W> {
    /// The arm at power-up (as `SimBus::new`: at `sim.initial_position_deg`, every drive's
    /// boot-up frame queued for the wire) at wall time `now_ns`, with periods of the
    /// configuration's cycle and a grace of `grace` periods before it runs without SYNC.
    pub fn new(cfg: &RobotConfig, wire: W, grace: u64, now_ns: u64) -> VirtualArm<W> {
        VirtualArm {
            sim: SimBus::new(cfg),
            wire,
            pace: Pace::new(cfg.cycle_period_ns(), grace, now_ns),
            counters: Counters::default(),
            silent: 0,
        }
    }

    pub fn counters(&self) -> Counters {
        self.counters
    }

    /// What the drives saw go wrong on the bus, summed over the six: setpoints (RPDO1) missing
    /// at a SYNC, SDO aborts, the master's heartbeat timed out, faults for want of SYNC, and the
    /// master's NMT stops met with the abort connection reaction (0x6007); and the loop restarts
    /// the master asked for (not printed: not a fault).
    pub fn drive_counters(&self) -> DriveCounters {
        (0..NUM_AXES)
            .filter_map(|i| self.sim.drive(i))
            .map(|d| d.counters())
            .fold(DriveCounters::default(), |a, c| DriveCounters {
                rpdo1_missing: a.rpdo1_missing + c.rpdo1_missing,
                sdo_aborts: a.sdo_aborts + c.sdo_aborts,
                heartbeat_timeouts: a.heartbeat_timeouts + c.heartbeat_timeouts,
                sync_losses: a.sync_losses + c.sync_losses,
                connection_aborts: a.connection_aborts + c.connection_aborts,
                loop_restarts: a.loop_restarts + c.loop_restarts,
            })
    }

    /// The simulated bus (drives, physics), for inspection.
    pub fn sim(&self) -> &SimBus {
        &self.sim
    }

    /// The wire back, when the arm is done.
    pub fn into_wire(self) -> W {
        self.wire
    }

    /// The wall time by which [`VirtualArm::poll`] must run again, frame or not.
    pub fn deadline_ns(&self) -> u64 {
        self.pace.deadline_ns()
    }

    /// Wait for frames until `deadline_ns` at most (the wire's `recv`), then [`poll`].
    ///
    /// [`poll`]: VirtualArm::poll
    pub fn wait_and_poll(
        &mut self,
        deadline_ns: u64,
        now: impl Fn() -> u64,
        events: &mut impl FnMut(Event),
    ) {
        match self.wire.recv(deadline_ns) {
            Ok(Some(frame)) => self.take(&frame, now(), events),
            Ok(None) => {}
            Err(e) => {
                self.counters.wire_errors += 1;
                events(Event::WireError(e));
            }
        }
        self.poll(now(), events);
    }

    /// Take every frame waiting on the wire, run the periods without SYNC that are due at
    /// `now_ns`, and send what the drives transmitted.
    pub fn poll(&mut self, now_ns: u64, events: &mut impl FnMut(Event)) {
        loop {
            match self.wire.recv(0) {
                Ok(Some(frame)) => self.take(&frame, now_ns, events),
                Ok(None) => break,
                Err(e) => {
                    self.counters.wire_errors += 1;
                    events(Event::WireError(e));
                    break;
                }
            }
        }
        let late = self.pace.overdue(now_ns);
        if late > 0 {
            if self.silent == 0 && self.counters.syncs > 0 {
                events(Event::SyncLost { periods: late });
            }
            self.silent += late;
            self.counters.periods_without_sync += late;
            for _ in 0..late {
                self.sim.period_without_sync();
            }
        }
        self.flush(events);
    }

    fn take(&mut self, frame: &Frame, now_ns: u64, events: &mut impl FnMut(Event)) {
        self.counters.frames_in += 1;
        if frame.id == SYNC_ID {
            self.counters.syncs += 1;
            if self.counters.syncs == 1 {
                events(Event::FirstSync);
            } else if self.silent > 0 {
                events(Event::SyncBack {
                    periods: self.silent,
                });
            }
            self.silent = 0;
            self.pace.on_sync(now_ns);
        }
        // The simulated bus never fails a send.
        let _ = self.sim.send(frame);
        // Answers go out at once, before the next frame is taken, as a drive answers.
        self.flush(events);
    }

    fn flush(&mut self, events: &mut impl FnMut(Event)) {
        while let Ok(Some(frame)) = self.sim.recv(0) {
            match self.wire.send(&frame) {
                Ok(()) => self.counters.frames_out += 1,
                Err(BusError::TxQueueFull { .. }) => self.counters.tx_dropped += 1,
                Err(e) => {
                    self.counters.wire_errors += 1;
                    events(Event::WireError(e));
                }
            }
        }
    }

    /// Apply a fault injection (the `sim` command's arguments; none: only read the truth) and send what the drives
    /// transmitted because of it (an EMCY, boot-ups); the truth after it.
    pub fn apply(
        &mut self,
        cmd: &SimCommand,
        events: &mut impl FnMut(Event),
    ) -> Result<SimTruth, SimCommandError> {
        self.sim.apply(cmd)?;
        if *cmd != SimCommand::default() {
            self.counters.faults += 1;
        }
        self.flush(events);
        Ok(self.sim.truth())
    }

    /// The ground truth: true joint angles and velocities [rad, rad/s], the emergency switch.
    pub fn truth(&self) -> SimTruth {
        self.sim.truth()
    }
}

#[cfg(test)]
mod tests;
