//! The per-node configuration sequence of `docs/drive-profile.md` ("Boot and configuration"), as a
//! state machine the master drives once per cycle: one expedited SDO transaction at a time,
//! each step retried at most [`MAX_RETRIES`] times after a timeout or an abort, then NMT start.
//!
//! Before the NMT start, the sequence reads the drive's stored calibration (step 12, see
//! [`CALIBRATION_OPS`]): 0x2100:2 (valid, u8) and, only if it is 1, 0x2100:1 (offset, i32,
//! encoder counts: the raw position actual at joint angle 0). 0x2100 is a manufacturer-specific
//! volatile object the drive keeps until it loses power (NMT resets keep it), so a restart of
//! the MCM finds the calibration the drives still hold; the master writes it with
//! [`super::master::Master::store_calibration`]. A drive that aborts the read (it has no such
//! object) counts as not calibrated; a timeout is retried and fails the boot like any step.
//! The result is [`BootSequence::calibration`], valid once the sequence is done.
//!
//! Started with [`StoredCalibration::Clear`] (the master wrote 0x2100 shortly before the drive
//! rebooted, so a write may have reached the drive after its reboot, against a new encoder
//! reference), step 12 writes 0x2100:2 = 0 instead of reading: the drive is not calibrated.
//!
//! Runs inside the cycle (only while the node is not operational): the operation list is a
//! fixed array built once from the configuration; `poll` allocates nothing.
//!
//! Usage, per cycle: feed the SDO outcome that `SdoClient::on_frame` returned for this node
//! (if any) into [`BootSequence::poll`] and send the frame it returns.

use super::nmt::{NmtCommand, nmt_frame};
use super::objects::*;
use super::sdo::{SdoAbortCode, SdoClient, SdoDone, SdoError, SdoRequest, SdoValue};
use mcm_bus::Frame;

/// Number of SDO operations of the sequence (steps 1..=11).
pub const BOOT_OPS: usize = 42;
/// Retries of one operation after a timeout or abort (so at most 3 attempts).
pub const MAX_RETRIES: u8 = 2;
/// TPDO2's event timer (0x1801:5) [ms], in the contract beside the bus load it enters.
pub use mcm_shared::busload::TPDO2_EVENT_TIMER_MS;

/// What one operation does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BootAction {
    /// Upload and compare with `expect`.
    Read {
        expect: u32,
    },
    Write(SdoValue),
    /// Upload and keep the value (the stored calibration).
    Upload,
}

/// Index of the drive's stored calibration (manufacturer-specific, volatile until power-off).
pub const CALIBRATION: u16 = 0x2100;
/// 0x2100:1, the calibration offset (i32, encoder counts at joint angle 0).
pub const CALIBRATION_OFFSET_SUB: u8 = 1;
/// 0x2100:2, the calibration is valid (u8, 0/1).
pub const CALIBRATION_VALID_SUB: u8 = 2;

/// Step 12, after the 42 operations of [`boot_ops`] and before the NMT start: read whether
/// the drive holds a calibration, then (only if it does) the offset.
/// With [`StoredCalibration::Clear`], step 12 is the third operation alone: mark the stored
/// calibration invalid.
pub const CALIBRATION_OPS: [BootOp; 3] = [
    BootOp {
        step: 12,
        addr: ObjectAddr::new(CALIBRATION, CALIBRATION_VALID_SUB),
        action: BootAction::Upload,
        what: "stored calibration valid",
    },
    BootOp {
        step: 12,
        addr: ObjectAddr::new(CALIBRATION, CALIBRATION_OFFSET_SUB),
        action: BootAction::Upload,
        what: "stored calibration offset",
    },
    BootOp {
        step: 12,
        addr: ObjectAddr::new(CALIBRATION, CALIBRATION_VALID_SUB),
        action: BootAction::Write(SdoValue::U8(0)),
        what: "stored calibration cleared (a store was cut short by the drive's reboot)",
    },
];

