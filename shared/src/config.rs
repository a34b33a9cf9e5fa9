//! The robot configuration file (TOML), read by both processes.
//!
//! Every physical parameter of the arm, its drives and the bus lives here, never in code.
//! Units in the file are the user's units (degrees, seconds, amperes, newton-metres);
//! the accessors named `*_rad` convert to the SI units used inside the controller.
//!
//! ```
//! let cfg = mcm_shared::config::RobotConfig::from_toml_str(
//!     mcm_shared::config::PROB2_DEFAULT_TOML).unwrap();
//! assert_eq!(cfg.axes.len(), 6);
//! assert_eq!(cfg.cycle.rate_hz, 200);
//! ```

use crate::NUM_AXES;
use crate::ranges::Num;
use crate::tool::{Tcp, Tool, ToolError, ToolField};
use serde::Deserialize;
use std::path::Path;

/// The P-Rob2 configuration shipped in `deploy/prob2.toml`, embedded so that the simulated
/// robot runs with no file at all.
pub const PROB2_DEFAULT_TOML: &str = include_str!("../../deploy/prob2.toml");

/// Why a configuration was refused. Every variant names the key.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ConfigError {
    #[error("cannot read config file {path}: {reason}")]
    Read { path: String, reason: String },
    #[error("config is not valid TOML or has an unknown/missing key: {0}")]
    Parse(String),
    #[error("config key `{key}` = {value} is not allowed: {allowed}")]
    Invalid {
        key: String,
        value: String,
        allowed: String,
    },
}

/// `x` is a finite number at least `min` (NaN fails).
fn finite_ge(x: f64, min: f64) -> bool {
    x.is_finite() && x >= min
}

/// `x` is a finite number above `min` (NaN fails).
fn finite_gt(x: f64, min: f64) -> bool {
    x.is_finite() && x > min
}

fn invalid(
    key: impl Into<String>,
    value: impl ToString,
    allowed: impl Into<String>,
) -> ConfigError {
    ConfigError::Invalid {
        key: key.into(),
        value: value.to_string(),
        allowed: allowed.into(),
    }
}

/// The whole robot configuration.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RobotConfig {
    pub robot: RobotSection,
    pub cycle: CycleConfig,
    pub bus: BusConfig,
    pub safety: SafetyConfig,
    /// Exactly six axes, in order 1..6.
    #[serde(rename = "axis")]
    pub axes: Vec<AxisConfig>,
    pub arm: ArmConfig,
    pub sim: SimConfig,
    /// The gateway's connections and access rules (optional section).
    #[serde(default)]
    pub gateway: GatewayConfig,
}

#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RobotSection {
    /// Model name shown to users, e.g. "P-Rob2".
    pub name: String,
}

/// The real-time cycle.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CycleConfig {
    /// Control and SYNC rate [Hz]. Bounded by the bus load budget (see `bus.load_budget`).
    pub rate_hz: u32,
    /// SCHED_FIFO priority of the cycle thread (1..=99).
    pub priority: u8,
    /// CPU core the cycle thread is pinned to.
    pub cpu: usize,
    /// Budget of one cycle's work [us] (0 < budget <= the period); cycles whose work takes
    /// longer are counted in the state's `timing.over_budget`. Default: half the period.
    #[serde(default)]
    pub work_budget_us: Option<u64>,
}

/// Which bus backend drives the arm. Its word ([`BusBackend::as_str`]) is the one of the
/// configuration's `bus.backend` and of `mcm-rt`'s ready line.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(try_from = "String")]
pub enum BusBackend {
    /// The simulated P-Rob2: simulated CiA 402 drives on an in-process bus.
    Sim,
    /// A real CAN interface through Linux SocketCAN.
    Socketcan,
}

impl BusBackend {
    /// Every backend.
    pub const ALL: [BusBackend; 2] = [BusBackend::Sim, BusBackend::Socketcan];

    /// Every word, for messages (a test checks it names each of [`BusBackend::ALL`]).
    pub const WORDS: &'static str = "`sim` or `socketcan`";

