//! The runner's edge allocates nothing in any mode.
//!
//! The edge ([`Edge::cycle`], [`Edge::end`] and [`Edge::signal_state`], what the real-time loop
//! runs each period) over
//! the simulated robot, with real iceoryx2 services of a test-own instance and the flight
//! recorder's writer thread. A client on the test thread talks to it as the gateway does:
//! typed requests ([`Request::encode`], stamped ids) through a publisher connected before the
//! measured window, answers read from the published state ([`Response::decode`]). Only the
//! edge's calls are counted (the cycle thread's work; the client's own allocations are not the
//! cycle's). Cycles run back to back on the real clock without sleeping; the controller's time
//! is k x period.
//!
//! The scenario: boot, hold, calibration of all axes, PVT with `move_all` (re-planned by a second
//! `move_all` while the arm moves), a `pvt_points` batch of many chunks streamed to its end and
//! `move_linear` lines (one from rest, one during a `move_all`: planned and sampled in the cycle),
//! `identify_payload` with `apply`, release, torque control with `set_torques`, velocity control
//! with `set_velocities`, then `set_cartesian_velocity` in the base and the tool frame (the TCP's
//! velocity through the Jacobian every cycle), back to `set_velocities`, and the timeout, a move
//! blocked through the simulator's edge (following-error trip, quick stop,
//! flight-recorder hand-off), more fault injection, and the way back to HOLD. Every command must be
//! answered OK and every mode reached, so the count cannot be zero for lack of work.

use super::Meter;
use crate::common::{node, state_listener, state_reader};
use iceoryx2::port::listener::Listener;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::reader::EntryHandle;
use iceoryx2::prelude::*;
use mcm_rt_core::clock;
use mcm_rt_core::cycle::Cycle;
use mcm_rt_core::edge::Edge;
use mcm_rt_core::flight::{FlightRecorder, FlightWriter};
use mcm_rt_core::ipc::RtIpc;
use mcm_rt_core::sim_edge::SimEdge;
use mcm_shared::command::{
    Axis, Calibrate, CartesianFrame, Direction, IdentifyPayload, MoveAll, MoveAxis, MoveLinear,
    Pvt, PvtChunk, PvtPoint, Request, SetCartesianVelocity, SetTorques, SetVelocities, SimCommand,
    TorqueControl, VelocityControl, Which,
};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{Mode, RejectCode};
use mcm_shared::reply::{Done, Outcome, Response};
use mcm_shared::sample::{
    AXIS_ONLINE, CommandSample, ReplyEntries, STATE_ALL_CALIBRATED, STATE_CARTESIAN,
    STATE_SIMULATED, StateSample, flight_recorder_file, open_reply_entries, read_reply,
};
use mcm_shared::service::{STATE_EVENT_ID, STATE_KEY, ServiceNames};
use mcm_sim::SimBus;

const CLIENT: u64 = 77;

/// A client of the core, as the gateway is one.
struct Client {
    _node: Node<ipc::Service>,
    publisher: Publisher<ipc::Service, CommandSample, ()>,
    state: EntryHandle<ipc::Service, u32, StateSample>,
    replies: ReplyEntries,
    state_event: Listener<ipc::Service>,
}

impl Client {
    fn open(names: &ServiceNames) -> Client {
        let node = node();
        let state_event = state_listener(&node, names);
        let reader = state_reader(&node, names);
        let state = reader.entry::<StateSample>(&STATE_KEY).unwrap();
        let replies = open_reply_entries(&reader).unwrap();
        let publisher = node
            .service_builder(&names.command_service())
            .publish_subscribe::<CommandSample>()
            .open()
            .unwrap()
            .publisher_builder()
            .create()
            .unwrap();
        Client {
            _node: node,
            publisher,
            state,
            replies,
            state_event,
        }
    }
}

/// The edge, its client, and what the scenario saw.
struct Rig {
    edge: Edge<SimBus>,
    writer: Option<FlightWriter>,
    client: Client,
    meter: Meter,
    names: ServiceNames,
    dir: std::path::PathBuf,
    next_deadline: u64,
    next_request: u64,
    /// Newest reply already looked at.
    reply_seen: u64,
    /// Modes seen in the published state, by wire value.
    modes: [bool; 8],
    answered_ok: u64,
    cycles: u64,
}

