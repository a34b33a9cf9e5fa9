//! Coverage-guided search over the deterministic simulation tester's world: libFuzzer's bytes
//! become, through `arbitrary`, a robot (the simulator's seed, hence its encoder offsets, and
//! a start pose within the software limits) and steps of cycles, each with commands from four
//! clients and bus faults. The commands are of every kind of `CommandKind::ALL`, each as
//! likely, with valid and invalid arguments drawn by [`Cmd::of_kind`] (a `match` over the kind,
//! so a new command does not compile until its arguments are drawn), and samples that do not
//! decode.
//! `mcm_dst::fuzz_input::run_script` runs them through the world and checks every cycle with
//! the run's invariants; a broken one panics with its message (the crash libFuzzer keeps).
//!
//! The fuzz target `fuzz_targets/world_steps.rs` feeds it libFuzzer's bytes: `cargo +nightly fuzz
//! run --features libfuzzer world_steps -- -max_total_time=120` (`docs/testing.md`,
//! "Deterministic simulation testing"). A library, so that the workspace's test run compiles it and runs it on a few
//! inputs (`tests.rs`) on stable, without the fuzzer.

use arbitrary::{Arbitrary, Unstructured};
use mcm_dst::clients::Limits as Ranges;
use mcm_dst::faults::PUSH_MAX_NM;
use mcm_dst::faulty_bus::BusFaults;
use mcm_dst::fuzz_input::{Limits, SCRIPT_CLIENTS, Script, ScriptReport, Step, run_script};
use mcm_dst::rng::Rng;
use mcm_dst::run::config;
use mcm_shared::NUM_AXES;
use mcm_shared::command::{
    Axis, Calibrate, CartesianFrame, Direction, IdentifyPayload, MoveAll, MoveAxis, MoveLinear,
    Pvt, PvtChunk, PvtPoint, Request, SetCartesianVelocity, SetTool, SetTorques, SetVelocities,
    SimCommand, TorqueControl, VelocityControl, Which,
};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::CommandKind;
use mcm_shared::ranges::Arg;
use mcm_shared::sample::{COMMAND_ARGS, CommandSample, PVT_POINTS_PER_COMMAND};
use mcm_shared::tool::{MAX_MASS_KG, Tcp, Tool};

/// Cycles of one input at most (100 simulated s at 200 Hz), so that each input is quick.
const MAX_CYCLES: u64 = 20_000;
/// Cycles of one step at most.
const MAX_STEP_CYCLES: u8 = 200;
/// Kind numbers of raw samples: from 0 (no kind) to six beyond the last known.
const RAW_KINDS: u32 = CommandKind::ALL[CommandKind::ALL.len() - 1].to_wire() + 7;
/// The chances per frame a bus fault may have: the fault schedule's (`dst/src/faults.rs`),
/// which the checker's lag allowances were set for.
const BUS_CHANCES: [f64; 3] = [0.001, 0.01, 0.1];

/// One fuzz input: a robot and the steps it is driven through.
#[derive(Debug, Arbitrary)]
pub struct Input {
    /// Draws the robot as a seed's run does ([`config`]).
    seed: u64,
    /// Start angles, each a fraction (of 255) of its axis's software range, instead of the
    /// seed's.
    start: Option<[u8; NUM_AXES]>,
    steps: Vec<StepIn>,
}

#[derive(Debug, Arbitrary)]
struct StepIn {
    /// 1 to [`MAX_STEP_CYCLES`] cycles.
    cycles: u8,
    commands: Vec<(u8, Cmd)>,
    bus: Option<BusIn>,
}

/// A number: inside its field's range (or up to a tenth of the range beyond either end), or
/// something else.
#[derive(Debug, Clone, Copy, Arbitrary)]
enum Num {
    In(u16),
    Out(Wild),
}

#[derive(Debug, Clone, Copy, Arbitrary)]
enum Wild {
    Raw(f64),
    Nan,
    Inf,
    NegInf,
    Zero,
}

impl Num {
    fn within(self, lo: f64, hi: f64) -> f64 {
        match self {
            Num::In(x) => lo + (hi - lo) * (f64::from(x) / f64::from(u16::MAX) * 1.2 - 0.1),
            Num::Out(w) => w.value(),
        }
    }

    /// [`Num::within`] the argument table's fixed range of `arg`.
    fn within_range_of(self, arg: Arg) -> f64 {
        let (lo, hi) = arg.fixed_bounds();
        self.within(lo, hi)
    }
}

