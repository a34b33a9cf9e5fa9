//! The CANopen master of the MCM: boots and configures the six drives, supervises them
//! (heartbeat, missed TPDOs, EMCY) and turns per-axis [`DriveRequest`]s into RPDOs, walking the
//! CiA 402 state machine one hop per cycle and handling CSP/CST mode switches safely.
//!
//! Sans-I/O and lock-step: per cycle the controller
//! 1. passes every received frame to [`Master::handle_frame`],
//! 2. reads [`Master::feedback`] and [`Master::poll_event`],
//! 3. calls [`Master::cycle`], which appends the frames to send (SYNC last) to a [`FrameBuf`].
//!
//! Runs inside the cycle: `handle_frame`, `cycle`, `feedback` and `poll_event` allocate
//! nothing, take no locks and never panic on bad frames; everything is preallocated by
//! [`Master::new`], which also refuses a configuration above the bus-load budget.
//!
//! Axis indices are 0-based (0..6) everywhere in this API.
//!
//! Calibration kept by the drives: while booting a drive the master reads its stored
//! calibration 0x2100 (see [`super::boot`]) and reports it as [`MasterEvent::Calibration`]
//! right after [`MasterEvent::Configured`]; [`Master::store_calibration`] writes it.
//!
//! ```
//! use mcm_rt_core::canopen::master::{DriveRequest, FrameBuf, Master};
//! let cfg = mcm_shared::config::RobotConfig::prob2_default();
//! let mut master = Master::new(&cfg).unwrap();
//! let mut out = FrameBuf::new();
//! master.cycle(0, &[DriveRequest::Disable; 6], &[1.0; 6], &mut out);
//! assert_eq!(out.as_slice().last().unwrap().to_string(), "080#"); // SYNC last
//! ```

use super::boot::{
    BootOutput, BootParams, BootSequence, CALIBRATION, CALIBRATION_OFFSET_SUB,
    CALIBRATION_VALID_SUB, StoredCalibration,
};
use super::busload::{BusLoad, check_config};
use super::cia402::{ControlWord, State, StatusWord, Target, next_controlword};
use super::emcy::Emcy;
use super::heartbeat::{HeartbeatConsumer, HeartbeatProducer};
use super::nmt::{NmtCommand, NmtState, decode_heartbeat, nmt_frame, sync_frame};
use super::objects::{ObjectAddr, Service, classify};
use super::pdo::{Rpdo1, Rpdo2, Tpdo1, Tpdo2};
use super::sdo::{SdoClient, SdoDone, SdoError, SdoValue};
use super::types::EventRing;
pub use super::types::{
    AxisFeedback, CONFIG_RETRIES, DriveRequest, EVENT_CAPACITY, FAULT_RESET_EDGES,
    FRAME_BUF_CAPACITY, FrameBuf, LostReason, MODE_CSP, MODE_CST, MasterEvent, MasterSetupError,
    RPDO2_REPEATS,
};
use mcm_bus::Frame;
use mcm_shared::NUM_AXES;
use mcm_shared::config::{AxisConfig, RobotConfig};

/// Cycles between the NMT stops sent to a lost drive asked to power off (`Master::cut_off`).
pub const NMT_STOP_REPEAT_CYCLES: u64 = 4;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Link {
    WaitingBootUp,
    Configuring,
    Operational,
    /// The configuration failed: the drive is reset and configured again at `retry_at_ns`
    /// (`None`: [`CONFIG_RETRIES`] ran out).
    Failed {
        retry_at_ns: Option<u64>,
    },
}

/// A write of the stored calibration in progress: 0x2100:1 = `offset`, then 0x2100:2 = 1;
/// with no offset, 0x2100:2 = 0 alone (the stored calibration is no longer valid).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct CalStore {
    offset: Option<i32>,
    /// Writes acknowledged so far (0 or 1).
    written: u8,
    /// The SDO of write `written` is outstanding.
    waiting: bool,
}

/// What the configuration fixes for one drive (set once, in [`AxisRt::new`]).
#[derive(Debug, Clone)]
struct AxisParams {
    node: u8,
    counts_per_rad: f64,
    /// Amperes per per-mille of rated current.
    amps_per_permille: f64,
    torque_per_amp: f64,
    /// Per-mille of rated motor torque per joint Nm.
    permille_per_joint_nm: f64,
    rated_current_a: f64,
    max_current_permille: u16,
    /// Largest position step per cycle [counts].
    max_step_counts: f64,
}

impl AxisParams {
    /// A joint torque [Nm] as the drive's per-mille of its rated motor torque (0x6071, the
    /// torque offset 0x60B2), rounded and clamped to i16; 0 for a torque that is not finite.
    fn torque_permille(&self, torque_nm: f64) -> i16 {
        let t = torque_nm * self.permille_per_joint_nm;
        if t.is_finite() {
            t.round().clamp(-32767.0, 32767.0) as i16
        } else {
            0
        }
    }
}