    /// Its word.
    pub const fn as_str(self) -> &'static str {
        match self {
            BusBackend::Sim => "sim",
            BusBackend::Socketcan => "socketcan",
        }
    }
}

/// A word that names no [`BusBackend`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown bus backend `{word}`; expected {}", BusBackend::WORDS)]
pub struct UnknownBackend {
    pub word: String,
}

impl std::str::FromStr for BusBackend {
    type Err = UnknownBackend;

    fn from_str(word: &str) -> Result<BusBackend, UnknownBackend> {
        BusBackend::ALL
            .into_iter()
            .find(|b| b.as_str() == word)
            .ok_or_else(|| UnknownBackend {
                word: word.to_string(),
            })
    }
}

impl TryFrom<String> for BusBackend {
    type Error = UnknownBackend;

    fn try_from(word: String) -> Result<BusBackend, UnknownBackend> {
        word.parse()
    }
}

impl std::fmt::Display for BusBackend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BusConfig {
    pub backend: BusBackend,
    /// SocketCAN interface name (ignored by the simulation, which names its bus `sim0`).
    pub interface: String,
    /// Bit rate [bit/s]; used for the bus load check (and by the simulated bus).
    pub bitrate: u32,
    /// Refuse a configuration whose worst-case cyclic bus load exceeds this fraction (0..1].
    pub load_budget: f64,
    /// Node id of the master (for its own heartbeat, consumed by the drives).
    pub master_node_id: u8,
    /// Master heartbeat period [ms].
    pub master_heartbeat_ms: u16,
    /// Heartbeat period the drives are configured to produce (0x1017) [ms].
    pub drive_heartbeat_ms: u16,
    /// Heartbeat consumer time of both directions [ms]: the master's for each drive's
    /// heartbeat, and each drive's for the master's (written to 0x1016:1). Must exceed the
    /// longer of the two heartbeat periods plus one cycle.
    pub heartbeat_timeout_ms: u16,
    /// Timeout of one SDO transaction [ms].
    pub sdo_timeout_ms: u16,
    /// How long to wait for a drive's boot-up before reporting it missing [ms].
    pub boot_timeout_ms: u32,
    /// Consecutive missed TPDOs after which a drive counts as disconnected.
    pub max_missed_tpdos: u16,
    /// If set, every frame is logged in candump format to this file.
    #[serde(default)]
    pub candump_log: Option<String>,
}

/// Safety parameters shared by all axes.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SafetyConfig {
    /// Position margin kept before each limit by the dynamic (braking distance) check [deg].
    pub limit_margin_deg: f64,
    /// Fraction of the maximum deceleration assumed available for braking (0..1].
    pub braking_efficiency: f64,
    /// Reaction latency assumed by the braking check, in cycles.
    pub reaction_cycles: u32,
    /// Velocity above `overspeed_factor * max_velocity` trips the velocity check.
    pub overspeed_factor: f64,
    /// Seconds of cycles kept by the flight recorder.
    pub flight_recorder_seconds: f64,
    /// Directory where flight-recorder files are written.
    pub flight_recorder_dir: String,
    /// RELEASE's soft speed limit: the share of each axis's `max_velocity_deg_s` at which its
    /// damping starts (none below).
    #[serde(default = "default_release_speed_onset")]
    pub release_speed_onset: f64,
    /// RELEASE's soft speed limit: the full damping, as a share of the strongest damping one
    /// control cycle can carry on the axis's inertia (`J / cycle period`).
    #[serde(default = "default_release_speed_damping")]
    pub release_speed_damping: f64,
}

/// P-Rob2 value of `safety.release_speed_onset` (also the default when the key is absent).
pub const DEFAULT_RELEASE_SPEED_ONSET: f64 = 0.4;
/// P-Rob2 value of `safety.release_speed_damping` (also the default when the key is absent).
pub const DEFAULT_RELEASE_SPEED_DAMPING: f64 = 0.3;

fn default_release_speed_onset() -> f64 {
    DEFAULT_RELEASE_SPEED_ONSET
}

