//! `mcm --ros2` with DDS Security (`--ros2-enclave`, an SROS2 keystore made by
//! `scripts/ros2-keystore`) against a peer nobody here wrote: Debian's Cyclone DDS with its DDS
//! Security plugins (`tests/ros2/secure_peer/`, `common::secure_peer`), in a network namespace
//! of its own with its own domain id, as the other ROS 2 tests.

use crate::common;

use common::Client;
use common::netns::Netns;
use common::ros2::{self, Distro, JOINTS, mcm_in};
use common::secure_peer::{self, cyclone_config};
use mcm_client::launch::SimulatedMcm;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A secured node on a calibrated arm that nobody controls (so a trajectory the node took
/// would move it), in its own namespace and domain.
struct Setup {
    ns: Netns,
    domain: u32,
    keystore: PathBuf,
    peer: PathBuf,
    _mcm: SimulatedMcm,
    json: Client,
}

fn setup(test: &str, tag: &str) -> Option<Setup> {
    let peer = secure_peer::peer_or_skip(test)?;
    let ns = Netns::or_skip(test, tag)?;
    let domain = ros2::unique_domain_id();
    let keystore = secure_peer::keystore(tag);
    let enclave = keystore.join("enclaves").join("mcm");
    let mcm = mcm_in(
        &ns,
        &common::unique_instance(tag),
        Distro::Kilted,
        &[
            format!("--domain-id={domain}"),
            format!("--ros2-enclave={}", enclave.display()),
        ],
    );
    let json = ros2::calibrated_client(&ns, &mcm);
    Some(Setup {
        ns,
        domain,
        keystore,
        peer,
        _mcm: mcm,
        json,
    })
}

impl Drop for Setup {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.keystore);
    }
}

impl Setup {
    /// Run the peer `args...` as the participant of `enclave` (none: without security); its
    /// stdout, and whether it exited with success.
    fn peer(&self, enclave: Option<&str>, args: &[&str]) -> (String, bool) {
        let dir = enclave.map(|e| self.keystore.join("enclaves").join(e));
        let mut cmd: Command = self.ns.command(&self.peer);
        cmd.args(args)
            .env("CYCLONEDDS_URI", cyclone_config(dir.as_deref()));
        let out = cmd.output().expect("run the Cyclone DDS peer");
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        eprintln!(
            "[secure_peer {enclave:?} {args:?}] {text}{}",
            String::from_utf8_lossy(&out.stderr)
        );
        (text, out.status.success())
    }

    /// The peer reads `count` joint states within `timeout_s` (as `enclave`).
    fn read(&self, enclave: Option<&str>, count: u32, timeout_s: f64) -> (String, bool) {
        let domain = self.domain.to_string();
        let count = count.to_string();
        let timeout = timeout_s.to_string();
        self.peer(enclave, &["read", &domain, "/", &count, &timeout])
    }

    /// The peer publishes, for `seconds`, a trajectory to the arm's true position with
    /// `base_delta_deg` added to the base (as `enclave`); the true position before it [deg].
    fn send_trajectory(
        &mut self,
        enclave: Option<&str>,
        base_delta_deg: f64,
        seconds: f64,
    ) -> ([f64; 6], String) {
        let (q0, _) = self.json.truth();
        let pairs: Vec<String> = JOINTS
            .iter()
            .zip(q0)
            .enumerate()
            .map(|(i, (n, deg))| {
                let deg = if i == 0 { deg + base_delta_deg } else { deg };
                format!("{n}={}", deg.to_radians())
            })
            .collect();
        let domain = self.domain.to_string();
        let seconds = seconds.to_string();
        let mut args: Vec<&str> = vec!["trajectory", &domain, "/", &seconds];
        args.extend(pairs.iter().map(String::as_str));
        let (out, ok) = self.peer(enclave, &args);
        assert!(ok, "the peer failed: {out}");
        (q0, out)
    }

