//! Every refusal the protocol has carries its `error_code` (`docs/protocol.md`, "Error codes"),
//! end to end with the real processes on the simulated arm: each code a client can provoke
//! from outside is provoked here and its `error_code` checked, with the `command` it answers
//! and its `outcome` (refused, failed, invalid); a safety error's code equal to its `check`, and
//! no spontaneous error naming a command or an outcome. [`where_checked`] decides, for every code of `mcm_shared::error_code` (the compiler
//! refuses a new code until it is decided), whether it is provoked here or, when it cannot be
//! from outside (real hardware, a fault of the gateway, a race with a shutdown, another
//! configuration), which test one level lower checks it; the test fails when what it provoked
//! and what the table says differ.

use crate::common;

use common::{Client, EventClient, Mcm, WAIT, assert_ok};
use mcm_shared::error_code::ErrorCode;
use mcm_shared::protocol::results::ErrorOutcome::{self, Failed, Invalid, Refused};
use serde_json::Value;
use std::collections::BTreeSet;
use std::time::{Duration, Instant};

/// Where a code is checked.
enum Where {
    /// Provoked by [`every_refusal_a_client_can_provoke_carries_its_code`].
    Here,
    /// Not provoked from outside here: the test one level lower that checks it.
    Lower(&'static str),
}

/// Every reason of the core, rendered for a client, with its code and its `check`.
const EVERY_REASON: &str = "shared: protocol::results::tests::every_reason_carries_its_code";
const SERVER: &str = "gateway: transport::server::tests";
const ACCESS: &str =
    "gateway: command::tests::the_access_rules_and_an_absent_core_refuse_with_their_codes";
const BRIDGE: &str =
    "gateway: command::tests::a_request_the_bridge_could_not_complete_has_its_code";

fn where_checked(code: ErrorCode) -> Where {
    use ErrorCode::*;
    match code {
        InvalidJson | InvalidCommand | UnknownCommand | UnknownArgument | MissingArgument
        | InvalidArgument | OutOfRange | Unreachable | WrongMode | NotOwner | NotCalibrated
        | EmergencyStop | DriveDisconnected | Aborted | Busy | PvtPoint | FollowingError
        | LineTooLong | CoreStopping | CoreStopped | GatewayStopping => Where::Here,
        // The simulated arm cannot show these from outside, or not in a bounded time: a drive
        // fault, a joint past its limit or too fast (the planner and the brakes prevent it;
        // `safety::` pushes one with a torque and takes whichever of the three trips), a
        // calibration that finds no stop, a full PVT queue (the gateway refuses a batch that
        // does not fit before the core sees it), a build without a command, a real robot that
        // refuses `sim`, a command in the core's own shutdown (a race with it).
        DriveFault | PositionLimit | VelocityLimit | BrakingDistance | CalibrationFailed
        | QueueFull | NotAvailable | NotSimulated | ShuttingDown => Where::Lower(EVERY_REASON),
        // `identify_payload`'s poses tell the load apart from every pose of the P-Rob2 within
        // reach (condition number at most about 10, limit 15): the estimator's refusal is
        // checked by `mcm-dynamics`' `payload::tests`, its words and code here.
        NotIdentifiable => Where::Lower(EVERY_REASON),
        // Provoked end to end by a test of its own (a motor heated until i2t derates it).
        Overload => Where::Lower(
            "end_to_end: safety::sustained_high_current_derates_the_motor_without_an_error",
        ),
        TooManyConnections | IdleTimeout | LineTimeout | Evicted => Where::Lower(SERVER),
        NetworkRefused | NotAuthenticated | WrongSecret | RemoteSimRefused | CoreUnavailable
        | InternalError => Where::Lower(ACCESS),
        OutcomeUnknown | VersionMismatch => Where::Lower(BRIDGE),
        CoreVanished => Where::Lower(
            "end_to_end: hostile_lifecycle::kill_9_of_mcm_rt_tells_clients_the_core_stopped_before_the_launcher_stops_the_gateway",
        ),
        EventsLost => Where::Lower(
            "gateway: transport::json::connection::tests::lost_events_are_told_with_their_code",
        ),
        TooManyRequests => Where::Lower(
            "gateway: transport::zmq::router::tests::a_full_queue_and_a_full_peer_table_are_told_with_their_codes",
        ),
    }
}

/// The codes seen, and the check of each ERROR.
#[derive(Default)]
struct Seen(BTreeSet<&'static str>);

impl Seen {
    /// `v` is an ERROR of `code`.
    fn check(&mut self, v: &Value, code: ErrorCode) {
        assert_eq!(v["result_type"], "generic", "{v}");
        assert_eq!(v["error_status"], "ERROR", "{v}");
        assert_eq!(v["error_code"], code.as_str(), "{v}");
        self.0.insert(code.as_str());
    }

    /// `v` is an ERROR of `code` that answers `command` (`None`: a line that names no known
    /// command) and ended as `outcome`.
    fn answer(&mut self, v: &Value, code: ErrorCode, command: Option<&str>, outcome: ErrorOutcome) {
        assert_eq!(v.get("command").and_then(Value::as_str), command, "{v}");
        assert_eq!(v["outcome"], outcome.as_str(), "{v}");
        self.check(v, code);
    }

    /// `v` is the core's refusal of `command` (nothing changed), of `code`.
    fn refused(&mut self, v: &Value, code: ErrorCode, command: &str) {
        self.answer(v, code, Some(command), Refused);
    }

    /// `v` is a spontaneous ERROR of `code`: it answers no command.
    fn notice(&mut self, v: &Value, code: ErrorCode) {
        assert!(v.get("command").is_none(), "{v}");
        assert!(v.get("outcome").is_none(), "{v}");
        self.check(v, code);
    }

    /// `v` is a spontaneous safety error of `code`: its `error_code` is its `check`.
    fn trip(&mut self, v: &Value, code: ErrorCode) {
        assert_eq!(v["check"], code.as_str(), "{v}");
        self.notice(v, code);
    }
}

const MOVE_1: &str = r#"{"command":"move_axis","arguments":{"axis_index":1,"target_position":10}}"#;

fn wait_drives_online(c: &mut EventClient) {
    let deadline = Instant::now() + WAIT;
    loop {
        let s = c.request(r#"{"command":"status","arguments":{"detail":true}}"#);
        let online = s["detail"]["drive_online"]
            .as_array()
            .is_some_and(|a| a.iter().all(|x| x == true));
        if online {
            return;
        }
        assert!(Instant::now() < deadline, "drives not online: {s}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// `hold` until it is accepted (refused while a drive still boots after its fault).
fn hold(c: &mut EventClient) {
    let deadline = Instant::now() + WAIT;
    loop {
        let r = c.request(r#"{"command":"hold"}"#);
        if r["result_type"] == "status" {
            return;
        }
        assert!(Instant::now() < deadline, "hold not accepted: {r}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn sim(c: &mut EventClient, arguments: &str) {
    let r = c.request(&format!(r#"{{"command":"sim","arguments":{arguments}}}"#));
    assert_eq!(r["result_type"], "sim", "{r}");
}

#[test]
fn every_refusal_a_client_can_provoke_carries_its_code() {
    let mcm = Mcm::start("error-codes");
    let mut seen = Seen::default();
    let mut a = EventClient::connect(mcm.json);
    let mut b = EventClient::connect(mcm.json);

    // Lines the gateway's parser refuses: `invalid`, naming the command the line names.
    let parser = [
        ("hello", ErrorCode::InvalidJson, None),
        (r#"{"arguments":{}}"#, ErrorCode::InvalidCommand, None),
        (r#"{"command":"stauts"}"#, ErrorCode::UnknownCommand, None),
        (
            r#"{"command":"status","arguments":{"bogus":1}}"#,
            ErrorCode::UnknownArgument,
            Some("status"),
        ),
        (
            r#"{"command":"move_axis","arguments":{"axis_index":1}}"#,
            ErrorCode::MissingArgument,
            Some("move_axis"),
        ),
        (
            r#"{"command":"status","arguments":{"detail":"yes"}}"#,
            ErrorCode::InvalidArgument,
            Some("status"),
        ),
        (
            r#"{"command":"move_axis","arguments":{"axis_index":9,"target_position":0}}"#,
            ErrorCode::OutOfRange,
            Some("move_axis"),
        ),
        (
            r#"{"command":"move_axis","arguments":{"axis_index":1,"target_position":175}}"#,
            ErrorCode::Unreachable,
            Some("move_axis"),
        ),
    ];
    for (line, code, command) in parser {
        let v = a.request(line);
        seen.answer(&v, code, command, Invalid);
    }

    // Control and modes, in OFF: the core refuses.
    wait_drives_online(&mut a);
    assert_ok(&a.request(r#"{"command":"take_control"}"#));
    seen.refused(&b.request(MOVE_1), ErrorCode::NotOwner, "move_axis");
    seen.refused(&a.request(MOVE_1), ErrorCode::WrongMode, "move_axis");
    hold(&mut a);
    let pvt = a.request(r#"{"command":"pvt"}"#);
    seen.refused(&pvt, ErrorCode::NotCalibrated, "pvt");

    // Safety checks: the emergency stop, a drive lost.
    sim(&mut a, r#"{"emergency_stop":true}"#);
    let e = a.wait_event("emergency stop", WAIT);
    seen.trip(&e, ErrorCode::EmergencyStop);
    let held = a.request(r#"{"command":"hold"}"#);
    seen.refused(&held, ErrorCode::EmergencyStop, "hold");
    sim(&mut a, r#"{"emergency_stop":false}"#);
    hold(&mut a);
    sim(&mut a, r#"{"disconnect_axis":2}"#);
    let e = a.wait_event("drive lost", WAIT);
    seen.trip(&e, ErrorCode::DriveDisconnected);
    sim(&mut a, r#"{"reconnect_axis":2}"#);
    wait_drives_online(&mut a);
    hold(&mut a);

    // A calibration superseded by `hold` from another client (once it runs: a `hold` goes out
    // ahead of other commands).
    a.send(r#"{"command":"calibrate"}"#);
    let deadline = Instant::now() + WAIT;
    while b.request(r#"{"command":"status"}"#)["operating_mode"] != "CALIBRATION" {
        assert!(Instant::now() < deadline, "the calibration did not start");
        std::thread::sleep(Duration::from_millis(10));
    }
    assert_eq!(b.request(r#"{"command":"hold"}"#)["result_type"], "status");
    // It ran, then failed: `failed`.
    let aborted = a.result_within(r#"{"command":"calibrate"}"#, WAIT);
    seen.answer(&aborted, ErrorCode::Aborted, Some("calibrate"), Failed);

    // Calibrated, in PVT: a batch during a move, an obstacle in the way of a move.
    hold(&mut a);
    let calibrate = a.request_within(r#"{"command":"calibrate"}"#, Duration::from_secs(600));
    assert_ok(&calibrate);
    assert_eq!(a.request(r#"{"command":"pvt"}"#)["result_type"], "status");
    let too_fast = r#"{"command":"pvt_points","arguments":{"points":[{"position":[0,0,0,0,0,0],"velocity":[0,0,0,0,0,0]},{"position":[1,0,0,0,0,0],"velocity":[96.512,0,0,0,0,0]}]}}"#;
    seen.refused(&a.request(too_fast), ErrorCode::PvtPoint, "pvt_points");
    let long_move = r#"{"command":"move_axis","arguments":{"axis_index":1,"target_position":60,"velocity_factor":0.05}}"#;
    assert_ok(&a.request(long_move));
    let batch = r#"{"command":"pvt_points","arguments":{"points":[{"position":[0,0,0,0,0,0],"velocity":[0,0,0,0,0,0]}]}}"#;
    seen.refused(&a.request(batch), ErrorCode::Busy, "pvt_points");
    sim(&mut a, r#"{"block_axis":1}"#);
    let e = a.wait_event("following error", WAIT);
    seen.trip(&e, ErrorCode::FollowingError);
    sim(&mut a, r#"{"unblock_axis":1}"#);

    // A line longer than the limit closes its connection.
    let mut c = Client::connect(mcm.json);
    c.send_raw(&vec![b'x'; mcm_shared::protocol::MAX_COMMAND_BYTES + 1]);
    seen.answer(&c.recv(), ErrorCode::LineTooLong, None, Invalid);
    assert!(c.closed(), "the connection is closed after a line too long");

    // The MCM stops: its notices, in order, the gateway's last.
    drop(b);
    let status = mcm.stop();
    assert!(status.success(), "{status}");
    let notices: Vec<Value> = a
        .until_closed(WAIT)
        .into_iter()
        .filter(|v| v["error_status"] == "ERROR" && v.get("check").is_none())
        .collect();
    let codes: Vec<&str> = notices
        .iter()
        .map(|v| v["error_code"].as_str().unwrap_or("(none)"))
        .collect();
    assert!(codes.contains(&"core_stopping"), "{notices:?}");
    assert!(
        codes.ends_with(&["core_stopped", "gateway_stopping"]),
        "{notices:?}"
    );
    for v in &notices {
        let code = ErrorCode::from_name(v["error_code"].as_str().unwrap()).unwrap();
        seen.notice(v, code);
    }

    for c in ErrorCode::ALL {
        if let Where::Lower(test) = where_checked(*c) {
            assert!(test.contains("::"), "{c}: `{test}` names no test");
        }
    }
    let here: BTreeSet<&str> = ErrorCode::ALL
        .iter()
        .filter(|c| matches!(where_checked(**c), Where::Here))
        .map(|c| c.as_str())
        .collect();
    assert_eq!(
        seen.0, here,
        "the codes provoked here and the codes `where_checked` says are provoked here differ"
    );
}
