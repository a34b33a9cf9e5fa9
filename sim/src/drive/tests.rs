//! Unit tests of one `SimDrive` against a unit-inertia joint (no arm model): SDO transactions
//! and abort codes, NMT, heartbeats, PDOs, CiA 402, emergency stop, power cycle.

use super::*;
use mcm_shared::config::RobotConfig;

const NODE: u8 = 2;

/// One drive on a test bench: a bare joint of inertia 0.5 kg m^2 without gravity.
struct Rig {
    d: SimDrive,
    out: Vec<Frame>,
    q: f64,
    v: f64,
    /// SYNCs so far; while `master_alive`, the master's heartbeat goes out every 10th.
    cycle: u64,
    master_alive: bool,
}

fn abort_code(f: &Frame) -> u32 {
    u32::from_le_bytes(f.data[4..8].try_into().unwrap())
}

impl Rig {
    fn new() -> Rig {
        let cfg = RobotConfig::prob2_default();
        let mut out = Vec::new();
        let d = SimDrive::new(
            DriveParams::from_config(&cfg, &cfg.axes[usize::from(NODE) - 1]),
            0.1,
            0.0,
            &mut out,
        );
        Rig {
            d,
            out,
            q: 0.1,
            v: 0.0,
            cycle: 0,
            master_alive: true,
        }
    }

    fn take(&mut self) -> Vec<Frame> {
        std::mem::take(&mut self.out)
    }

    fn send(&mut self, id: u16, payload: &[u8]) {
        self.d
            .on_frame(&Frame::new(id, payload).unwrap(), &mut self.out);
    }

    fn sdo(&mut self, req: [u8; 8]) -> Frame {
        self.take();
        self.send(0x600 + u16::from(NODE), &req);
        let resp: Vec<Frame> = self
            .take()
            .into_iter()
            .filter(|f| f.id == 0x580 + u16::from(NODE))
            .collect();
        assert_eq!(resp.len(), 1, "one SDO response to {req:02X?}");
        resp[0]
    }

    fn read(&mut self, index: u16, sub: u8) -> Result<u32, u32> {
        let [i0, i1] = index.to_le_bytes();
        let r = self.sdo([0x40, i0, i1, sub, 0, 0, 0, 0]);
        if r.data[0] == 0x80 {
            Err(abort_code(&r))
        } else {
            Ok(abort_code(&r))
        }
    }

    fn write(&mut self, index: u16, sub: u8, value: u32, size: u8) -> Result<(), u32> {
        let [i0, i1] = index.to_le_bytes();
        let [v0, v1, v2, v3] = value.to_le_bytes();
        let cs = 0x23 | ((4 - size) << 2);
        let r = self.sdo([cs, i0, i1, sub, v0, v1, v2, v3]);
        match r.data[0] {
            0x60 => Ok(()),
            0x80 => Err(abort_code(&r)),
            other => panic!("unexpected response {other:02X}"),
        }
    }

    /// One SYNC period; returns the frames sent during it.
    fn sync(&mut self) -> Vec<Frame> {
        if self.master_alive && self.cycle.is_multiple_of(10) {
            self.master_heartbeat();
        }
        self.cycle += 1;
        self.d.on_sync(true, &mut self.out);
        for k in 0..10 {
            let tau = self.d.control(self.q, self.v, f64::from(k) / 10.0, 0.0005);
            self.v += tau / 0.5 * 0.0005;
            self.q += self.v * 0.0005;
        }
        self.d.end_period();
        self.take()
    }

