//! Both transports against the real simulated MCM (the `mcm` launcher of this workspace, as the
//! test command built it, started with a unique instance on free ports): ownership between
//! shared-memory clients and its release on drop, events kept apart from results, safety
//! errors on both transports, the control loop's clean ends, VELOCITY_CONTROL on both.

#[path = "../../tests/common/built.rs"]
#[allow(dead_code)]
mod built;

use mcm_client::Mode;
use mcm_client::launch::SimulatedMcm;
use mcm_client::shm::{ControlEnd, ControlOutput, RequestError, ShmClient, ShmEvent, WaitError};
use mcm_client::tcp::{Error, ErrorKind, Event, TcpClient, TorqueOptions, VelocityOptions};
use mcm_shared::command::{Axis, Calibrate, SimCommand, TorqueControl, VelocityControl, Which};
use mcm_shared::mode::RejectCode;
use mcm_shared::reply::Reason;
use std::path::PathBuf;
use std::process::Stdio;
use std::time::{Duration, Instant};

const WAIT: Duration = Duration::from_secs(20);

/// The workspace's `mcm` launcher (the root package's binary), as the test command built it for
/// the root package's own tests (`built`, shared with the root package's tests).
fn mcm_binary() -> PathBuf {
    built::Executable {
        name: "mcm",
        kind: "bin",
        test: false,
        manifest: "../Cargo.toml",
    }
    .path()
}

fn start(tag: &str) -> SimulatedMcm {
    let instance = format!("cl{}-{tag}", std::process::id());
    SimulatedMcm::start(&mcm_binary(), &instance, &[], Stdio::inherit(), WAIT).unwrap()
}

fn calibrate(c: &mut ShmClient) {
    c.hold().unwrap();
    c.calibrate(Calibrate {
        which: Which::All,
        elbow_direction: Default::default(),
        wrist_direction: Default::default(),
        force_mechanical_stop: false,
    })
    .unwrap();
}

#[test]
fn shared_memory_clients_obey_ownership_and_release_it_on_drop() {
    let mcm = start("own");
    let mut a = ShmClient::connect(&mcm.instance).unwrap();
    let mut b = ShmClient::connect(&mcm.instance).unwrap();
    assert_ne!(a.client_id(), b.client_id());
    assert_eq!(a.client_id() >> 32, u64::from(std::process::id()));

    // States come once each, in order.
    let s1 = a.wait_state().unwrap();
    let s2 = a.wait_state().unwrap();
    assert!(s2.seq > s1.seq);
    assert_eq!(a.info().unwrap().num_axes, 6);

    a.take_control().unwrap();
    assert_eq!(a.latest().owner_client_id, a.client_id());
    let e = b.take_control().unwrap_err();
    assert_eq!(
        e.reason(),
        Some(&Reason::NotOwner {
            owner: a.client_id()
        }),
        "{e}"
    );
    assert!(
        e.to_string()
            .starts_with("take_control refused: another client"),
        "{e}"
    );
    b.hold().expect("hold is open to every client");
    // A motion command of B is refused too, with the MCM's words.
    let e = b.release().unwrap_err();
    assert!(matches!(e, RequestError::Refused { .. }), "{e}");

    // A goes away: its drop says `client_gone`, and B may take control.
    let a_id = a.client_id();
    drop(a);
    b.wait_until("control released", WAIT, |s| s.owner_client_id != a_id)
        .unwrap();
    b.take_control().unwrap();
    b.release_control().unwrap();
    assert_eq!(b.latest().owner_client_id, 0);

    // A state that does not come is a typed timeout.
    drop(mcm);
    let deadline = Instant::now() + WAIT;
    let e = loop {
        match b.wait_state_timeout(Duration::from_millis(300)) {
            Err(e) => break e,
            Ok(_) => assert!(Instant::now() < deadline, "the core kept publishing"),
        }
    };
    assert!(matches!(e, WaitError::Timeout { .. }), "{e}");
}