impl Wild {
    fn value(self) -> f64 {
        match self {
            Wild::Raw(x) => x,
            Wild::Nan => f64::NAN,
            Wild::Inf => f64::INFINITY,
            Wild::NegInf => f64::NEG_INFINITY,
            Wild::Zero => 0.0,
        }
    }
}

#[derive(Debug, Clone, Copy, Arbitrary)]
enum WhichIn {
    All,
    Elbow,
    Wrist,
    Axis(u8),
}

/// A push's torque: within what the checker allows for (the fault schedule's pushes, up to
/// [`PUSH_MAX_NM`]), or one the decoding refuses (not finite, or beyond its 1000 Nm).
#[derive(Debug, Clone, Copy, Arbitrary)]
enum TorqueIn {
    Push(i8),
    Refused(Wild),
}

impl TorqueIn {
    fn value(self) -> f64 {
        match self {
            TorqueIn::Push(x) => PUSH_MAX_NM * f64::from(x) / 128.0,
            TorqueIn::Refused(w) => match w.value() {
                x if x.is_finite() => 2000.0_f64.copysign(x),
                x => x,
            },
        }
    }
}

#[derive(Debug, Clone, Copy, Arbitrary)]
struct SimIn {
    emergency_stop: Option<bool>,
    disconnect_axis: Option<u8>,
    reconnect_axis: Option<u8>,
    block_axis: Option<u8>,
    unblock_axis: Option<u8>,
    external_torques: Option<[TorqueIn; NUM_AXES]>,
    power_cycle: bool,
}

/// One command: a kind of `CommandKind::ALL` with its arguments, or a raw sample.
#[derive(Debug, Clone)]
enum Cmd {
    Status,
    Hold,
    Info,
    Calibrate {
        which: WhichIn,
        elbow_negative: bool,
        wrist_negative: bool,
        force_mechanical_stop: bool,
    },
    Release,
    TorqueControl {
        timeout_s: Option<Num>,
        gravity_compensation: bool,
    },
    Pvt {
        dt_s: Num,
    },
    MoveAxis {
        axis: u8,
        target: Num,
        velocity_factor: Num,
    },
    MoveAll {
        targets: [Num; NUM_AXES],
        velocity_factor: Num,
    },
    /// A chunk of one point and up to three more.
    PvtPoints {
        first: PointIn,
        more: Vec<PointIn>,
        last: bool,
    },
    SetTorques([Num; NUM_AXES]),
    Sim(SimIn),
    TakeControl,
    ReleaseControl,
    ClientGone,
    VelocityControl {
        timeout_s: Option<Num>,
    },
    SetVelocities([Num; NUM_AXES]),
    /// `set_tool`: the TCP's position and turn about the flange's z axis, the mass, the centre
    /// of mass and the principal moments of inertia.
    SetTool {
        tcp: [Num; 3],
        turn: Num,
        mass: Num,
        center_of_mass: [Num; 3],
        moments: [Num; 3],
    },
    /// `identify_payload`, with or without `apply`.
    IdentifyPayload {
        apply: bool,
    },
    /// `set_cartesian_velocity`: the linear and angular velocity, in the tool frame or not.
    SetCartesianVelocity {
        linear: [Num; 3],
        angular: [Num; 3],
        tool: bool,
    },
    /// `move_linear`: the TCP's target as an offset from a point in front of the arm, an
    /// optional turn about z, speed and acceleration.
    MoveLinear {
        offset: [Num; 3],
        turn: Option<Num>,
        velocity: Option<Num>,
        acceleration: Option<Num>,
    },
    /// A sample of any kind number, flags and arguments (most do not decode).
    Raw {
        kind: u8,
        flags: u32,
        args: Vec<(u8, Wild)>,
    },
}

/// A PVT point: six positions and six velocities.
type PointIn = ([Num; NUM_AXES], [Num; NUM_AXES]);

impl<'a> Arbitrary<'a> for Cmd {
    /// A kind of `CommandKind::ALL` or a raw sample, each as likely; then its arguments.
    fn arbitrary(u: &mut Unstructured<'a>) -> arbitrary::Result<Cmd> {
        match CommandKind::ALL.get(u.choose_index(CommandKind::ALL.len() + 1)?) {
            Some(kind) => Cmd::of_kind(*kind, u),
            None => Ok(Cmd::Raw {
                kind: u.arbitrary()?,
                flags: u.arbitrary()?,
                args: u.arbitrary()?,
            }),
        }
    }
}