    /// Profile steps 2-11 for node 2, then NMT start.
    fn configure(&mut self) {
        let n = u32::from(NODE);
        let steps: &[(u16, u8, u32, u8)] = &[
            (0x1017, 0, 50, 2),
            (0x1016, 1, (127 << 16) | 150, 4),
            (0x1400, 1, 0x8000_0200 + n, 4),
            (0x1600, 0, 0, 1),
            (0x1600, 1, 0x6040_0010, 4),
            (0x1600, 2, 0x607A_0020, 4),
            (0x1600, 3, 0x6071_0010, 4),
            (0x1600, 0, 3, 1),
            (0x1400, 2, 1, 1),
            (0x1400, 1, 0x200 + n, 4),
            (0x1401, 1, 0x8000_0300 + n, 4),
            (0x1601, 0, 0, 1),
            (0x1601, 1, 0x6060_0008, 4),
            (0x1601, 2, 0x6073_0010, 4),
            (0x1601, 0, 2, 1),
            (0x1401, 2, 255, 1),
            (0x1401, 1, 0x300 + n, 4),
            (0x1800, 1, 0x8000_0180 + n, 4),
            (0x1A00, 0, 0, 1),
            (0x1A00, 1, 0x6041_0010, 4),
            (0x1A00, 2, 0x6064_0020, 4),
            (0x1A00, 3, 0x6078_0010, 4),
            (0x1A00, 0, 3, 1),
            (0x1800, 2, 1, 1),
            (0x1800, 1, 0x180 + n, 4),
            (0x1801, 1, 0x8000_0280 + n, 4),
            (0x1A01, 0, 0, 1),
            (0x1A01, 1, 0x6061_0008, 4),
            (0x1A01, 0, 1, 1),
            (0x1801, 2, 255, 1),
            (0x1801, 1, 0x280 + n, 4),
            (0x60C2, 1, 5, 1),
            (0x60C2, 2, 0xFD, 1),
            (0x6075, 0, 4000, 4),
            (0x6076, 0, 480, 4),
            (0x6073, 0, 2500, 2),
            (0x6060, 0, 8, 1),
        ];
        assert_eq!(self.read(0x1000, 0), Ok(0x0002_0192));
        for &(i, s, v, size) in steps {
            self.write(i, s, v, size)
                .unwrap_or_else(|c| panic!("{i:04X}:{s} = {v:X}: abort {c:08X}"));
        }
        self.send(0x000, &[0x01, NODE]);
    }

    fn rpdo1(&mut self, cw: u16, target: i32, torque: i16) {
        let mut p = [0u8; 8];
        p[..2].copy_from_slice(&cw.to_le_bytes());
        p[2..6].copy_from_slice(&target.to_le_bytes());
        p[6..].copy_from_slice(&torque.to_le_bytes());
        self.send(0x200 + u16::from(NODE), &p);
    }

    fn master_heartbeat(&mut self) {
        self.send(0x77F, &[0x05]);
    }

    /// Configure, start, and walk to OPERATION ENABLED in CSP via RPDO1 (holding position).
    fn enable(&mut self) {
        self.configure();
        self.master_heartbeat();
        self.sync();
        for cw in [0x06, 0x07, 0x0F] {
            self.rpdo1(cw, self.position(), 0);
            self.sync();
        }
        assert_eq!(self.d.state(), State::OperationEnabled);
    }

    fn position(&self) -> i32 {
        self.d.od().i32(od::POSITION_ACTUAL)
    }
}

fn tpdo1(frames: &[Frame]) -> Option<(u16, i32, i16)> {
    let f = frames.iter().find(|f| f.id == 0x180 + u16::from(NODE))?;
    let d = f.data;
    Some((
        u16::from_le_bytes([d[0], d[1]]),
        i32::from_le_bytes([d[2], d[3], d[4], d[5]]),
        i16::from_le_bytes([d[6], d[7]]),
    ))
}

fn emcy(frames: &[Frame]) -> Vec<String> {
    frames
        .iter()
        .filter(|f| f.id == 0x80 + u16::from(NODE))
        .map(|f| f.to_string())
        .collect()
}

#[test]
fn power_up_boots_and_reaches_switch_on_disabled_at_first_sync() {
    let mut r = Rig::new();
    assert_eq!(
        r.take().iter().map(|f| f.to_string()).collect::<Vec<_>>(),
        ["702#00"]
    );
    assert_eq!(r.d.state(), State::NotReadyToSwitchOn);
    assert_eq!(r.d.nmt_state(), NmtState::PreOperational);
    assert_eq!(r.sync(), [], "no heartbeat, no PDO by default");
    assert_eq!(r.d.state(), State::SwitchOnDisabled);
    assert_eq!(r.read(0x6041, 0), Ok(0x0250));
}

#[test]
fn sdo_transactions_on_the_wire() {
    let mut r = Rig::new();
    assert_eq!(
        r.sdo([0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]).to_string(),
        "582#4300100092010200"
    );
    assert_eq!(
        r.sdo([0x2B, 0x17, 0x10, 0x00, 0x32, 0, 0, 0]).to_string(),
        "582#6017100000000000"
    );
    assert_eq!(
        r.sdo([0x40, 0x17, 0x10, 0x00, 0, 0, 0, 0]).to_string(),
        "582#4B17100032000000"
    );
    assert_eq!(
        r.sdo([0x2F, 0x60, 0x60, 0x00, 0x0A, 0, 0, 0]).to_string(),
        "582#6060600000000000"
    );
    assert_eq!(r.read(0x6061, 0), Ok(10), "mode display follows at once");
    assert_eq!(r.read(0x60C2, 2), Ok(0xFD), "i8 -3");
    assert_eq!(r.write(0x1011, 1, 0x6461_6F6C, 4), Ok(()));
    // size not indicated (0x22): the object's own size is used
    assert_eq!(r.sdo([0x22, 0x17, 0x10, 0x00, 0x64, 0, 0, 0]).data[0], 0x60);
    assert_eq!(r.read(0x1017, 0), Ok(100));
}

