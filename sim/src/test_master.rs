//! A small scripted CANopen master for the simulator's whole-bus tests (test-only; the real
//! master is `crate::canopen`). It follows `docs/drive-profile.md` to the letter: on every boot-up
//! it configures the node with the 12 boot steps (one expedited SDO transaction per node at a
//! time), starts it, sends RPDO2 (CSP, max current), then streams RPDO1 every cycle, walking
//! the CiA 402 state machine to OPERATION ENABLED holding the actual position. Every cycle:
//! read all frames, send requests / RPDOs / the heartbeat when due, and LAST the SYNC.

use mcm_bus::{Bus, Frame};
use mcm_shared::config::RobotConfig;

/// One SDO transaction of the boot sequence: (index, sub, value, size in bytes); size 0 = read.
type Step = (u16, u8, u32, u8);

/// The boot steps 1-11 of `docs/drive-profile.md` ("Boot and configuration") for one axis.
pub fn boot_steps(cfg: &RobotConfig, axis: usize) -> Vec<Step> {
    let a = &cfg.axes[axis];
    let n = u32::from(a.node_id);
    let b = &cfg.bus;
    let t_ms = (cfg.cycle_period_ns() / 1_000_000) as u32;
    vec![
        (0x1000, 0, 0x0002_0192, 0),
        (0x1017, 0, u32::from(b.drive_heartbeat_ms), 2),
        (
            0x1016,
            1,
            (u32::from(b.master_node_id) << 16) | u32::from(b.heartbeat_timeout_ms),
            4,
        ),
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
        (0x60C2, 1, t_ms, 1),
        (0x60C2, 2, (-3i8) as u8 as u32, 1),
        (0x6075, 0, (a.rated_current_a * 1000.0).round() as u32, 4),
        (
            0x6076,
            0,
            (a.torque_constant_nm_a * a.rated_current_a * 1000.0).round() as u32,
            4,
        ),
        (0x6073, 0, max_current_permille(cfg, axis) as u32, 2),
        (0x605A, 0, 2, 2),
        (0x6007, 0, 2, 2),
        (0x6060, 0, 8, 1),
    ]
}

fn max_current_permille(cfg: &RobotConfig, axis: usize) -> u16 {
    let a = &cfg.axes[axis];
    (a.max_current_a / a.rated_current_a * 1000.0).round() as u16
}

/// The master's view of one node.
#[derive(Debug, Clone, Default)]
pub struct Node {
    pub node: u8,
    steps: Vec<Step>,
    next: usize,
    waiting: bool,
    /// NMT start sent after a complete configuration.
    pub started: bool,
    pub boot_ups: u32,
    /// From TPDO1 / TPDO2.
    pub statusword: u16,
    pub position: i32,
    pub current: i16,
    pub mode_display: i8,
    pub tpdos: u64,
    /// Walk to OPERATION ENABLED (else send "disable voltage").
    pub enable: bool,
    /// Target sent while enabled; set to the actual position when OPERATION ENABLED is first seen.
    pub target: i32,
    pub enabled_seen: bool,
    /// In FAULT, toggle controlword bit 7 (fault reset on its rising edge).
    pub reset_faults: bool,
    pub controlword: u16,
    /// Received EMCY codes and SDO aborts (index, sub, code).
    pub emcy: Vec<u16>,
    pub aborts: Vec<(u16, u8, u32)>,
}

impl Node {
    /// The CiA 402 state from the statusword is OPERATION ENABLED.
    pub fn is_enabled(&self) -> bool {
        self.statusword & 0x6F == 0x27
    }
    pub fn is_fault(&self) -> bool {
        self.statusword & 0x4F == 0x08
    }
}

/// The scripted master.
pub struct TestMaster {
    cfg: RobotConfig,
    pub cycle: u64,
    pub nodes: Vec<Node>,
    /// Every frame received, in order.
    pub received: Vec<Frame>,
    /// Every frame sent, in order.
    pub sent: Vec<Frame>,
    /// Send the master heartbeat (set false to simulate a dead master).
    pub heartbeat: bool,
}

impl TestMaster {
    pub fn new(cfg: &RobotConfig) -> TestMaster {
        let nodes = (0..cfg.axes.len())
            .map(|i| Node {
                node: cfg.axes[i].node_id,
                steps: boot_steps(cfg, i),
                enable: true,
                ..Node::default()
            })
            .collect();
        TestMaster {
            cfg: cfg.clone(),
            cycle: 0,
            nodes,
            received: Vec::new(),
            sent: Vec::new(),
            heartbeat: true,
        }
    }

    fn send(&mut self, bus: &mut dyn Bus, f: Frame) {
        self.sent.push(f);
        bus.send(&f).unwrap();
    }