impl Rig {
    fn start(cfg: &mut RobotConfig) -> Rig {
        let names = ServiceNames::new(&format!("noalloc-{}", std::process::id())).unwrap();
        let dir = std::env::temp_dir().join(format!("mcm-noalloc-{}", std::process::id()));
        cfg.safety.flight_recorder_dir = dir.to_str().unwrap().to_string();
        let cycle = Box::new(Cycle::new(cfg, SimBus::new(cfg)).unwrap());
        let ipc = RtIpc::create(&names).unwrap();
        let records = (cfg.safety.flight_recorder_seconds * f64::from(cfg.cycle.rate_hz)) as usize;
        let (recorder, writer) =
            FlightRecorder::start(records, &cfg.safety.flight_recorder_dir, names.instance())
                .unwrap();
        let sim = SimEdge::new(|b: &mut SimBus| b as _);
        let mut edge = Edge::new(
            cycle,
            Some(sim),
            ipc,
            recorder,
            cfg.cycle_period_ns(),
            cfg.work_budget_ns(),
            false,
        );
        let client = Client::open(&names);
        let next_deadline = edge.start(clock::now_ns());
        let mut rig = Rig {
            edge,
            writer: Some(writer),
            client,
            meter: Meter::new(),
            names,
            dir,
            next_deadline,
            next_request: 1,
            reply_seen: 0,
            modes: [false; 8],
            answered_ok: 0,
            cycles: 0,
        };
        // The publisher joined: the first receive connects it and allocates (once, at
        // start-up: see `mcm_rt_core::ipc`). That the meter sees it shows that it sees what
        // the edge allocates; the count starts again after it.
        rig.cycle();
        assert!(
            rig.meter.allocs > 0,
            "connecting the publisher allocates inside the edge, and the meter sees it"
        );
        (rig.meter.allocs, rig.meter.bytes, rig.cycles) = (0, 0, 0);
        rig
    }

    /// One cycle of the edge, counted; the state the client reads afterwards.
    fn cycle(&mut self) -> StateSample {
        let wake = clock::now_ns().max(self.next_deadline);
        let edge = &mut self.edge;
        self.next_deadline = self.meter.measure(|| {
            edge.cycle(wake);
            let next = edge.end(clock::now_ns());
            edge.signal_state();
            next
        });
        self.cycles += 1;
        let mut woken = 0;
        self.client
            .state_event
            .try_wait(|e| {
                assert_eq!(e.id.as_value(), STATE_EVENT_ID);
                woken += 1;
            })
            .unwrap();
        assert_eq!(woken, 1, "the listener is woken once after each cycle");
        assert_eq!(self.edge.figures().notify_failures, 0);
        let s = *self.client.state.get();
        assert_eq!(&s, self.edge.state(), "the published state is this cycle's");
        self.modes[s.mode as usize] = true;
        s
    }

    fn run(&mut self, cycles: u64) -> StateSample {
        let mut s = self.cycle();
        for _ in 1..cycles {
            s = self.cycle();
        }
        s
    }

    fn run_until(
        &mut self,
        what: &str,
        max: u64,
        done: impl Fn(&StateSample) -> bool,
    ) -> StateSample {
        for _ in 0..max {
            let s = self.cycle();
            if done(&s) {
                return s;
            }
        }
        panic!("{what}: not reached within {max} cycles");
    }

    /// Send `req` through the publisher, as a client does; its request id.
    fn send(&mut self, req: &Request) -> u64 {
        let mut sample = req.encode();
        sample.client_id = CLIENT;
        sample.request_id = self.next_request;
        self.next_request += 1;
        self.client.publisher.send_copy(sample).unwrap();
        sample.request_id
    }

    /// Run until the answer to request `id` is published (at most `max` cycles).
    fn answer(&mut self, id: u64, max: u64) -> Response {
        for _ in 0..max {
            let s = self.cycle();
            for n in self.reply_seen + 1..=s.reply_head {
                let r = read_reply(&self.client.replies, n);
                let r = &r.expect("the reply blocks hold every reply");
                self.reply_seen = n;
                if r.client_id == CLIENT && r.request_id == id {
                    return Response::decode(r).expect("a reply of this version");
                }
            }
        }
        panic!("no answer to request {id} within {max} cycles");
    }

