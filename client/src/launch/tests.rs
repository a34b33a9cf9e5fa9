use super::*;
use mcm_shared::ready::GatewayReady;

fn ready() -> McmReady {
    McmReady {
        robot: "simulated P-Rob2".into(),
        instance: "b1".into(),
        gateway: GatewayReady {
            json: "127.0.0.1:4000".parse().unwrap(),
            hmi: "127.0.0.1:4001".parse().unwrap(),
            web: None,
            zmq: None,
        },
        rt_pid: 12,
        gateway_pid: 13,
    }
}

/// A channel holding `lines`, its sender kept open (as while the launcher runs) or dropped.
fn stdout(lines: &[String], open: bool) -> (mpsc::Receiver<String>, Option<mpsc::Sender<String>>) {
    let (tx, rx) = mpsc::channel();
    for l in lines {
        tx.send(l.clone()).unwrap();
    }
    (rx, open.then_some(tx))
}

#[test]
fn the_ready_line_is_read_typed_after_the_other_lines() {
    let (rx, _tx) = stdout(&["mcm: starting".into(), ready().to_string()], true);
    let got = wait_ready(&rx, Path::new("mcm"), Duration::ZERO).unwrap();
    assert_eq!(got, ready());
    assert_eq!((got.gateway.json.port(), got.gateway_pid), (4000, 13));
}

#[test]
fn a_ready_line_without_a_field_is_refused_naming_it() {
    let line = ready().to_string().replace(" gateway_pid=13", "");
    let (rx, _tx) = stdout(&[line], true);
    let e = wait_ready(&rx, Path::new("mcm"), Duration::ZERO).unwrap_err();
    assert!(
        matches!(
            &e,
            LaunchError::ReadyLine {
                source: ReadyError::Missing {
                    key: "gateway_pid",
                    ..
                },
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("`gateway_pid=`"), "{e}");
}

#[test]
fn no_ready_line_in_time_or_before_the_launcher_stops_is_an_error() {
    let (rx, _tx) = stdout(&["mcm: starting".into()], true);
    let e = wait_ready(&rx, Path::new("mcm"), Duration::ZERO).unwrap_err();
    assert!(matches!(e, LaunchError::NotReady { .. }), "{e:?}");
    let (rx, _) = stdout(&["mcm: starting".into()], false);
    let e = wait_ready(&rx, Path::new("mcm"), Duration::from_secs(60)).unwrap_err();
    assert!(matches!(e, LaunchError::Exited { .. }), "{e:?}");
}

#[test]
fn a_line_is_found_by_its_prefix_and_its_absence_names_the_prefix() {
    let (rx, _tx) = stdout(
        &["mcm: starting".into(), "mcm: gateway restarted".into()],
        true,
    );
    let got = wait_line(&rx, Path::new("mcm"), "mcm: gateway", Duration::ZERO).unwrap();
    assert_eq!(got, "mcm: gateway restarted");
    let e = wait_line(&rx, Path::new("mcm"), "mcm: stopped", Duration::ZERO).unwrap_err();
    assert!(
        matches!(&e, LaunchError::NoLine { prefix, .. } if prefix == "mcm: stopped"),
        "{e:?}"
    );
    assert!(e.to_string().contains("\"mcm: stopped\""), "{e}");
}
