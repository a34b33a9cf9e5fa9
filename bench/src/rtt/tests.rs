use super::*;

#[test]
fn the_time_after_the_answering_cycle_comes_from_the_status_time() {
    use mcm_shared::protocol::results::Status;
    let state = mcm_shared::sample::StateSample {
        t_ns: 10_001_500_000,
        ..Default::default()
    };
    let v = Answer::Status(Box::new(Status::from_state(&state, false).unwrap()));
    let d = after_cycle(&v, 10.0035).unwrap();
    assert!((d.as_secs_f64() - 0.002).abs() < 1e-9, "{d:?}");
    assert_eq!(after_cycle(&Answer::ok(), 1.0), None);
    // A clock read before the stamp (cannot happen on one clock) counts as zero.
    assert_eq!(after_cycle(&v, 10.0), Some(Duration::ZERO));
}

#[test]
fn a_batch_is_one_json_line_of_n_points() {
    let b = pvt_batch(3, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    assert!(!b.contains('\n'));
    let v: serde_json::Value = serde_json::from_str(&b).unwrap();
    assert_eq!(v["command"], "pvt_points");
    let pts = v["arguments"]["points"].as_array().unwrap();
    assert_eq!(pts.len(), 3);
    assert_eq!(pts[2]["position"][5], 6);
    // The gateway closes a connection whose command exceeds 64 KiB.
    let full = pvt_batch(1000, [-123.4, 95.6, -150.2, 17.0, -12.0, 9.9]);
    assert!(full.len() < 64 * 1024, "{} bytes", full.len());
}