/// What the master knows of one drive since it last booted: `Default` is "just booted".
#[derive(Debug, Clone)]
struct Session {
    sdo_outcome: Option<Result<SdoDone, SdoError>>,
    boot_deadline_ns: Option<u64>,
    reset_pending: bool,
    reset_sent: bool,
    /// Since when the drive counts as lost [ns] (`None`: not lost); a drive lost and silent
    /// for a boot timeout is reset.
    lost_since_ns: Option<u64>,
    /// When the last NMT stop went to the drive, lost and asked to power off [ns] (see
    /// [`Master::cut_off`]).
    stop_sent_ns: Option<u64>,
    tpdo_this_cycle: bool,
    tpdo_seen_since_start: bool,
    missed: u16,
    last_tpdo_ns: Option<u64>,
    prev_cw: ControlWord,
    commanded_mode: i8,
    rpdo2_sent: Option<Rpdo2>,
    /// Repeats of the last urgent RPDO2 still to send ([`RPDO2_REPEATS`]).
    rpdo2_repeats: u8,
    fault_reset_edges: u8,
    /// Send one fault-reset edge while OPERATION ENABLED (see [`Master::restart_position_loop`]).
    loop_restart: bool,
    cal_store: Option<CalStore>,
    /// A store to do once the write in progress is done (`None` inside: forget the stored one).
    cal_queued: Option<Option<i32>>,
}

impl Session {
    fn lost(&self) -> bool {
        self.lost_since_ns.is_some()
    }
}

impl Default for Session {
    fn default() -> Self {
        Session {
            sdo_outcome: None,
            boot_deadline_ns: None,
            reset_pending: false,
            reset_sent: false,
            lost_since_ns: None,
            stop_sent_ns: None,
            tpdo_this_cycle: false,
            tpdo_seen_since_start: false,
            missed: 0,
            last_tpdo_ns: None,
            prev_cw: ControlWord(0),
            commanded_mode: MODE_CSP,
            rpdo2_sent: None,
            rpdo2_repeats: 0,
            fault_reset_edges: 0,
            loop_restart: false,
            cal_store: None,
            cal_queued: None,
        }
    }
}

/// Whether the calibration the drive holds (0x2100) can be read back at its next boot, as far
/// as the master's own writes of it go. Kept across [`AxisRt::forget`].
///
/// A write the master sent may reach the drive after a reboot it has not heard of yet (its
/// boot-up is on its way, or lost): the drive then holds an offset, or a valid flag, taken
/// against the encoder reference it had before, and would read back as calibrated, off by
/// whatever the new reference differs. So a write counts as confirmed only once a TPDO comes
/// after its answer: a drive that rebooted sends none before it is configured again.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum StoreTrust {
    /// No write of 0x2100 unconfirmed.
    Settled,
    /// A write of 0x2100 is outstanding.
    Writing,
    /// The writes are answered (or failed); no TPDO since.
    Written,
    /// The drive's session ended while `Writing` or `Written`: its next boot clears 0x2100.
    InDoubt,
}

/// Runtime state of one drive.
#[derive(Debug, Clone)]
struct AxisRt {
    params: AxisParams,
    /// The protocol machines, built from the configuration; [`AxisRt::forget`] resets them.
    boot: BootSequence,
    sdo: SdoClient,
    hb: HeartbeatConsumer,
    session: Session,
    // Kept across `forget` (see there).
    link: Link,
    started_ns: u64,
    last_pos_counts: i32,
    last_emcy_code: u16,
    last_target_counts: i32,
    /// The torque feed-forward asked for in CSP [joint Nm] (see [`Master::set_torque_offset`]).
    torque_offset_nm: f64,
    /// Configurations failed in a row (see [`CONFIG_RETRIES`]).
    config_failures: u8,
    cal_trust: StoreTrust,
}

impl AxisRt {
    fn new(index: usize, a: &AxisConfig, cfg: &RobotConfig) -> Result<AxisRt, MasterSetupError> {
        let b = &cfg.bus;
        let period_s = cfg.cycle_period_s();
        let bad = |key, value, derived, derived_value, allowed| MasterSetupError::AxisValue {
            axis: index,
            key,
            value,
            derived,
            derived_value,
            allowed,
        };
        let rated_ma = (a.rated_current_a * 1000.0).round();
        if !(1.0..=f64::from(u32::MAX)).contains(&rated_ma) {
            return Err(bad(
                "rated_current_a",
                a.rated_current_a,
                "0x6075 [mA]",
                rated_ma,
                "u32 1..=4294967295",
            ));
        }
        let rated_torque_mnm = (a.torque_constant_nm_a * a.rated_current_a * 1000.0).round();
        if !(1.0..=f64::from(u32::MAX)).contains(&rated_torque_mnm) {
            return Err(bad(
                "torque_constant_nm_a",
                a.torque_constant_nm_a,
                "0x6076 [mNm]",
                rated_torque_mnm,
                "u32 1..=4294967295",
            ));
        }
        let max_pm = (a.max_current_a / a.rated_current_a * 1000.0).round();
        if !(0.0..=f64::from(u16::MAX)).contains(&max_pm) {
            return Err(bad(
                "max_current_a",
                a.max_current_a,
                "0x6073 [per-mille]",
                max_pm,
                "u16 0..=65535",
            ));
        }
        let cycle_ms = (cfg.cycle_period_ns() / 1_000_000) as u8;
        let params = BootParams {
            node: a.node_id,
            axis: index,
            drive_heartbeat_ms: b.drive_heartbeat_ms,
            master_node_id: b.master_node_id,
            master_heartbeat_timeout_ms: b.heartbeat_timeout_ms,
            cycle_ms,
            rated_current_ma: rated_ma as u32,
            rated_torque_mnm: rated_torque_mnm as u32,
            max_current_permille: max_pm as u16,
        };
        let counts_per_rad = a.counts_per_rad();
        let rated_motor_torque_nm = rated_torque_mnm / 1000.0;
        Ok(AxisRt {
            params: AxisParams {
                node: a.node_id,
                counts_per_rad,
                amps_per_permille: a.rated_current_a / 1000.0,
                torque_per_amp: a.torque_per_amp(),
                permille_per_joint_nm: 1000.0
                    / (rated_motor_torque_nm * a.gear_ratio * a.gear_efficiency),
                rated_current_a: a.rated_current_a,
                max_current_permille: max_pm as u16,
                max_step_counts: a.max_velocity_deg_s.to_radians()
                    * cfg.safety.overspeed_factor
                    * period_s
                    * counts_per_rad,
            },
            boot: BootSequence::new(&params),
            sdo: SdoClient::new(a.node_id, u64::from(b.sdo_timeout_ms) * 1_000_000),
            hb: HeartbeatConsumer::new(u64::from(b.heartbeat_timeout_ms) * 1_000_000),
            session: Session::default(),
            link: Link::WaitingBootUp,
            started_ns: 0,
            last_pos_counts: 0,
            last_emcy_code: 0,
            last_target_counts: 0,
            torque_offset_nm: 0.0,
            config_failures: 0,
            cal_trust: StoreTrust::Settled,
        })
    }