#[test]
fn events_results_and_the_control_loops_ends_on_both_transports() {
    let mcm = start("ev");
    let mut shm = ShmClient::connect(&mcm.instance).unwrap();
    let mut tcp = TcpClient::connect(&mcm.json.to_string()).unwrap();

    // Refusals carry the command, the words and the code.
    tcp.hold().unwrap();
    let e = tcp.move_axis(1, 10.0, 0.5).unwrap_err();
    let m = e.mcm().unwrap_or_else(|| panic!("{e}"));
    assert_eq!(
        (m.command.as_str(), m.kind),
        ("move_axis", ErrorKind::Refused)
    );
    assert!(m.code.is_some(), "{m:?}");
    let e = tcp.move_axis(9, 10.0, 0.5).unwrap_err();
    assert!(
        matches!(&e, Error::Mcm(m) if m.kind == ErrorKind::Invalid),
        "{e}"
    );
    // The refused move_axis took control (the first motion command does): give it up.
    tcp.release_control().unwrap();

    // The control loop runs only in TORQUE_CONTROL or PVT.
    let e = shm.control(|_| ControlOutput::Finish).unwrap_err();
    assert!(
        matches!(*e.end, ControlEnd::NotControlling(Mode::Hold)),
        "{e}"
    );

    calibrate(&mut shm);
    shm.release_control().unwrap();

    // TCP torque session: every cycle's state as an event; a refused set_torques as an event;
    // the timeout's fall back to HOLD as a last status.
    let info = tcp.info().unwrap();
    tcp.torque_control(TorqueOptions {
        timeout_s: Some(0.2),
        dt_status_s: Some(info.cycle_time),
        gravity_compensation: true,
    })
    .unwrap();
    let mut ticks = 0;
    let mut refused = None;
    let mut left = None;
    let deadline = Instant::now() + WAIT;
    while left.is_none() && Instant::now() < deadline {
        match tcp.next_event(Duration::from_secs(2)).unwrap() {
            Some(Event::Status(s)) if s.mode == Mode::TorqueControl => {
                ticks += 1;
                if ticks <= 20 {
                    let big = if ticks == 10 { 1e4 } else { 0.0 };
                    tcp.set_torques([big, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
                }
            }
            Some(Event::Status(s)) => left = Some(s.mode),
            Some(Event::CommandError(e)) => refused = Some(e),
            other => panic!("unexpected {other:?}"),
        }
    }
    assert!(ticks >= 20, "{ticks} ticks");
    let refused = refused.expect("the refused set_torques");
    assert_eq!(refused.command, "set_torques");
    assert_eq!(left, Some(Mode::Hold), "the timeout's fall back");
    tcp.release_control().unwrap();

    // The shared-memory loop ends cleanly when someone else sends `hold`.
    shm.torque_control(TorqueControl {
        timeout_s: None,
        gravity_compensation: true,
    })
    .unwrap();
    let mut n = 0;
    let e = shm
        .control(|_| {
            n += 1;
            if n == 20 {
                tcp.hold().unwrap();
            }
            ControlOutput::Torques([0.0; 6])
        })
        .unwrap_err();
    assert!(
        matches!(
            *e.end,
            ControlEnd::ModeLeft {
                from: Mode::TorqueControl,
                to: Mode::Hold
            }
        ),
        "{e}"
    );
    assert!(e.summary.cycles >= 20 && e.summary.sent >= 20, "{e}");

    // A safety error reaches both.
    tcp.sim(SimCommand {
        disconnect_axis: Axis::new(2),
        ..Default::default()
    })
    .unwrap();
    shm.wait_until("the trip", WAIT, |s| s.mode == Mode::Error.to_wire())
        .unwrap();
    let ev = std::iter::from_fn(|| shm.next_event()).find_map(|e| match e {
        ShmEvent::SafetyError(e) => Some(e),
        _ => None,
    });
    assert_eq!(
        ev.map(|e| e.reason.code()),
        Some(RejectCode::DriveDisconnected)
    );
    let deadline = Instant::now() + WAIT;
    loop {
        match tcp.next_event(Duration::from_secs(2)).unwrap() {
            Some(Event::SafetyError { check, axis, .. }) => {
                assert_eq!(
                    (check, axis),
                    (Some(RejectCode::DriveDisconnected), Some(2))
                );
                break;
            }
            Some(_) => {}
            None => panic!("no safety error over TCP"),
        }
        assert!(Instant::now() < deadline);
    }
}

#[test]
fn velocity_control_moves_an_axis_towards_its_velocity_on_both_transports() {
    let mcm = start("vel");
    let mut shm = ShmClient::connect(&mcm.instance).unwrap();
    let mut tcp = TcpClient::connect(&mcm.json.to_string()).unwrap();
    calibrate(&mut shm);
    shm.release_control().unwrap();

    // TCP: a tick every cycle; axis 1 asked for 10 deg/s on every tick until its measured
    // velocity is past 8 deg/s; one set beyond the maximum is refused as an event; `hold`.
    let info = tcp.info().unwrap();
    let s = tcp
        .velocity_control(VelocityOptions {
            timeout_s: Some(0.5),
            dt_status_s: Some(info.cycle_time),
        })
        .unwrap();
    assert_eq!(s.mode, Mode::VelocityControl);
    let start_pos = s.axis_states.position[0];
    tcp.set_velocities([0.0, 0.0, 0.0, 0.0, 0.0, 1e4]).unwrap();
    let (mut fast, mut refused) = (None, None);
    let deadline = Instant::now() + WAIT;
    while (fast.is_none() || refused.is_none()) && Instant::now() < deadline {
        match tcp.next_event(Duration::from_secs(2)).unwrap() {
            Some(Event::Status(s)) if s.mode == Mode::VelocityControl => {
                if s.axis_states.velocity[0] > 8.0 {
                    fast.get_or_insert(s);
                }
                tcp.set_velocities([10.0, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
            }
            Some(Event::CommandError(e)) => refused = Some(e),
            other => panic!("unexpected {other:?}"),
        }
    }
    let fast = fast.expect("axis 1 faster than 8 deg/s");
    assert!(fast.axis_states.velocity[0] < 10.5, "{fast:?}");
    assert!(fast.axis_states.position[0] > start_pos, "{fast:?}");
    let refused = refused.expect("the refused set_velocities");
    assert_eq!(
        (refused.command.as_str(), refused.kind),
        ("set_velocities", ErrorKind::Invalid),
        "{refused:?}"
    );
    assert_eq!(tcp.hold().unwrap().mode, Mode::Hold);
    tcp.release_control().unwrap();

    // Shared memory: the control loop answers every state with -10 deg/s on axis 2 until its
    // velocity is below -8 deg/s, then finishes; the mode is left as it was, `hold` ends it.
    shm.velocity_control(VelocityControl {
        timeout_s: Some(0.5),
    })
    .unwrap();
    let mut reached = None;
    let summary = shm
        .control(|s| {
            if s.velocity[1] < -8.0 {
                reached = Some(s.velocity[1]);
                return ControlOutput::Finish;
            }
            ControlOutput::Velocities([0.0, -10.0, 0.0, 0.0, 0.0, 0.0])
        })
        .unwrap();
    let v = reached.expect("axis 2 reached -8 deg/s");
    assert!(v > -10.5, "{v}");
    assert!(summary.sent > 10, "{summary}");
    assert_eq!(shm.latest().mode, Mode::VelocityControl.to_wire());
    shm.hold().unwrap();
    shm.wait_until("HOLD and at rest", WAIT, |s| {
        s.mode == Mode::Hold.to_wire() && s.velocity[1].abs() < 0.01
    })
    .unwrap();
}

/// A signal that interrupts the wait for the next state (a handled signal here; a stop and
/// continue alike) is no error: the wait goes on for the time left.
#[test]
fn an_interrupted_wait_for_the_state_goes_on() {
    extern "C" fn nothing(_: libc::c_int) {}
    let mcm = start("eintr");
    // SAFETY: a handler that does nothing, installed without SA_RESTART so that the waiting
    // thread's blocking call returns EINTR; sigaction's struct is zeroed, then filled.
    unsafe {
        let mut act: libc::sigaction = std::mem::zeroed();
        act.sa_sigaction = nothing as extern "C" fn(libc::c_int) as usize;
        libc::sigemptyset(&mut act.sa_mask);
        assert_eq!(
            libc::sigaction(libc::SIGUSR1, &act, std::ptr::null_mut()),
            0
        );
    }
    let instance = mcm.instance.clone();
    let (tid_tx, tid) = std::sync::mpsc::channel();
    let waiter = std::thread::spawn(move || {
        let mut c = ShmClient::connect(&instance).expect("connect");
        // SAFETY: pthread_self has no preconditions.
        tid_tx
            .send(unsafe { libc::pthread_self() })
            .expect("the test waits");
        (0..20)
            .map(|_| c.wait_state_timeout(Duration::from_secs(2)))
            .find_map(Result::err)
    });
    let tid = tid.recv().expect("the waiting thread's id");
    while !waiter.is_finished() {
        // SAFETY: the thread is not joined yet, so its id is valid; SIGUSR1 is handled.
        unsafe { libc::pthread_kill(tid, libc::SIGUSR1) };
        std::thread::sleep(Duration::from_millis(1));
    }
    assert_eq!(waiter.join().expect("the waiter"), None::<WaitError>);
}