#[test]
fn every_abort_code() {
    let mut r = Rig::new();
    assert_eq!(r.read(0x2000, 0), Err(0x0602_0000), "object does not exist");
    assert_eq!(r.write(0x1402, 1, 0, 4), Err(0x0602_0000));
    assert_eq!(
        r.read(0x1018, 5),
        Err(0x0609_0011),
        "sub-index does not exist"
    );
    assert_eq!(
        r.write(0x6041, 0, 0, 2),
        Err(0x0601_0002),
        "write to read-only"
    );
    assert_eq!(r.write(0x1000, 0, 0, 4), Err(0x0601_0002), "write to const");
    assert_eq!(r.read(0x1011, 1), Err(0x0601_0001), "read of write-only");
    assert_eq!(
        r.write(0x6040, 0, 6, 4),
        Err(0x0607_0010),
        "u16 written with 4 bytes"
    );
    assert_eq!(r.write(0x1017, 0, 6, 1), Err(0x0607_0010));
    assert_eq!(r.write(0x1400, 1, 0x202, 4), Ok(()), "RPDO1 valid");
    assert_eq!(
        r.write(0x1600, 0, 0, 1),
        Err(0x0800_0022),
        "mapping while the PDO is valid"
    );
    assert_eq!(r.write(0x1400, 1, 0x8000_0202, 4), Ok(()));
    assert_eq!(
        r.write(0x1600, 1, 0x6041_0010, 4),
        Err(0x0604_0041),
        "statusword into an RPDO"
    );
    assert_eq!(r.write(0x1600, 1, 0x6064_0020, 4), Err(0x0604_0041));
    assert_eq!(
        r.write(0x1A00, 1, 0x6075_0020, 4),
        Err(0x0604_0041),
        "not mappable at all"
    );
    for k in 1..=3 {
        assert_eq!(r.write(0x1A00, k, 0x6064_0020, 4), Ok(()));
    }
    assert_eq!(r.write(0x1A00, 0, 3, 1), Err(0x0604_0042), "96 bits");
    assert_eq!(
        r.write(0x6060, 0, 3, 1),
        Err(0x0609_0030),
        "mode 3 not supported"
    );
    assert_eq!(
        r.write(0x6073, 0, 2501, 2),
        Err(0x0609_0030),
        "above the peak current"
    );
    // 0x605A: option 2 is the one the drive has; the others are refused and leave it at 2.
    assert_eq!(r.read(0x605A, 0), Ok(2));
    assert_eq!(r.write(0x605A, 0, 2, 2), Ok(()));
    for option in [0u16, 1, 3, 5, 6, 7, 8, (-1i16) as u16] {
        assert_eq!(
            r.write(0x605A, 0, u32::from(option), 2),
            Err(0x0609_0030),
            "quick stop option {}",
            option as i16
        );
    }
    assert_eq!(
        r.write(0x605A, 0, 2, 1),
        Err(0x0607_0010),
        "an i16 is 2 bytes"
    );
    assert_eq!(r.read(0x605A, 0), Ok(2));
    assert_eq!(
        r.write(0x1400, 2, 0, 1),
        Err(0x0609_0030),
        "transmission type 0"
    );
    assert_eq!(
        r.write(0x1011, 1, 1, 4),
        Err(0x0609_0030),
        "restore without the signature"
    );
    assert_eq!(
        abort_code(&r.sdo([0xE0, 0x00, 0x10, 0x00, 0, 0, 0, 0])),
        0x0504_0001,
        "invalid command specifier"
    );
    assert_eq!(r.sdo([0xE0, 0x00, 0x10, 0x00, 0, 0, 0, 0]).data[0], 0x80);
    r.send(0x000, &[0x01, NODE]);
    assert_eq!(
        r.write(0x1A01, 1, 0x6061_0008, 4),
        Err(0x0800_0022),
        "mapping while OPERATIONAL"
    );
}