fn default_release_speed_damping() -> f64 {
    DEFAULT_RELEASE_SPEED_DAMPING
}

/// How an axis finds its zero during calibration.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CalibrationConfig {
    /// +1: search the stop at the positive end; -1: at the negative end.
    pub direction: i8,
    /// Joint angle of the mechanical stop in that direction [deg].
    pub stop_deg: f64,
    /// Joint angle at which the light barrier switches, if the axis has one [deg].
    #[serde(default)]
    pub light_barrier_deg: Option<f64>,
    /// Search velocity [deg/s].
    pub search_velocity_deg_s: f64,
    /// Current limit while searching [A].
    pub search_current_a: f64,
    /// How far two approaches to the stop or edge (and the reference and where the axis's
    /// previous calibration puts it) may disagree before the calibration fails [deg].
    #[serde(default = "default_calibration_tolerance")]
    pub tolerance_deg: f64,
}

/// `axis.calibration.tolerance_deg` when left out [deg].
pub const DEFAULT_CALIBRATION_TOLERANCE_DEG: f64 = 0.5;

fn default_calibration_tolerance() -> f64 {
    DEFAULT_CALIBRATION_TOLERANCE_DEG
}

/// One axis: limits, drive, motor and gear.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AxisConfig {
    pub name: String,
    /// CANopen node id of the axis's drive (1..=127).
    pub node_id: u8,
    /// Software position limits [deg].
    pub min_deg: f64,
    pub max_deg: f64,
    /// Maximum joint velocity [deg/s], acceleration [deg/s^2], jerk [deg/s^3].
    pub max_velocity_deg_s: f64,
    pub max_acceleration_deg_s2: f64,
    #[serde(default)]
    pub max_jerk_deg_s3: Option<f64>,
    /// Gear ratio (motor turns per joint turn).
    pub gear_ratio: f64,
    /// Gear efficiency (0..1].
    pub gear_efficiency: f64,
    /// Encoder counts per motor revolution.
    pub encoder_counts_per_rev: u32,
    /// Motor torque constant [Nm/A].
    pub torque_constant_nm_a: f64,
    /// Rated (continuous) motor current [A]; the i2t reference.
    pub rated_current_a: f64,
    /// Peak motor current [A].
    pub max_current_a: f64,
    /// Thermal time constant of the motor winding for i2t [s].
    pub i2t_time_constant_s: f64,
    /// Current limit applied while the motor is derated by i2t [A].
    pub i2t_derated_current_a: f64,
    /// Joint friction: Coulomb [Nm] and viscous [Nm s/rad], joint side.
    pub coulomb_friction_nm: f64,
    pub viscous_friction_nm_s_rad: f64,
    /// Reflected motor inertia N^2 * J_rotor [kg m^2], joint side.
    pub armature_kg_m2: f64,
    /// Following error band: |commanded - actual| above this trips [deg].
    pub following_error_deg: f64,
    /// Whether the joint has a holding brake, engaged while the drive is not enabled.
    #[serde(default)]
    pub brake: bool,
    pub calibration: CalibrationConfig,
}

/// Rigid-body model: standard DH parameters and inertial data per link.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ArmConfig {
    /// Gravity vector in the base frame [m/s^2].
    pub gravity: [f64; 3],
    #[serde(rename = "link")]
    pub links: Vec<LinkConfig>,
    pub tool: ToolConfig,
}

#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LinkConfig {
    /// Standard DH: theta = q + offset; d, a [m]; alpha [deg].
    pub d: f64,
    pub a: f64,
    pub alpha_deg: f64,
    pub offset_deg: f64,
    pub mass: f64,
    /// Centre of mass in the link's DH frame [m].
    pub com: [f64; 3],
    /// Principal inertia about the centre of mass, axes of the link frame [kg m^2].
    pub inertia: [f64; 3],
}

