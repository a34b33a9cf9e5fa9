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
pub const BOOT_OPS: usize = 39;
/// Retries of one operation after a timeout or abort (so at most 3 attempts).
pub const MAX_RETRIES: u8 = 2;

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

/// Step 12, after the 39 operations of [`boot_ops`] and before the NMT start: read whether
/// the drive holds a calibration, then (only if it does) the offset.
pub const CALIBRATION_OPS: [BootOp; 2] = [
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
];

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
    pub master_heartbeat_ms: u16,
    /// Cycle period T in whole milliseconds (0x60C2:1).
    pub cycle_ms: u8,
    /// 0x6075, motor rated current [mA].
    pub rated_current_ma: u32,
    /// 0x6076, motor rated torque [mNm].
    pub rated_torque_mnm: u32,
    /// 0x6073, max current [per-mille of rated current].
    pub max_current_permille: u16,
}

/// The 39 operations of steps 1..=11, in order.
pub fn boot_ops(p: &BootParams) -> [BootOp; BOOT_OPS] {
    let n = u32::from(p.node);
    let a = ObjectAddr::new;
    let w = |step, addr, v, what| BootOp {
        step,
        addr,
        action: BootAction::Write(v),
        what,
    };
    use SdoValue::{I8, U8, U16, U32};
    let consumer = (u32::from(p.master_node_id) << 16) | (3 * u32::from(p.master_heartbeat_ms));
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
        // 7. TPDO2, event-driven mode display.
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
        // 11. Mode: cyclic synchronous position.
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

    /// (Re)start from step 1, e.g. after a boot-up.
    pub fn start(&mut self) {
        self.next = 0;
        self.failures = 0;
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

    /// Index of the current operation (0..BOOT_OPS, then up to 2 more for the calibration
    /// reads), for progress displays.
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
                Err(SdoError::Aborted { .. }) if op.action == BootAction::Upload => None,
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
                    _ => false,
                };
                self.next += 1;
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
mod tests {
    use super::*;
    use crate::canopen::sdo::{abort_frame, decode_response};
    use crate::canopen::testdrive::{FakeDrive, Fault};

    const MS: u64 = 1_000_000;

    fn params() -> BootParams {
        BootParams {
            node: 3,
            axis: 2,
            drive_heartbeat_ms: 50,
            master_node_id: 127,
            master_heartbeat_ms: 50,
            cycle_ms: 5,
            rated_current_ma: 4000,
            rated_torque_mnm: 480,
            max_current_permille: 2500,
        }
    }

    /// Run the sequence against the fake drive, one cycle per 5 ms; the drive answers in the
    /// next cycle. Returns the frames sent and the final output.
    fn run(drive: &mut FakeDrive, cycles: usize) -> (Vec<Frame>, BootOutput) {
        let mut seq = BootSequence::new(&params());
        let mut sdo = SdoClient::new(3, 50 * MS);
        seq.start();
        let mut sent = Vec::new();
        let mut inbox: Vec<Frame> = Vec::new();
        for k in 0..cycles {
            let now = k as u64 * 5 * MS;
            let mut outcome = None;
            for f in inbox.drain(..) {
                if let Some(o) = sdo.on_frame(&f) {
                    outcome = Some(o);
                }
            }
            let out = seq.poll(now, &mut sdo, outcome);
            match out {
                BootOutput::Send(f) => {
                    sent.push(f);
                    inbox.extend(drive.receive(&f));
                }
                BootOutput::Done(f) => {
                    sent.push(f);
                    drive.receive(&f);
                    return (sent, out);
                }
                BootOutput::Failed(_) => return (sent, out),
                BootOutput::Waiting | BootOutput::Idle => {}
            }
        }
        (sent, BootOutput::Waiting)
    }

    #[test]
    fn sequence_is_exactly_the_drive_profile() {
        let mut drive = FakeDrive::new(3);
        let (sent, out) = run(&mut drive, 200);
        assert_eq!(out, BootOutput::Done(nmt_frame(NmtCommand::Start, 3)));
        let text: Vec<String> = sent.iter().map(|f| f.to_string()).collect();
        let expected = [
            "603#4000100000000000", // 1. read 0x1000
            "603#2B17100032000000", // 2. 0x1017 = 50
            "603#2316100196007F00", // 3. 0x1016:1 = 127 << 16 | 150
            "603#2300140103020080", // 4.
            "603#2F00160000000000",
            "603#2300160110004060",
            "603#2300160220007A60",
            "603#2300160310007160",
            "603#2F00160003000000",
            "603#2F00140201000000",
            "603#2300140103020000",
            "603#2301140103030080", // 5.
            "603#2F01160000000000",
            "603#2301160108006060",
            "603#2301160210007360",
            "603#230116031000B260",
            "603#2F01160003000000",
            "603#2F011402FF000000",
            "603#2301140103030000",
            "603#2300180183010080", // 6.
            "603#2F001A0000000000",
            "603#23001A0110004160",
            "603#23001A0220006460",
            "603#23001A0310007860",
            "603#2F001A0003000000",
            "603#2F00180201000000",
            "603#2300180183010000",
            "603#2301180183020080", // 7.
            "603#2F011A0000000000",
            "603#23011A0108006160",
            "603#2F011A0001000000",
            "603#2F011802FF000000",
            "603#2301180183020000",
            "603#2FC2600105000000", // 8.
            "603#2FC26002FD000000",
            "603#23756000A00F0000", // 9. 4000 mA
            "603#23766000E0010000",
            "603#2B736000C4090000", // 10. 2500
            "603#2F60600008000000", // 11.
            "603#4000210200000000", // 12. read 0x2100:2 (not valid: offset not read)
            "000#0103",             // NMT start
        ];
        assert_eq!(text, expected);
        assert!(drive.nmt_started());
        assert_eq!(drive.object(0x1016, 1), Some((127 << 16) | 150));
        assert_eq!(drive.object(0x6076, 0), Some(480));
    }

    #[test]
    fn stored_calibration_is_read_before_the_nmt_start() {
        let mut drive = FakeDrive::new(3);
        drive.set_object(0x2100, 1, (-7_654_321i32) as u32);
        drive.set_object(0x2100, 2, 1);
        let mut seq = BootSequence::new(&params());
        let mut sdo = SdoClient::new(3, 50 * MS);
        seq.start();
        let mut sent = Vec::new();
        let mut inbox: Vec<Frame> = Vec::new();
        for k in 0..200 {
            let mut outcome = None;
            for f in inbox.drain(..) {
                outcome = sdo.on_frame(&f).or(outcome);
            }
            match seq.poll(k * 5 * MS, &mut sdo, outcome) {
                BootOutput::Send(f) => {
                    sent.push(f.to_string());
                    inbox.extend(drive.receive(&f));
                }
                BootOutput::Done(f) => {
                    sent.push(f.to_string());
                    break;
                }
                other => assert!(matches!(other, BootOutput::Waiting), "{other:?}"),
            }
        }
        assert_eq!(
            sent[BOOT_OPS..],
            ["603#4000210200000000", "603#4000210100000000", "000#0103"]
        );
        assert_eq!(seq.calibration(), Some(-7_654_321));
        // Valid = 0: no offset read, not calibrated.
        let mut drive = FakeDrive::new(3);
        drive.set_object(0x2100, 1, 99);
        drive.set_object(0x2100, 2, 0);
        let (sent, out) = run(&mut drive, 200);
        assert!(matches!(out, BootOutput::Done(_)));
        assert_eq!(sent.len(), BOOT_OPS + 2);
        // A drive without 0x2100 aborts the read: booted, not calibrated, no retry.
        let mut drive = FakeDrive::new(3);
        drive.script(0x2100, 2, Fault::Abort(0x0602_0000), 1);
        let (sent, out) = run(&mut drive, 200);
        assert!(matches!(out, BootOutput::Done(_)), "{out:?}");
        assert_eq!(sent.len(), BOOT_OPS + 2);
        // A timeout is retried like any step and then fails the boot.
        let mut drive = FakeDrive::new(3);
        drive.script(0x2100, 2, Fault::Silent, 3);
        let (_, out) = run(&mut drive, 300);
        let BootOutput::Failed(err) = out else {
            panic!("{out:?}")
        };
        assert_eq!((err.step, err.attempts), (12, 3));
        assert!(
            err.to_string()
                .contains("0x2100:2 stored calibration valid"),
            "{err}"
        );
    }

    #[test]
    fn aborts_are_retried_twice_then_reported_with_their_text() {
        let mut drive = FakeDrive::new(3);
        drive.script(0x1600, 1, Fault::Abort(0x0800_0022), 2);
        let (_, out) = run(&mut drive, 200);
        assert!(
            matches!(out, BootOutput::Done(_)),
            "two aborts are retried: {out:?}"
        );

        let mut drive = FakeDrive::new(3);
        drive.script(0x1600, 1, Fault::Abort(0x0800_0022), 3);
        let (sent, out) = run(&mut drive, 200);
        let BootOutput::Failed(err) = out else {
            panic!("{out:?}")
        };
        assert_eq!(err.step, 4);
        assert_eq!(err.attempts, 3);
        assert_eq!(
            sent.iter()
                .filter(|f| f.data[1..4] == [0x00, 0x16, 0x01])
                .count(),
            3
        );
        assert_eq!(
            err.to_string(),
            "node 3 (axis 3) configuration step 4 (0x1600:1 RPDO1 mapping 1: controlword) failed after \
             3 attempt(s): SDO abort 0x08000022 (data cannot be transferred or stored because of the \
             present device state)"
        );
    }

    #[test]
    fn timeouts_are_retried_and_reported() {
        let mut drive = FakeDrive::new(3);
        drive.script(0x1017, 0, Fault::Silent, 3);
        let (sent, out) = run(&mut drive, 200);
        let BootOutput::Failed(err) = out else {
            panic!("{out:?}")
        };
        assert_eq!((err.node, err.axis, err.step, err.attempts), (3, 2, 2, 3));
        assert_eq!(err.cause, BootCause::Timeout { timeout_ms: 50 });
        assert_eq!(sent.len(), 1 + 3);
        assert!(
            err.to_string()
                .contains("step 2 (0x1017:0 drive heartbeat producer time)"),
            "{err}"
        );
        assert!(
            err.to_string().ends_with("no SDO response within 50 ms"),
            "{err}"
        );
    }

    #[test]
    fn wrong_device_type_fails_at_once() {
        let mut drive = FakeDrive::new(3);
        drive.set_object(0x1000, 0, 0x0004_0191);
        let (sent, out) = run(&mut drive, 200);
        assert_eq!(sent.len(), 1);
        let BootOutput::Failed(err) = out else {
            panic!("{out:?}")
        };
        assert_eq!(
            err.to_string(),
            "node 3 (axis 3) configuration step 1 (0x1000:0 device type (CiA 402 servo drive expected)) \
             failed after 1 attempt(s): device type is 0x00040191, expected 0x00020192 (CiA 402 servo drive)"
        );
    }

    #[test]
    fn fake_drive_answers_like_an_sdo_server() {
        let mut drive = FakeDrive::new(5);
        let r = drive.receive(&crate::canopen::sdo::upload_request(
            5,
            ObjectAddr::new(0x1000, 0),
        ));
        assert_eq!(r[0].to_string(), "585#4300100092010200");
        let missing = drive.receive(&crate::canopen::sdo::upload_request(
            5,
            ObjectAddr::new(0x2000, 0),
        ));
        assert_eq!(
            missing[0],
            abort_frame(5, ObjectAddr::new(0x2000, 0), 0x0602_0000, true)
        );
        assert!(decode_response(&missing[0]).is_some());
    }
}