#[test]
fn nmt_states_gate_pdos_and_sdos() {
    let mut r = Rig::new();
    r.configure();
    r.send(0x000, &[0x80, NODE]);
    assert_eq!(r.d.nmt_state(), NmtState::PreOperational);
    r.sync();
    r.rpdo1(0x06, 0, 0);
    let frames = r.sync();
    assert_eq!(tpdo1(&frames), None, "no TPDO in PRE-OPERATIONAL");
    assert_eq!(
        r.d.state(),
        State::SwitchOnDisabled,
        "RPDO ignored in PRE-OPERATIONAL"
    );

    r.send(0x000, &[0x01, 0]); // broadcast start
    assert_eq!(r.d.nmt_state(), NmtState::Operational);
    assert_eq!(
        r.take().iter().map(|f| f.to_string()).collect::<Vec<_>>(),
        ["282#08"],
        "TPDO2 once on start"
    );
    let frames = r.sync();
    assert_eq!(tpdo1(&frames).unwrap().0, 0x0250, "TPDO1 at every SYNC");
    assert!(tpdo1(&r.sync()).is_some());

    r.send(0x000, &[0x02, NODE]);
    assert_eq!(r.d.nmt_state(), NmtState::Stopped);
    r.send(0x602, &[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]);
    assert_eq!(r.take(), [], "no SDO in STOPPED");
    let frames: Vec<Frame> = (0..10).flat_map(|_| r.sync()).collect();
    assert_eq!(
        frames.iter().map(|f| f.to_string()).collect::<Vec<_>>(),
        ["702#04"],
        "only the heartbeat"
    );
    r.send(0x000, &[0x01, NODE]);
    assert_eq!(r.d.nmt_state(), NmtState::Operational);
}

#[test]
fn resets_send_boot_up_and_restore_defaults() {
    let mut r = Rig::new();
    r.configure();
    r.take();
    r.send(0x000, &[0x82, NODE]);
    assert_eq!(
        r.take().iter().map(|f| f.to_string()).collect::<Vec<_>>(),
        ["702#00"]
    );
    assert_eq!(r.d.nmt_state(), NmtState::PreOperational);
    assert_eq!(
        r.read(0x1400, 1),
        Ok(0x8000_0202),
        "communication objects reset"
    );
    assert_eq!(r.read(0x1A00, 0), Ok(0));
    assert_eq!(
        r.read(0x6060, 0),
        Ok(8),
        "application objects kept by reset communication"
    );
    r.send(0x000, &[0x81, 0]);
    assert_eq!(
        r.take().iter().map(|f| f.to_string()).collect::<Vec<_>>(),
        ["702#00"]
    );
    assert_eq!(
        r.read(0x6060, 0),
        Ok(0),
        "reset node resets the application"
    );
    assert_eq!(r.d.state(), State::NotReadyToSwitchOn);
    r.sync();
    assert_eq!(r.d.state(), State::SwitchOnDisabled);
}

#[test]
fn heartbeat_producer_period_follows_0x1017() {
    let mut r = Rig::new();
    r.write(0x1017, 0, 50, 2).unwrap();
    let sent: Vec<usize> = (0..100)
        .filter(|_| r.sync().iter().any(|f| f.to_string() == "702#7F"))
        .collect();
    assert_eq!(
        sent,
        [10, 20, 30, 40, 50, 60, 70, 80, 90],
        "every 50 ms = 10 SYNCs of 5 ms"
    );
    r.write(0x1017, 0, 20, 2).unwrap();
    let sent: Vec<usize> = (0..20)
        .filter(|_| r.sync().iter().any(|f| f.id == 0x702))
        .collect();
    assert_eq!(sent, [4, 8, 12, 16], "20 ms = 4 SYNCs");
}