/// The tool at start (gripper plus payload, and its TCP): the active tool until `set_tool`.
/// Checked by [`crate::tool::Tool::new`], as `set_tool` is.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ToolConfig {
    /// [kg]
    pub mass: f64,
    /// Centre of mass in the flange frame (DH frame 6) [m].
    pub com: [f64; 3],
    /// The TCP as a transform of the flange frame; absent: on the flange.
    #[serde(default)]
    pub tcp: Option<TcpConfig>,
    /// `[ixx, iyy, izz, ixy, ixz, iyz]` about the centre of mass [kg m^2]; absent: a point mass.
    #[serde(default)]
    pub inertia: Option<[f64; 6]>,
}

/// `[arm.tool.tcp]`: the TCP's position [m] and orientation (unit quaternion `[x, y, z, w]`)
/// in the flange frame.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TcpConfig {
    pub position: [f64; 3],
    pub orientation: [f64; 4],
}

impl ToolConfig {
    /// The tool this table configures, checked as `set_tool` checks it.
    pub fn tool(&self) -> Result<Tool, ToolError> {
        let tcp = self.tcp.map_or(Tcp::FLANGE, |t| Tcp {
            position: t.position,
            orientation: t.orientation,
        });
        Tool::new(tcp, self.mass, self.com, self.inertia)
    }

    /// The configured tool; the configuration was validated, so it is valid.
    pub fn active(&self) -> Tool {
        self.tool().unwrap_or(Tool::NONE)
    }
}

/// The simulated robot.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SimConfig {
    /// True joint angles at power-up [deg].
    pub initial_position_deg: [f64; NUM_AXES],
    /// Physics integration step [us]; the cycle period must be a multiple of it.
    pub physics_step_us: u32,
    /// Seed of the pseudo-random encoder offsets drawn at every power-up.
    pub seed: u64,
    /// Largest encoder offset drawn at power-up [deg of joint angle].
    pub max_encoder_offset_deg: f64,
    /// Stiffness [Nm/rad] and damping [Nm s/rad] of the mechanical stops and of obstacles.
    pub stop_stiffness_nm_rad: f64,
    pub stop_damping_nm_s_rad: f64,
}

