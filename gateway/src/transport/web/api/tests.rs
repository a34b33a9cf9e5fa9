use super::*;

#[test]
fn only_this_instances_complete_records_are_named() {
    assert_eq!(
        parse_name("mcm-default-1795320947790-following_error.csv", "default"),
        Some((1795320947790, "following_error".to_string()))
    );
    // Instances may hold dashes.
    assert_eq!(
        parse_name("mcm-t-1-5-drive_disconnected.csv", "t-1"),
        Some((5, "drive_disconnected".to_string()))
    );
    for other in [
        "mcm-other-1-following_error.csv",
        "mcm-default-1-following_error.csv.tmp",
        "mcm-default-x-following_error.csv",
        "mcm-default-1-.csv",
        "mcm-default-1-../../etc/passwd.csv",
        "mcm-default-1-a/b.csv",
        "notes.txt",
    ] {
        assert_eq!(parse_name(other, "default"), None, "{other}");
        assert_eq!(
            record_path(Path::new("/d"), "default", other),
            None,
            "{other}"
        );
    }
}

#[test]
fn records_are_listed_newest_first_and_others_left_out() {
    let dir = std::env::temp_dir().join(format!("mcm-web-records-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, body) in [
        ("mcm-w1-100-following_error.csv", "a"),
        ("mcm-w1-300-drive_disconnected.csv", "abc"),
        ("mcm-w1-200-emergency_stop.csv.tmp", "x"),
        ("mcm-w2-400-following_error.csv", "x"),
    ] {
        std::fs::write(dir.join(name), body).unwrap();
    }
    let got = records(&dir, "w1");
    let names: Vec<&str> = got.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "mcm-w1-300-drive_disconnected.csv",
            "mcm-w1-100-following_error.csv"
        ]
    );
    assert_eq!(got[0].bytes, 3);
    assert_eq!(got[0].check, "drive_disconnected");
    assert!(records(&dir.join("missing"), "w1").is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_model_has_six_axes_and_links_and_the_bus_load() {
    let m = model(&RobotConfig::prob2_default(), "default");
    assert_eq!(m["axes"].as_array().unwrap().len(), 6);
    assert_eq!(m["links"].as_array().unwrap().len(), 6);
    assert_eq!(m["axes"][0]["name"], "base");
    assert_eq!(m["axes"][1]["min_deg"], -120.0);
    assert_eq!(m["links"][0]["d"], 0.26);
    let load = m["bus"]["worst_case_load"].as_f64().unwrap();
    assert!(load > 0.5 && load < 0.8, "{load}");
}

#[test]
fn connections_name_channel_peer_and_the_owner() {
    use crate::command::access::Channel;
    let peer: std::net::SocketAddr = "10.0.0.5:4000".parse().unwrap();
    let v = connections(&[(7, Channel::Web, peer), (9, Channel::Json, peer)], 9);
    assert_eq!(v["owner_client_id"], 9);
    assert_eq!(v["clients"][0]["channel"], "browser pendant");
    assert_eq!(v["clients"][0]["controls_the_arm"], false);
    assert_eq!(v["clients"][1]["peer"], "10.0.0.5:4000");
    assert_eq!(v["clients"][1]["controls_the_arm"], true);
}

proptest::proptest! {
    /// Whatever name a request carries, it is either refused or a plain file name of this
    /// instance's records inside the records' directory: never a path elsewhere, never a panic.
    #[test]
    fn no_name_reaches_outside_the_records(
        name in "[a-z0-9_./-]{0,24}|.{0,80}",
        ms in proptest::num::u64::ANY,
    ) {
        let dir = Path::new("/var/mcm/records");
        for candidate in [name.clone(), format!("mcm-default-{ms}-{name}.csv")] {
            if let Some(path) = record_path(dir, "default", &candidate) {
                proptest::prop_assert_eq!(path.parent(), Some(dir));
                proptest::prop_assert!(!candidate.contains('/') && !candidate.contains(".."));
            }
        }
    }
}
