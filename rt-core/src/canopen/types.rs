//! The interface types of the CANopen [`Master`](super::master::Master): per-axis requests
//! and feedback, events, the fixed-capacity frame buffer and the setup error. All are plain
//! `Copy`/fixed-size data, so the cyclic path can use them without allocating.
//!
//! Runs inside the cycle (data only).

use super::boot::BootError;
use super::busload::BusLoadError;
use super::cia402::State;
use super::emcy::Emcy;
use super::nmt::NmtState;
use super::sdo::SdoError;
use mcm_bus::Frame;
use mcm_shared::NUM_AXES;

/// Capacity of a [`FrameBuf`]. One cycle needs at most 1 heartbeat + 6 x 2 (NMT or SDO, or
/// RPDO2 + RPDO1) + SYNC = 14 frames.
pub const FRAME_BUF_CAPACITY: usize = 64;
/// Capacity of the event ring; further events are counted as dropped.
pub const EVENT_CAPACITY: usize = 64;
/// Modes of operation used by the MCM.
pub const MODE_CSP: i8 = 8;
pub const MODE_CST: i8 = 10;
/// An RPDO2 with a new mode or current limit is sent again in this many following cycles:
/// the drive confirms a mode (0x6061 in TPDO2) but not a current limit, and a lost frame must
/// not leave a drive at an old limit (a calibration's reduced current, holding an arm it
/// cannot). Event-driven, like the frame it repeats: not in the periodic bus load.
pub const RPDO2_REPEATS: u8 = 2;
/// Fault-reset edges sent per [`Master::reset_faults`] call to a drive that stays in FAULT.
pub const FAULT_RESET_EDGES: u8 = 3;
/// Times in a row the master resets and configures again a drive whose configuration failed
/// ([`MasterEvent::ConfigFailed`]), `bus.boot_timeout_ms` after each failure; then it leaves
/// the drive down until it boots by itself or [`super::Master::reset_node`] is called. A drive
/// that comes up configured, or is missing (no boot-up after a reset), starts the count again.
pub const CONFIG_RETRIES: u8 = 3;

const _: () = assert!(2 + NUM_AXES * 3 <= FRAME_BUF_CAPACITY);

/// What the controller wants from one drive this cycle (joint side, raw encoder frame, i.e.
/// without calibration offset).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DriveRequest {
    /// Power stage off (SWITCH ON DISABLED).
    Disable,
    /// Quick stop ramp, then SWITCH ON DISABLED.
    QuickStop,
    /// OPERATION ENABLED in CSP, following this position [rad].
    Position { position_rad: f64 },
    /// OPERATION ENABLED in CST with this joint torque [Nm].
    Torque { torque_nm: f64 },
}

/// What the master knows about one drive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisFeedback {
    /// CANopen node id of the drive.
    pub node: u8,
    /// Configured, started and its heartbeat fresh (and not lost).
    pub online: bool,
    /// NMT OPERATIONAL as far as the master knows (started and heartbeat 05 or TPDO1 seen).
    pub operational: bool,
    pub state: State,
    /// 0x6061 from TPDO2.
    pub mode_display: Option<i8>,
    /// OPERATION ENABLED in the requested mode (0x6061 confirmed).
    pub enabled: bool,
    /// Joint position, raw encoder frame [rad].
    pub position_rad: f64,
    /// Derived from successive TPDO1 positions [rad/s].
    pub velocity_rad_s: f64,
    /// Motor current [A] (signed).
    pub current_a: f64,
    /// Joint-side torque from the current [Nm].
    pub torque_nm: f64,
    pub statusword: u16,
    /// Statusword bit 14: emergency stop / safe torque off.
    pub estop: bool,
    /// Statusword bit 15: positive side of the light barrier.
    pub light_barrier: bool,
    /// The last EMCY with a non-zero code; cleared by an EMCY 0x0000 (error reset).
    pub last_emcy: Option<Emcy>,
    /// Cycles since the last TPDO1 (0 = received for this cycle; `u16::MAX` before the first).
    pub tpdo_age_cycles: u16,
    /// The position setpoint of this cycle was limited to the velocity limit
    /// (`max_velocity_deg_s * safety.overspeed_factor`).
    pub target_clamped: bool,
}

impl AxisFeedback {
    pub(super) fn new(node: u8) -> AxisFeedback {
        AxisFeedback {
            node,
            online: false,
            operational: false,
            state: State::Unknown,
            mode_display: None,
            enabled: false,
            position_rad: 0.0,
            velocity_rad_s: 0.0,
            current_a: 0.0,
            torque_nm: 0.0,
            statusword: 0,
            estop: false,
            light_barrier: false,
            last_emcy: None,
            tpdo_age_cycles: u16::MAX,
            target_clamped: false,
        }
    }
}

/// Why a drive counts as lost.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LostReason {
    /// No heartbeat for `bus.heartbeat_timeout_ms`.
    HeartbeatTimeout,
    /// `bus.max_missed_tpdos` consecutive cycles without TPDO1.
    MissedTpdos { missed: u16 },
    /// The drive sent a boot-up while configured (power cycle or reset); it is reconfigured.
    BootUp,
    /// Its heartbeat reports a state other than OPERATIONAL; it is reset and reconfigured.
    NotOperational { state: NmtState },
}