    /// Back to "just booted": configuration state and feedback forgotten.
    ///
    /// A write of the stored calibration not yet confirmed puts it in doubt ([`StoreTrust`]).
    ///
    /// Kept: `link` (every caller sets it next), `config_failures`, `cal_trust`, `started_ns` (read only while
    /// operational, and set when the drive becomes so), `last_pos_counts` and `last_target_counts`
    /// (the setpoint holds the last known position until new feedback comes, so nothing jumps),
    /// `last_emcy_code` (a `Fault` event names the drive's last EMCY, whenever it came); in the
    /// feedback the position and the last EMCY.
    fn forget(&mut self, fb: &mut AxisFeedback) {
        if matches!(self.cal_trust, StoreTrust::Writing | StoreTrust::Written) {
            self.cal_trust = StoreTrust::InDoubt;
        }
        self.sdo.cancel();
        self.boot.stop();
        self.hb.reset();
        self.session = Session::default();
        let last_emcy = fb.last_emcy;
        *fb = AxisFeedback {
            position_rad: fb.position_rad,
            last_emcy,
            ..AxisFeedback::new(self.params.node)
        };
    }
}

/// The CANopen master (see the module documentation).
#[derive(Debug, Clone)]
pub struct Master {
    period_ns: u64,
    max_missed: u16,
    boot_timeout_ns: u64,
    hb_grace_ns: u64,
    hb_producer: HeartbeatProducer,
    axes: [AxisRt; NUM_AXES],
    feedback: [AxisFeedback; NUM_AXES],
    events: EventRing,
    frames_dropped: u64,
    bad_frames: u64,
    load: BusLoad,
}

impl Master {
    /// Check the configuration (bus load, cycle period, per-axis values) and preallocate
    /// everything.
    pub fn new(cfg: &RobotConfig) -> Result<Master, MasterSetupError> {
        if cfg.axes.len() != NUM_AXES {
            return Err(MasterSetupError::AxisCount {
                got: cfg.axes.len(),
            });
        }
        let load = check_config(cfg)?;
        let period_ns = cfg.cycle_period_ns();
        if !period_ns.is_multiple_of(1_000_000) || !(1..=255).contains(&(period_ns / 1_000_000)) {
            return Err(MasterSetupError::CyclePeriod {
                rate_hz: cfg.cycle.rate_hz,
                period_us: period_ns / 1000,
            });
        }
        let mut built = Vec::with_capacity(NUM_AXES);
        for (i, a) in cfg.axes.iter().enumerate() {
            built.push(AxisRt::new(i, a, cfg)?);
        }
        let mut axes: [AxisRt; NUM_AXES] = built
            .try_into()
            .map_err(|v: Vec<AxisRt>| MasterSetupError::AxisCount { got: v.len() })?;
        // Drives powered before the master started sent their boot-ups to nobody, and after
        // power-up they send no heartbeat (0x1017 = 0): a drive whose boot-up is not among the
        // frames of the first cycle is reset (NMT reset communication) in that cycle, rather than
        // reported missing a boot timeout later. On a real robot that is every start of mcm-rt:
        // the drives power up with the cabinet, before the computer has booted.
        for ax in &mut axes {
            ax.session.reset_pending = true;
        }
        let feedback = core::array::from_fn(|i| AxisFeedback::new(axes[i].params.node));
        let b = &cfg.bus;
        Ok(Master {
            period_ns,
            max_missed: b.max_missed_tpdos,
            boot_timeout_ns: u64::from(b.boot_timeout_ms) * 1_000_000,
            hb_grace_ns: u64::from(b.heartbeat_timeout_ms) * 1_000_000,
            hb_producer: HeartbeatProducer::new(
                b.master_node_id,
                u64::from(b.master_heartbeat_ms) * 1_000_000,
            ),
            axes,
            feedback,
            events: EventRing::new(),
            frames_dropped: 0,
            bad_frames: 0,
            load,
        })
    }

    /// The bus load computed (and accepted) at start-up.
    pub fn bus_load(&self) -> &BusLoad {
        &self.load
    }

    /// Per-axis feedback, updated by `handle_frame` and `cycle`.
    pub fn feedback(&self) -> &[AxisFeedback; NUM_AXES] {
        &self.feedback
    }

