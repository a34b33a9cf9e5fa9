//! NMT slave of the simulated drive (CiA 301 §7.2.8; `docs/drive-profile.md`, "Bus and nodes"): the
//! NMT state, the decoding of NMT commands (`000#<cs><node>`), the heartbeat producer (0x1017) and
//! the consumer of the master's heartbeat (0x1016:1).
//!
//! Runs inside the cycle: plain data, no allocation. Time is the drive's own SYNC-driven
//! clock in nanoseconds, passed in by the caller.
//!
//! ```
//! use mcm_sim::nmt::{HeartbeatProducer, NmtCommand};
//! use mcm_bus::Frame;
//! let start_node_5 = Frame::new(0x000, &[0x01, 0x05]).unwrap();
//! assert_eq!(NmtCommand::decode(&start_node_5, 5), Some(NmtCommand::Start));
//! assert_eq!(NmtCommand::decode(&start_node_5, 6), None);
//! let mut hb = HeartbeatProducer::default();
//! hb.configure(50, 0);
//! assert!(!hb.due(45_000_000));
//! assert!(hb.due(50_000_000));
//! ```

use mcm_bus::Frame;

/// COB-ID of NMT node control.
pub const NMT_ID: u16 = 0x000;
/// COB-ID base of heartbeat / boot-up frames.
pub const HEARTBEAT_BASE: u16 = 0x700;

/// The NMT state of a node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NmtState {
    PreOperational,
    Operational,
    Stopped,
}

impl NmtState {
    /// The state byte of a heartbeat frame.
    pub const fn heartbeat_byte(self) -> u8 {
        match self {
            NmtState::PreOperational => 0x7F,
            NmtState::Operational => 0x05,
            NmtState::Stopped => 0x04,
        }
    }
    /// SDO is served (PRE-OPERATIONAL and OPERATIONAL).
    pub const fn sdo_allowed(self) -> bool {
        !matches!(self, NmtState::Stopped)
    }
    /// EMCY may be sent (PRE-OPERATIONAL and OPERATIONAL).
    pub const fn emcy_allowed(self) -> bool {
        !matches!(self, NmtState::Stopped)
    }
}

/// An NMT command addressed to this node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NmtCommand {
    /// `01`: start remote node -> OPERATIONAL.
    Start,
    /// `02`: stop -> STOPPED.
    Stop,
    /// `80`: enter PRE-OPERATIONAL.
    EnterPreOperational,
    /// `81`: reset node (application + communication) -> boot-up.
    ResetNode,
    /// `82`: reset communication -> boot-up.
    ResetCommunication,
}

impl NmtCommand {
    /// Decode an NMT frame for `node_id` (node 0 in the frame = broadcast). `None` if the frame
    /// is not NMT, not for this node, not 2 bytes, or has an unknown command specifier.
    pub fn decode(frame: &Frame, node_id: u8) -> Option<NmtCommand> {
        if frame.id != NMT_ID || frame.len != 2 {
            return None;
        }
        let [cs, node] = [frame.data[0], frame.data[1]];
        if node != 0 && node != node_id {
            return None;
        }
        match cs {
            0x01 => Some(NmtCommand::Start),
            0x02 => Some(NmtCommand::Stop),
            0x80 => Some(NmtCommand::EnterPreOperational),
            0x81 => Some(NmtCommand::ResetNode),
            0x82 => Some(NmtCommand::ResetCommunication),
            _ => None,
        }
    }
}

/// `700+n#00`.
pub fn boot_up_frame(node_id: u8) -> Frame {
    heartbeat_frame(node_id, 0x00)
}

/// `700+n#<state>`.
pub fn heartbeat_frame(node_id: u8, state_byte: u8) -> Frame {
    let mut data = [0u8; 8];
    data[0] = state_byte;
    Frame {
        id: HEARTBEAT_BASE + u16::from(node_id),
        len: 1,
        data,
    }
}

/// Heartbeat producer per 0x1017 (period in ms, 0 = off).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct HeartbeatProducer {
    period_ns: u64,
    next_due_ns: u64,
}

impl HeartbeatProducer {
    /// (Re)start with a new period at `now_ns`; the first heartbeat is due one period later.
    pub fn configure(&mut self, period_ms: u16, now_ns: u64) {
        self.period_ns = u64::from(period_ms) * 1_000_000;
        self.next_due_ns = now_ns + self.period_ns;
    }

    /// Whether a heartbeat is due at `now_ns`; if so, schedules the next one (on the period's
    /// grid, skipping periods that were missed entirely).
    pub fn due(&mut self, now_ns: u64) -> bool {
        if self.period_ns == 0 || now_ns < self.next_due_ns {
            return false;
        }
        while self.next_due_ns <= now_ns {
            self.next_due_ns += self.period_ns;
        }
        true
    }
}

/// Consumer of one producer's heartbeat per 0x1016:i = `(node << 16) | time_ms`. It is armed
/// by the first heartbeat received after configuration and fires once when no heartbeat has
/// arrived for longer than the time; it then waits for the next heartbeat to re-arm.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct HeartbeatConsumer {
    producer: u8,
    timeout_ns: u64,
    last_seen_ns: Option<u64>,
}

impl HeartbeatConsumer {
    /// Configure from a 0x1016 entry (node 0 or time 0 = off). Disarms.
    pub fn configure(&mut self, entry: u32) {
        self.producer = ((entry >> 16) & 0x7F) as u8;
        self.timeout_ns = u64::from(entry & 0xFFFF) * 1_000_000;
        self.last_seen_ns = None;
    }

    fn enabled(&self) -> bool {
        self.producer != 0 && self.timeout_ns != 0
    }

    /// Look at a received frame; a heartbeat of the watched producer (re)arms the timer.
    pub fn on_frame(&mut self, frame: &Frame, now_ns: u64) {
        if self.enabled() && frame.len >= 1 && frame.id == HEARTBEAT_BASE + u16::from(self.producer)
        {
            self.last_seen_ns = Some(now_ns);
        }
    }

    /// `true` once when the heartbeat has been missing for longer than the time.
    pub fn expired(&mut self, now_ns: u64) -> bool {
        match self.last_seen_ns {
            Some(seen) if self.enabled() && now_ns.saturating_sub(seen) > self.timeout_ns => {
                self.last_seen_ns = None;
                true
            }
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests;
