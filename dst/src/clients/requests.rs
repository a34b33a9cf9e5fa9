//! The command kinds of a run and who sends each: the clients draw every kind of
//! `CommandKind::ALL` but those another sender has, each with its arguments drawn here. Both are
//! a `match` over `CommandKind`, so a new command does not compile until it says who sends it
//! and how its arguments are drawn, and from then on the clients draw it.

use super::{Client, Limits, calibrate, move_all, move_axis};
use crate::rng::Rng;
use mcm_shared::command::{
    CartesianFrame, IdentifyPayload, MoveLinear, Pvt, Request, SetCartesianVelocity, SetTool,
    SetTorques, SetVelocities, TorqueControl, VelocityControl,
};
use mcm_shared::mode::CommandKind;
use mcm_shared::ranges::Arg;
use mcm_shared::sample::StateSample;
use mcm_shared::tool::{MAX_MASS_KG, Tcp, Tool};

/// Who sends a command kind in a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sender {
    /// The clients, among their random draws ([`draw`]).
    Clients,
    /// The fault injector ([`crate::faults`]), never a client.
    FaultInjector,
    /// A client as it disconnects ([`Client::gone`]).
    Disconnecting,
}

impl Sender {
    /// Who sends `kind`.
    pub const fn of(kind: CommandKind) -> Sender {
        match kind {
            CommandKind::Status
            | CommandKind::Hold
            | CommandKind::Info
            | CommandKind::Calibrate
            | CommandKind::Release
            | CommandKind::TorqueControl
            | CommandKind::Pvt
            | CommandKind::MoveAxis
            | CommandKind::MoveAll
            | CommandKind::PvtPoints
            | CommandKind::SetTorques
            | CommandKind::TakeControl
            | CommandKind::ReleaseControl
            | CommandKind::VelocityControl
            | CommandKind::SetVelocities
            | CommandKind::SetTool
            | CommandKind::IdentifyPayload
            | CommandKind::SetCartesianVelocity
            | CommandKind::MoveLinear => Sender::Clients,
            CommandKind::Sim => Sender::FaultInjector,
            CommandKind::ClientGone => Sender::Disconnecting,
        }
    }
}

/// The kinds the clients draw, in the order of `CommandKind::ALL`.
pub fn drawn_kinds() -> impl Iterator<Item = CommandKind> {
    CommandKind::ALL
        .iter()
        .copied()
        .filter(|k| Sender::of(*k) == Sender::Clients)
}

/// What a random draw sends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Draw {
    Kind(CommandKind),
    /// A sample that may not decode (`Client::garbage`).
    Garbage,
}

/// Draws besides one per kind of [`drawn_kinds`]: one more `status` (the read a real client
/// sends most), and two garbage samples.
const EXTRA_STATUS: usize = 1;
const GARBAGE: usize = 2;

/// One random draw: a kind of [`drawn_kinds`], or garbage.
pub fn draw(rng: &mut Rng) -> Draw {
    let kinds = drawn_kinds().count();
    let i = rng.below((kinds + EXTRA_STATUS + GARBAGE) as u64) as usize;
    match drawn_kinds().nth(i) {
        Some(kind) => Draw::Kind(kind),
        None if i < kinds + EXTRA_STATUS => Draw::Kind(CommandKind::Status),
        None => Draw::Garbage,
    }
}