    /// The next event, oldest first.
    pub fn poll_event(&mut self) -> Option<MasterEvent> {
        self.events.pop()
    }

    /// Events lost because the ring was full.
    pub fn events_dropped(&self) -> u64 {
        self.events.dropped
    }

    /// Frames not sent because the caller's `FrameBuf` was full.
    pub fn frames_dropped(&self) -> u64 {
        self.frames_dropped
    }

    /// Frames of known drives that could not be decoded (wrong length).
    pub fn bad_frames(&self) -> u64 {
        self.bad_frames
    }

    /// The next cycles send the fault-reset edge (up to [`FAULT_RESET_EDGES`] times) to every
    /// drive that is in FAULT (or FAULT REACTION ACTIVE) now.
    pub fn reset_faults(&mut self) {
        for (ax, fb) in self.axes.iter_mut().zip(&self.feedback) {
            if fb.state.is_fault() {
                ax.session.fault_reset_edges = FAULT_RESET_EDGES;
            }
        }
    }

    /// Restart the position loop of drive `axis` where the joint stands: the next cycle's
    /// controlword carries a fault-reset edge (`0x008F`) while the drive is OPERATION ENABLED,
    /// which the MCM drive profile makes a restart of the CSP loop at the actual position with
    /// its integral cleared (the state machine ignores the bit outside FAULT). Used after a
    /// following-error trip, so that a loop wound up against an obstacle stops pressing.
    /// Out-of-range axes are ignored.
    pub fn restart_position_loop(&mut self, axis: usize) {
        if let Some(ax) = self.axes.get_mut(axis) {
            ax.session.loop_restart = true;
        }
    }

    /// The torque feed-forward of drive `axis`'s position loop in CSP [joint Nm] (0x60B2, in
    /// RPDO2; e.g. the gravity load, so that the loop's integral does not have to carry it).
    /// It goes out with the next RPDO2 the mode or current limit needs, or on the axis's turn
    /// (one drive a cycle: every drive's RPDO2 is restated then, changed or not).
    /// 0 is sent in CST. Out-of-range axes and non-finite values are ignored.
    pub fn set_torque_offset(&mut self, axis: usize, torque_nm: f64) {
        if let Some(ax) = self.axes.get_mut(axis)
            && torque_nm.is_finite()
        {
            ax.torque_offset_nm = torque_nm;
        }
    }

    /// Whether the master gave up on drive `axis`: its configuration failed [`CONFIG_RETRIES`]
    /// times after the first, and it stays down until it boots by itself or
    /// [`Master::reset_node`] is called. Out-of-range axes: `false`.
    pub fn gave_up(&self, axis: usize) -> bool {
        self.axes
            .get(axis)
            .is_some_and(|ax| ax.link == Link::Failed { retry_at_ns: None })
    }

    /// Reset the communication of one drive (NMT `82`) in the next cycle: it boots again and
    /// is reconfigured. The master does so by itself after a `ConfigFailed`, up to
    /// [`CONFIG_RETRIES`] times in a row; this is for more. Out-of-range axes are ignored.
    pub fn reset_node(&mut self, axis: usize) {
        if let Some(ax) = self.axes.get_mut(axis) {
            ax.config_failures = 0;
        }
        self.reset_again(axis);
    }

    /// Forget drive `axis` and send it NMT reset communication in the next cycle.
    fn reset_again(&mut self, axis: usize) {
        if let (Some(ax), Some(fb)) = (self.axes.get_mut(axis), self.feedback.get_mut(axis)) {
            ax.forget(fb);
            ax.link = Link::WaitingBootUp;
            ax.session.reset_pending = true;
        }
    }

    /// Store a calibration offset [encoder counts: raw position at joint angle 0] in the drive
    /// of `axis`, so that it survives a restart of the MCM (not a power cycle of the drive):
    /// the next cycles write 0x2100:1 = `offset_counts`, then 0x2100:2 = 1, one SDO at a time
    /// with the usual SDO timeout. The result comes as [`MasterEvent::CalibrationStored`] or
    /// [`MasterEvent::CalibrationStoreFailed`]. Only for an operational drive (ignored
    /// otherwise, and for out-of-range axes); a store requested while one is in progress
    /// follows it. Allocates nothing.
    pub fn store_calibration(&mut self, axis: usize, offset_counts: i32) {
        self.queue_calibration_store(axis, Some(offset_counts));
    }

    /// Mark the calibration the drive of `axis` holds as no longer valid (0x2100:2 = 0), so
    /// that a restart of the MCM does not read back a calibration found to be in doubt; as
    /// [`Master::store_calibration`] otherwise. Allocates nothing.
    pub fn forget_stored_calibration(&mut self, axis: usize) {
        self.queue_calibration_store(axis, None);
    }

    fn queue_calibration_store(&mut self, axis: usize, offset: Option<i32>) {
        if let Some(ax) = self.axes.get_mut(axis)
            && ax.link == Link::Operational
        {
            if ax.session.cal_store.is_some() {
                ax.session.cal_queued = Some(offset);
            } else {
                ax.session.cal_store = Some(CalStore {
                    offset,
                    written: 0,
                    waiting: false,
                });
            }
        }
    }

    fn axis_of(&self, node: u8) -> Option<usize> {
        self.axes.iter().position(|a| a.params.node == node)
    }