#[test]
fn master_heartbeat_loss_faults_with_emcy_0x8130_and_fault_reset_clears() {
    let mut r = Rig::new();
    r.enable();
    while !r.cycle.is_multiple_of(10) {
        r.sync();
    }
    for _ in 0..600 {
        // master heartbeat every 10 cycles: no fault
        r.rpdo1(0x0F, r.position(), 0);
        assert!(emcy(&r.sync()).is_empty());
    }
    // silence: the consumer time is 150 ms = 30 cycles after the last heartbeat
    r.master_alive = false;
    let mut fired_at = None;
    for k in 1..=40 {
        r.rpdo1(0x0F, r.position(), 0);
        let frames = r.sync();
        if let Some(e) = emcy(&frames).first() {
            assert_eq!(e, "082#3081110000000000");
            fired_at = Some(k);
            break;
        }
    }
    // the last heartbeat came 10 SYNCs before k = 1; SYNC j after it is checked at
    // t0 + j * 5 ms and fires once more than 150 ms have passed: j = 31, k = 22
    assert_eq!(fired_at, Some(22));
    assert_eq!(r.d.state(), State::Fault);
    assert_eq!(r.read(0x603F, 0), Ok(0x8130));
    assert_eq!(r.read(0x1001, 0), Ok(0x11));
    r.sync();
    assert_eq!(r.d.current_a(), 0.0, "fault reaction: current 0");
    r.rpdo1(0x00, 0, 0);
    let f = r.sync();
    assert_eq!(tpdo1(&f).unwrap().0 & 0x4F, 0x08);
    assert!(emcy(&f).is_empty(), "EMCY once");
    r.rpdo1(0x80, 0, 0);
    let f = r.sync();
    assert_eq!(emcy(&f), ["082#0000000000000000"]);
    assert_eq!(r.d.state(), State::SwitchOnDisabled);
    assert_eq!(r.read(0x1001, 0), Ok(0));
}

#[test]
fn rpdo_is_applied_at_the_next_sync_and_enabling_holds_the_actual_position() {
    let mut r = Rig::new();
    r.configure();
    r.master_heartbeat();
    r.sync();
    r.rpdo1(0x06, 0, 0);
    assert_eq!(
        r.d.state(),
        State::SwitchOnDisabled,
        "latched, not applied yet"
    );
    r.sync();
    assert_eq!(r.d.state(), State::ReadyToSwitchOn);
    r.rpdo1(0x07, 0, 0);
    r.sync();
    let actual = r.position();
    // enabling RPDO carries a far-away target: the drive holds its actual position instead
    r.rpdo1(0x0F, actual + 100_000, 0);
    let f = r.sync();
    assert_eq!(tpdo1(&f).unwrap().0 & 0x6F, 0x27);
    assert_eq!(r.read(0x607A, 0), Ok(actual as u32));
    for _ in 0..20 {
        r.rpdo1(0x0F, actual, 0);
        r.sync();
    }
    assert!(
        (r.position() - actual).abs() <= 1,
        "{} vs {actual}",
        r.position()
    );
    // a new target is followed
    for k in 1..=200 {
        r.rpdo1(0x0F, actual + 100 * k, 0);
        r.sync();
    }
    for _ in 0..100 {
        r.rpdo1(0x0F, actual + 20_000, 0);
        r.sync();
    }
    assert!(
        (r.position() - (actual + 20_000)).abs() <= 2,
        "{}",
        r.position() - actual
    );
}

#[test]
fn mode_change_by_event_rpdo_and_cst_current_limit() {
    let mut r = Rig::new();
    r.enable();
    r.take();
    // RPDO2: CST, max current 500 per-mille of 4 A = 2 A
    r.send(0x302, &[10, 0xF4, 0x01]);
    assert_eq!(
        r.take().iter().map(|f| f.to_string()).collect::<Vec<_>>(),
        ["282#0A"],
        "TPDO2 at once"
    );
    r.rpdo1(0x0F, 0, 1000); // rated torque -> 4 A wanted, clamped to 2 A
    let _ = r.sync();
    let f = r.sync();
    assert_eq!(
        tpdo1(&f).unwrap().2,
        500,
        "current actual in per-mille of rated"
    );
    assert!((r.d.current_a() - 2.0).abs() < 1e-12);
    r.rpdo1(0x0F, 0, -100); // 0.4 A
    r.sync();
    assert!((r.d.current_a() + 0.4).abs() < 1e-9, "{}", r.d.current_a());
}

#[test]
fn quick_stop_decelerates_then_switch_on_disabled() {
    let mut r = Rig::new();
    r.enable();
    let start = r.position();
    // move at 400 counts per cycle (~1 rad/s), then quick stop
    let mut target = start;
    for _ in 0..100 {
        target += 400;
        r.rpdo1(0x0F, target, 0);
        r.sync();
    }
    assert!(r.v > 0.9, "moving: {}", r.v);
    r.rpdo1(0x02, target + 400, 0);
    let f = r.sync();
    assert_eq!(tpdo1(&f).unwrap().0 & 0x6F, 0x07, "quick stop active");
    let mut cycles = 0;
    while r.d.state() == State::QuickStopActive {
        r.rpdo1(0x02, target, 0);
        r.sync();
        cycles += 1;
        assert!(cycles < 200);
    }
    assert_eq!(r.d.state(), State::SwitchOnDisabled);
    // deceleration 180 deg/s^2 = 3.14 rad/s^2 from ~1 rad/s: ~0.33 s = ~66 cycles
    assert!((50..=80).contains(&cycles), "{cycles}");
    assert!(r.v.abs() < 0.05, "{}", r.v);
}

