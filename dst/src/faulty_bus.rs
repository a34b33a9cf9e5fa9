//! The simulated bus with bus faults: lost, corrupted (dropped by the CRC check), delayed and
//! duplicated frames, lost heartbeats of one drive, a stuck SYNC and a drive rebooting,
//! between the CANopen master and [`SimBus`].
//!
//! Runs inside the cycle (it is the cycle's bus): fixed-capacity queues, no allocation. Its
//! randomness is its own [`Rng`], seeded from the run's seed, so a run stays deterministic.
//! What goes wrong is set from outside the cycle by the fault schedule ([`BusFaults`]); with
//! the default (nothing) it passes every frame through untouched.

use crate::rng::Rng;
use mcm_bus::{Bus, BusError, Frame};
use mcm_sim::SimBus;
use mcm_sim::bus::SYNC_ID;

/// Frames held back at most. A frame that would wait behind a delayed one of its COB-ID when
/// the queue is full is lost (a receive queue's overrun); one the bus would delay is delivered
/// at once.
const DELAYED: usize = 128;
/// The most SYNCs a delayed frame to the master arrives late.
pub const MAX_DELAY_SYNCS: usize = 3;

/// What the bus does wrong: probabilities per frame (0: never), and states that last while
/// they are set.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BusFaults {
    /// A frame from the master to the drives is lost, SYNC included. The simulated robot's
    /// time advances on SYNC (lock-step time, `sim/src/bus.rs`); a lost SYNC's period passes
    /// all the same ([`SimBus::period_without_sync`]): the arm moves on, the drives miss it.
    pub lose_tx: f64,
    /// A frame from the drives to the master is lost.
    pub lose_rx: f64,
    /// A frame to the master is hit by a bit error. As on a real bus, the receiving CAN
    /// controller finds its CRC wrong and discards it (an error frame): the master never sees
    /// a corrupted frame. The sender's automatic retransmission is not modelled: the frame is
    /// lost.
    pub corrupt_rx: f64,
    /// A frame to the master arrives twice.
    pub duplicate_rx: f64,
    /// A frame to the master arrives one to three SYNCs late. The delayed frames keep their
    /// order: one due earlier than the frame delayed before it waits for that one, which is
    /// still at most three SYNCs after its own delay began. The frames of one COB-ID keep
    /// their order too, as on a real bus (a node sends them in turn) and in SocketCAN's receive
    /// queue: a frame whose COB-ID has a delayed frame pending waits behind it.
    pub delay_rx: f64,
    /// The heartbeats (0x700 + node) of this node are lost.
    pub lose_heartbeats_of: Option<u8>,
    /// The SYNC producer is stuck: no SYNC reaches the drives, whose periods pass without it
    /// ([`SimBus::period_without_sync`]): they hold their last setpoint and send no TPDO,
    /// while the arm moves on and their heartbeats go on.
    pub sync_stuck: bool,
    /// The drive of this axis (0-based) is rebooting: its supply off from the first bus access
    /// that sees it set ([`SimBus::power_off_drive`]) until the first that sees it cleared,
    /// when it boots as at power-up ([`SimBus::power_on_drive`]).
    pub rebooting: Option<usize>,
}

impl BusFaults {
    pub fn any(&self) -> bool {
        *self != BusFaults::default()
    }
}

/// What the faulty bus did, for the campaign's "sometimes" counts.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BusFaultCounts {
    pub lost_tx: u64,
    pub lost_rx: u64,
    pub corrupted: u64,
    pub duplicated: u64,
    pub delayed: u64,
    pub heartbeats_lost: u64,
    /// SYNCs held back by a stuck SYNC (those lost count in `lost_tx`).
    pub syncs_stuck: u64,
    /// Drives switched off for a reboot.
    pub reboots: u64,
}