    fn on_frame(&mut self, f: Frame) {
        self.received.push(f);
        let Some(node) = self
            .nodes
            .iter_mut()
            .find(|n| f.id & 0x7F == u16::from(n.node))
        else {
            return;
        };
        let d = f.data;
        match f.id & !0x7F {
            0x700 if f.len == 1 && d[0] == 0 => {
                node.boot_ups += 1;
                node.next = 0;
                node.waiting = false;
                node.started = false;
                node.enabled_seen = false;
            }
            0x580 => {
                let (index, sub) = (u16::from_le_bytes([d[1], d[2]]), d[3]);
                let step = node.steps[node.next];
                assert_eq!(
                    (index, sub),
                    (step.0, step.1),
                    "SDO response for another object"
                );
                let value = u32::from_le_bytes([d[4], d[5], d[6], d[7]]);
                if d[0] == 0x80 {
                    node.aborts.push((index, sub, value));
                } else if step.3 == 0 {
                    assert_eq!(value, step.2, "read 0x{index:04X}:{sub}");
                }
                node.waiting = false;
                node.next += 1;
            }
            0x180 => {
                node.statusword = u16::from_le_bytes([d[0], d[1]]);
                node.position = i32::from_le_bytes([d[2], d[3], d[4], d[5]]);
                node.current = i16::from_le_bytes([d[6], d[7]]);
                node.tpdos += 1;
                if node.is_enabled() && !node.enabled_seen {
                    node.enabled_seen = true;
                    node.target = node.position;
                }
                if !node.is_enabled() {
                    node.enabled_seen = false;
                }
            }
            0x280 => node.mode_display = d[0] as i8,
            0x080 => node.emcy.push(u16::from_le_bytes([d[0], d[1]])),
            _ => {}
        }
    }

    /// One master cycle against `bus`, ending with SYNC.
    pub fn run_cycle(&mut self, bus: &mut dyn Bus) {
        while let Some(f) = bus.recv(0).unwrap() {
            self.on_frame(f);
        }
        for i in 0..self.nodes.len() {
            let n = &self.nodes[i];
            let id = u16::from(n.node);
            if n.next < n.steps.len() {
                if !n.waiting {
                    let (index, sub, value, size) = n.steps[n.next];
                    let cs = if size == 0 {
                        0x40
                    } else {
                        0x23 | ((4 - size) << 2)
                    };
                    let [i0, i1] = index.to_le_bytes();
                    let [v0, v1, v2, v3] = if size == 0 {
                        [0; 4]
                    } else {
                        value.to_le_bytes()
                    };
                    self.nodes[i].waiting = true;
                    self.send(
                        bus,
                        Frame::new(0x600 + id, &[cs, i0, i1, sub, v0, v1, v2, v3]).unwrap(),
                    );
                }
                continue;
            }
            if !n.started {
                let node = n.node;
                self.nodes[i].started = true;
                self.send(bus, Frame::new(0x000, &[0x01, node]).unwrap());
                let [c0, c1] = max_current_permille(&self.cfg, i).to_le_bytes();
                self.send(bus, Frame::new(0x300 + id, &[8, c0, c1]).unwrap());
                continue;
            }
            if n.tpdos == 0 {
                continue;
            }
            let (cw, target) = match (n.enable, n.statusword) {
                (false, _) => (0x00, n.position),
                (true, sw) if sw & 0x4F == 0x40 => (0x06, n.position),
                (true, sw) if sw & 0x6F == 0x21 => (0x07, n.position),
                (true, sw) if sw & 0x6F == 0x23 => (0x0F, n.position),
                (true, sw) if sw & 0x6F == 0x27 => (0x0F, n.target),
                (true, sw) if sw & 0x4F == 0x08 && n.reset_faults && n.controlword == 0x00 => {
                    (0x80, n.position)
                }
                (true, _) => (0x00, n.position),
            };
            self.nodes[i].controlword = cw;
            let mut p = [0u8; 8];
            p[..2].copy_from_slice(&cw.to_le_bytes());
            p[2..6].copy_from_slice(&target.to_le_bytes());
            self.send(bus, Frame::new(0x200 + id, &p).unwrap());
        }
        let every =
            u64::from(self.cfg.bus.master_heartbeat_ms) * 1_000_000 / self.cfg.cycle_period_ns();
        if self.heartbeat && self.cycle.is_multiple_of(every.max(1)) {
            let id = 0x700 + u16::from(self.cfg.bus.master_node_id);
            self.send(bus, Frame::new(id, &[0x05]).unwrap());
        }
        self.send(bus, Frame::new(0x080, &[]).unwrap());
        self.cycle += 1;
    }

    /// Run until every node is enabled (seen in a TPDO1); returns the cycles taken.
    pub fn run_until_enabled(&mut self, bus: &mut dyn Bus, max_cycles: u64) -> u64 {
        let start = self.cycle;
        while !self.nodes.iter().all(|n| n.enabled_seen) {
            assert!(
                self.cycle - start < max_cycles,
                "not all enabled after {max_cycles} cycles: {:?}",
                self.states()
            );
            self.run_cycle(bus);
        }
        self.cycle - start
    }

    /// Statuswords of all nodes, for messages.
    pub fn states(&self) -> Vec<String> {
        self.nodes
            .iter()
            .map(|n| format!("{}:{:04X} aborts {:X?}", n.node, n.statusword, n.aborts))
            .collect()
    }
}