    /// Process one received frame.
    pub fn handle_frame(&mut self, now_ns: u64, frame: &Frame) {
        let (i, service) = match classify(frame.id) {
            s @ (Service::Heartbeat { node }
            | Service::Tpdo { node, .. }
            | Service::Emcy { node }
            | Service::SdoResponse { node }) => match self.axis_of(node) {
                Some(i) => (i, s),
                None => return,
            },
            _ => return,
        };
        match service {
            Service::Heartbeat { .. } => match decode_heartbeat(frame) {
                Some(NmtState::BootUp) => self.on_boot_up(i),
                Some(state) => self.on_heartbeat(i, now_ns, state),
                None => self.bad_frames += 1,
            },
            Service::Tpdo { pdo: 1, .. } => match Tpdo1::decode(frame) {
                Ok(t) => self.on_tpdo1(i, now_ns, t),
                Err(_) => self.bad_frames += 1,
            },
            Service::Tpdo { pdo: 2, .. } => match Tpdo2::decode(frame) {
                Ok(t) if self.axes[i].link == Link::Operational => {
                    self.feedback[i].mode_display = Some(t.mode_display);
                }
                Ok(_) => {}
                Err(_) => self.bad_frames += 1,
            },
            Service::Emcy { .. } => match Emcy::decode(frame, i) {
                Ok(e) => {
                    self.events.push(MasterEvent::Emcy { axis: i, emcy: e });
                    self.axes[i].last_emcy_code = e.code;
                    self.feedback[i].last_emcy = (!e.is_reset()).then_some(e);
                }
                Err(_) => self.bad_frames += 1,
            },
            Service::SdoResponse { .. } => {
                if let Some(o) = self.axes[i].sdo.on_frame(frame) {
                    self.axes[i].session.sdo_outcome = Some(o);
                }
            }
            _ => {}
        }
        self.refresh(i, now_ns);
    }

    fn on_boot_up(&mut self, i: usize) {
        let (ax, fb) = (&mut self.axes[i], &mut self.feedback[i]);
        if ax.link == Link::Operational && !ax.session.lost() {
            self.events.push(MasterEvent::Lost {
                axis: i,
                node: ax.params.node,
                reason: LostReason::BootUp,
            });
        }
        self.events.push(MasterEvent::Booted { axis: i });
        ax.forget(fb);
        ax.link = Link::Configuring;
        ax.boot.start(match ax.cal_trust {
            StoreTrust::InDoubt => StoredCalibration::Clear,
            _ => StoredCalibration::Read,
        });
    }

    fn on_heartbeat(&mut self, i: usize, now_ns: u64, state: NmtState) {
        let grace = self.hb_grace_ns;
        let ax = &mut self.axes[i];
        ax.hb.on_heartbeat(now_ns, state);
        match ax.link {
            Link::WaitingBootUp if !ax.session.reset_sent => ax.session.reset_pending = true,
            Link::Operational
                if state != NmtState::Operational
                    && now_ns.saturating_sub(ax.started_ns) >= grace =>
            {
                let node = ax.params.node;
                self.reset_again(i);
                self.events.push(MasterEvent::Lost {
                    axis: i,
                    node,
                    reason: LostReason::NotOperational { state },
                });
            }
            _ => {}
        }
    }

    fn on_tpdo1(&mut self, i: usize, now_ns: u64, t: Tpdo1) {
        let period_ns = self.period_ns;
        let (ax, fb) = (&mut self.axes[i], &mut self.feedback[i]);
        if ax.link != Link::Operational {
            return;
        }
        let sw = StatusWord(t.statusword);
        let state = sw.state();
        if state == State::Fault && fb.state != State::Fault {
            self.events.push(MasterEvent::Fault {
                axis: i,
                code: ax.last_emcy_code,
            });
        }
        fb.velocity_rad_s = match ax.session.last_tpdo_ns {
            Some(prev) => {
                let cycles = ((now_ns.saturating_sub(prev)) as f64 / period_ns as f64)
                    .round()
                    .max(1.0);
                let delta = f64::from(t.position.wrapping_sub(ax.last_pos_counts))
                    / ax.params.counts_per_rad;
                delta / (cycles * period_ns as f64 * 1e-9)
            }
            None => 0.0,
        };
        ax.session.last_tpdo_ns = Some(now_ns);
        ax.last_pos_counts = t.position;
        ax.session.tpdo_this_cycle = true;
        ax.session.tpdo_seen_since_start = true;
        if ax.cal_trust == StoreTrust::Written && ax.session.cal_store.is_none() {
            ax.cal_trust = StoreTrust::Settled;
        }
        fb.state = state;
        fb.statusword = t.statusword;
        fb.estop = sw.emergency_stop();
        fb.light_barrier = sw.light_barrier();
        fb.position_rad = f64::from(t.position) / ax.params.counts_per_rad;
        fb.current_a = f64::from(t.current_permille) * ax.params.amps_per_permille;
        fb.torque_nm = fb.current_a * ax.params.torque_per_amp;
        fb.tpdo_age_cycles = 0;
    }

    /// Recompute the derived flags of axis `i`.
    fn refresh(&mut self, i: usize, now_ns: u64) {
        let (ax, fb) = (&self.axes[i], &mut self.feedback[i]);
        let started = ax.link == Link::Operational;
        // Online once its position has been measured: between NMT start and the first TPDO1
        // the feedback still holds no measurement (its position reads 0).
        fb.online = started
            && ax.session.tpdo_seen_since_start
            && !ax.session.lost()
            && ax.hb.is_fresh(now_ns);
        fb.operational = started
            && (ax.hb.state() == Some(NmtState::Operational) || ax.session.tpdo_seen_since_start);
        fb.enabled = started
            && fb.state == State::OperationEnabled
            && fb.mode_display == Some(ax.session.commanded_mode);
    }