/// [`SimBus`] behind a faulty cable.
pub struct FaultyBus {
    sim: SimBus,
    pub faults: BusFaults,
    pub counts: BusFaultCounts,
    rng: Rng,
    syncs: u64,
    /// (SYNC count at which it is delivered, frame).
    delayed: heapless::Deque<(u64, Frame), DELAYED>,
    /// A duplicate to deliver on the next `recv`.
    again: Option<Frame>,
    /// The axis whose drive is off for its reboot.
    off: Option<usize>,
}

impl FaultyBus {
    pub fn new(sim: SimBus, rng: Rng) -> FaultyBus {
        FaultyBus {
            sim,
            faults: BusFaults::default(),
            counts: BusFaultCounts::default(),
            rng,
            syncs: 0,
            delayed: heapless::Deque::new(),
            again: None,
            off: None,
        }
    }

    /// Switch a drive off or on when [`BusFaults::rebooting`] changed: the schedule sets the
    /// faults between cycles, the bus follows at its next access.
    fn follow_reboots(&mut self) {
        let want = self.faults.rebooting;
        if want == self.off {
            return;
        }
        if let Some(axis) = self.off {
            self.sim.power_on_drive(axis);
        }
        if let Some(axis) = want {
            self.sim.power_off_drive(axis);
            self.counts.reboots += 1;
        }
        self.off = want;
    }

    /// The simulated robot inside (the simulator's edge reaches it through this).
    pub fn sim_mut(&mut self) -> &mut SimBus {
        &mut self.sim
    }

    /// The simulated robot inside, for inspection.
    pub fn sim(&self) -> &SimBus {
        &self.sim
    }

    fn is_heartbeat_of(frame: &Frame, node: Option<u8>) -> bool {
        node.is_some_and(|n| frame.id == 0x700 + u16::from(n))
    }
}

impl Bus for FaultyBus {
    fn send(&mut self, frame: &Frame) -> Result<(), BusError> {
        self.follow_reboots();
        let sync = frame.id == SYNC_ID;
        if sync {
            self.syncs += 1;
        }
        if sync && self.faults.sync_stuck {
            self.counts.syncs_stuck += 1;
        } else if self.faults.lose_tx > 0.0 && self.rng.chance(self.faults.lose_tx) {
            self.counts.lost_tx += 1;
        } else {
            return self.sim.send(frame);
        }
        // Lost: the drives miss it, but a SYNC's period passes all the same.
        if sync {
            self.sim.period_without_sync();
        }
        Ok(())
    }

    fn recv(&mut self, deadline_ns: u64) -> Result<Option<Frame>, BusError> {
        self.follow_reboots();
        if let Some(f) = self.again.take() {
            return Ok(Some(f));
        }
        if let Some(&(due, f)) = self.delayed.front()
            && due <= self.syncs
        {
            self.delayed.pop_front();
            return Ok(Some(f));
        }
        loop {
            let Some(f) = self.sim.recv(deadline_ns)? else {
                return Ok(None);
            };
            if self.delayed.iter().any(|(_, d)| d.id == f.id) {
                // Due now, but after the earlier frame of its COB-ID still held back (also
                // once the faults are over).
                if self.delayed.push_back((self.syncs, f)).is_err() {
                    self.counts.lost_rx += 1;
                }
                continue;
            }
            let faults = self.faults;
            if !faults.any() {
                return Ok(Some(f));
            }
            if Self::is_heartbeat_of(&f, faults.lose_heartbeats_of) {
                self.counts.heartbeats_lost += 1;
                continue;
            }
            if self.rng.chance(faults.lose_rx) {
                self.counts.lost_rx += 1;
                continue;
            }
            if self.rng.chance(faults.corrupt_rx) {
                self.counts.corrupted += 1;
                continue;
            }
            if self.rng.chance(faults.delay_rx) {
                let due = self.syncs + 1 + self.rng.below(MAX_DELAY_SYNCS as u64);
                if self.delayed.push_back((due, f)).is_ok() {
                    self.counts.delayed += 1;
                    continue;
                }
            }
            if self.rng.chance(faults.duplicate_rx) {
                self.again = Some(f);
                self.counts.duplicated += 1;
            }
            return Ok(Some(f));
        }
    }
}

#[cfg(test)]
mod tests;