impl Cmd {
    /// A command of `kind`, its arguments from `u`.
    fn of_kind(kind: CommandKind, u: &mut Unstructured<'_>) -> arbitrary::Result<Cmd> {
        Ok(match kind {
            CommandKind::Status => Cmd::Status,
            CommandKind::Hold => Cmd::Hold,
            CommandKind::Info => Cmd::Info,
            CommandKind::Calibrate => Cmd::Calibrate {
                which: u.arbitrary()?,
                elbow_negative: u.arbitrary()?,
                wrist_negative: u.arbitrary()?,
                force_mechanical_stop: u.arbitrary()?,
            },
            CommandKind::Release => Cmd::Release,
            CommandKind::TorqueControl => Cmd::TorqueControl {
                timeout_s: u.arbitrary()?,
                gravity_compensation: u.arbitrary()?,
            },
            CommandKind::Pvt => Cmd::Pvt {
                dt_s: u.arbitrary()?,
            },
            CommandKind::MoveAxis => Cmd::MoveAxis {
                axis: u.arbitrary()?,
                target: u.arbitrary()?,
                velocity_factor: u.arbitrary()?,
            },
            CommandKind::MoveAll => Cmd::MoveAll {
                targets: u.arbitrary()?,
                velocity_factor: u.arbitrary()?,
            },
            CommandKind::PvtPoints => Cmd::PvtPoints {
                first: u.arbitrary()?,
                more: u.arbitrary()?,
                last: u.arbitrary()?,
            },
            CommandKind::SetTorques => Cmd::SetTorques(u.arbitrary()?),
            CommandKind::Sim => Cmd::Sim(u.arbitrary()?),
            CommandKind::TakeControl => Cmd::TakeControl,
            CommandKind::ReleaseControl => Cmd::ReleaseControl,
            CommandKind::ClientGone => Cmd::ClientGone,
            CommandKind::VelocityControl => Cmd::VelocityControl {
                timeout_s: u.arbitrary()?,
            },
            CommandKind::SetVelocities => Cmd::SetVelocities(u.arbitrary()?),
            CommandKind::SetTool => Cmd::SetTool {
                tcp: u.arbitrary()?,
                turn: u.arbitrary()?,
                mass: u.arbitrary()?,
                center_of_mass: u.arbitrary()?,
                moments: u.arbitrary()?,
            },
            CommandKind::IdentifyPayload => Cmd::IdentifyPayload {
                apply: u.arbitrary()?,
            },
            CommandKind::SetCartesianVelocity => Cmd::SetCartesianVelocity {
                linear: u.arbitrary()?,
                angular: u.arbitrary()?,
                tool: u.arbitrary()?,
            },
            CommandKind::MoveLinear => Cmd::MoveLinear {
                offset: u.arbitrary()?,
                turn: u.arbitrary()?,
                velocity: u.arbitrary()?,
                acceleration: u.arbitrary()?,
            },
        })
    }
}

#[derive(Debug, Clone, Copy, Arbitrary)]
struct BusIn {
    lose_tx: Option<u8>,
    lose_rx: Option<u8>,
    corrupt_rx: Option<u8>,
    duplicate_rx: Option<u8>,
    delay_rx: Option<u8>,
    lose_heartbeats_of: Option<u8>,
    sync_stuck: bool,
    rebooting: Option<u8>,
}

fn axis(a: u8) -> Axis {
    Axis::from_index(usize::from(a) % NUM_AXES).expect("below NUM_AXES")
}

fn chance(c: Option<u8>) -> f64 {
    c.map_or(0.0, |i| BUS_CHANCES[usize::from(i) % BUS_CHANCES.len()])
}

impl BusIn {
    fn faults(self, cfg: &RobotConfig) -> BusFaults {
        BusFaults {
            lose_tx: chance(self.lose_tx),
            lose_rx: chance(self.lose_rx),
            corrupt_rx: chance(self.corrupt_rx),
            duplicate_rx: chance(self.duplicate_rx),
            delay_rx: chance(self.delay_rx),
            lose_heartbeats_of: self
                .lose_heartbeats_of
                .map(|a| cfg.axes[axis(a).index()].node_id),
            sync_stuck: self.sync_stuck,
            rebooting: self.rebooting.map(|a| axis(a).index()),
        }
    }
}

fn direction(negative: bool) -> Direction {
    if negative {
        Direction::Negative
    } else {
        Direction::Positive
    }
}

fn timeout(t: Option<Num>) -> Option<f64> {
    t.map(|n| n.within(0.0, 2.0))
}

