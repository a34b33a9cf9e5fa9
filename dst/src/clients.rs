//! The clients of a run: several at once, each sending random commands of every kind that
//! [`requests::Sender`] gives the clients (all but `sim`, the fault injector's,
//! [`crate::faults`], and `client_gone`, sent when a client disconnects, then a new connection
//! with a new id), valid and invalid, at its own random cadence, taking and losing control,
//! streaming `pvt_points`, `set_torques`, `set_velocities` and `set_cartesian_velocity`, and
//! sending `hold` at random
//! moments; besides, garbage samples of any kind number from 0 to two beyond the last known
//! (those two kinds included), with wild arguments.
//!
//! A client reads the published state as a real one does, and pursues a goal (a mode) most of
//! the time, so that every mode is reached: from HOLD it sends what enters its goal, in the
//! goal it sends what that mode serves. The rest of its commands are drawn from every kind
//! with random arguments, some outside their ranges, some not decodable at all.

use crate::rng::Rng;
use crate::stamp::Stamp;
use mcm_shared::NUM_AXES;
use mcm_shared::command::{
    Axis, Calibrate, CartesianFrame, Direction, MoveAll, MoveAxis, Pvt, PvtChunk, PvtPoint,
    Request, SetCartesianVelocity, SetTorques, SetVelocities, TorqueControl, VelocityControl,
    Which,
};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, Mode};
use mcm_shared::sample::{
    AXIS_CALIBRATED, COMMAND_ARGS, CommandSample, PVT_POINTS_PER_COMMAND, StateSample,
};
use requests::{Draw, draw};

pub mod requests;

/// Kind numbers of garbage samples: from 0 (no kind) to two beyond the last known.
const GARBAGE_KINDS: u64 = CommandKind::ALL[CommandKind::ALL.len() - 1].to_wire() as u64 + 3;

/// Client ids of the random clients start here; the fault injector and the quiet phase's
/// client have their own below.
pub const FIRST_CLIENT_ID: u64 = 100;

/// What a client is after.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Goal {
    Pvt,
    Release,
    Torque,
    Velocity,
    Calibrate,
    Idle,
}

const GOALS: [Goal; 6] = [
    Goal::Pvt,
    Goal::Release,
    Goal::Torque,
    Goal::Velocity,
    Goal::Calibrate,
    Goal::Idle,
];

/// The limits a client draws its arguments within (and sometimes beyond).
#[derive(Debug, Clone)]
pub struct Limits {
    pub min_deg: [f64; NUM_AXES],
    pub max_deg: [f64; NUM_AXES],
    pub max_velocity: [f64; NUM_AXES],
    /// The largest joint torque each motor gives [Nm].
    pub max_torque: [f64; NUM_AXES],
}

impl Limits {
    pub fn of(cfg: &RobotConfig) -> Limits {
        Limits {
            min_deg: core::array::from_fn(|i| cfg.axes[i].min_deg),
            max_deg: core::array::from_fn(|i| cfg.axes[i].max_deg),
            max_velocity: core::array::from_fn(|i| cfg.axes[i].max_velocity_deg_s),
            max_torque: core::array::from_fn(|i| {
                cfg.axes[i].max_current_a * cfg.axes[i].torque_per_amp()
            }),
        }
    }
}

/// One client connection.
#[derive(Debug, Clone)]
pub struct Client {
    stamp: Stamp,
    goal: Goal,
    /// Chance per cycle to send a command.
    cadence: f64,
    /// Chance that a command is drawn at random rather than towards the goal.
    chaos: f64,
    /// Phase of its PVT stream [s].
    phase: f64,
}

impl Client {
    pub fn new(id: u64, rng: &mut Rng) -> Client {
        Client {
            stamp: Stamp::new(id),
            goal: rng.pick(&GOALS),
            cadence: rng.pick(&[0.02, 0.1, 0.3, 0.8]),
            chaos: rng.pick(&[0.05, 0.2, 0.5]),
            phase: 0.0,
        }
    }

    pub fn id(&self) -> u64 {
        self.stamp.client_id
    }