/// The master's NMT stop cuts the connection of an enabled drive: it reacts as 0x6007 says,
/// at once, with no SYNC after it (the master may get none through), and the reaction is its
/// own: the RPDO1 latched before the stop is not applied afterwards. Power-up value 1 (fault);
/// option 0 does nothing; NMT stop outside OPERATIONAL is no abort of a connection.
#[test]
fn nmt_stop_while_operational_reacts_as_the_abort_connection_option_says() {
    // (option, state at once, state a SYNC later: the quick stop of a joint at rest ends
    // within its first period, in SWITCH ON DISABLED as 0x605A = 2 says).
    for (option, state, later) in [
        (None, State::Fault, State::Fault),
        (Some(0), State::OperationEnabled, State::OperationEnabled),
        (Some(1), State::Fault, State::Fault),
        (Some(2), State::SwitchOnDisabled, State::SwitchOnDisabled),
        (Some(3), State::QuickStopActive, State::SwitchOnDisabled),
    ] {
        let mut r = Rig::new();
        if let Some(o) = option {
            assert_eq!(r.write(0x6007, 0, o, 2), Ok(()), "option {o}");
        }
        r.enable();
        r.rpdo1(0x0F, r.position(), 0);
        r.send(0x000, &[0x02, NODE]);
        assert_eq!(r.d.state(), state, "option {option:?}");
        assert_eq!(
            r.d.brake_engaged(),
            !state.is_enabled(),
            "option {option:?}"
        );
        assert_eq!(r.d.counters().connection_aborts, 1);
        r.sync();
        assert_eq!(r.d.state(), later, "option {option:?}, a SYNC later");
        // Stopped again: no second abort.
        r.send(0x000, &[0x02, NODE]);
        assert_eq!(r.d.counters().connection_aborts, 1);
    }
    let mut r = Rig::new();
    for bad in [4u32, 0xFFFF] {
        assert_eq!(r.write(0x6007, 0, bad, 2), Err(0x0609_0030), "option {bad}");
    }
    assert_eq!(r.read(0x6007, 0), Ok(1));
    r.send(0x000, &[0x02, NODE]); // PRE-OPERATIONAL
    assert_eq!(r.d.counters().connection_aborts, 0);
}

#[test]
fn emergency_stop_faults_an_enabled_drive_and_blocks_enabling() {
    let mut r = Rig::new();
    r.enable();
    r.take();
    r.d.set_safe_torque_off(true, &mut r.out);
    assert_eq!(emcy(&r.take()), ["082#4154050000000000"]);
    assert_eq!(r.d.state(), State::Fault);
    r.rpdo1(0x0F, r.position(), 0);
    let sw = tpdo1(&r.sync()).unwrap().0;
    assert_eq!(
        (sw & 0x4F, sw & 0x4000 != 0, sw & 0x10 != 0),
        (0x08, true, false),
        "{sw:04X}"
    );
    r.rpdo1(0x80, 0, 0);
    r.sync();
    assert_eq!(
        r.d.state(),
        State::SwitchOnDisabled,
        "fault reset works while pressed"
    );
    r.rpdo1(0x06, 0, 0);
    r.sync();
    assert_eq!(
        r.d.state(),
        State::SwitchOnDisabled,
        "transition 2 refused while pressed"
    );
    assert_eq!(r.d.current_a(), 0.0);
    r.d.set_safe_torque_off(false, &mut r.out);
    r.rpdo1(0x06, 0, 0);
    let sw = tpdo1(&r.sync()).unwrap().0;
    assert_eq!((sw & 0x6F, sw & 0x4000), (0x21, 0), "{sw:04X}");
    assert_eq!(r.d.state(), State::ReadyToSwitchOn);
}

