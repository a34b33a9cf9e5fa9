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

#[test]
fn a_file_appears_only_once_it_is_complete() {
    let dir = std::env::temp_dir().join(format!("mcm-flight-whole-{}", std::process::id()));
    let path = dir.join("mcm-t-1-following_error.csv");
    let tmp = dir.join("mcm-t-1-following_error.csv.tmp");
    write_whole(&path, |f| {
        writeln!(f, "cycle")?;
        assert!(
            !path.exists(),
            "{} exists while it is written",
            path.display()
        );
        writeln!(f, "1")
    })
    .unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "cycle\n1\n");
    assert!(!tmp.exists(), "{} left behind", tmp.display());
    // A write that fails leaves neither the file nor its temporary.
    let failed = dir.join("mcm-t-2-following_error.csv");
    let err = write_whole(&failed, |f| {
        writeln!(f, "cycle")?;
        Err(std::io::Error::other("disk full"))
    })
    .unwrap_err();
    assert_eq!(err.to_string(), "disk full");
    assert!(!failed.exists());
    assert!(!dir.join("mcm-t-2-following_error.csv.tmp").exists());
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_trip_is_logged_in_words_with_its_file() {
    use mcm_shared::reply::{Reason, SafetyError};
    let e = SafetyError {
        seq: 1,
        cycle: 7,
        unix_ns: 0,
        reason: Reason::EmergencyStop,
    };
    let line = trip_line(&e.encode(), Path::new("/tmp/f.csv"));
    assert!(
        line.starts_with("safety check tripped: the emergency stop is pressed")
            && line.ends_with("; flight recorder: /tmp/f.csv"),
        "{line}"
    );
}
