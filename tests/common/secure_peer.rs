//! DDS Security for the tests of the ROS 2 node against a peer nobody here wrote: Debian's
//! Cyclone DDS (its C library and its DDS Security plugins, `libddsc0debian`) in
//! `tests/ros2/secure_peer/` (reads the joint states, or publishes a trajectory), and an SROS2
//! keystore made by `scripts/ros2-keystore`.
//!
//! [`peer`] builds the peer (Cyclone's `idlc` for the message types, then `cc`) once per source
//! hash under `CARGO_TARGET_TMPDIR`, under an exclusive file lock; without Cyclone DDS's
//! development files, `idlc`, a C compiler or openssl the test is skipped with the install
//! command ([`super::skip`]), or fails when `CI` is set.

use super::python::{FileLock, repo_root};
use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicU32, Ordering};

/// What to install when the peer cannot be built.
pub const INSTALL: &str =
    "apt-get install cyclonedds-dev cyclonedds-tools libddsc0debian gcc openssl";

/// Where Debian puts Cyclone DDS's security plugins.
const PLUGINS: &str = "/usr/lib/x86_64-linux-gnu/libddsc0debian";

fn sources() -> PathBuf {
    repo_root().join("tests").join("ros2").join("secure_peer")
}

fn run(cmd: &mut Command) -> Result<(), String> {
    let out = cmd
        .output()
        .map_err(|e| format!("cannot run {cmd:?}: {e}"))?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "{cmd:?} failed ({}): {}{}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// The built peer, or why it cannot be built (the tools it needs are missing).
fn build() -> Result<PathBuf, String> {
    for (tool, what) in [
        ("idlc", "cyclonedds-tools"),
        ("cc", "gcc"),
        ("openssl", "openssl"),
    ] {
        if super::find_program(tool).is_none() {
            return Err(format!("no {tool} ({what}) on PATH"));
        }
    }
    for plugin in ["auth", "ac", "crypto"] {
        let lib = Path::new(PLUGINS).join(format!("libdds_security_{plugin}.so"));
        if !lib.is_file() {
            return Err(format!("no {} (libddsc0debian)", lib.display()));
        }
    }
    let mut h = DefaultHasher::new();
    for f in ["secure_peer.c", "ros2_msgs.idl"] {
        std::fs::read(sources().join(f))
            .map_err(|e| format!("cannot read {f}: {e}"))?
            .hash(&mut h);
    }
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("secure-peer-{:x}", h.finish()));
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let _lock = FileLock::take(&dir.join("lock"))?;
    let exe = dir.join("secure_peer");
    if exe.is_file() {
        return Ok(exe);
    }
    run(Command::new("idlc")
        .current_dir(&dir)
        .arg(sources().join("ros2_msgs.idl")))?;
    let tmp = dir.join("secure_peer.tmp");
    run(Command::new("cc")
        .current_dir(&dir)
        .args(["-O1", "-Wall", "-o"])
        .arg(&tmp)
        .arg(sources().join("secure_peer.c"))
        .args(["ros2_msgs.c", "-I.", "-lddsc", "-lm"]))?;
    std::fs::rename(&tmp, &exe).map_err(|e| format!("cannot rename {}: {e}", tmp.display()))?;
    Ok(exe)
}

/// The peer's program, or `None` after saying `test` is skipped (a failure under `CI`).
pub fn peer_or_skip(test: &str) -> Option<PathBuf> {
    match build() {
        Ok(p) => Some(p),
        Err(e) => {
            super::skip(
                test,
                &format!("cannot build the Cyclone DDS peer ({e}); install: {INSTALL}"),
            );
            None
        }
    }
}