#[test]
fn power_cycle_draws_a_new_offset_and_forgets_the_configuration() {
    let mut r = Rig::new();
    r.enable();
    let offset = r.d.encoder_offset_counts();
    let before = r.position();
    r.take();
    r.d.power_cycle(&mut r.out);
    assert_eq!(
        r.take().iter().map(|f| f.to_string()).collect::<Vec<_>>(),
        ["702#00"]
    );
    assert_ne!(r.d.encoder_offset_counts(), offset);
    assert_eq!(r.d.state(), State::NotReadyToSwitchOn);
    assert_eq!(r.d.nmt_state(), NmtState::PreOperational);
    assert_eq!(r.read(0x1A00, 0), Ok(0), "mapping gone");
    assert_eq!(r.read(0x1800, 1), Ok(0x8000_0182), "PDO invalid");
    assert_eq!(r.read(0x1017, 0), Ok(0));
    assert_eq!(r.read(0x6060, 0), Ok(0));
    assert_eq!(r.sync(), []);
    assert_eq!(r.d.state(), State::SwitchOnDisabled);
    let shift = i64::from(r.position()) - i64::from(before);
    assert!(
        (shift - (r.d.encoder_offset_counts() - offset)).abs() <= 2,
        "position jumps by the offset change"
    );
}

#[test]
fn stored_calibration_survives_nmt_resets_but_not_a_power_cycle() {
    let mut r = Rig::new();
    assert_eq!(
        (r.read(0x2100, 0), r.read(0x2100, 1), r.read(0x2100, 2)),
        (Ok(2), Ok(0), Ok(0))
    );
    assert_eq!(r.write(0x2100, 1, (-98_765i32) as u32, 4), Ok(()));
    assert_eq!(r.write(0x2100, 2, 1, 1), Ok(()));
    assert_eq!(
        r.write(0x2100, 2, 2, 1),
        Err(0x0609_0030),
        "valid is 0 or 1"
    );
    assert_eq!(r.write(0x2100, 1, 1, 2), Err(0x0607_0010), "i32");
    assert_eq!(
        r.write(0x1600, 1, 0x2100_0120, 4),
        Err(0x0604_0041),
        "not mappable"
    );
    for cmd in [0x81u8, 0x82] {
        r.send(0x000, &[cmd, NODE]);
        assert_eq!(r.take().last().unwrap().to_string(), "702#00");
        assert_eq!(r.read(0x2100, 1), Ok((-98_765i32) as u32), "NMT {cmd:02X}");
        assert_eq!(r.read(0x2100, 2), Ok(1));
    }
    let kept = r.d.retained();
    assert_eq!(
        (kept.calibration_offset, kept.calibration_valid),
        (-98_765, 1)
    );
    r.d.power_cycle(&mut r.out);
    assert_eq!((r.read(0x2100, 1), r.read(0x2100, 2)), (Ok(0), Ok(0)));
}

#[test]
fn resume_keeps_offset_and_calibration_and_boots_like_a_reset() {
    let mut r = Rig::new();
    r.enable();
    r.write(0x2100, 1, 4242, 4).unwrap();
    r.write(0x2100, 2, 1, 1).unwrap();
    r.d.power_cycle(&mut crate::Discard);
    r.write(0x2100, 1, 4242, 4).unwrap();
    r.write(0x2100, 2, 1, 1).unwrap();
    let kept = r.d.retained();
    assert_eq!(kept.power_cycles, 1);
    let cfg = RobotConfig::prob2_default();
    let mut out = Vec::new();
    let d = SimDrive::resume(
        DriveParams::from_config(&cfg, &cfg.axes[usize::from(NODE) - 1]),
        r.q,
        0.0,
        kept,
        &mut out,
    );
    assert_eq!(
        out.iter().map(|f| f.to_string()).collect::<Vec<_>>(),
        ["702#00"]
    );
    assert_eq!(d.retained(), kept);
    assert_eq!(d.encoder_offset_counts(), r.d.encoder_offset_counts());
    assert_eq!(d.nmt_state(), NmtState::PreOperational);
    assert_eq!(d.state(), State::NotReadyToSwitchOn);
    assert_eq!(
        d.od().raw(od::PRODUCER_HEARTBEAT),
        0,
        "configuration forgotten"
    );
}

