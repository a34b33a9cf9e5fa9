//! The publication loop over a real libzmq PUB socket and a SUB socket in this test, with
//! channels that play the bridge.

use super::*;
use crate::core_link::lifecycle::Notice;
use mcm_shared::sample::StateSample;
use std::sync::Arc;
use tokio::sync::{broadcast, watch};

/// Longest wait for one message.
const WAIT_MS: i32 = 10_000;

/// The next message on the `error` topic, within [`WAIT_MS`] (states are skipped).
fn next_error(sub: &zmq::Socket) -> Value {
    loop {
        let frames = sub
            .recv_multipart(0)
            .unwrap_or_else(|e| panic!("no message within {WAIT_MS} ms: {e}"));
        assert_eq!(frames.len(), 2, "topic and JSON: {frames:?}");
        match frames[0].as_slice() {
            b"state" => continue,
            b"error" => return serde_json::from_slice(&frames[1]).unwrap(),
            other => panic!("unknown topic {:?}", String::from_utf8_lossy(other)),
        }
    }
}

/// The core is killed just before the gateway stops (the launcher stops it within
/// milliseconds, before the publisher's next look at the core): a subscriber still hears that
/// the core vanished, then that the gateway stops, as a TCP client does.
#[test]
fn on_stop_the_notice_about_the_core_comes_before_the_gateways_own() {
    let zctx = zmq::Context::new();
    let endpoint = format!("inproc://mcm-publish-test-{}", std::process::id());
    let publisher = zctx.socket(zmq::PUB).unwrap();
    publisher.bind(&endpoint).unwrap();
    let sub = zctx.socket(zmq::SUB).unwrap();
    sub.set_rcvtimeo(WAIT_MS).unwrap();
    sub.connect(&endpoint).unwrap();
    sub.set_subscribe(b"").unwrap();

    let (states_tx, states) = broadcast::channel::<Arc<StateSample>>(16);
    let (_errors_tx, errors) = broadcast::channel(16);
    let running = StateSample {
        seq: 7,
        ..StateSample::default()
    };
    let (core_tx, core_rx) = watch::channel(Some(Box::new(running)));
    let (stop, stopped) = oneshot::channel();
    let thread = std::thread::spawn(move || {
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .unwrap();
        rt.block_on(async move {
            let core = CoreWatch::new(core_rx);
            run(Sink::Libzmq(publisher), states, errors, core, stopped).await;
        });
    });

    // A state reaches the subscriber: the loop runs and the subscription is through (a SUB
    // socket misses what is published before it is). Until then, publish it again.
    sub.set_rcvtimeo(50).unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_millis(WAIT_MS as u64);
    let first = loop {
        states_tx.send(Arc::new(running)).unwrap();
        if let Ok(frames) = sub.recv_multipart(0) {
            break frames;
        }
        assert!(std::time::Instant::now() < deadline, "no state published");
    };
    assert_eq!(first[0], b"state");
    sub.set_rcvtimeo(WAIT_MS).unwrap();

    // The core is gone, then at once the gateway stops.
    core_tx.send_replace(None);
    stop.send(()).unwrap();
    let vanished = next_error(&sub);
    assert_eq!(vanished, Notice::RtVanished.result());
    let stopping = next_error(&sub);
    assert_eq!(
        stopping,
        Notice::GatewayStopping.result(),
        "the gateway's own last line comes last"
    );
    thread.join().unwrap();
    assert_eq!(
        sub.poll(zmq::POLLIN, 0).unwrap(),
        0,
        "nothing after the gateway's last line"
    );
}

/// A state this version cannot read as a status (a core of another MCM version) is published
/// as an ERROR on `error`, not as a state without a status on `state`.
#[test]
fn a_state_that_is_no_status_goes_to_the_error_topic() {
    let good = StateSample {
        seq: 7,
        ..StateSample::default()
    };
    let (topic, v) = state_message(&good);
    assert_eq!(topic, "state");
    assert_eq!(v["result_type"], "status", "{v}");
    assert_eq!(v["cycle"], 7, "{v}");
    let other_version = StateSample {
        seq: 8,
        mode: 99,
        ..StateSample::default()
    };
    let (topic, v) = state_message(&other_version);
    assert_eq!(topic, "error", "{v}");
    assert_eq!(v["result_type"], "generic", "{v}");
    assert_eq!(v["error_status"], "ERROR", "{v}");
    assert!(v.get("cycle").is_none(), "{v}");
    let message = v["error_message"].as_str().unwrap_or_default();
    assert!(message.contains("different MCM versions"), "{v}");
}

/// The `state` topic carries the TCP's state once every axis is calibrated, as `status` does,
/// and none before.
#[test]
fn the_state_topic_carries_the_cartesian_state_once_calibrated() {
    use mcm_shared::sample::{STATE_ALL_CALIBRATED, STATE_CARTESIAN, TcpState};
    let mut s = StateSample {
        seq: 9,
        cartesian: TcpState {
            position: [0.3, -0.1, 0.7],
            orientation: [0.0, 0.0, 0.0, 1.0],
            linear_velocity: [0.05, 0.0, 0.0],
            angular_velocity: [0.0, 0.0, -20.0],
        },
        ..StateSample::default()
    };
    let (topic, v) = state_message(&s);
    assert_eq!(topic, "state");
    assert!(v.get("cartesian_state").is_none(), "{v}");
    s.flags = STATE_ALL_CALIBRATED | STATE_CARTESIAN;
    let (topic, v) = state_message(&s);
    assert_eq!(topic, "state");
    assert_eq!(
        v["cartesian_state"],
        serde_json::json!({
            "position": [0.3, -0.1, 0.7],
            "orientation": [0.0, 0.0, 0.0, 1.0],
            "linear_velocity": [0.05, 0.0, 0.0],
            "angular_velocity": [0.0, 0.0, -20.0],
        }),
        "{v}"
    );
    assert_eq!(v["cycle"], 9);
}