    /// Send `req`; it must be answered OK within `max` cycles.
    fn ok(&mut self, req: Request, max: u64) -> Response {
        let id = self.send(&req);
        let r = self.answer(id, max);
        assert!(
            matches!(r.outcome, Outcome::Done(_)),
            "{req:?} was not answered OK: {r:?}"
        );
        self.answered_ok += 1;
        r
    }

    fn sim(&mut self, cmd: SimCommand) {
        self.ok(Request::Sim(cmd), 5);
    }

    fn at_rest(&mut self) -> StateSample {
        self.run_until("at rest", 4_000, |s| {
            s.velocity.iter().all(|v| v.abs() < 1e-6)
        })
    }
}

fn axis(n: u8) -> Axis {
    Axis::new(n).unwrap()
}

fn max_diff(a: &[f64; 6], b: &[f64; 6]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Boot, hold, calibrate all axes, back in HOLD.
fn calibrate(rig: &mut Rig) {
    rig.run_until("drives online", 2_000, |s| {
        s.axis_flags.iter().all(|f| f & AXIS_ONLINE != 0)
    });
    rig.ok(Request::Hold, 2_000);
    rig.ok(
        Request::Calibrate(Calibrate {
            which: Which::All,
            elbow_direction: Direction::Positive,
            wrist_direction: Direction::Positive,
            force_mechanical_stop: false,
        }),
        20_000,
    );
    let s = rig.cycle();
    assert_ne!(s.flags & STATE_ALL_CALIBRATED, 0, "all axes calibrated");
    assert_eq!(s.mode, Mode::Hold.to_wire());
}

/// PVT: a `move_all`, re-planned from the moving state by a second one, then a batch of many
/// `pvt_points` chunks (a full sine period around the target, ending at rest) streamed to its end.
fn pvt(rig: &mut Rig) {
    rig.ok(Request::Pvt(Pvt { dt_s: 0.01 }), 5);
    let target = [20.0, -30.0, 45.0, 60.0, -40.0, 90.0];
    for velocity_factor in [0.8, 0.5] {
        rig.ok(
            Request::MoveAll(MoveAll {
                targets_deg: target,
                velocity_factor,
            }),
            5,
        );
        // The second one re-plans each axis from its commanded state (online planner).
        let s = rig.run_until("moving", 200, |s| s.velocity.iter().any(|v| v.abs() > 1.0));
        // The TCP's state is composed in the measured cycles too.
        assert_ne!(s.flags & STATE_CARTESIAN, 0, "the TCP's state is published");
        assert!(
            s.cartesian.linear_velocity.iter().any(|v| v.abs() > 1e-3),
            "the TCP moves: {:?}",
            s.cartesian
        );
    }
    let s = rig.run_until("move_all arrived", 4_000, |s| {
        max_diff(&s.sim_true_position, &target) < 0.05 && s.velocity.iter().all(|v| *v == 0.0)
    });
    assert_eq!(s.mode, Mode::Pvt.to_wire());
    // 200 points of 10 ms: 5 deg amplitude, 0.5 Hz, from rest to rest.
    let (amp, w) = (5.0, core::f64::consts::PI);
    let points: Vec<PvtPoint> = (1..=200)
        .map(|k| {
            let t = f64::from(k) * 0.01;
            PvtPoint {
                position_deg: target.map(|p| p + amp * (1.0 - (w * t).cos())),
                velocity_deg_s: [amp * w * (w * t).sin(); 6],
            }
        })
        .collect();
    let chunks: Vec<PvtChunk> = PvtChunk::batch(&points).collect();
    assert_eq!(chunks.len(), 50);
    for chunk in chunks {
        rig.ok(Request::PvtPoints(chunk), 5);
    }
    let s = rig.cycle();
    assert!(s.pvt_queued > 150, "the batch is queued: {}", s.pvt_queued);
    let s = rig.run_until("the stream half way", 300, |s| s.pvt_queued < 100);
    assert!(
        max_diff(&s.commanded_position, &target) > 1.0,
        "the stream moves the arm: {:?}",
        s.commanded_position
    );
    rig.run_until("the stream played to its end", 600, |s| s.pvt_queued == 0);
    let s = rig.at_rest();
    assert!(
        max_diff(&s.sim_true_position, &target) < 0.1,
        "back at the target: {:?}",
        s.sim_true_position
    );
    lines(rig, &target);
}

/// `move_linear` (each line planned in the measured cycle that hands it over: the inline
/// planner), from rest to its end; then one during a `move_all`: the move comes to rest, the
/// line runs back to where the first one started.
fn lines(rig: &mut Rig, target: &[f64; 6]) {
    let line = |position| {
        Request::MoveLinear(MoveLinear {
            position,
            orientation: None,
            velocity: Some(0.2),
            acceleration: None,
        })
    };
    let arrived = |at: [f64; 3]| {
        move |s: &StateSample| {
            let d: f64 = (0..3)
                .map(|i| (s.cartesian.position[i] - at[i]).powi(2))
                .sum();
            d.sqrt() < 1e-6 && s.velocity.iter().all(|v| *v == 0.0)
        }
    };
    let start = rig.cycle().cartesian.position;
    let to = [start[0], start[1] + 0.05, start[2] - 0.03];
    rig.ok(line(to), 5);
    let s = rig.run_until("moving on the line", 20, |s| {
        s.cartesian.linear_velocity.iter().any(|v| v.abs() > 1e-3)
    });
    assert_eq!(s.mode, Mode::Pvt.to_wire());
    rig.run_until("the line's end", 1_000, arrived(to));
    let mut away = *target;
    away[0] += 20.0;
    rig.ok(
        Request::MoveAll(MoveAll {
            targets_deg: away,
            velocity_factor: 0.5,
        }),
        5,
    );
    rig.run_until("the move_all moving", 200, |s| {
        s.velocity.iter().any(|v| v.abs() > 5.0)
    });
    rig.ok(line(start), 400);
    rig.run_until("back on the line's start", 2_000, arrived(start));
}

#[test]
fn the_edge_allocates_nothing_in_any_mode() {
    let mut cfg = RobotConfig::prob2_default();
    let mut rig = Rig::start(&mut cfg);
    calibrate(&mut rig);
    pvt(&mut rig);

    // `identify_payload` in HOLD (its moves, settles and averages, the estimate, `apply`).
    rig.ok(Request::Hold, 5);
    rig.at_rest();
    let identified = rig.ok(
        Request::IdentifyPayload(IdentifyPayload { apply: true }),
        8_000,
    );
    assert!(
        matches!(identified.outcome, Outcome::Done(Done::Payload(_))),
        "{identified:?}"
    );

    // RELEASE, with a hand pushing on a joint.
    rig.ok(Request::Release, 5);
    let mut push = [0.0; 6];
    push[0] = 3.0;
    rig.sim(SimCommand {
        external_torques_nm: Some(push),
        ..SimCommand::default()
    });
    rig.run(50);
    rig.sim(SimCommand {
        external_torques_nm: Some([0.0; 6]),
        ..SimCommand::default()
    });
    rig.run(20);

    // TORQUE_CONTROL with set_torques.
    rig.ok(Request::Hold, 5);
    rig.ok(
        Request::TorqueControl(TorqueControl {
            timeout_s: Some(0.5),
            gravity_compensation: true,
        }),
        5,
    );
    for _ in 0..20 {
        rig.ok(
            Request::SetTorques(SetTorques {
                torques_nm: [0.0; 6],
            }),
            5,
        );
        rig.run(3);
    }
    assert_eq!(rig.cycle().mode, Mode::TorqueControl.to_wire());
    rig.ok(Request::Hold, 5);
    rig.run(50);

    // VELOCITY_CONTROL with set_velocities: the ramp, then the timeout's controlled stop.
    rig.ok(
        Request::VelocityControl(VelocityControl {
            timeout_s: Some(0.2),
        }),
        5,
    );
    for _ in 0..20 {
        rig.ok(
            Request::SetVelocities(SetVelocities {
                velocities_deg_s: [5.0, -5.0, 0.0, 0.0, 0.0, 10.0],
            }),
            5,
        );
        rig.run(3);
    }
    // The TCP's velocity, in the base frame and then the tool's: the joint velocities of the
    // twist every cycle, then joint velocities again.
    for frame in CartesianFrame::ALL {
        for _ in 0..20 {
            rig.ok(
                Request::SetCartesianVelocity(SetCartesianVelocity {
                    linear_m_s: [0.03, -0.02, 0.01],
                    angular_deg_s: [0.0, 5.0, -5.0],
                    frame,
                }),
                5,
            );
            rig.run(3);
        }
        let s = rig.cycle();
        assert_eq!(s.mode, Mode::VelocityControl.to_wire());
        assert!(
            s.cartesian.linear_velocity.iter().any(|v| v.abs() > 0.005),
            "the TCP moves in the {} frame: {:?}",
            frame.as_str(),
            s.cartesian
        );
    }
    rig.ok(
        Request::SetVelocities(SetVelocities {
            velocities_deg_s: [0.0, 0.0, 5.0, 0.0, 0.0, 0.0],
        }),
        5,
    );
    assert_eq!(rig.cycle().mode, Mode::VelocityControl.to_wire());
    rig.run_until("the timeout's HOLD", 200, |s| {
        s.mode == Mode::Hold.to_wire()
    });
    rig.run(50);

    // A move blocked through the simulator's edge: following-error trip, quick stop, the
    // flight recorder's history handed to its writer.
    let errors_before = rig.cycle().last_error.seq;
    rig.ok(Request::Pvt(Pvt { dt_s: 0.01 }), 5);
    rig.ok(
        Request::MoveAxis(MoveAxis {
            axis: axis(1),
            target_deg: 80.0,
            velocity_factor: 0.5,
        }),
        5,
    );
    rig.run_until("axis 1 moving", 1_000, |s| s.velocity[0] > 10.0);
    rig.sim(SimCommand {
        block_axis: Some(axis(1)),
        ..SimCommand::default()
    });
    let tripped = rig.run_until("the following-error trip", 1_000, |s| {
        s.mode == Mode::Error.to_wire()
    });
    assert_eq!(
        tripped.last_error.seq,
        errors_before + 1,
        "one error record"
    );
    assert_eq!(
        tripped.last_error.code,
        RejectCode::FollowingError.to_wire()
    );
    assert_ne!(tripped.last_error.unix_ns, 0, "the edge stamped the error");
    let error = tripped.last_error;

    // More fault injection through the simulator's edge, then back to HOLD.
    rig.sim(SimCommand {
        unblock_axis: Some(axis(1)),
        ..SimCommand::default()
    });
    rig.sim(SimCommand {
        disconnect_axis: Some(axis(6)),
        ..SimCommand::default()
    });
    rig.run(100);
    rig.sim(SimCommand {
        reconnect_axis: Some(axis(6)),
        ..SimCommand::default()
    });
    rig.run_until("drive 6 back online", 2_000, |s| {
        s.axis_flags.iter().all(|f| f & AXIS_ONLINE != 0)
    });
    rig.at_rest();
    let mut refusals = 0;
    loop {
        let id = rig.send(&Request::Hold);
        match rig.answer(id, 2_000).outcome {
            Outcome::Done(_) => break,
            Outcome::Refused(reason) => {
                refusals += 1;
                assert!(refusals < 50, "hold refused again and again: {reason}");
                rig.run(20);
            }
            Outcome::Failed(reason) => panic!("hold failed: {reason}"),
        }
    }
    rig.answered_ok += 1;
    let last = rig.run(20);
    assert_eq!(last.mode, Mode::Hold.to_wire(), "back in HOLD");
    assert_ne!(last.flags & STATE_SIMULATED, 0);

    let (allocs, bytes, cycles) = (rig.meter.allocs, rig.meter.bytes, rig.cycles);
    eprintln!(
        "edge scenario: {cycles} cycles, {} commands answered OK, hold refused {refusals} times after the trip",
        rig.answered_ok
    );
    // The scenario did what it says.
    for mode in Mode::ALL {
        assert!(rig.modes[mode.to_wire() as usize], "mode {mode} reached");
    }
    assert!(rig.answered_ok >= 80, "{} answered OK", rig.answered_ok);
    assert_eq!(last.command_receive_errors, 0);
    // The flight recorder's writer wrote the file of the trip.
    let writer = rig.writer.take().unwrap();
    writer.stop();
    let file = flight_recorder_file(rig.dir.to_str().unwrap(), rig.names.instance(), &error);
    let csv = std::fs::read_to_string(&file).expect("the flight-recorder file of the trip");
    assert!(csv.lines().count() > 100, "{} rows", csv.lines().count());
    let _ = std::fs::remove_dir_all(&rig.dir);
    assert_eq!(
        (allocs, bytes),
        (0, 0),
        "the edge allocated {allocs} times ({bytes} bytes) in {cycles} cycles"
    );
}