    fn request(&mut self, r: Request) -> CommandSample {
        self.stamp.request(r)
    }

    /// Its `client_gone` (its connection closes).
    pub fn gone(&mut self) -> CommandSample {
        self.request(Request::ClientGone)
    }

    /// This cycle's command of this client, if it sends one; `Gone` when it disconnects.
    pub fn act(&mut self, s: &StateSample, lim: &Limits, rng: &mut Rng) -> Action {
        if rng.chance(0.0005) {
            return Action::Gone(self.gone());
        }
        if rng.chance(0.002) {
            self.goal = rng.pick(&GOALS);
        }
        if !rng.chance(self.cadence) {
            return Action::None;
        }
        if rng.chance(0.01) {
            return Action::Send(self.request(Request::Hold));
        }
        let sent = if rng.chance(self.chaos) {
            self.random(s, lim, rng)
        } else {
            self.towards_goal(s, lim, rng)
        };
        match sent {
            Some(x) => Action::Send(x),
            None => Action::None,
        }
    }

    fn towards_goal(
        &mut self,
        s: &StateSample,
        lim: &Limits,
        rng: &mut Rng,
    ) -> Option<CommandSample> {
        let mode = Mode::try_from(s.mode).unwrap_or(Mode::Off);
        let calibrated = s.axis_flags.iter().all(|f| f & AXIS_CALIBRATED != 0);
        if s.owner_client_id != self.id() && s.owner_client_id != 0 && rng.chance(0.7) {
            return None; // someone else drives: mostly wait
        }
        if s.owner_client_id == 0 && self.goal != Goal::Idle && rng.chance(0.3) {
            return Some(self.request(Request::TakeControl));
        }
        let r = match (mode, self.goal) {
            (_, Goal::Idle) => rng.pick(&[Request::Status, Request::Info, Request::ReleaseControl]),
            (Mode::Off | Mode::Error, _) => Request::Hold,
            (Mode::Hold, Goal::Calibrate) => Request::Calibrate(calibrate(rng)),
            (Mode::Hold, _) if !calibrated => Request::Calibrate(calibrate(rng)),
            (Mode::Hold, Goal::Pvt) => Request::Pvt(Pvt {
                dt_s: rng.pick(&[0.005, 0.01, 0.02, 0.05]),
            }),
            (Mode::Hold, Goal::Release) => Request::Release,
            (Mode::Hold, Goal::Torque) => Request::TorqueControl(TorqueControl {
                timeout_s: rng.pick(&[None, Some(0.05), Some(0.5)]),
                gravity_compensation: rng.chance(0.9),
            }),
            (Mode::Hold, Goal::Velocity) => Request::VelocityControl(VelocityControl {
                timeout_s: rng.pick(&[None, Some(0.05), Some(0.5)]),
            }),
            (Mode::Pvt, _) => match rng.below(4) {
                0 => Request::MoveAxis(move_axis(lim, rng)),
                1 => Request::MoveAll(move_all(lim, rng)),
                _ => Request::PvtPoints(self.pvt_chunk(s, rng)),
            },
            (Mode::TorqueControl, _) => Request::SetTorques(SetTorques {
                torques_nm: core::array::from_fn(|_| rng.range(-3.0, 3.0)),
            }),
            // The TCP's velocity now and then, in either frame.
            (Mode::VelocityControl, _) if rng.chance(0.3) => {
                Request::SetCartesianVelocity(SetCartesianVelocity {
                    linear_m_s: core::array::from_fn(|_| rng.range(-0.1, 0.1)),
                    angular_deg_s: core::array::from_fn(|_| rng.range(-20.0, 20.0)),
                    frame: rng.pick(&CartesianFrame::ALL),
                })
            }
            (Mode::VelocityControl, _) => Request::SetVelocities(SetVelocities {
                velocities_deg_s: core::array::from_fn(|i| {
                    rng.range(-0.5, 0.5) * lim.max_velocity[i]
                }),
            }),
            (Mode::Calibration, _) => Request::Status,
            (Mode::Release, _) => {
                if rng.chance(0.05) {
                    Request::Hold
                } else {
                    Request::Status
                }
            }
        };
        Some(self.request(r))
    }