impl Cmd {
    /// The sample sent (the script stamps its ids).
    fn sample(&self, r: &Ranges) -> CommandSample {
        let six = |v: &[Num; NUM_AXES], lo: &[f64; NUM_AXES], hi: &[f64; NUM_AXES]| {
            core::array::from_fn(|i| v[i].within(lo[i], hi[i]))
        };
        let neg = |a: &[f64; NUM_AXES]| a.map(|x| -x);
        let request = match self {
            Cmd::Status => Request::Status,
            Cmd::Hold => Request::Hold,
            Cmd::Info => Request::Info,
            Cmd::Calibrate {
                which,
                elbow_negative,
                wrist_negative,
                force_mechanical_stop,
            } => Request::Calibrate(Calibrate {
                which: match which {
                    WhichIn::All => Which::All,
                    WhichIn::Elbow => Which::Elbow,
                    WhichIn::Wrist => Which::Wrist,
                    WhichIn::Axis(a) => Which::Axis(axis(*a)),
                },
                elbow_direction: direction(*elbow_negative),
                wrist_direction: direction(*wrist_negative),
                force_mechanical_stop: *force_mechanical_stop,
            }),
            Cmd::Release => Request::Release,
            Cmd::TorqueControl {
                timeout_s,
                gravity_compensation,
            } => Request::TorqueControl(TorqueControl {
                timeout_s: timeout(*timeout_s),
                gravity_compensation: *gravity_compensation,
            }),
            Cmd::Pvt { dt_s } => Request::Pvt(Pvt {
                dt_s: dt_s.within(0.0, Pvt::MAX_DT_S),
            }),
            Cmd::MoveAxis {
                axis: a,
                target,
                velocity_factor,
            } => {
                let a = axis(*a);
                let i = a.index();
                Request::MoveAxis(MoveAxis {
                    axis: a,
                    target_deg: target.within(r.min_deg[i], r.max_deg[i]),
                    velocity_factor: velocity_factor.within(0.0, 1.0),
                })
            }
            Cmd::MoveAll {
                targets,
                velocity_factor,
            } => Request::MoveAll(MoveAll {
                targets_deg: six(targets, &r.min_deg, &r.max_deg),
                velocity_factor: velocity_factor.within(0.0, 1.0),
            }),
            Cmd::PvtPoints { first, more, last } => {
                let points: Vec<PvtPoint> = core::iter::once(first)
                    .chain(more)
                    .take(PVT_POINTS_PER_COMMAND)
                    .map(|(p, v)| PvtPoint {
                        position_deg: six(p, &r.min_deg, &r.max_deg),
                        velocity_deg_s: six(v, &neg(&r.max_velocity), &r.max_velocity),
                    })
                    .collect();
                Request::PvtPoints(PvtChunk::new(&points, *last).expect("1 to 4 points"))
            }
            Cmd::SetTorques(t) => Request::SetTorques(SetTorques {
                torques_nm: six(t, &neg(&r.max_torque), &r.max_torque),
            }),
            Cmd::Sim(s) => Request::Sim(SimCommand {
                emergency_stop: s.emergency_stop,
                disconnect_axis: s.disconnect_axis.map(axis),
                reconnect_axis: s.reconnect_axis.map(axis),
                block_axis: s.block_axis.map(axis),
                unblock_axis: s.unblock_axis.map(axis),
                external_torques_nm: s.external_torques.map(|t| t.map(TorqueIn::value)),
                power_cycle: s.power_cycle,
                // The true load changes only the simulated arm's physics; a field more in
                // `SimIn` would give every kept input another meaning.
                true_tool: None,
            }),
            Cmd::TakeControl => Request::TakeControl,
            Cmd::ReleaseControl => Request::ReleaseControl,
            Cmd::ClientGone => Request::ClientGone,
            Cmd::VelocityControl { timeout_s } => Request::VelocityControl(VelocityControl {
                timeout_s: timeout(*timeout_s),
            }),
            Cmd::SetVelocities(v) => Request::SetVelocities(SetVelocities {
                velocities_deg_s: six(v, &neg(&r.max_velocity), &r.max_velocity),
            }),
            Cmd::SetTool {
                tcp,
                turn,
                mass,
                center_of_mass,
                moments,
            } => {
                let near = |v: &[Num; 3]| v.map(|x| x.within(-0.3, 0.3));
                let half_turn = turn.within(-1.6, 1.6);
                let tcp = Tcp {
                    position: near(tcp),
                    orientation: [0.0, 0.0, half_turn.sin(), half_turn.cos()],
                };
                let [ixx, iyy, izz] = moments.map(|x| x.within(0.0, 0.05));
                let inertia = Some([ixx, iyy, izz, 0.0, 0.0, 0.0]);
                let m = mass.within(0.0, MAX_MASS_KG);
                // A tool its checks refuse is no request: those values reach the core in raw
                // samples.
                let tool = Tool::new(tcp, m, near(center_of_mass), inertia).unwrap_or(Tool::NONE);
                Request::SetTool(SetTool { tool })
            }
            Cmd::IdentifyPayload { apply } => {
                Request::IdentifyPayload(IdentifyPayload { apply: *apply })
            }
            Cmd::SetCartesianVelocity {
                linear,
                angular,
                tool,
            } => Request::SetCartesianVelocity(SetCartesianVelocity {
                linear_m_s: linear.map(|x| x.within_range_of(Arg::Linear)),
                angular_deg_s: angular.map(|x| x.within_range_of(Arg::Angular)),
                frame: if *tool {
                    CartesianFrame::Tool
                } else {
                    CartesianFrame::Base
                },
            }),
            Cmd::MoveLinear {
                offset,
                turn,
                velocity,
                acceleration,
            } => {
                // Up to 2 m from a point in front of the arm: near lines and unreachable ones.
                let [x, y, z] = offset.map(|v| v.within(-1.0, 1.0));
                Request::MoveLinear(MoveLinear {
                    position: [0.4 + x, y, 0.4 + z],
                    orientation: turn.map(|t| {
                        let h = t.within(-1.6, 1.6);
                        [0.0, 0.0, h.sin(), h.cos()]
                    }),
                    velocity: velocity.map(|v| v.within_range_of(Arg::LinearVelocity)),
                    acceleration: acceleration.map(|a| a.within_range_of(Arg::LinearAcceleration)),
                })
            }
            Cmd::Raw { kind, flags, args } => return raw(*kind, *flags, args),
        };
        request.encode()
    }
}