impl core::fmt::Display for LostReason {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            LostReason::HeartbeatTimeout => f.write_str("heartbeat timeout"),
            LostReason::MissedTpdos { missed } => write!(f, "{missed} consecutive TPDO1 missed"),
            LostReason::BootUp => f.write_str("unexpected boot-up (drive rebooted)"),
            LostReason::NotOperational { state } => write!(f, "heartbeat reports {}", state.name()),
        }
    }
}

/// Something happened on the bus. `axis` is 0-based.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MasterEvent {
    /// Boot-up frame seen; configuration starts.
    Booted {
        axis: usize,
    },
    /// Configuration done and NMT start sent.
    Configured {
        axis: usize,
    },
    /// The calibration offset the drive holds in 0x2100 (`None`: it holds none), read while
    /// booting it. Once per boot, in the same cycle right after `Configured`.
    Calibration {
        axis: usize,
        offset_counts: Option<i32>,
    },
    /// [`super::Master::store_calibration`] wrote 0x2100:1 and 0x2100:2 of the drive.
    CalibrationStored {
        axis: usize,
    },
    /// [`super::Master::store_calibration`] failed: the drive aborted a write (the error
    /// names node, object and abort text) or did not answer within `bus.sdo_timeout_ms`.
    CalibrationStoreFailed {
        axis: usize,
        error: SdoError,
    },
    /// A configuration step failed after its retries. The master resets the drive and
    /// configures it again `bus.boot_timeout_ms` later, up to [`CONFIG_RETRIES`] times in a row.
    ConfigFailed {
        axis: usize,
        node: u8,
        error: BootError,
    },
    /// No boot-up within `bus.boot_timeout_ms`; NMT reset communication sent.
    Missing {
        axis: usize,
        node: u8,
    },
    Lost {
        axis: usize,
        node: u8,
        reason: LostReason,
    },
    /// A lost drive's heartbeat and TPDO1 are back (without reboot).
    Recovered {
        axis: usize,
        node: u8,
    },
    Emcy {
        axis: usize,
        emcy: Emcy,
    },
    /// The drive entered FAULT; `code` is the last EMCY code received (0 if none).
    Fault {
        axis: usize,
        code: u16,
    },
}

/// Fixed-capacity list of frames to send; never allocates (a [`heapless::Vec`] inside).
#[derive(Clone)]
pub struct FrameBuf {
    frames: heapless::Vec<Frame, FRAME_BUF_CAPACITY>,
}

impl FrameBuf {
    pub const fn new() -> FrameBuf {
        FrameBuf {
            frames: heapless::Vec::new(),
        }
    }

    /// Append; `false` (frame not stored) when full.
    pub fn push(&mut self, frame: Frame) -> bool {
        self.frames.push(frame).is_ok()
    }

    pub fn clear(&mut self) {
        self.frames.clear();
    }

    pub fn len(&self) -> usize {
        self.frames.len()
    }

    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    pub fn as_slice(&self) -> &[Frame] {
        &self.frames
    }

    pub fn iter(&self) -> core::slice::Iter<'_, Frame> {
        self.frames.iter()
    }
}

impl Default for FrameBuf {
    fn default() -> Self {
        FrameBuf::new()
    }
}

impl core::fmt::Debug for FrameBuf {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_list().entries(self.as_slice()).finish()
    }
}

/// The master cannot run with this configuration.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MasterSetupError {
    #[error(transparent)]
    BusLoad(#[from] BusLoadError),
    #[error("config has {got} axes; the master drives exactly {NUM_AXES}")]
    AxisCount { got: usize },
    #[error(
        "cycle period {period_us} us (cycle.rate_hz = {rate_hz}) is not allowed: 0x60C2 is configured in \
         whole milliseconds, so the period must be 1..=255 ms"
    )]
    CyclePeriod { rate_hz: u32, period_us: u64 },
    #[error("axis[{}].{key} = {value} gives {derived} = {derived_value}, which does not fit {allowed}", axis + 1)]
    AxisValue {
        axis: usize,
        key: &'static str,
        value: f64,
        derived: &'static str,
        derived_value: f64,
        allowed: &'static str,
    },
}

/// Fixed-capacity FIFO of events (inline, no heap); further events are counted as dropped.
#[derive(Debug, Clone)]
pub(super) struct EventRing {
    buf: heapless::Deque<MasterEvent, EVENT_CAPACITY>,
    pub(super) dropped: u64,
}

impl EventRing {
    pub(super) fn new() -> EventRing {
        EventRing {
            buf: heapless::Deque::new(),
            dropped: 0,
        }
    }

    pub(super) fn push(&mut self, e: MasterEvent) {
        if self.buf.push_back(e).is_err() {
            self.dropped += 1;
        }
    }

    pub(super) fn pop(&mut self) -> Option<MasterEvent> {
        self.buf.pop_front()
    }
}
