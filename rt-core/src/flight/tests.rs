use super::*;

fn wait_written(w: &FlightWriter, n: u64) {
    let deadline = std::time::Instant::now() + Duration::from_secs(10);
    while w.written() < n {
        assert!(std::time::Instant::now() < deadline, "file not written");
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn writes_the_last_cycles_in_order() {
    let dir = std::env::temp_dir().join(format!("mcm-flight-test-{}", std::process::id()));
    let (mut rec, writer) = FlightRecorder::start(5, dir.to_str().unwrap(), "t").unwrap();
    let error = |n: u64| ErrorRecord {
        seq: n,
        unix_ns: n * 1_000_000,
        code: mcm_shared::mode::RejectCode::FollowingError.to_wire(),
        ..ErrorRecord::default()
    };
    for cycle in 1..=12 {
        rec.record(&Record {
            cycle,
            ..Record::default()
        });
    }
    let path = flight_recorder_file(dir.to_str().unwrap(), "t", &error(1));
    rec.trigger(&error(1));
    wait_written(&writer, 1);
    let text = std::fs::read_to_string(&path).unwrap();
    let cycles: Vec<&str> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(
        cycles,
        ["8", "9", "10", "11", "12"],
        "the last five, oldest first"
    );
    assert!(
        text.lines()
            .next()
            .unwrap()
            .contains("following_error_deg_6")
    );
    // Recording goes on in the other buffer; a second trigger writes only what came after.
    rec.record(&Record {
        cycle: 13,
        ..Record::default()
    });
    let path2 = flight_recorder_file(dir.to_str().unwrap(), "t", &error(2));
    rec.trigger(&error(2));
    writer.stop();
    let text = std::fs::read_to_string(&path2).unwrap();
    assert_eq!(text.lines().count(), 2, "{text}");
    let _ = std::fs::remove_dir_all(dir);
}