/// A raw sample; one that decodes as a `sim` push harder than the checker allows for
/// ([`PUSH_MAX_NM`]) has its torques clamped, as a push beyond that is outside what the
/// invariants' stop penetration was set for.
fn raw(kind: u8, flags: u32, args: &[(u8, Wild)]) -> CommandSample {
    let mut s = CommandSample {
        kind: u32::from(kind) % RAW_KINDS,
        flags,
        ..CommandSample::default()
    };
    for (i, w) in args {
        s.args[usize::from(*i) % COMMAND_ARGS] = w.value();
    }
    if let Ok(Request::Sim(mut cmd)) = Request::decode(&s)
        && let Some(t) = cmd.external_torques_nm.as_mut()
        && t.iter().any(|x| x.abs() > PUSH_MAX_NM)
    {
        for x in t.iter_mut() {
            *x = x.clamp(-PUSH_MAX_NM, PUSH_MAX_NM);
        }
        return Request::Sim(cmd).encode();
    }
    s
}

fn script(input: &Input) -> Script {
    let mut cfg = config(&mut Rng::new(input.seed));
    if let Some(start) = input.start {
        for ((q, a), f) in cfg
            .sim
            .initial_position_deg
            .iter_mut()
            .zip(&cfg.axes)
            .zip(start)
        {
            *q = a.min_deg + (a.max_deg - a.min_deg) * f64::from(f) / 255.0;
        }
    }
    let ranges = Ranges::of(&cfg);
    let steps = input
        .steps
        .iter()
        .map(|s| Step {
            cycles: u32::from(s.cycles % MAX_STEP_CYCLES) + 1,
            commands: s
                .commands
                .iter()
                .map(|(client, c)| (usize::from(*client) % SCRIPT_CLIENTS, c.sample(&ranges)))
                .collect(),
            bus: s.bus.map(|b| b.faults(&cfg)),
        })
        .collect();
    Script {
        cfg,
        bus_seed: input.seed.rotate_left(32),
        steps,
    }
}

/// Run `input` through the world, checking every cycle; panics with the first broken invariant
/// (the crash libFuzzer keeps). Returns what the run did.
pub fn run(input: &Input) -> ScriptReport {
    let limits = Limits {
        max_cycles: MAX_CYCLES,
        // The sanitizer and the coverage counters make the cycle's work several times slower
        // than the builds its budget is for.
        cpu_budget: false,
    };
    run_script(&script(input), limits).unwrap_or_else(|v| panic!("invariant broken: {v}"))
}

#[cfg(test)]
mod tests;