impl Client {
    /// A request of `kind`, its arguments drawn wide (some refused); `None` for a kind that
    /// another [`Sender`] sends.
    pub(super) fn random_request(
        &mut self,
        kind: CommandKind,
        s: &StateSample,
        lim: &Limits,
        rng: &mut Rng,
    ) -> Option<Request> {
        Some(match kind {
            CommandKind::Status => Request::Status,
            CommandKind::Hold => Request::Hold,
            CommandKind::Info => Request::Info,
            CommandKind::Calibrate => Request::Calibrate(calibrate(rng)),
            CommandKind::Release => Request::Release,
            CommandKind::TorqueControl => Request::TorqueControl(TorqueControl {
                timeout_s: rng.pick(&[None, Some(0.01), Some(1.0)]),
                gravity_compensation: rng.chance(0.5),
            }),
            CommandKind::Pvt => Request::Pvt(Pvt {
                dt_s: rng.pick(&[0.0, 0.001, 0.005, 0.1, 1.0, 2.0]),
            }),
            CommandKind::MoveAxis => {
                let mut m = move_axis(lim, rng);
                m.target_deg += rng.pick(&[0.0, 0.0, 200.0, -200.0]);
                m.velocity_factor = rng.pick(&[m.velocity_factor, 0.0, 1.0, 1.5]);
                Request::MoveAxis(m)
            }
            CommandKind::MoveAll => Request::MoveAll(move_all(lim, rng)),
            CommandKind::PvtPoints => Request::PvtPoints(self.pvt_chunk(s, rng)),
            CommandKind::SetTorques => Request::SetTorques(SetTorques {
                torques_nm: core::array::from_fn(|_| rng.range(-20.0, 20.0)),
            }),
            CommandKind::TakeControl => Request::TakeControl,
            CommandKind::ReleaseControl => Request::ReleaseControl,
            CommandKind::VelocityControl => Request::VelocityControl(VelocityControl {
                timeout_s: rng.pick(&[None, Some(0.01), Some(2.0)]),
            }),
            CommandKind::SetVelocities => Request::SetVelocities(SetVelocities {
                velocities_deg_s: core::array::from_fn(|i| {
                    rng.range(-1.2, 1.2) * lim.max_velocity[i]
                }),
            }),
            CommandKind::SetTool => Request::SetTool(SetTool {
                tool: random_tool(rng),
            }),
            CommandKind::IdentifyPayload => Request::IdentifyPayload(IdentifyPayload {
                apply: rng.chance(0.5),
            }),
            // Up to 1.2 times each component's range (a few refused), in either frame.
            CommandKind::SetCartesianVelocity => {
                Request::SetCartesianVelocity(SetCartesianVelocity {
                    linear_m_s: core::array::from_fn(|_| beyond(rng, Arg::Linear)),
                    angular_deg_s: core::array::from_fn(|_| beyond(rng, Arg::Angular)),
                    frame: rng.pick(&CartesianFrame::ALL),
                })
            }
            CommandKind::MoveLinear => Request::MoveLinear(move_linear(s, rng)),
            CommandKind::Sim | CommandKind::ClientGone => return None,
        })
    }
}

/// A straight line from where the TCP is (the state's `cartesian`): mostly a few centimetres
/// (planned and run), sometimes a metre or two (refused `unreachable` or `out_of_range`), some
/// with a turn about z, speed and acceleration.
fn move_linear(s: &StateSample, rng: &mut Rng) -> MoveLinear {
    let reach = rng.pick(&[0.05, 0.05, 0.15, 2.0]);
    let here = s.cartesian.position;
    let turn = rng.range(-0.5, 0.5);
    MoveLinear {
        position: core::array::from_fn(|i| here[i] + rng.range(-reach, reach)),
        orientation: rng.chance(0.3).then(|| [0.0, 0.0, turn.sin(), turn.cos()]),
        velocity: rng.chance(0.5).then(|| rng.range(0.01, 1.0)),
        acceleration: rng.chance(0.5).then(|| rng.range(0.1, 10.0)),
    }
}

/// A tool within its checks (a tool that is not allowed does not make a `Request`; garbage
/// samples send such values): up to the heaviest, its centre of mass and TCP within 10 cm of
/// the flange, the TCP turned about the flange's z axis.
fn random_tool(rng: &mut Rng) -> Tool {
    let near = |rng: &mut Rng| -> [f64; 3] { core::array::from_fn(|_| rng.range(-0.1, 0.1)) };
    let half_turn = rng.range(-1.5, 1.5);
    let tcp = Tcp {
        position: near(rng),
        orientation: [0.0, 0.0, half_turn.sin(), half_turn.cos()],
    };
    let mass = rng.range(0.0, MAX_MASS_KG);
    let com = near(rng);
    Tool::new(tcp, mass, com, None).unwrap_or(Tool::NONE)
}

/// A value up to 1.2 times the argument table's fixed range of `arg` (a few refused).
fn beyond(rng: &mut Rng, arg: Arg) -> f64 {
    let (lo, hi) = arg.fixed_bounds();
    rng.range(1.2 * lo, 1.2 * hi)
}