#[test]
fn encoder_offsets_are_deterministic_bounded_and_distinct() {
    let cfg = RobotConfig::prob2_default();
    let cpr = cfg.axes[0].counts_per_rad();
    let max = (20.0f64).to_radians() * cpr;
    let mut seen = Vec::new();
    for node in 1..=6 {
        for cycle in 0..50 {
            let o = encoder_offset_counts(2026, node, cycle, 20f64.to_radians(), cpr);
            assert_eq!(
                o,
                encoder_offset_counts(2026, node, cycle, 20f64.to_radians(), cpr)
            );
            assert!((o as f64).abs() <= max.ceil());
            seen.push(o);
        }
    }
    let spread = seen.iter().filter(|o| o.abs() as f64 > max / 2.0).count();
    assert!(
        spread > 100 && spread < 200,
        "roughly half beyond max/2: {spread}"
    );
    for node in 1..=6 {
        for cycle in 0..50 {
            let o = |c| encoder_offset_counts(2026, node, c, 20f64.to_radians(), cpr);
            assert_ne!(o(cycle), o(cycle + 1), "a power cycle draws a new offset");
        }
    }
    assert_ne!(
        encoder_offset_counts(1, 1, 0, 0.3, cpr),
        encoder_offset_counts(2, 1, 0, 0.3, cpr)
    );
}

mod fuzz {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Any frames at all (ids, lengths, payloads), interleaved with SYNCs, never panic;
        /// every SDO request with DLC 8 gets exactly one answer naming the same object.
        #[test]
        fn arbitrary_frames_never_panic_and_sdo_always_answers(
            frames in proptest::collection::vec((0u16..0x800, 0usize..=8, any::<[u8; 8]>()), 1..80)
        ) {
            let mut r = Rig::new();
            r.configure();
            for (k, (id, len, data)) in frames.into_iter().enumerate() {
                let id = if k % 3 == 0 { 0x602 } else { id };
                let len = if k % 3 == 0 { 8 } else { len };
                r.take();
                r.send(id, &data[..len]);
                let out = r.take();
                if id == 0x602 && len == 8 && data[0] >> 5 != 4 && r.d.nmt_state() != NmtState::Stopped {
                    let resp: Vec<&Frame> = out.iter().filter(|f| f.id == 0x582).collect();
                    prop_assert_eq!(resp.len(), 1);
                    prop_assert_eq!(&resp[0].data[1..4], &data[1..4]);
                }
                if k % 7 == 0 {
                    r.sync();
                }
            }
        }
    }
}

/// A fault-reset edge while OPERATION ENABLED in CSP is a new hold target where the joint
/// stands, with the position loop's integral cleared: a loop wound up against an obstacle
/// stops pressing. Without the edge the integral keeps pressing.
/// [`Rig::sync`] with an obstacle at 0.1 rad: a stiff spring-damper on the joint.
fn sync_blocked(r: &mut Rig) {
    if r.cycle.is_multiple_of(10) {
        r.master_heartbeat();
    }
    r.cycle += 1;
    r.d.on_sync(true, &mut r.out);
    for k in 0..10 {
        let tau = r.d.control(r.q, r.v, f64::from(k) / 10.0, 0.0005);
        let obstacle = -1.0e6 * (r.q - 0.1) - 1.0e3 * r.v;
        // semi-implicit in the stiff terms
        r.v = (r.v + (tau + obstacle) / 0.5 * 0.0005) / (1.0 + 1.0e3 / 0.5 * 0.0005);
        r.q += r.v * 0.0005;
    }
    r.d.end_period();
    r.take();
}

#[test]
fn fault_reset_edge_while_enabled_restarts_the_wound_up_loop() {
    let wound_up = |r: &mut Rig| {
        r.enable();
        let actual = r.position();
        // An obstacle holds the joint while the target runs away.
        for k in 1..=100 {
            r.rpdo1(0x0F, actual + 200 * k, 0);
            sync_blocked(r);
        }
        let pressing = r.d.current_a();
        assert!(pressing > 5.0, "wound up: {pressing} A");
        actual
    };
    // Without the edge: the target back at the joint, the integral still presses.
    let mut r = Rig::new();
    let actual = wound_up(&mut r);
    for _ in 0..40 {
        r.rpdo1(0x0F, actual, 0);
        sync_blocked(&mut r);
    }
    let still = r.d.current_a();
    assert!(still > 5.0, "a wound-up integral keeps pressing: {still} A");

    // With the edge (0x008F, then 0x000F): no current into the obstacle.
    let mut r = Rig::new();
    let actual = wound_up(&mut r);
    r.rpdo1(0x8F, actual, 0);
    sync_blocked(&mut r);
    assert_eq!(
        r.d.state(),
        State::OperationEnabled,
        "the state machine ignores it"
    );
    for _ in 0..40 {
        r.rpdo1(0x0F, actual, 0);
        sync_blocked(&mut r);
    }
    let after = r.d.current_a();
    assert!(after.abs() < 0.5, "restarted where it stands: {after} A");
}
