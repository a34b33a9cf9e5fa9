//! The faults under way, for the checker (which excuses what the arm does while a fault moves
//! it, [`Fault::moves_the_arm`]), derived from the inputs the world gets: the `sim` commands
//! of any sender and the bus faults. The [`World`](crate::world::World) keeps one, so that a
//! seed's run, the replay of its script ([`crate::script`]) and the fuzz target's scripted
//! runs ([`crate::fuzz_input`]) tell the checker the same.
//!
//! Nothing here runs inside the real-time cycle.

use crate::faults::Fault;
use crate::faulty_bus::BusFaults;
use mcm_shared::NUM_AXES;
use mcm_shared::command::{Request, SimCommand};
use mcm_shared::reply::{Outcome, Response};
use mcm_shared::sample::{CommandSample, Reply};

/// The faults the script's `sim` commands put under way, for the checker (which excuses what
/// the arm does while a fault moves it, [`Fault::moves_the_arm`]).
///
/// The simulator applies a `sim` command when the cycle serves it and answers it in the same
/// cycle, in the order it serves them; so the state here follows the simulator's by applying
/// each command answered OK, in the order of the replies ([`SimBus`](mcm_sim::SimBus)'s
/// `apply`). Until it is answered, what a command starts counts as under way already (from
/// the cycle it is sent, as the fault schedule's started faults do), and what it undoes still
/// acts; a fault undone counts for the cycle of its answer too.
#[derive(Debug, Default)]
pub struct UnderWay {
    emergency_stop: bool,
    silent: [bool; NUM_AXES],
    blocked: [bool; NUM_AXES],
    pushed: bool,
    /// `sim` commands sent and not answered: (client, request, command).
    pending: Vec<(u64, u64, SimCommand)>,
}

impl UnderWay {
    /// A sample is sent: a well-formed `sim` command is pending until answered.
    pub fn sent(&mut self, c: &CommandSample) {
        if let Ok(Request::Sim(cmd)) = Request::decode(c) {
            self.pending.push((c.client_id, c.request_id, cmd));
        }
    }

    /// A cycle's replies: the `sim` commands answered OK act from now on.
    pub fn answered(&mut self, replies: &[Reply]) {
        for r in replies {
            let Some(i) = self
                .pending
                .iter()
                .position(|&(c, q, _)| c == r.client_id && q == r.request_id)
            else {
                continue;
            };
            let (_, _, cmd) = self.pending.remove(i);
            let done = Response::decode(r).is_ok_and(|x| matches!(x.outcome, Outcome::Done(_)));
            if done {
                self.apply(&cmd);
            }
        }
    }

    fn apply(&mut self, cmd: &SimCommand) {
        if let Some(pressed) = cmd.emergency_stop {
            self.emergency_stop = pressed;
        }
        if let Some(a) = cmd.disconnect_axis {
            self.silent[a.index()] = true;
        }
        if let Some(a) = cmd.reconnect_axis {
            self.silent[a.index()] = false;
        }
        if let Some(a) = cmd.block_axis {
            self.blocked[a.index()] = true;
        }
        if let Some(a) = cmd.unblock_axis {
            self.blocked[a.index()] = false;
        }
        if let Some(tau) = cmd.external_torques_nm {
            self.pushed = tau.iter().any(|t| *t != 0.0);
        }
    }

    /// The faults under way now, with the bus faults `bus` (named in a violation), into `out`.
    pub fn faults(&self, bus: &BusFaults, out: &mut Vec<Fault>) {
        let pending = |f: fn(&SimCommand) -> bool| self.pending.iter().any(|(_, _, c)| f(c));
        let mut add = |on: bool, f: Fault| {
            if on && !out.contains(&f) {
                out.push(f);
            }
        };
        add(
            self.emergency_stop || pending(|c| c.emergency_stop == Some(true)),
            Fault::EmergencyStop,
        );
        add(
            self.silent.iter().any(|s| *s) || pending(|c| c.disconnect_axis.is_some()),
            Fault::DriveSilent,
        );
        add(
            self.blocked.iter().any(|b| *b) || pending(|c| c.block_axis.is_some()),
            Fault::Obstacle,
        );
        add(
            self.pushed
                || pending(|c| {
                    c.external_torques_nm
                        .is_some_and(|t| t.iter().any(|x| *x != 0.0))
                }),
            Fault::Push,
        );
        add(pending(|c| c.power_cycle), Fault::PowerCycle);
        add(bus.lose_rx > 0.0 || bus.lose_tx > 0.0, Fault::BusLoss);
        add(bus.corrupt_rx > 0.0, Fault::BusCorruption);
        add(bus.delay_rx > 0.0, Fault::BusDelay);
        add(bus.duplicate_rx > 0.0, Fault::BusDuplication);
        add(bus.lose_heartbeats_of.is_some(), Fault::HeartbeatLoss);
        add(bus.sync_stuck, Fault::SyncStuck);
        add(bus.rebooting.is_some(), Fault::DriveReboot);
    }
}

#[cfg(test)]
mod tests;