    /// Run one cycle: supervision, boot configuration, CiA 402 and setpoints. Appends the
    /// frames to send to `out` (SYNC last). `max_current_a` is the current limit per axis [A]
    /// (clamped to `0..=axis.max_current_a`; sent in RPDO2 when it changes).
    pub fn cycle(
        &mut self,
        now_ns: u64,
        requests: &[DriveRequest; NUM_AXES],
        max_current_a: &[f64; NUM_AXES],
        out: &mut FrameBuf,
    ) {
        if let Some(f) = self.hb_producer.poll(now_ns) {
            self.push(out, f);
        }
        for i in 0..NUM_AXES {
            self.axis_cycle(i, now_ns, requests[i], max_current_a[i], out);
            self.axes[i].session.tpdo_this_cycle = false;
            self.refresh(i, now_ns);
        }
        self.push(out, sync_frame());
    }

    fn push(&mut self, out: &mut FrameBuf, f: Frame) {
        push_counted(out, f, &mut self.frames_dropped);
    }

    fn axis_cycle(
        &mut self,
        i: usize,
        now_ns: u64,
        req: DriveRequest,
        max_current_a: f64,
        out: &mut FrameBuf,
    ) {
        let boot_timeout = self.boot_timeout_ns;
        let node = self.axes[i].params.node;
        match self.axes[i].link {
            Link::WaitingBootUp => {
                let ax = &mut self.axes[i];
                let deadline = *ax
                    .session
                    .boot_deadline_ns
                    .get_or_insert(now_ns + boot_timeout);
                if ax.session.reset_pending || now_ns >= deadline {
                    if !ax.session.reset_pending {
                        // Gone rather than refusing its configuration: count afresh.
                        ax.config_failures = 0;
                        self.events.push(MasterEvent::Missing { axis: i, node });
                    }
                    ax.session.reset_pending = false;
                    ax.session.reset_sent = true;
                    ax.session.boot_deadline_ns = Some(now_ns + boot_timeout);
                    push_counted(
                        out,
                        nmt_frame(NmtCommand::ResetCommunication, node),
                        &mut self.frames_dropped,
                    );
                }
            }
            Link::Configuring => {
                let ax = &mut self.axes[i];
                let outcome = ax.session.sdo_outcome.take();
                match ax.boot.poll(now_ns, &mut ax.sdo, outcome) {
                    BootOutput::Send(f) => push_counted(out, f, &mut self.frames_dropped),
                    BootOutput::Done(f) => {
                        ax.link = Link::Operational;
                        ax.config_failures = 0;
                        if ax.cal_trust == StoreTrust::InDoubt {
                            ax.cal_trust = StoreTrust::Settled;
                        }
                        ax.started_ns = now_ns;
                        ax.hb.arm(now_ns);
                        ax.session.missed = 0;
                        self.events.push(MasterEvent::Configured { axis: i });
                        self.events.push(MasterEvent::Calibration {
                            axis: i,
                            offset_counts: ax.boot.calibration(),
                        });
                        push_counted(out, f, &mut self.frames_dropped);
                    }
                    BootOutput::Failed(error) => {
                        ax.config_failures = ax.config_failures.saturating_add(1);
                        // The drive may have been away (its cable, its power) or the bus bad:
                        // reset and configure it again a boot timeout later, a bounded number
                        // of times, rather than leave it down until it reboots by itself.
                        ax.link = Link::Failed {
                            retry_at_ns: (ax.config_failures <= CONFIG_RETRIES)
                                .then_some(now_ns + boot_timeout),
                        };
                        self.events.push(MasterEvent::ConfigFailed {
                            axis: i,
                            node,
                            error,
                        });
                    }
                    BootOutput::Waiting | BootOutput::Idle => {}
                }
            }
            Link::Operational => {
                self.supervise(i, now_ns);
                self.cut_off(i, now_ns, req, out);
                self.setpoints(i, now_ns, req, max_current_a, out);
                self.store_step(i, now_ns, out);
            }
            Link::Failed { retry_at_ns } => {
                self.axes[i].session.sdo_outcome = None;
                if retry_at_ns.is_some_and(|t| now_ns >= t) {
                    self.reset_again(i);
                }
            }
        }
    }

    /// Drive the calibration write of axis `i` (see [`Master::store_calibration`]).
    fn store_step(&mut self, i: usize, now_ns: u64, out: &mut FrameBuf) {
        let ax = &mut self.axes[i];
        let outcome = ax.session.sdo_outcome.take();
        if ax.session.cal_store.is_none() {
            ax.session.cal_store = ax.session.cal_queued.take().map(|offset| CalStore {
                offset,
                written: 0,
                waiting: false,
            });
        }
        let Some(mut st) = ax.session.cal_store else {
            return;
        };
        if st.waiting {
            let result = match outcome {
                Some(r) => r,
                None => match ax.sdo.poll(now_ns) {
                    Some(e) => Err(e),
                    None => return,
                },
            };
            st.waiting = false;
            ax.cal_trust = StoreTrust::Written;
            match result {
                Ok(_) if st.written == 1 || st.offset.is_none() => {
                    ax.session.cal_store = None;
                    self.events.push(MasterEvent::CalibrationStored { axis: i });
                    return;
                }
                Ok(_) => st.written += 1,
                Err(error) => {
                    ax.session.cal_store = None;
                    self.events
                        .push(MasterEvent::CalibrationStoreFailed { axis: i, error });
                    return;
                }
            }
        }
        let (sub, value) = match st.offset {
            Some(offset) if st.written == 0 => (CALIBRATION_OFFSET_SUB, SdoValue::I32(offset)),
            Some(_) => (CALIBRATION_VALID_SUB, SdoValue::U8(1)),
            None => (CALIBRATION_VALID_SUB, SdoValue::U8(0)),
        };
        if let Ok(f) = ax
            .sdo
            .write(now_ns, ObjectAddr::new(CALIBRATION, sub), value)
        {
            st.waiting = true;
            self.axes[i].cal_trust = StoreTrust::Writing;
            push_counted(out, f, &mut self.frames_dropped);
        }
        self.axes[i].session.cal_store = Some(st);
    }