/// What step 12 does with the calibration the drive holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StoredCalibration {
    /// Read it (0x2100:2, then 0x2100:1): the drive is calibrated if it holds one.
    Read,
    /// Mark it invalid (0x2100:2 = 0): the drive is not calibrated. For a drive that rebooted
    /// while a write of 0x2100 was under way or not yet confirmed.
    Clear,
}

/// One SDO operation of the sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BootOp {
    /// Step number in `docs/drive-profile.md`, "Boot and configuration" (1..=12).
    pub step: u8,
    pub addr: ObjectAddr,
    pub action: BootAction,
    /// What the operation configures, for error messages.
    pub what: &'static str,
}

/// Values the sequence writes, taken from the configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BootParams {
    pub node: u8,
    /// 0-based axis index (texts print it 1-based).
    pub axis: usize,
    pub drive_heartbeat_ms: u16,
    pub master_node_id: u8,
    /// The drive's consumer time of the master's heartbeat (0x1016:1) [ms]:
    /// `bus.heartbeat_timeout_ms`, the one heartbeat timeout of both directions.
    pub master_heartbeat_timeout_ms: u16,
    /// Cycle period T in whole milliseconds (0x60C2:1).
    pub cycle_ms: u8,
    /// 0x6075, motor rated current [mA].
    pub rated_current_ma: u32,
    /// 0x6076, motor rated torque [mNm].
    pub rated_torque_mnm: u32,
    /// 0x6073, max current [per-mille of rated current].
    pub max_current_permille: u16,
}

