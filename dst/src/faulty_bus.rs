//! The simulated bus with bus faults: lost, corrupted (dropped by the CRC check), delayed and
//! duplicated frames, and lost heartbeats of one drive, between the CANopen master and
//! [`SimBus`].
//!
//! Runs inside the cycle (it is the cycle's bus): fixed-capacity queues, no allocation. Its
//! randomness is its own [`Rng`], seeded from the run's seed, so a run stays deterministic.
//! What goes wrong is set from outside the cycle by the fault schedule ([`BusFaults`]); with
//! the default (nothing) it passes every frame through untouched.

use crate::rng::Rng;
use mcm_bus::{Bus, BusError, Frame};
use mcm_sim::SimBus;
use mcm_sim::bus::SYNC_ID;

/// Frames held back at most (more are delivered at once).
const DELAYED: usize = 64;

/// What the bus does wrong, each a probability per frame (0: never).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BusFaults {
    /// A frame from the master to the drives is lost, but never SYNC: the simulated robot's
    /// time and physics advance only on SYNC (lock-step time, `sim/src/bus.rs`), so a lost
    /// SYNC would stop the world for a cycle rather than make the drives miss one; a lost or
    /// stuck SYNC is not modelled (`docs/testing.md`, "Not yet built").
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
    /// still at most three SYNCs after its own delay began.
    pub delay_rx: f64,
    /// The heartbeats (0x700 + node) of this node are lost.
    pub lose_heartbeats_of: Option<u8>,
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
        }
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
        if frame.id == SYNC_ID {
            self.syncs += 1;
        } else if self.faults.lose_tx > 0.0 && self.rng.chance(self.faults.lose_tx) {
            self.counts.lost_tx += 1;
            return Ok(());
        }
        self.sim.send(frame)
    }

    fn recv(&mut self, deadline_ns: u64) -> Result<Option<Frame>, BusError> {
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
                let due = self.syncs + 1 + self.rng.below(3);
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