    fn supervise(&mut self, i: usize, now_ns: u64) {
        let max_missed = self.max_missed;
        let boot_timeout = self.boot_timeout_ns;
        let (ax, fb) = (&mut self.axes[i], &mut self.feedback[i]);
        if ax.session.tpdo_this_cycle {
            ax.session.missed = 0;
        } else {
            ax.session.missed = ax.session.missed.saturating_add(1);
            fb.tpdo_age_cycles = fb.tpdo_age_cycles.saturating_add(1);
            if ax.session.missed == max_missed && !ax.session.lost() {
                ax.session.lost_since_ns = Some(now_ns);
                self.events.push(MasterEvent::Lost {
                    axis: i,
                    node: ax.params.node,
                    reason: LostReason::MissedTpdos {
                        missed: ax.session.missed,
                    },
                });
            }
        }
        if ax.hb.check(now_ns) && !ax.session.lost() {
            ax.session.lost_since_ns = Some(now_ns);
            self.events.push(MasterEvent::Lost {
                axis: i,
                node: ax.params.node,
                reason: LostReason::HeartbeatTimeout,
            });
        }
        if ax.session.lost() && ax.session.missed == 0 && ax.hb.is_fresh(now_ns) {
            ax.session.lost_since_ns = None;
            self.events.push(MasterEvent::Recovered {
                axis: i,
                node: ax.params.node,
            });
        }
        // Lost for a boot timeout and silent: its cable out for that long, or its power cycled
        // while its boot-up went unheard, after which it sits in PRE-OPERATIONAL without
        // heartbeats (0x1017 = 0 after power-up) and would never be heard again. Reset it and
        // wait for it as for a drive that never answered (resets repeated every boot timeout,
        // `Missing`). A drive whose heartbeats still come is not reset: it only misses its
        // TPDOs (no SYNC reaches it, the bus loses them) and recovers when they come back; one
        // that leaves OPERATIONAL is reset by its heartbeat (`on_heartbeat`).
        if !ax.hb.is_fresh(now_ns)
            && ax
                .session
                .lost_since_ns
                .is_some_and(|t| now_ns.saturating_sub(t) >= boot_timeout)
        {
            self.reset_again(i);
        }
    }

    /// A lost drive (its TPDOs missed, or its heartbeat) asked to power off: the disabling
    /// controlword of RPDO1 needs a SYNC to take effect, and the drive may get none (the SYNC
    /// stuck, its receive path broken), so the power off also goes by NMT stop, which a drive
    /// acts on at once: its abort connection reaction (0x6007 = 2, step 11 of the boot) disables
    /// its voltage and its brake holds. Sent again every [`NMT_STOP_REPEAT_CYCLES`] while the
    /// drive stays lost and the request stands (an NMT frame can be lost too). The drive's next
    /// heartbeat then says STOPPED, and the master resets and configures it again as any drive
    /// that left OPERATIONAL (`on_heartbeat`); one that sends no heartbeat is reset a boot
    /// timeout after it was lost (`supervise`).
    fn cut_off(&mut self, i: usize, now_ns: u64, req: DriveRequest, out: &mut FrameBuf) {
        let repeat_ns = self.period_ns * NMT_STOP_REPEAT_CYCLES;
        let ax = &mut self.axes[i];
        if !ax.session.lost() || req != DriveRequest::Disable {
            ax.session.stop_sent_ns = None;
            return;
        }
        if ax
            .session
            .stop_sent_ns
            .is_some_and(|t| now_ns.saturating_sub(t) < repeat_ns)
        {
            return;
        }
        ax.session.stop_sent_ns = Some(now_ns);
        let f = nmt_frame(NmtCommand::Stop, ax.params.node);
        self.push(out, f);
    }