/// The 42 operations of steps 1..=11, in order.
pub fn boot_ops(p: &BootParams) -> [BootOp; BOOT_OPS] {
    let n = u32::from(p.node);
    let a = ObjectAddr::new;
    let w = |step, addr, v, what| BootOp {
        step,
        addr,
        action: BootAction::Write(v),
        what,
    };
    use SdoValue::{I8, I16, U8, U16, U32};
    let consumer = (u32::from(p.master_node_id) << 16) | u32::from(p.master_heartbeat_timeout_ms);
    [
        BootOp {
            step: 1,
            addr: a(DEVICE_TYPE, 0),
            action: BootAction::Read {
                expect: DEVICE_TYPE_CIA402_SERVO,
            },
            what: "device type (CiA 402 servo drive expected)",
        },
        w(
            2,
            a(PRODUCER_HEARTBEAT_TIME, 0),
            U16(p.drive_heartbeat_ms),
            "drive heartbeat producer time",
        ),
        w(
            3,
            a(CONSUMER_HEARTBEAT_TIME, 1),
            U32(consumer),
            "heartbeat consumer of the master",
        ),
        // 4. RPDO1, cyclic setpoints.
        w(
            4,
            a(RPDO_COMM, 1),
            U32(PDO_COB_ID_INVALID | (0x200 + n)),
            "RPDO1 COB-ID (disable)",
        ),
        w(4, a(RPDO_MAP, 0), U8(0), "RPDO1 mapping count = 0"),
        w(
            4,
            a(RPDO_MAP, 1),
            U32(mapping_entry(CONTROLWORD, 0, 16)),
            "RPDO1 mapping 1: controlword",
        ),
        w(
            4,
            a(RPDO_MAP, 2),
            U32(mapping_entry(TARGET_POSITION, 0, 32)),
            "RPDO1 mapping 2: target position",
        ),
        w(
            4,
            a(RPDO_MAP, 3),
            U32(mapping_entry(TARGET_TORQUE, 0, 16)),
            "RPDO1 mapping 3: target torque",
        ),
        w(4, a(RPDO_MAP, 0), U8(3), "RPDO1 mapping count = 3"),
        w(
            4,
            a(RPDO_COMM, 2),
            U8(1),
            "RPDO1 transmission type (synchronous)",
        ),
        w(4, a(RPDO_COMM, 1), U32(0x200 + n), "RPDO1 COB-ID (enable)"),
        // 5. RPDO2, event-driven mode, current limit and torque feed-forward.
        w(
            5,
            a(RPDO_COMM + 1, 1),
            U32(PDO_COB_ID_INVALID | (0x300 + n)),
            "RPDO2 COB-ID (disable)",
        ),
        w(5, a(RPDO_MAP + 1, 0), U8(0), "RPDO2 mapping count = 0"),
        w(
            5,
            a(RPDO_MAP + 1, 1),
            U32(mapping_entry(MODES_OF_OPERATION, 0, 8)),
            "RPDO2 mapping 1: modes of operation",
        ),
        w(
            5,
            a(RPDO_MAP + 1, 2),
            U32(mapping_entry(MAX_CURRENT, 0, 16)),
            "RPDO2 mapping 2: max current",
        ),
        w(
            5,
            a(RPDO_MAP + 1, 3),
            U32(mapping_entry(TORQUE_OFFSET, 0, 16)),
            "RPDO2 mapping 3: torque offset",
        ),
        w(5, a(RPDO_MAP + 1, 0), U8(3), "RPDO2 mapping count = 3"),
        w(
            5,
            a(RPDO_COMM + 1, 2),
            U8(255),
            "RPDO2 transmission type (event-driven)",
        ),
        w(
            5,
            a(RPDO_COMM + 1, 1),
            U32(0x300 + n),
            "RPDO2 COB-ID (enable)",
        ),
        // 6. TPDO1, cyclic feedback.
        w(
            6,
            a(TPDO_COMM, 1),
            U32(PDO_COB_ID_INVALID | (0x180 + n)),
            "TPDO1 COB-ID (disable)",
        ),
        w(6, a(TPDO_MAP, 0), U8(0), "TPDO1 mapping count = 0"),
        w(
            6,
            a(TPDO_MAP, 1),
            U32(mapping_entry(STATUSWORD, 0, 16)),
            "TPDO1 mapping 1: statusword",
        ),
        w(
            6,
            a(TPDO_MAP, 2),
            U32(mapping_entry(POSITION_ACTUAL, 0, 32)),
            "TPDO1 mapping 2: position actual",
        ),
        w(
            6,
            a(TPDO_MAP, 3),
            U32(mapping_entry(CURRENT_ACTUAL, 0, 16)),
            "TPDO1 mapping 3: current actual",
        ),
        w(6, a(TPDO_MAP, 0), U8(3), "TPDO1 mapping count = 3"),
        w(
            6,
            a(TPDO_COMM, 2),
            U8(1),
            "TPDO1 transmission type (synchronous)",
        ),
        w(6, a(TPDO_COMM, 1), U32(0x180 + n), "TPDO1 COB-ID (enable)"),
        // 7. TPDO2, event-driven mode display, repeated by its event timer.
        w(
            7,
            a(TPDO_COMM + 1, 1),
            U32(PDO_COB_ID_INVALID | (0x280 + n)),
            "TPDO2 COB-ID (disable)",
        ),
        w(7, a(TPDO_MAP + 1, 0), U8(0), "TPDO2 mapping count = 0"),
        w(
            7,
            a(TPDO_MAP + 1, 1),
            U32(mapping_entry(MODES_OF_OPERATION_DISPLAY, 0, 8)),
            "TPDO2 mapping 1: modes of operation display",
        ),
        w(7, a(TPDO_MAP + 1, 0), U8(1), "TPDO2 mapping count = 1"),
        w(
            7,
            a(TPDO_COMM + 1, 2),
            U8(255),
            "TPDO2 transmission type (event-driven)",
        ),
        w(
            7,
            a(TPDO_COMM + 1, 5),
            U16(TPDO2_EVENT_TIMER_MS),
            "TPDO2 event timer (ms)",
        ),
        w(
            7,
            a(TPDO_COMM + 1, 1),
            U32(0x280 + n),
            "TPDO2 COB-ID (enable)",
        ),
        // 8. Interpolation period = SYNC period.
        w(
            8,
            a(INTERPOLATION_TIME_PERIOD, 1),
            U8(p.cycle_ms),
            "interpolation time period units (ms)",
        ),
        w(
            8,
            a(INTERPOLATION_TIME_PERIOD, 2),
            I8(-3),
            "interpolation time period index (10^-3 s)",
        ),
        // 9. Motor data.
        w(
            9,
            a(MOTOR_RATED_CURRENT, 0),
            U32(p.rated_current_ma),
            "motor rated current (mA)",
        ),
        w(
            9,
            a(MOTOR_RATED_TORQUE, 0),
            U32(p.rated_torque_mnm),
            "motor rated torque (mNm)",
        ),
        // 10. Current limit.
        w(
            10,
            a(MAX_CURRENT, 0),
            U16(p.max_current_permille),
            "max current (per-mille of rated)",
        ),
        // 11. Quick stop and abort connection reactions, then the mode: cyclic synchronous
        // position.
        w(
            11,
            a(QUICK_STOP_OPTION_CODE, 0),
            I16(QUICK_STOP_OPTION_DISABLE),
            "quick stop option code = 2 (quick-stop ramp, then SWITCH ON DISABLED)",
        ),
        w(
            11,
            a(ABORT_CONNECTION_OPTION_CODE, 0),
            I16(ABORT_CONNECTION_DISABLE_VOLTAGE),
            "abort connection option code = 2 (disable voltage on the master's NMT stop)",
        ),
        w(
            11,
            a(MODES_OF_OPERATION, 0),
            I8(8),
            "modes of operation = 8 (CSP)",
        ),
    ]
}

