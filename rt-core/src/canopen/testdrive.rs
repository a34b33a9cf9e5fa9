//! A tiny scripted fake CiA 402 drive for the master's unit tests (test-only).
//!
//! It answers expedited SDO, obeys NMT, applies RPDO1 at SYNC with the CiA 402 transitions of
//! [`apply_controlword`], follows the CSP target exactly, sends TPDO1 on SYNC, TPDO2 on mode
//! changes and when its event timer (0x1801:5) runs out, and its heartbeat on its own
//! SYNC-driven clock. Faults can be scripted per object.
//! It is deliberately not the simulated drive of `sim/` (no physics).

use super::cia402::{ControlWord, State, apply_controlword, statusword_for};
use super::emcy::Emcy;
use super::nmt::{NmtState, heartbeat_frame};
use super::objects::{ObjectAddr, Service, classify};
use super::pdo::{Rpdo1, Rpdo2, Tpdo1, Tpdo2};
use super::sdo::abort_frame;
use mcm_bus::Frame;
use std::collections::HashMap;

/// A scripted misbehaviour for one object.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    /// Answer with this abort code.
    Abort(u32),
    /// Do not answer at all.
    Silent,
}

pub struct FakeDrive {
    pub node: u8,
    objects: HashMap<(u16, u8), u32>,
    script: HashMap<(u16, u8), (Fault, u32)>,
    pub nmt: NmtState,
    pub state: State,
    prev_cw: ControlWord,
    rpdo1: Option<Rpdo1>,
    pub mode: i8,
    pub position: i32,
    pub current_permille: i16,
    pub last_torque: i16,
    /// Does not send anything (but still listens).
    pub silent: bool,
    /// Skip TPDO1 (but keep heartbeats).
    pub drop_tpdos: bool,
    pub estop: bool,
    /// Stay in FAULT on a fault-reset edge (the cause persists).
    pub refuse_fault_reset: bool,
    /// Skip heartbeats (but keep TPDOs).
    pub mute_heartbeat: bool,
    /// Lose every RPDO2 sent to it (the bus lost them).
    pub deaf_rpdo2: bool,
    time_ms: u64,
    period_ms: u64,
    next_hb_ms: u64,
    tpdo2_sent_ms: u64,
}

impl FakeDrive {
    pub fn new(node: u8) -> FakeDrive {
        let mut d = FakeDrive {
            node,
            objects: HashMap::new(),
            script: HashMap::new(),
            nmt: NmtState::PreOperational,
            state: State::SwitchOnDisabled,
            prev_cw: ControlWord(0),
            rpdo1: None,
            mode: 0,
            position: 1000 * i32::from(node),
            current_permille: 0,
            last_torque: 0,
            silent: false,
            drop_tpdos: false,
            estop: false,
            refuse_fault_reset: false,
            mute_heartbeat: false,
            deaf_rpdo2: false,
            time_ms: 0,
            period_ms: 5,
            next_hb_ms: 0,
            tpdo2_sent_ms: 0,
        };
        d.reset_objects();
        d
    }

    /// NMT reset: every object back to its default, except the stored calibration 0x2100,
    /// which a real drive keeps until it loses power.
    fn reset_objects(&mut self) {
        self.objects.retain(|&(index, _), _| index == 0x2100);
        self.objects.insert((0x1000, 0), 0x0002_0192);
        self.objects.insert((0x1017, 0), 0);
    }

    pub fn script(&mut self, index: u16, sub: u8, fault: Fault, times: u32) {
        self.script.insert((index, sub), (fault, times));
    }

    pub fn set_object(&mut self, index: u16, sub: u8, value: u32) {
        self.objects.insert((index, sub), value);
    }

    pub fn object(&self, index: u16, sub: u8) -> Option<u32> {
        self.objects.get(&(index, sub)).copied()
    }

    pub fn nmt_started(&self) -> bool {
        self.nmt == NmtState::Operational
    }

    /// The boot-up frame (power-on).
    pub fn boot_up(&self) -> Frame {
        heartbeat_frame(self.node, NmtState::BootUp)
    }

    fn pdo_valid(&self, comm: u16) -> bool {
        self.object(comm, 1).is_some_and(|c| c & 0x8000_0000 == 0)
    }

    fn out(&self, frames: Vec<Frame>) -> Vec<Frame> {
        if self.silent { Vec::new() } else { frames }
    }

    /// Inject a fault: EMCY and FAULT state.
    pub fn fault(&mut self, code: u16, register: u8) -> Vec<Frame> {
        self.state = State::Fault;
        let e = Emcy {
            node: self.node,
            axis: 0,
            code,
            register,
            vendor: [0; 5],
        };
        self.out(vec![e.encode()])
    }