    fn setpoints(
        &mut self,
        i: usize,
        now_ns: u64,
        req: DriveRequest,
        max_current_a: f64,
        out: &mut FrameBuf,
    ) {
        let period_ns = self.period_ns;
        let (ax, fb) = (&mut self.axes[i], &mut self.feedback[i]);
        let target = match req {
            DriveRequest::Disable => Target::SwitchOnDisabled,
            DriveRequest::QuickStop => Target::QuickStop,
            DriveRequest::Position { .. } => {
                ax.session.commanded_mode = MODE_CSP;
                Target::OperationEnabled
            }
            DriveRequest::Torque { .. } => {
                ax.session.commanded_mode = MODE_CST;
                Target::OperationEnabled
            }
        };
        // RPDO2: mode and current limit, on change (and repeated while unconfirmed).
        let pm = max_current_a / ax.params.rated_current_a * 1000.0;
        let pm = if pm.is_nan() {
            0.0
        } else {
            pm.round()
                .clamp(0.0, f64::from(ax.params.max_current_permille))
        };
        let offset = if ax.session.commanded_mode == MODE_CSP {
            ax.params.torque_permille(ax.torque_offset_nm)
        } else {
            0
        };
        let rpdo2 = Rpdo2 {
            mode: ax.session.commanded_mode,
            max_current_permille: pm as u16,
            torque_offset: offset,
        };
        let confirmed = fb.mode_display == Some(ax.session.commanded_mode);
        let mut frames = [None, None];
        // RPDO2 goes out at once when the mode or the current limit changes, and again in the
        // next RPDO2_REPEATS cycles: nothing confirms a current limit, and a drive that missed
        // a raised limit would hold a loaded axis with a lowered one, which may not carry it.
        // And every drive's RPDO2 goes out on its axis's turn, one axis a cycle (one RPDO2 a
        // cycle, counted in the bus load), changed or not: a drive that lost a change and all
        // its repeats has it again within six cycles (a search's lowered limit kept by the drive
        // would hide every contact from the calibration), a mode 0x6061 has not confirmed is
        // restated, and a new feed-forward alone waits for the turn.
        let turn = (now_ns / period_ns.max(1)) % NUM_AXES as u64 == i as u64;
        let urgent = ax.session.rpdo2_sent.is_none_or(|p| {
            p.mode != rpdo2.mode
                || p.max_current_permille != rpdo2.max_current_permille
                || (p.torque_offset != rpdo2.torque_offset && rpdo2.mode != MODE_CSP)
        });
        let repeat = !urgent && ax.session.rpdo2_repeats > 0;
        if urgent {
            ax.session.rpdo2_repeats = RPDO2_REPEATS;
        } else if repeat {
            ax.session.rpdo2_repeats -= 1;
        }
        if urgent || repeat || turn {
            frames[0] = Some(rpdo2.encode(ax.params.node));
            ax.session.rpdo2_sent = Some(rpdo2);
        }
        // Controlword: one hop towards the target, fault-reset edges when asked for.
        if !fb.state.is_fault() {
            ax.session.fault_reset_edges = 0;
        }
        let reset = ax.session.fault_reset_edges > 0 && fb.state == State::Fault;
        let mut cw = next_controlword(fb.state, target, ax.session.prev_cw, reset);
        if ax.session.loop_restart && fb.state == State::OperationEnabled {
            if cw == ControlWord::ENABLE_OPERATION && !ax.session.prev_cw.fault_reset_bit() {
                cw = ControlWord(cw.0 | ControlWord::FAULT_RESET_BIT);
                // The drive's target becomes the actual position: so does the reference the
                // next setpoint's step is limited from.
                ax.last_target_counts = ax.last_pos_counts;
            }
            ax.session.loop_restart = false;
        } else if fb.state != State::OperationEnabled {
            ax.session.loop_restart = false;
        }
        if reset && cw.fault_reset_bit() {
            ax.session.fault_reset_edges -= 1;
        }
        ax.session.prev_cw = cw;
        // Setpoints: a position only in OPERATION ENABLED with CSP confirmed (target = actual
        // otherwise, so nothing jumps); a torque in OPERATION ENABLED (see below).
        let enabled = fb.state == State::OperationEnabled && confirmed;
        let actual = ax.last_pos_counts;
        fb.target_clamped = false;
        let (position, torque) = match req {
            DriveRequest::Position { position_rad }
                if enabled && ax.session.commanded_mode == MODE_CSP =>
            {
                let wanted = position_rad * ax.params.counts_per_rad;
                let last = f64::from(ax.last_target_counts);
                let p = if wanted.is_finite() {
                    let clamped = wanted.clamp(
                        last - ax.params.max_step_counts,
                        last + ax.params.max_step_counts,
                    );
                    fb.target_clamped = clamped != wanted;
                    clamped
                        .round()
                        .clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32
                } else {
                    ax.last_target_counts
                };
                (p, 0)
            }
            // The torque goes out as soon as the drive is enabled, even before it confirms
            // CST: in CSP the drive ignores 0x6071, and the moment it switches it already has
            // the right torque (a zero there would let a gravity-loaded arm sag).
            DriveRequest::Torque { torque_nm } if fb.state == State::OperationEnabled => {
                (actual, ax.params.torque_permille(torque_nm))
            }
            // Back to CSP from CST, not yet confirmed: the drive still applies 0x6071, so it
            // gets the gravity feed-forward there until it switches (a zero would let a
            // gravity-loaded arm fall while the mode change is lost on the bus); in CSP the
            // drive ignores it.
            DriveRequest::Position { .. } if fb.state == State::OperationEnabled => {
                (actual, ax.params.torque_permille(ax.torque_offset_nm))
            }
            _ => (actual, 0),
        };
        ax.last_target_counts = position;
        frames[1] = Some(
            Rpdo1 {
                controlword: cw.0,
                target_position: position,
                target_torque: torque,
            }
            .encode(ax.params.node),
        );
        for f in frames.into_iter().flatten() {
            self.push(out, f);
        }
    }
}

fn push_counted(out: &mut FrameBuf, f: Frame, dropped: &mut u64) {
    if !out.push(f) {
        *dropped += 1;
    }
}

#[cfg(test)]
mod tests;