/// Why a configuration step failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum BootCause {
    #[error("no SDO response within {timeout_ms} ms")]
    Timeout { timeout_ms: u64 },
    #[error("SDO abort {0}")]
    Aborted(SdoAbortCode),
    #[error("device type is 0x{got:08X}, expected 0x{expected:08X} (CiA 402 servo drive)")]
    WrongDeviceType { got: u32, expected: u32 },
    #[error(
        "segmented SDO transfer of {size} bytes offered; only expedited transfers are supported"
    )]
    Segmented { size: u32 },
}

/// Configuration of a node failed; names node, axis (1-based in the text), step and cause.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error(
    "node {node} (axis {}) configuration step {step} ({addr} {what}) failed after {attempts} attempt(s): {cause}",
    axis + 1
)]
pub struct BootError {
    pub node: u8,
    /// 0-based.
    pub axis: usize,
    pub step: u8,
    pub addr: ObjectAddr,
    pub what: &'static str,
    pub attempts: u8,
    pub cause: BootCause,
}

/// What the sequence wants the master to do in this cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BootOutput {
    /// Not running (not started, done or failed).
    Idle,
    /// Waiting for the response of the outstanding SDO.
    Waiting,
    /// Send this SDO request.
    Send(Frame),
    /// All steps done: send this NMT start (after step 12); the node is configured and
    /// [`BootSequence::calibration`] holds what it stored.
    Done(Frame),
    /// The node could not be configured.
    Failed(BootError),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    Idle,
    Running { waiting: bool },
}

/// The configuration state machine of one node.
#[derive(Debug, Clone)]
pub struct BootSequence {
    node: u8,
    axis: usize,
    ops: [BootOp; BOOT_OPS],
    /// Index of the current operation: `0..BOOT_OPS` in `ops`, then `BOOT_OPS + k` for
    /// `CALIBRATION_OPS[k]`.
    next: usize,
    failures: u8,
    phase: Phase,
    stored: StoredCalibration,
    calibration: Option<i32>,
}

impl BootSequence {
    pub fn new(params: &BootParams) -> BootSequence {
        BootSequence {
            node: params.node,
            axis: params.axis,
            ops: boot_ops(params),
            next: 0,
            failures: 0,
            phase: Phase::Idle,
            stored: StoredCalibration::Read,
            calibration: None,
        }
    }

    /// The calibration offset [counts] the drive holds (0x2100:1 when 0x2100:2 is 1), as read
    /// by the last run of the sequence; `None` before it is done.
    pub fn calibration(&self) -> Option<i32> {
        self.calibration
    }

    fn op(&self, k: usize) -> BootOp {
        match k.checked_sub(BOOT_OPS) {
            None => self.ops[k],
            Some(c) => CALIBRATION_OPS[c],
        }
    }

    pub fn ops(&self) -> &[BootOp; BOOT_OPS] {
        &self.ops
    }

