//! The gateway and the real-time core word a value out of range the same way: every numeric
//! argument of every command (the table of `shared/src/ranges.rs`) is tried below, at and above
//! each bound, once through the gateway's parser (`Command::from_json`) and once as a raw
//! request sample straight into the core (decoding and the controller's checks, the simulated
//! robot in virtual time, no processes), worded by `Generic::reply_error` (the gateway's words). Both must
//! accept the same values and refuse the others with the same text. Arguments only the
//! gateway reads (`dt_status`, `duration`) are checked against the table's own words.

use mcm_rt_core::sim_edge::SimCycle;
use mcm_shared::command::{
    Axis, Calibrate, CartesianFrame, Direction, MoveAll, MoveAxis, MoveLinear, Pvt, Request,
    SetCartesianVelocity, SetTorques, SetVelocities, SimCommand, TorqueControl, VelocityControl,
    Which,
};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, Mode};
use mcm_shared::protocol::Command;
use mcm_shared::protocol::results::Generic;
use mcm_shared::ranges::{ARGS, Arg};
use mcm_shared::reply::{Outcome, Response};
use mcm_shared::sample::CommandSample;
use mcm_sim::SimBus;

/// The simulated robot in virtual time, one client.
struct Robot {
    cycle: SimCycle,
    k: u64,
    period: u64,
    next_id: u64,
}

impl Robot {
    fn new(cfg: &RobotConfig) -> Robot {
        let mut r = Robot {
            cycle: SimCycle::new(cfg, SimBus::new(cfg)).expect("the simulated robot starts"),
            k: 0,
            period: cfg.cycle_period_ns(),
            next_id: 1,
        };
        r.run(400);
        r
    }

    fn step(&mut self, commands: &[CommandSample]) -> Vec<mcm_shared::sample::Reply> {
        self.cycle.run(self.k * self.period, commands);
        self.k += 1;
        self.cycle.replies().to_vec()
    }

    fn run(&mut self, cycles: u64) {
        for _ in 0..cycles {
            self.step(&[]);
        }
    }

    fn mode(&self) -> Mode {
        Mode::try_from(self.cycle.state().mode).expect("a known mode")
    }

    /// Send a raw sample and wait (bounded, in cycles) for its answer.
    fn send(&mut self, mut s: CommandSample, max_cycles: u64) -> Outcome {
        s.client_id = 7 << 32 | 1;
        s.request_id = self.next_id;
        self.next_id += 1;
        let mut replies = self.step(&[s]);
        for _ in 0..max_cycles {
            if let Some(r) = replies.iter().find(|r| r.request_id == s.request_id) {
                return Response::decode(r).expect("a well-formed reply").outcome;
            }
            replies = self.step(&[]);
        }
        panic!("no reply to {s:?} within {max_cycles} cycles");
    }

    fn ok(&mut self, req: Request, max_cycles: u64) {
        let outcome = self.send(req.encode(), max_cycles);
        assert!(matches!(outcome, Outcome::Done(_)), "{req:?}: {outcome:?}");
    }

    /// Bring the robot to `mode` (HOLD, PVT, TORQUE_CONTROL or VELOCITY_CONTROL), at rest.
    fn enter(&mut self, mode: Mode) {
        if self.mode() != Mode::Hold {
            self.ok(Request::Hold, 400);
            // A controlled stop ends within 2 s of robot time.
            self.run(400);
        }
        match mode {
            Mode::Pvt => self.ok(Request::Pvt(Pvt { dt_s: 0.01 }), 5),
            Mode::TorqueControl => self.ok(
                Request::TorqueControl(TorqueControl {
                    timeout_s: None,
                    gravity_compensation: true,
                }),
                5,
            ),
            Mode::VelocityControl => self.ok(
                Request::VelocityControl(VelocityControl { timeout_s: None }),
                5,
            ),
            _ => {}
        }
    }
}

/// One argument of one command: the JSON command holding `x`, the raw sample holding `x`,
/// the mode the core must be in to check it (`None`: any mode, the simulator's own commands),
/// and the element index of a per-axis array.
struct Case {
    command: &'static str,
    arg: Arg,
    axis0: Option<usize>,
    mode: Option<Mode>,
    json: fn(f64) -> String,
    sample: fn(f64) -> CommandSample,
}

fn six_with(i: usize, x: f64) -> [f64; 6] {
    let mut v = [0.0; 6];
    v[i] = x;
    v
}

fn json6(i: usize, x: f64) -> String {
    let v: Vec<String> = six_with(i, x).iter().map(|v| format!("{v:?}")).collect();
    format!("[{}]", v.join(","))
}