/// A fresh SROS2 keystore made by `scripts/ros2-keystore`, with the enclaves `/mcm` (the
/// node), `/viewer` (read-only) and `/cell` (motion). Returns the keystore's directory.
pub fn keystore(tag: &str) -> PathBuf {
    static N: AtomicU32 = AtomicU32::new(0);
    let ks = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!(
        "keystore-{}-{}-{tag}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&ks);
    let script = repo_root().join("scripts").join("ros2-keystore");
    let make = |args: &[&str]| {
        run(Command::new(&script).args(args)).unwrap_or_else(|e| panic!("ros2-keystore: {e}"))
    };
    let k = ks.to_str().expect("a UTF-8 path");
    make(&["init", k]);
    make(&["enclave", k, "/mcm", "node"]);
    make(&["enclave", k, "/viewer", "read-only"]);
    make(&["enclave", k, "/cell", "motion"]);
    ks
}

/// Cyclone DDS's configuration (`CYCLONEDDS_URI`) for a participant of `enclave` (a directory
/// of SROS2's six files), or without security for `None`. RustDDS needs the handshake's
/// optional fields (`dh1`, `dh2`, the hashes), which Cyclone DDS leaves out by default.
pub fn cyclone_config(enclave: Option<&Path>) -> String {
    let security = enclave.map_or_else(String::new, |e| {
        let e = e.display();
        let lib = |name: &str, init: &str| {
            format!(
                "<Library path=\"{PLUGINS}/libdds_security_{name}.so\" \
                 initFunction=\"init_{init}\" finalizeFunction=\"finalize_{init}\"/>"
            )
        };
        format!(
            "<Security><Authentication>{}\
             <IdentityCertificate>file:{e}/cert.pem</IdentityCertificate>\
             <IdentityCA>file:{e}/identity_ca.cert.pem</IdentityCA>\
             <PrivateKey>file:{e}/key.pem</PrivateKey>\
             <IncludeOptionalFields>true</IncludeOptionalFields></Authentication>\
             <AccessControl>{}\
             <PermissionsCA>file:{e}/permissions_ca.cert.pem</PermissionsCA>\
             <Governance>file:{e}/governance.p7s</Governance>\
             <Permissions>file:{e}/permissions.p7s</Permissions></AccessControl>\
             <Cryptographic>{}</Cryptographic></Security>",
            lib("auth", "authentication"),
            lib("ac", "access_control"),
            lib("crypto", "crypto"),
        )
    });
    format!(
        "<CycloneDDS><Domain id=\"any\"><Tracing><Verbosity>warning</Verbosity>\
         <OutputFile>stderr</OutputFile></Tracing>{security}</Domain></CycloneDDS>"
    )
}

/// A copy of the enclave `from` of `keystore` as `FROM-forged`, whose permissions are those of
/// the enclave `grants_of` made out to `from`'s certificate and signed, with the governance, by
/// a CA of its own (a client that holds a read-only enclave and writes itself the permissions
/// of a motion one). Its DDS library finds them valid (the forger's CA is its permissions CA);
/// the node must not. Returns the enclave's name.
pub fn forged_enclave(keystore: &Path, from: &str, grants_of: &str) -> String {
    let name = format!("{from}-forged");
    let enclaves = keystore.join("enclaves");
    let dst = enclaves.join(&name);
    std::fs::create_dir_all(&dst).unwrap();
    for f in ["cert.pem", "key.pem", "identity_ca.cert.pem"] {
        std::fs::copy(enclaves.join(from).join(f), dst.join(f)).unwrap();
    }
    let ca_key = dst.join("forger.key.pem");
    let ca_cert = dst.join("permissions_ca.cert.pem");
    let sh = |cmd: &mut Command| run(cmd).unwrap_or_else(|e| panic!("forge: {e}"));
    sh(Command::new("openssl")
        .args([
            "req",
            "-x509",
            "-newkey",
            "ec",
            "-pkeyopt",
            "ec_paramgen_curve:prime256v1",
        ])
        .args(["-nodes", "-days", "1", "-subj", "/CN=forger", "-keyout"])
        .arg(&ca_key)
        .arg("-out")
        .arg(&ca_cert));
    let permissions = std::fs::read_to_string(enclaves.join(grants_of).join("permissions.xml"))
        .unwrap()
        .replace(&format!("/{grants_of}<"), &format!("/{from}<"))
        .replace(&format!("\"/{grants_of}\""), &format!("\"/{from}\""));
    assert!(
        permissions.contains(&format!("CN=/{from}<")),
        "{permissions}"
    );
    let sign = |xml: &Path, out: &str| {
        sh(Command::new("openssl")
            .args(["smime", "-sign", "-text", "-in"])
            .arg(xml)
            .arg("-out")
            .arg(dst.join(out))
            .arg("-signer")
            .arg(&ca_cert)
            .arg("-inkey")
            .arg(&ca_key))
    };
    let xml = dst.join("permissions.xml");
    std::fs::write(&xml, permissions).unwrap();
    sign(&xml, "permissions.p7s");
    sign(&enclaves.join("governance.xml"), "governance.p7s");
    name
}