    /// The arm's true position has not changed from `q0` and it stands still, 400 of the
    /// robot's cycles after now (the trajectories last 200).
    fn assert_unmoved(&mut self, q0: [f64; 6], why: &str) {
        let c0 = self.cycle();
        let _ = self.json.wait_status("400 cycles", |s| {
            s["detail"]["cycle"].as_u64() >= Some(c0 + 400)
        });
        let (q1, v1) = self.json.truth();
        for i in 0..6 {
            assert!(
                (q1[i] - q0[i]).abs() < 0.05 && v1[i].abs() < 0.05,
                "{why}: the arm moved: {q0:?} -> {q1:?} deg, velocity {v1:?} deg/s"
            );
        }
    }

    fn cycle(&mut self) -> u64 {
        let s = self
            .json
            .request(r#"{"command":"status","arguments":{"detail":true}}"#);
        s["detail"]["cycle"].as_u64().expect("status detail.cycle")
    }
}

/// A peer of the read-only enclave reads the joint states (the MCM's positions) through the
/// encrypted, authenticated domain; its trajectory is not taken: Cyclone DDS does not even
/// make the topic its permissions do not grant, and the arm's true position stays.
#[test]
fn a_read_only_peer_reads_joint_states_and_cannot_move_the_arm() {
    let test = "a_read_only_peer_reads_joint_states_and_cannot_move_the_arm";
    let Some(mut s) = setup(test, "sros-ro") else {
        return;
    };
    let (out, ok) = s.read(Some("viewer"), 20, 30.0);
    assert!(ok && out.contains("ok joint_states messages=20"), "{out}");
    ros2::assert_read_the_arm(&out, &mut s.json);
    let (q0, out) = s.send_trajectory(Some("viewer"), 10.0, 3.0);
    assert!(
        out.contains("refused: create topic rt/joint_trajectory: Not Allowed By Security"),
        "a read-only peer's writer was matched: {out}"
    );
    s.assert_unmoved(q0, "a read-only peer's trajectory");
}

/// A peer with forged permissions gets nothing: the read-only enclave's certificate and key
/// with the motion enclave's grants made out to it, signed by a CA of its own (which its
/// Cyclone DDS, configured with that CA, accepts). The node and the peer each refuse the
/// other's permissions (neither is signed by a CA it trusts): the peer reads no joint state and
/// its trajectory is matched with nothing, while the read-only enclave itself reads them, and
/// the arm's true position stays.
#[test]
fn a_peer_with_forged_permissions_gets_nothing() {
    let test = "a_peer_with_forged_permissions_gets_nothing";
    let Some(mut s) = setup(test, "sros-fg") else {
        return;
    };
    let forged = secure_peer::forged_enclave(&s.keystore, "viewer", "cell");
    let (out, ok) = s.read(Some("viewer"), 5, 30.0);
    assert!(ok, "the read-only enclave itself reads: {out}");
    let (out, ok) = s.read(Some(&forged), 1, 5.0);
    assert!(!ok && out.contains("FAILED: 0 of 1 joint states"), "{out}");
    let (q0, out) = s.send_trajectory(Some(&forged), 10.0, 3.0);
    assert!(
        out.contains("published") && out.contains("matched=0"),
        "{out}"
    );
    s.assert_unmoved(q0, "a trajectory under forged permissions");
}

/// A peer of the motion enclave moves the arm: its trajectory on `joint_trajectory` reaches
/// the node through the secured domain, and the arm's true position follows it.
#[test]
fn a_motion_peer_moves_the_arm() {
    let test = "a_motion_peer_moves_the_arm";
    let Some(mut s) = setup(test, "sros-mv") else {
        return;
    };
    let (q0, out) = s.send_trajectory(Some("cell"), 10.0, 3.0);
    assert!(
        out.contains("matched=1"),
        "the node's subscription was not matched: {out}"
    );
    let (q1, _) = s.json.wait_truth("the base 10 deg further", |p, v| {
        (p[0] - (q0[0] + 10.0)).abs() < 0.1 && v[0].abs() < 0.1
    });
    assert!((q1[1] - q0[1]).abs() < 0.1, "{q0:?} -> {q1:?}");
}

/// A peer without a certificate (Cyclone DDS without security) reads no joint state and its
/// trajectory moves nothing: the node's participant does not talk to it.
#[test]
fn a_peer_without_a_certificate_sees_nothing() {
    let test = "a_peer_without_a_certificate_sees_nothing";
    let Some(mut s) = setup(test, "sros-no") else {
        return;
    };
    // The joint states come at 200 Hz: in 5 s an unsecured peer would have read thousands.
    let (out, ok) = s.read(None, 1, 5.0);
    assert!(!ok && out.contains("FAILED: 0 of 1 joint states"), "{out}");
    let (q0, out) = s.send_trajectory(None, 10.0, 3.0);
    assert!(out.contains("matched=0"), "{out}");
    s.assert_unmoved(q0, "an unauthenticated peer's trajectory");
}

/// The enclave's files are checked at start: a node whose enclave lacks a file does not
/// start, naming the file.
#[test]
fn a_node_with_an_incomplete_enclave_refuses_to_start() {
    let test = "a_node_with_an_incomplete_enclave_refuses_to_start";
    if common::find_program("openssl").is_none() {
        common::skip(test, "no openssl on PATH (apt-get install openssl)");
        return;
    }
    let keystore = secure_peer::keystore("sros-bad");
    let enclave = keystore.join("enclaves").join("mcm");
    std::fs::remove_file(enclave.join("permissions.p7s")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_mcm"))
        .args(["ros2", "--instance", "nobody-sros-bad", "--ros2-enclave"])
        .arg(&enclave)
        .output()
        .expect("run mcm ros2");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(
        err.contains(&format!(
            "{}",
            Path::new(&enclave).join("permissions.p7s").display()
        )),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&keystore);
}

/// The traffic on the wire is encrypted: while a read-only peer reads 200 joint states (about
/// a second of them), every frame in the namespace is captured, and no UDP frame holds a
/// joint's name as a CDR string, which every `joint_states` message carries in clear without
/// DDS Security.
#[test]
fn the_joint_states_are_encrypted_on_the_wire() {
    let test = "the_joint_states_are_encrypted_on_the_wire";
    let Some(s) = setup(test, "sros-wire") else {
        return;
    };
    let ns_name = s.ns.name.clone();
    let capture = std::thread::scope(|scope| {
        let capture = scope.spawn(|| s.ns.capture(std::time::Duration::from_secs(4)));
        let (out, ok) = s.read(Some("viewer"), 200, 30.0);
        assert!(ok, "{out}");
        capture.join().expect("the capture")
    })
    .unwrap_or_else(|e| panic!("capture in {ns_name}: {e}"));
    // DDS is UDP (the test's JSON client, TCP, names the joints too): IPv4 (EtherType 0x0800
    // after the two addresses) and protocol 17 at byte 9 of the IP header.
    let udp: Vec<&[u8]> = capture
        .iter()
        .filter(|f| f.len() > 34 && f[12..14] == [0x08, 0x00] && f[14 + 9] == 17)
        .map(Vec::as_slice)
        .collect();
    let bytes: usize = udp.iter().map(|f| f.len()).sum();
    assert!(bytes > 10_000, "{bytes} bytes of UDP captured");
    for joint in JOINTS {
        // A joint's name as a `joint_states` message carries it: a CDR string (its length with
        // the NUL, little-endian, then the bytes and the NUL). The handshake's certificates and
        // permissions, which DDS Security sends in clear, are text and base64.
        let mut cdr = ((joint.len() + 1) as u32).to_le_bytes().to_vec();
        cdr.extend_from_slice(joint.as_bytes());
        cdr.push(0);
        let clear: Vec<&[u8]> = udp
            .iter()
            .copied()
            .filter(|f| f.windows(cdr.len()).any(|w| w == cdr))
            .collect();
        assert!(
            clear.is_empty(),
            "{joint:?} is in clear in {} of {} UDP frames ({bytes} bytes); the first: {}",
            clear.len(),
            udp.len(),
            clear[0].escape_ascii()
        );
    }
}