    /// (Re)start from step 1, e.g. after a boot-up; `stored`: what step 12 does.
    pub fn start(&mut self, stored: StoredCalibration) {
        self.next = 0;
        self.failures = 0;
        self.stored = stored;
        self.calibration = None;
        self.phase = Phase::Running { waiting: false };
    }

    /// Stop without a result.
    pub fn stop(&mut self) {
        self.phase = Phase::Idle;
    }

    pub fn is_running(&self) -> bool {
        matches!(self.phase, Phase::Running { .. })
    }

    /// Index of the current operation (0..BOOT_OPS, then up to 3 more for the stored
    /// calibration), for progress displays.
    pub fn progress(&self) -> usize {
        self.next
    }

    /// Drive the sequence once per cycle. `outcome` is what the node's SDO client reported
    /// for a response received since the last call.
    pub fn poll(
        &mut self,
        now_ns: u64,
        sdo: &mut SdoClient,
        outcome: Option<Result<SdoDone, SdoError>>,
    ) -> BootOutput {
        let Phase::Running { waiting } = self.phase else {
            return BootOutput::Idle;
        };
        let op = self.op(self.next);
        if waiting {
            let result = match outcome {
                Some(r) => r,
                None => match sdo.poll(now_ns) {
                    Some(e) => Err(e),
                    None => return BootOutput::Waiting,
                },
            };
            let mut value = None;
            let cause = match result {
                Ok(SdoDone::Read { data, .. }) => match op.action {
                    BootAction::Read { expect } if data != expect => {
                        // A wrong device stays wrong: no retry.
                        self.phase = Phase::Idle;
                        return BootOutput::Failed(self.error(
                            op,
                            BootCause::WrongDeviceType {
                                got: data,
                                expected: expect,
                            },
                        ));
                    }
                    _ => {
                        value = Some(data);
                        None
                    }
                },
                Ok(SdoDone::Written(_)) => None,
                // A drive without the stored calibration object: not calibrated.
                Err(SdoError::Aborted { .. }) if op.addr.index == CALIBRATION => None,
                Err(SdoError::Timeout { timeout_ms, .. }) => {
                    Some(BootCause::Timeout { timeout_ms })
                }
                Err(SdoError::Aborted { code, .. }) => Some(BootCause::Aborted(code)),
                Err(SdoError::Segmented { size, .. }) => Some(BootCause::Segmented { size }),
                Err(SdoError::Busy { .. }) => None,
            };
            if let Some(cause) = cause {
                self.failures += 1;
                if self.failures > MAX_RETRIES {
                    self.phase = Phase::Idle;
                    return BootOutput::Failed(self.error(op, cause));
                }
            } else {
                self.failures = 0;
                let valid = BOOT_OPS;
                let done = match self.next {
                    n if n == valid => value.map(|v| v & 0xFF) != Some(1),
                    n if n == valid + 1 => {
                        self.calibration = value.map(|v| v as i32);
                        true
                    }
                    n => n == valid + 2,
                };
                self.next += 1;
                if self.next == valid && self.stored == StoredCalibration::Clear {
                    self.next = valid + 2;
                }
                if done {
                    self.next = 0;
                    self.phase = Phase::Idle;
                    return BootOutput::Done(nmt_frame(NmtCommand::Start, self.node));
                }
            }
        }
        let op = self.op(self.next);
        let req = match op.action {
            BootAction::Read { .. } | BootAction::Upload => SdoRequest::Read(op.addr),
            BootAction::Write(v) => SdoRequest::Write(op.addr, v),
        };
        sdo.cancel();
        match sdo.start(now_ns, req) {
            Ok(frame) => {
                self.phase = Phase::Running { waiting: true };
                BootOutput::Send(frame)
            }
            Err(_) => BootOutput::Waiting,
        }
    }

    fn error(&self, op: BootOp, cause: BootCause) -> BootError {
        BootError {
            node: self.node,
            axis: self.axis,
            step: op.step,
            addr: op.addr,
            what: op.what,
            attempts: self.failures.max(1),
            cause,
        }
    }
}

#[cfg(test)]
mod tests;