impl RobotConfig {
    /// Parse and validate a configuration.
    pub fn from_toml_str(text: &str) -> Result<Self, ConfigError> {
        let cfg: RobotConfig =
            toml::from_str(text).map_err(|e| ConfigError::Parse(e.to_string()))?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Read, parse and validate a configuration file.
    pub fn from_file(path: &Path) -> Result<Self, ConfigError> {
        let text = std::fs::read_to_string(path).map_err(|e| ConfigError::Read {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
        Self::from_toml_str(&text)
    }

    /// The embedded P-Rob2 configuration.
    pub fn prob2_default() -> Self {
        Self::from_toml_str(PROB2_DEFAULT_TOML).expect("embedded deploy/prob2.toml is valid")
    }

    /// Cycle period [s].
    pub fn cycle_period_s(&self) -> f64 {
        1.0 / f64::from(self.cycle.rate_hz)
    }

    /// Cycle period [ns].
    pub fn cycle_period_ns(&self) -> u64 {
        1_000_000_000 / u64::from(self.cycle.rate_hz)
    }

    /// Budget of one cycle's work [ns]: `cycle.work_budget_us`, or half the period.
    pub fn work_budget_ns(&self) -> u64 {
        self.cycle
            .work_budget_us
            .map_or(self.cycle_period_ns() / 2, |us| us.saturating_mul(1000))
    }

    /// Check every value; the first problem found is returned, naming its key.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.gateway.validate()?;
        let c = &self.cycle;
        if !(1..=1000).contains(&c.rate_hz) {
            return Err(invalid("cycle.rate_hz", c.rate_hz, "1..=1000 Hz"));
        }
        if 1_000_000_000 % c.rate_hz != 0 {
            return Err(invalid(
                "cycle.rate_hz",
                c.rate_hz,
                "a rate whose period is a whole number of nanoseconds (e.g. 100, 200, 250)",
            ));
        }
        if !(1..=99).contains(&c.priority) {
            return Err(invalid("cycle.priority", c.priority, "1..=99 (SCHED_FIFO)"));
        }
        if let Some(budget) = c.work_budget_us {
            let period_us = self.cycle_period_ns() / 1000;
            if budget == 0 || budget > period_us {
                return Err(invalid(
                    "cycle.work_budget_us",
                    budget,
                    format!("1..={period_us} us (above 0, at most the cycle period)"),
                ));
            }
        }
        let b = &self.bus;
        if b.bitrate == 0 {
            return Err(invalid("bus.bitrate", b.bitrate, "> 0 bit/s"));
        }
        if !(b.load_budget > 0.0 && b.load_budget <= 1.0) {
            return Err(invalid("bus.load_budget", b.load_budget, "0 < budget <= 1"));
        }
        if !(1..=127).contains(&b.master_node_id) {
            return Err(invalid("bus.master_node_id", b.master_node_id, "1..=127"));
        }
        if b.drive_heartbeat_ms == 0 {
            return Err(invalid("bus.drive_heartbeat_ms", 0, "> 0 ms"));
        }
        if b.master_heartbeat_ms == 0 {
            return Err(invalid("bus.master_heartbeat_ms", 0, "> 0 ms"));
        }
        // One timeout for both directions; heartbeats are sent and stamped on cycle instants,
        // so two of them can be up to a producer period plus one cycle apart.
        let period_us = self.cycle_period_ns() / 1000;
        let producer_ms = b.drive_heartbeat_ms.max(b.master_heartbeat_ms);
        let floor_us = u64::from(producer_ms) * 1000 + period_us;
        if u64::from(b.heartbeat_timeout_ms) * 1000 <= floor_us {
            return Err(invalid(
                "bus.heartbeat_timeout_ms",
                b.heartbeat_timeout_ms,
                format!(
                    "more than the longer heartbeat period plus one cycle, max(bus.drive_heartbeat_ms = {}, \
                     bus.master_heartbeat_ms = {}) + {} ms (cycle.rate_hz = {}) = {} ms: it is the consumer \
                     time of both directions, the master's for each drive and each drive's (0x1016:1) for \
                     the master",
                    b.drive_heartbeat_ms,
                    b.master_heartbeat_ms,
                    period_us as f64 / 1000.0,
                    c.rate_hz,
                    floor_us as f64 / 1000.0
                ),
            ));
        }
        if b.sdo_timeout_ms == 0 {
            return Err(invalid("bus.sdo_timeout_ms", 0, "> 0 ms"));
        }
        if b.boot_timeout_ms == 0 {
            return Err(invalid("bus.boot_timeout_ms", 0, "> 0 ms"));
        }
        if b.max_missed_tpdos == 0 {
            return Err(invalid("bus.max_missed_tpdos", 0, ">= 1"));
        }
        self.validate_bounds()?;
        if self.axes.len() != NUM_AXES {
            return Err(invalid(
                "axis",
                self.axes.len(),
                "exactly 6 [[axis]] tables",
            ));
        }
        let mut seen_ids = [false; 128];
        for (i, a) in self.axes.iter().enumerate() {
            let key = format!("axis[{}]", i + 1);
            a.validate(&key, &mut seen_ids)?;
            a.validate_bounds(&key)?;
            if a.node_id == b.master_node_id {
                return Err(invalid(
                    format!("axis[{}].node_id", i + 1),
                    a.node_id,
                    "a node id different from bus.master_node_id",
                ));
            }
        }
        if !self.arm.gravity.iter().all(|v| v.is_finite()) {
            return Err(invalid(
                "arm.gravity",
                format!("{:?}", self.arm.gravity),
                "three finite values (m/s^2)",
            ));
        }
        if self.arm.links.len() != NUM_AXES {
            return Err(invalid(
                "arm.link",
                self.arm.links.len(),
                "exactly 6 [[arm.link]] tables",
            ));
        }
        for (i, l) in self.arm.links.iter().enumerate() {
            let key = format!("arm.link[{}]", i + 1);
            let geometry = [
                ("d", l.d),
                ("a", l.a),
                ("alpha_deg", l.alpha_deg),
                ("offset_deg", l.offset_deg),
            ];
            for (name, v) in geometry {
                if !v.is_finite() {
                    return Err(invalid(format!("{key}.{name}"), v, "a finite value"));
                }
            }
            if !finite_gt(l.mass, 0.0) {
                return Err(invalid(format!("{key}.mass"), l.mass, "> 0 kg"));
            }
            if l.inertia.iter().any(|v| !finite_gt(*v, 0.0)) {
                return Err(invalid(
                    format!("{key}.inertia"),
                    format!("{:?}", l.inertia),
                    "three values > 0 kg m^2",
                ));
            }
            if !l.com.iter().all(|v| v.is_finite()) {
                return Err(invalid(
                    format!("{key}.com"),
                    format!("{:?}", l.com),
                    "three finite values (m)",
                ));
            }
        }
        if let Err(e) = self.arm.tool.tool() {
            let field = e.field();
            let name = match field.name {
                ToolField::CENTER_OF_MASS => "com",
                name => name,
            };
            let index = field.index.map(|i| format!("[{i}]")).unwrap_or_default();
            return Err(invalid(
                format!("arm.tool.{name}{index}"),
                Num(e.value()),
                e.allowed(),
            ));
        }
        let sim = &self.sim;
        if sim.physics_step_us == 0
            || !self
                .cycle_period_ns()
                .is_multiple_of(u64::from(sim.physics_step_us) * 1000)
        {
            return Err(invalid(
                "sim.physics_step_us",
                sim.physics_step_us,
                format!(
                    "> 0 and a divisor of the cycle period ({} us)",
                    self.cycle_period_ns() / 1000
                ),
            ));
        }
        for (i, (q, a)) in sim.initial_position_deg.iter().zip(&self.axes).enumerate() {
            if !(*q >= a.min_deg && *q <= a.max_deg) {
                return Err(invalid(
                    format!("sim.initial_position_deg[{}]", i + 1),
                    q,
                    format!("within the axis limits [{}, {}] deg", a.min_deg, a.max_deg),
                ));
            }
        }
        if !finite_ge(sim.max_encoder_offset_deg, 0.0) {
            return Err(invalid(
                "sim.max_encoder_offset_deg",
                sim.max_encoder_offset_deg,
                "a finite value >= 0 deg",
            ));
        }
        if !finite_gt(sim.stop_stiffness_nm_rad, 0.0) {
            return Err(invalid(
                "sim.stop_stiffness_nm_rad",
                sim.stop_stiffness_nm_rad,
                "a finite value > 0 Nm/rad",
            ));
        }
        if !finite_ge(sim.stop_damping_nm_s_rad, 0.0) {
            return Err(invalid(
                "sim.stop_damping_nm_s_rad",
                sim.stop_damping_nm_s_rad,
                "a finite value >= 0 Nm s/rad",
            ));
        }
        Ok(())
    }
}

impl AxisConfig {
    fn validate(&self, key: &str, seen_ids: &mut [bool; 128]) -> Result<(), ConfigError> {
        if !(1..=127).contains(&self.node_id) {
            return Err(invalid(format!("{key}.node_id"), self.node_id, "1..=127"));
        }
        if seen_ids[self.node_id as usize] {
            return Err(invalid(
                format!("{key}.node_id"),
                self.node_id,
                "a node id no other axis uses",
            ));
        }
        seen_ids[self.node_id as usize] = true;
        for (name, v) in [("min_deg", self.min_deg), ("max_deg", self.max_deg)] {
            if !v.is_finite() {
                return Err(invalid(format!("{key}.{name}"), v, "a finite value"));
            }
        }
        if self.min_deg >= self.max_deg {
            return Err(invalid(
                format!("{key}.min_deg"),
                self.min_deg,
                format!("below {key}.max_deg ({})", self.max_deg),
            ));
        }
        let positive = [
            ("max_velocity_deg_s", self.max_velocity_deg_s),
            ("max_acceleration_deg_s2", self.max_acceleration_deg_s2),
            ("gear_ratio", self.gear_ratio),
            ("torque_constant_nm_a", self.torque_constant_nm_a),
            ("rated_current_a", self.rated_current_a),
            ("max_current_a", self.max_current_a),
            ("i2t_time_constant_s", self.i2t_time_constant_s),
            ("i2t_derated_current_a", self.i2t_derated_current_a),
            ("armature_kg_m2", self.armature_kg_m2),
            ("following_error_deg", self.following_error_deg),
            (
                "calibration.search_velocity_deg_s",
                self.calibration.search_velocity_deg_s,
            ),
            (
                "calibration.search_current_a",
                self.calibration.search_current_a,
            ),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(invalid(format!("{key}.{name}"), v, "a finite value > 0"));
            }
        }
        if let Some(j) = self.max_jerk_deg_s3
            && !(j.is_finite() && j > 0.0)
        {
            return Err(invalid(
                format!("{key}.max_jerk_deg_s3"),
                j,
                "a finite value > 0",
            ));
        }
        if !(self.gear_efficiency > 0.0 && self.gear_efficiency <= 1.0) {
            return Err(invalid(
                format!("{key}.gear_efficiency"),
                self.gear_efficiency,
                "0 < x <= 1",
            ));
        }
        if self.encoder_counts_per_rev == 0 {
            return Err(invalid(format!("{key}.encoder_counts_per_rev"), 0, "> 0"));
        }
        if self.rated_current_a > self.max_current_a {
            return Err(invalid(
                format!("{key}.rated_current_a"),
                self.rated_current_a,
                format!("<= {key}.max_current_a ({})", self.max_current_a),
            ));
        }
        if self.i2t_derated_current_a > self.max_current_a {
            return Err(invalid(
                format!("{key}.i2t_derated_current_a"),
                self.i2t_derated_current_a,
                format!("<= {key}.max_current_a ({})", self.max_current_a),
            ));
        }
        let friction = [
            ("coulomb_friction_nm", self.coulomb_friction_nm),
            ("viscous_friction_nm_s_rad", self.viscous_friction_nm_s_rad),
        ];
        for (name, v) in friction {
            if !finite_ge(v, 0.0) {
                return Err(invalid(format!("{key}.{name}"), v, "a finite value >= 0"));
            }
        }
        let cal = &self.calibration;
        if cal.direction != 1 && cal.direction != -1 {
            return Err(invalid(
                format!("{key}.calibration.direction"),
                cal.direction,
                "+1 or -1",
            ));
        }
        let outside = if cal.direction > 0 {
            cal.stop_deg > self.max_deg
        } else {
            cal.stop_deg < self.min_deg
        };
        if !outside {
            return Err(invalid(
                format!("{key}.calibration.stop_deg"),
                cal.stop_deg,
                format!(
                    "beyond the software limit in the search direction ({} deg)",
                    if cal.direction > 0 {
                        self.max_deg
                    } else {
                        self.min_deg
                    }
                ),
            ));
        }
        if let Some(lb) = cal.light_barrier_deg
            && !(lb > self.min_deg && lb < self.max_deg)
        {
            return Err(invalid(
                format!("{key}.calibration.light_barrier_deg"),
                lb,
                format!("inside the limits ({}, {}) deg", self.min_deg, self.max_deg),
            ));
        }
        Ok(())
    }

    /// Joint-side torque produced by `current` amperes [Nm].
    pub fn torque_per_amp(&self) -> f64 {
        self.torque_constant_nm_a * self.gear_ratio * self.gear_efficiency
    }

    /// Encoder counts per joint radian.
    pub fn counts_per_rad(&self) -> f64 {
        f64::from(self.encoder_counts_per_rev) * self.gear_ratio / core::f64::consts::TAU
    }
}

mod bounds;
mod gateway;
pub use bounds::*;
pub use gateway::{
    AccessConfig, Cidr, ConnectionLimits, GatewayConfig, HostName, WebConfig, ZmqConfig,
};

#[cfg(test)]
mod tests;