    /// Handle one frame seen on the bus; returns the frames the drive sends in response.
    pub fn receive(&mut self, f: &Frame) -> Vec<Frame> {
        let mut out = Vec::new();
        match classify(f.id) {
            Service::Nmt if f.len == 2 && (f.data[1] == 0 || f.data[1] == self.node) => {
                match f.data[0] {
                    0x01 => {
                        self.nmt = NmtState::Operational;
                        if self.pdo_valid(0x1801) {
                            out.push(self.tpdo2());
                        }
                    }
                    0x02 => self.nmt = NmtState::Stopped,
                    0x80 => self.nmt = NmtState::PreOperational,
                    0x81 | 0x82 => {
                        self.reset_objects();
                        self.nmt = NmtState::PreOperational;
                        self.next_hb_ms = self.time_ms;
                        out.push(self.boot_up());
                    }
                    _ => {}
                }
            }
            Service::Sync => out.extend(self.on_sync()),
            Service::SdoRequest { node } if node == self.node => out.extend(self.on_sdo(f)),
            Service::Rpdo { pdo: 1, node }
                if node == self.node && self.nmt == NmtState::Operational =>
            {
                self.rpdo1 = Rpdo1::decode(f).ok();
            }
            Service::Rpdo { pdo: 2, node }
                if node == self.node && self.nmt == NmtState::Operational && !self.deaf_rpdo2 =>
            {
                if let Ok(r) = Rpdo2::decode(f) {
                    self.objects
                        .insert((0x6073, 0), u32::from(r.max_current_permille));
                    if r.mode != self.mode {
                        self.mode = r.mode;
                        out.push(self.tpdo2());
                    }
                }
            }
            _ => {}
        }
        self.out(out)
    }

    /// TPDO2 (mode display), sent now: restarts its event timer.
    fn tpdo2(&mut self) -> Frame {
        self.tpdo2_sent_ms = self.time_ms;
        Tpdo2 {
            mode_display: self.mode,
        }
        .encode(self.node)
    }

    fn on_sync(&mut self) -> Vec<Frame> {
        let mut out = Vec::new();
        if let Some(r) = self.rpdo1.take() {
            let cw = ControlWord(r.controlword);
            let was = self.state;
            let mut next = apply_controlword(self.state, cw, self.prev_cw);
            if self.estop && next == State::ReadyToSwitchOn && was == State::SwitchOnDisabled {
                next = State::SwitchOnDisabled;
            }
            if self.refuse_fault_reset && was == State::Fault {
                next = State::Fault;
            }
            if next == State::QuickStopActive {
                next = State::SwitchOnDisabled; // 0x605A = 2 after an instant stop
            }
            self.state = next;
            self.prev_cw = cw;
            if self.state == State::OperationEnabled {
                match self.mode {
                    8 if was == State::OperationEnabled => self.position = r.target_position,
                    10 => self.last_torque = r.target_torque,
                    _ => {}
                }
            }
        }
        if self.nmt == NmtState::Operational && self.pdo_valid(0x1800) && !self.drop_tpdos {
            let mut sw = statusword_for(self.state).0;
            if self.estop {
                sw |= 1 << 14;
            }
            out.push(
                Tpdo1 {
                    statusword: sw,
                    position: self.position,
                    current_permille: self.current_permille,
                }
                .encode(self.node),
            );
        }
        let timer_ms = u64::from(self.object(0x1801, 5).unwrap_or(0));
        if self.nmt == NmtState::Operational
            && self.pdo_valid(0x1801)
            && timer_ms > 0
            && self.time_ms >= self.tpdo2_sent_ms + timer_ms
        {
            out.push(self.tpdo2());
        }
        self.time_ms += self.period_ms;
        let hb = u64::from(self.object(0x1017, 0).unwrap_or(0));
        if hb > 0 && self.time_ms >= self.next_hb_ms {
            if !self.mute_heartbeat {
                out.push(heartbeat_frame(self.node, self.nmt));
            }
            self.next_hb_ms = self.time_ms + hb;
        }
        out
    }

    fn on_sdo(&mut self, f: &Frame) -> Vec<Frame> {
        let d = f.data;
        let addr = ObjectAddr::new(u16::from_le_bytes([d[1], d[2]]), d[3]);
        let key = (addr.index, addr.sub);
        if let Some((fault, times)) = self.script.get_mut(&key)
            && *times > 0
        {
            *times -= 1;
            return match *fault {
                Fault::Abort(code) => vec![abort_frame(self.node, addr, code, true)],
                Fault::Silent => Vec::new(),
            };
        }
        let resp_id = 0x580 + u16::from(self.node);
        match d[0] {
            0x40 => match self.object(addr.index, addr.sub) {
                Some(v) => {
                    let [b0, b1, b2, b3] = v.to_le_bytes();
                    vec![Frame::new(resp_id, &[0x43, d[1], d[2], d[3], b0, b1, b2, b3]).unwrap()]
                }
                None => vec![abort_frame(self.node, addr, 0x0602_0000, true)],
            },
            0x23 | 0x27 | 0x2B | 0x2F => {
                let size = 4 - ((d[0] >> 2) & 3) as usize;
                let mut b = [0u8; 4];
                b[..size].copy_from_slice(&d[4..4 + size]);
                let v = u32::from_le_bytes(b);
                self.objects.insert(key, v);
                if key == (0x6060, 0) {
                    self.mode = v as u8 as i8;
                }
                vec![Frame::new(resp_id, &[0x60, d[1], d[2], d[3], 0, 0, 0, 0]).unwrap()]
            }
            _ => vec![abort_frame(self.node, addr, 0x0504_0001, true)],
        }
    }
}
