use super::*;

#[test]
fn a_missing_directory_is_created_and_probed() {
    let dir = std::env::temp_dir().join(format!("mcm-preflight-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let d = dir.join("nested");
    check_flight_recorder_dir(d.to_str().unwrap()).unwrap();
    assert!(d.is_dir());
    assert_eq!(
        std::fs::read_dir(&d).unwrap().count(),
        0,
        "the probe is removed"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_directory_that_cannot_exist_is_refused_naming_the_key() {
    // A path below a regular file cannot be created, not even by root.
    let err = check_flight_recorder_dir("/dev/null/flight").unwrap_err();
    let text = err.to_string();
    assert!(
        text.starts_with("config key `safety.flight_recorder_dir` = /dev/null/flight"),
        "{text}"
    );
    assert!(text.contains("cannot create it"), "{text}");
}

#[test]
fn a_cpu_this_process_cannot_use_is_refused_when_real_time_is_required() {
    let mut cfg = RobotConfig::prob2_default();
    cfg.safety.flight_recorder_dir = std::env::temp_dir().display().to_string();
    cfg.cycle.cpu = 100_000;
    let err = check(&cfg, true).unwrap_err();
    assert!(
        matches!(err, PreflightError::Cpu { cpu: 100_000, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("`cycle.cpu` = 100000"), "{err}");
    assert_eq!(check(&cfg, false), Ok(()));
}
