use super::*;

fn listen(args: &[&str]) -> ListenArgs {
    let mut all = vec!["mcm-gateway"];
    all.extend_from_slice(args);
    Cli::try_parse_from(all).expect("valid arguments").listen
}

#[test]
fn zmq_options_switch_the_interface_on_and_survive_the_launcher() {
    let mut cfg = mcm_shared::config::ZmqConfig::default();
    listen(&[]).apply_zmq(&mut cfg).unwrap();
    assert!(!cfg.enabled, "off unless asked for");

    let l = listen(&["--zmq-publish", "tcp://0.0.0.0:7000"]);
    l.apply_zmq(&mut cfg).unwrap();
    assert!(cfg.enabled, "an endpoint switches it on");
    assert_eq!(cfg.publish, "tcp://0.0.0.0:7000");
    assert_eq!(cfg.router, "tcp://127.0.0.1:18012");

    let l = listen(&["--zmq", "--zmq-router", "tcp://127.0.0.1:*"]);
    let passed: Vec<String> = l
        .to_args()
        .iter()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    let passed: Vec<&str> = passed.iter().map(String::as_str).collect();
    assert_eq!(listen(&passed), l, "the launcher passes them on unchanged");

    let bad = listen(&["--zmq-router", "localhost:1"]).apply_zmq(&mut cfg);
    let msg = bad.unwrap_err().to_string();
    assert!(
        msg.contains("`gateway.zmq.router` = \"localhost:1\""),
        "{msg}"
    );
}