fn move_axis(axis: u8, target_deg: f64, velocity_factor: f64) -> CommandSample {
    Request::MoveAxis(MoveAxis {
        axis: Axis::new(axis).unwrap(),
        target_deg,
        velocity_factor,
    })
    .encode()
}

fn cases() -> Vec<Case> {
    vec![
        Case {
            command: "move_axis",
            arg: Arg::AxisIndex,
            axis0: None,
            mode: Some(Mode::Pvt),
            json: |x| {
                format!(
                    r#"{{"command":"move_axis","arguments":{{"axis_index":{x:?},"target_position":0.5}}}}"#
                )
            },
            sample: |x| {
                let mut s = move_axis(1, 0.5, 0.33333);
                s.args[0] = x;
                s
            },
        },
        Case {
            command: "move_axis",
            arg: Arg::TargetPosition,
            axis0: Some(1),
            mode: Some(Mode::Pvt),
            json: |x| {
                format!(
                    r#"{{"command":"move_axis","arguments":{{"axis_index":2,"target_position":{x:?}}}}}"#
                )
            },
            sample: |x| move_axis(2, x, 0.33333),
        },
        Case {
            command: "move_axis",
            arg: Arg::VelocityFactor,
            axis0: None,
            mode: Some(Mode::Pvt),
            json: |x| {
                format!(
                    r#"{{"command":"move_axis","arguments":{{"axis_index":1,"target_position":0.5,"velocity_factor":{x:?}}}}}"#
                )
            },
            sample: |x| move_axis(1, 0.5, x),
        },
        Case {
            command: "move_all",
            arg: Arg::TargetPositions,
            axis0: Some(0),
            mode: Some(Mode::Pvt),
            json: |x| {
                format!(
                    r#"{{"command":"move_all","arguments":{{"target_positions":{}}}}}"#,
                    json6(0, x)
                )
            },
            sample: |x| {
                Request::MoveAll(MoveAll {
                    targets_deg: six_with(0, x),
                    velocity_factor: 0.33333,
                })
                .encode()
            },
        },
        Case {
            command: "move_all",
            arg: Arg::TargetPositions,
            axis0: Some(4),
            mode: Some(Mode::Pvt),
            json: |x| {
                format!(
                    r#"{{"command":"move_all","arguments":{{"target_positions":{}}}}}"#,
                    json6(4, x)
                )
            },
            sample: |x| {
                Request::MoveAll(MoveAll {
                    targets_deg: six_with(4, x),
                    velocity_factor: 0.33333,
                })
                .encode()
            },
        },
        Case {
            command: "move_all",
            arg: Arg::VelocityFactor,
            axis0: None,
            mode: Some(Mode::Pvt),
            json: |x| {
                format!(
                    r#"{{"command":"move_all","arguments":{{"target_positions":[0.5,0,0,0,0,0],"velocity_factor":{x:?}}}}}"#
                )
            },
            sample: |x| {
                Request::MoveAll(MoveAll {
                    targets_deg: six_with(0, 0.5),
                    velocity_factor: x,
                })
                .encode()
            },
        },
        Case {
            command: "pvt",
            arg: Arg::Dt,
            axis0: None,
            mode: Some(Mode::Hold),
            json: |x| format!(r#"{{"command":"pvt","arguments":{{"dt":{x:?}}}}}"#),
            sample: |x| Request::Pvt(Pvt { dt_s: x }).encode(),
        },
        Case {
            command: "torque_control",
            arg: Arg::Timeout,
            axis0: None,
            mode: Some(Mode::Hold),
            json: |x| format!(r#"{{"command":"torque_control","arguments":{{"timeout":{x:?}}}}}"#),
            sample: |x| {
                let mut s = Request::TorqueControl(TorqueControl {
                    timeout_s: Some(1.0),
                    gravity_compensation: true,
                })
                .encode();
                s.args[0] = x;
                s
            },
        },
        Case {
            command: "set_torques",
            arg: Arg::Torques,
            axis0: Some(2),
            mode: Some(Mode::TorqueControl),
            json: |x| {
                format!(
                    r#"{{"command":"set_torques","arguments":{{"torques":{}}}}}"#,
                    json6(2, x)
                )
            },
            sample: |x| {
                Request::SetTorques(SetTorques {
                    torques_nm: six_with(2, x),
                })
                .encode()
            },
        },
        Case {
            command: "velocity_control",
            arg: Arg::Timeout,
            axis0: None,
            mode: Some(Mode::Hold),
            json: |x| {
                format!(r#"{{"command":"velocity_control","arguments":{{"timeout":{x:?}}}}}"#)
            },
            sample: |x| {
                let mut s = Request::VelocityControl(VelocityControl {
                    timeout_s: Some(1.0),
                })
                .encode();
                s.args[0] = x;
                s
            },
        },
        Case {
            command: "set_velocities",
            arg: Arg::Velocities,
            axis0: Some(1),
            mode: Some(Mode::VelocityControl),
            json: |x| {
                format!(
                    r#"{{"command":"set_velocities","arguments":{{"velocities":{}}}}}"#,
                    json6(1, x)
                )
            },
            sample: |x| {
                Request::SetVelocities(SetVelocities {
                    velocities_deg_s: six_with(1, x),
                })
                .encode()
            },
        },
        Case {
            command: "set_velocities",
            arg: Arg::Velocities,
            axis0: Some(5),
            mode: Some(Mode::VelocityControl),
            json: |x| {
                format!(
                    r#"{{"command":"set_velocities","arguments":{{"velocities":{}}}}}"#,
                    json6(5, x)
                )
            },
            sample: |x| {
                Request::SetVelocities(SetVelocities {
                    velocities_deg_s: six_with(5, x),
                })
                .encode()
            },
        },
        Case {
            command: "set_cartesian_velocity",
            arg: Arg::Linear,
            axis0: Some(1),
            mode: Some(Mode::VelocityControl),
            json: |x| {
                format!(
                    r#"{{"command":"set_cartesian_velocity","arguments":{{"linear":[0.0,{x:?},0.0],"angular":[0,0,0]}}}}"#
                )
            },
            sample: |x| {
                Request::SetCartesianVelocity(SetCartesianVelocity {
                    linear_m_s: [0.0, x, 0.0],
                    angular_deg_s: [0.0; 3],
                    frame: CartesianFrame::Base,
                })
                .encode()
            },
        },
        Case {
            command: "set_cartesian_velocity",
            arg: Arg::Angular,
            axis0: Some(2),
            mode: Some(Mode::VelocityControl),
            json: |x| {
                format!(
                    r#"{{"command":"set_cartesian_velocity","arguments":{{"linear":[0,0,0],"angular":[0.0,0.0,{x:?}],"frame":"tool"}}}}"#
                )
            },
            sample: |x| {
                Request::SetCartesianVelocity(SetCartesianVelocity {
                    linear_m_s: [0.0; 3],
                    angular_deg_s: [0.0, 0.0, x],
                    frame: CartesianFrame::Tool,
                })
                .encode()
            },
        },
        // The simulator's commands come last: the torques they try push the arm into ERROR
        // (an overloaded axis then refuses HOLD until it cools), which they do not mind.
        Case {
            command: "sim",
            arg: Arg::ExternalTorques,
            axis0: Some(1),
            mode: None,
            json: |x| {
                format!(
                    r#"{{"command":"sim","arguments":{{"external_torques":{}}}}}"#,
                    json6(1, x)
                )
            },
            sample: |x| {
                Request::Sim(SimCommand {
                    external_torques_nm: Some(six_with(1, x)),
                    ..SimCommand::default()
                })
                .encode()
            },
        },
        Case {
            command: "sim",
            arg: Arg::BlockAxis,
            axis0: None,
            mode: None,
            json: |x| format!(r#"{{"command":"sim","arguments":{{"block_axis":{x:?}}}}}"#),
            sample: |x| {
                let mut s = Request::Sim(SimCommand {
                    block_axis: Axis::new(1),
                    ..SimCommand::default()
                })
                .encode();
                s.args[3] = x;
                s
            },
        },
    ]
}

/// Values below, at and above each bound (and 0 and a subnormal number).
fn values((min, max): (f64, f64)) -> Vec<f64> {
    let step = |b: f64| (b.abs() * 0.01).max(0.001);
    let mut v = vec![
        0.0,
        1e-320,
        -1e-320,
        min,
        max,
        max + step(max),
        max - step(max),
    ];
    if min > -1e300 {
        v.extend([min - step(min), min + step(min)]);
    } else {
        v.push(-1e6);
    }
    v
}

/// A JSON command holding a value.
type JsonOf = fn(f64) -> String;

fn gateway_text(cfg: &RobotConfig, json: &str) -> Option<String> {
    Command::from_json(json, cfg).err().map(|e| e.to_string())
}

#[test]
fn gateway_and_core_accept_and_refuse_the_same_values_in_the_same_words() {
    let cfg = RobotConfig::prob2_default();
    let mut robot = Robot::new(&cfg);
    robot.ok(
        Request::Calibrate(Calibrate {
            which: Which::All,
            elbow_direction: Direction::Positive,
            wrist_direction: Direction::Positive,
            force_mechanical_stop: false,
        }),
        20_000,
    );
    let cases = cases();
    let first_any = cases.iter().position(|c| c.mode.is_none());
    assert!(
        first_any.is_none_or(|f| cases[f..].iter().all(|c| c.mode.is_none())),
        "the cases checked in any mode come after those that need a mode"
    );
    let mut checked = 0;
    for case in cases {
        let bounds = case.arg.bounds(&cfg, case.axis0);
        for x in values(bounds) {
            let json = (case.json)(x);
            let gateway = gateway_text(&cfg, &json);
            if let Some(mode) = case.mode {
                robot.enter(mode);
            }
            let outcome = robot.send((case.sample)(x), 400);
            let core = match &outcome {
                Outcome::Done(_) => None,
                other => {
                    let kind = mcm_shared::protocol::find(case.command).and_then(|d| d.kind);
                    Generic::reply_error(kind.expect("a command of the core"), other).error_message
                }
            };
            assert_eq!(
                gateway, core,
                "{json}: the gateway's and the core's answers differ"
            );
            assert_eq!(
                gateway.is_none(),
                case.arg.accepts(x, bounds),
                "{json}: accepted against the table"
            );
            if let Some(text) = gateway {
                assert!(
                    text.starts_with(&format!("{}: argument \"{}", case.command, case.arg.name())),
                    "{text}"
                );
                assert!(
                    !text.contains("00000000"),
                    "a number that is not readable: {text}"
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 80, "{checked} values checked");
}

#[test]
fn arguments_only_the_gateway_reads_are_refused_in_the_table_s_words() {
    let cfg = RobotConfig::prob2_default();
    // (argument, command, the JSON command holding a value)
    let gateway_only: [(Arg, &str, JsonOf); 3] = [
        (Arg::DtStatus, "torque_control", |x| {
            format!(r#"{{"command":"torque_control","arguments":{{"dt_status":{x:?}}}}}"#)
        }),
        (Arg::DtStatus, "velocity_control", |x| {
            format!(r#"{{"command":"velocity_control","arguments":{{"dt_status":{x:?}}}}}"#)
        }),
        (Arg::Duration, "sleep", |x| {
            format!(r#"{{"command":"sleep","arguments":{{"duration":{x:?}}}}}"#)
        }),
    ];
    for (arg, command, json) in gateway_only {
        let bounds = arg.fixed_bounds();
        for x in values(bounds) {
            let text = gateway_text(&cfg, &json(x));
            let expected = arg
                .check(x, bounds, None)
                .err()
                .map(|e| format!("{command}: {e}"));
            assert_eq!(text, expected, "{}", json(x));
        }
    }
}

/// `move_linear`'s speed and acceleration: the core refuses them as it decodes the sample,
/// before any line is planned (a value the table accepts starts a plan, whose own outcome
/// depends on where the arm is), so the core's words are those of its refusal of the sample.
#[test]
fn move_linear_s_arguments_are_refused_in_the_same_words_by_the_gateway_and_the_core() {
    let cfg = RobotConfig::prob2_default();
    for arg in [Arg::LinearVelocity, Arg::LinearAcceleration] {
        let bounds = arg.fixed_bounds();
        for x in values(bounds) {
            let json = format!(
                r#"{{"command":"move_linear","arguments":{{"position":[0.4,0,0.5],"{}":{x:?}}}}}"#,
                arg.name()
            );
            let given = |a: Arg| (arg == a).then_some(x);
            let request = MoveLinear {
                position: [0.4, 0.0, 0.5],
                orientation: None,
                velocity: given(Arg::LinearVelocity),
                acceleration: given(Arg::LinearAcceleration),
            };
            let gateway = gateway_text(&cfg, &json);
            let sample = Request::MoveLinear(request).encode();
            let core = Request::decode(&sample).err().map(|e| {
                let reply = mcm_shared::reply::refuse_undecodable(&sample, &e);
                let outcome = Response::decode(&reply)
                    .expect("a well-formed reply")
                    .outcome;
                Generic::reply_error(CommandKind::MoveLinear, &outcome)
                    .error_message
                    .expect("words")
            });
            assert_eq!(gateway, core, "{json}");
            assert_eq!(gateway.is_none(), arg.accepts(x, bounds), "{json}");
        }
    }
}

#[test]
fn every_numeric_argument_of_the_table_is_walked() {
    let mut walked: Vec<Arg> = cases().iter().map(|c| c.arg).collect();
    walked.extend([Arg::DtStatus, Arg::Duration]);
    // Walked by `move_linear_s_arguments_are_refused_in_the_same_words_by_the_gateway_and_the_core`.
    walked.extend([Arg::LinearVelocity, Arg::LinearAcceleration]);
    // The sim axes share block_axis's check (one decode function, one table shape).
    walked.extend([Arg::DisconnectAxis, Arg::ReconnectAxis, Arg::UnblockAxis]);
    for spec in ARGS {
        assert!(walked.contains(&spec.arg), "{} is not walked", spec.name);
    }
}