    /// Up to a full chunk of points around the commanded position, a slow sine.
    fn pvt_chunk(&mut self, s: &StateSample, rng: &mut Rng) -> PvtChunk {
        let n = 1 + rng.below(PVT_POINTS_PER_COMMAND as u64) as usize;
        let amp = rng.range(0.0, 3.0);
        let mut points = [PvtPoint::default(); PVT_POINTS_PER_COMMAND];
        for p in points.iter_mut().take(n) {
            self.phase += 0.02;
            let (sin, cos) = self.phase.sin_cos();
            p.position_deg = core::array::from_fn(|i| s.commanded_position[i] + amp * sin * 0.1);
            p.velocity_deg_s = [amp * cos * 0.1; NUM_AXES];
        }
        PvtChunk::new(&points[..n], rng.chance(0.5)).expect("1..=N points")
    }

    /// Any command, its arguments drawn wide (some refused); or a sample that does not decode.
    fn random(&mut self, s: &StateSample, lim: &Limits, rng: &mut Rng) -> Option<CommandSample> {
        let r = match draw(rng) {
            Draw::Kind(kind) => self.random_request(kind, s, lim, rng)?,
            Draw::Garbage => return Some(self.garbage(rng)),
        };
        Some(self.request(r))
    }

    /// A sample that may not decode: an unknown kind, or a known kind with wild arguments.
    /// Its flags are mostly 0 (the flags every kind allows), so that the decoding gets to the
    /// arguments; a tenth of the samples have random flags, which every kind refuses first.
    fn garbage(&mut self, rng: &mut Rng) -> CommandSample {
        let flags = if rng.chance(0.1) {
            rng.next_u64() as u32
        } else {
            0
        };
        let mut sample = CommandSample {
            kind: rng.below(GARBAGE_KINDS) as u32,
            flags,
            ..CommandSample::default()
        };
        for a in sample
            .args
            .iter_mut()
            .take(1 + rng.below(COMMAND_ARGS as u64) as usize)
        {
            *a = rng.pick(&[f64::NAN, f64::INFINITY, -1e300, 0.0, 1.0, 7.0, -3.5, 1e-9]);
        }
        self.stamp.stamp(sample)
    }
}

/// What a client does this cycle.
#[derive(Debug, Clone, Copy)]
pub enum Action {
    None,
    Send(CommandSample),
    /// It sends `client_gone` and disconnects.
    Gone(CommandSample),
}

fn calibrate(rng: &mut Rng) -> Calibrate {
    let which = match rng.below(4) {
        0 => Which::All,
        1 => Which::Elbow,
        2 => Which::Wrist,
        _ => Which::Axis(axis(rng)),
    };
    let dir = |rng: &mut Rng| rng.pick(&[Direction::Positive, Direction::Negative]);
    Calibrate {
        which,
        elbow_direction: dir(rng),
        wrist_direction: dir(rng),
        force_mechanical_stop: rng.chance(0.3),
    }
}

fn axis(rng: &mut Rng) -> Axis {
    Axis::new(1 + rng.below(NUM_AXES as u64) as u8).expect("1..=6")
}

fn move_axis(lim: &Limits, rng: &mut Rng) -> MoveAxis {
    let a = axis(rng);
    let i = a.index();
    MoveAxis {
        axis: a,
        target_deg: rng.range(lim.min_deg[i], lim.max_deg[i]),
        velocity_factor: rng.pick(&[0.05, 0.2, 0.5, 1.0]),
    }
}

fn move_all(lim: &Limits, rng: &mut Rng) -> MoveAll {
    MoveAll {
        targets_deg: core::array::from_fn(|i| rng.range(lim.min_deg[i], lim.max_deg[i])),
        velocity_factor: rng.pick(&[0.05, 0.2, 0.5, 1.0]),
    }
}

#[cfg(test)]
mod tests;
