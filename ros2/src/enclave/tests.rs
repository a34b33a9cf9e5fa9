use super::*;
use std::sync::atomic::{AtomicU32, Ordering};

/// A fresh directory under the system's temporary directory.
fn scratch() -> PathBuf {
    static N: AtomicU32 = AtomicU32::new(0);
    let dir = std::env::temp_dir().join(format!(
        "mcm-ros2-enclave-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const CERT: &str = "-----BEGIN CERTIFICATE-----\nMII\n-----END CERTIFICATE-----\n";
const KEY: &str = "-----BEGIN PRIVATE KEY-----\nMIG\n-----END PRIVATE KEY-----\n";

/// A keystore made by `scripts/ros2-keystore` (openssl) in `ks`, with the enclaves `/mcm` and
/// `/viewer`.
fn keystore_in(ks: &Path) {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/ros2-keystore");
    let run = |args: &[&str]| {
        let out = std::process::Command::new(&script)
            .args(args)
            .output()
            .expect("run scripts/ros2-keystore (needs openssl)");
        assert!(out.status.success(), "{args:?}: {out:?}");
    };
    let k = ks.to_str().unwrap();
    run(&["init", k]);
    run(&["enclave", k, "/mcm", "node"]);
    run(&["enclave", k, "/viewer", "read-only"]);
}

/// An enclave of six files that fit together in `dir` (the `/mcm` of a new keystore).
fn enclave_in(dir: &Path) {
    let ks = scratch();
    keystore_in(&ks);
    std::fs::create_dir_all(dir).unwrap();
    for (name, _) in FILES {
        std::fs::copy(ks.join("enclaves/mcm").join(name), dir.join(name)).unwrap();
    }
}

fn env(enable: Option<&str>, strategy: Option<&str>, keystore: Option<&Path>) -> SecurityEnv {
    SecurityEnv {
        enable: enable.map(String::from),
        strategy: strategy.map(String::from),
        keystore: keystore.map(|k| k.display().to_string()),
        enclave: None,
    }
}

#[test]
fn without_flag_or_variables_security_is_off() {
    let chosen = choose(None, &SecurityEnv::default()).unwrap();
    assert_eq!(chosen.security, Security::Off);
    assert_eq!(chosen.warning, None);
}

#[test]
fn the_flag_names_the_enclave_directory() {
    let dir = scratch();
    enclave_in(&dir);
    let chosen = choose(Some(&dir), &SecurityEnv::default()).unwrap();
    assert_eq!(chosen.security, Security::Enclave(dir));
}

#[test]
fn each_missing_file_is_refused_by_name() {
    for (name, _) in FILES {
        let dir = scratch();
        enclave_in(&dir);
        std::fs::remove_file(dir.join(name)).unwrap();
        let e = choose(Some(&dir), &SecurityEnv::default()).unwrap_err();
        assert!(
            matches!(&e, EnclaveError::Unreadable { file, .. } if file == &dir.join(name)),
            "{name}: {e}"
        );
        assert!(e.to_string().contains(name), "{e}");
    }
}

#[test]
fn a_file_of_the_wrong_kind_is_refused_by_name() {
    for (name, holds) in FILES {
        let dir = scratch();
        enclave_in(&dir);
        // Each kind's file given another kind's content.
        let wrong = if holds == Holds::Certificate {
            KEY
        } else {
            CERT
        };
        std::fs::write(dir.join(name), wrong).unwrap();
        let e = choose(Some(&dir), &SecurityEnv::default()).unwrap_err();
        assert!(
            matches!(&e, EnclaveError::Content { file, .. } if file == &dir.join(name)),
            "{name}: {e}"
        );
    }
    let dir = scratch();
    enclave_in(&dir);
    std::fs::write(
        dir.join("key.pem"),
        "-----BEGIN ENCRYPTED PRIVATE KEY-----\nMI\n-----END ENCRYPTED PRIVATE KEY-----\n",
    )
    .unwrap();
    let e = check_files(&dir).unwrap_err();
    assert!(e.to_string().contains("without a password"), "{e}");
}

#[test]
fn a_missing_enclave_directory_is_refused() {
    let dir = scratch().join("nothing");
    let e = choose(Some(&dir), &SecurityEnv::default()).unwrap_err();
    assert!(matches!(e, EnclaveError::Dir { .. }), "{e}");
}

#[test]
fn the_variables_choose_the_keystores_enclave() {
    let ks = scratch();
    enclave_in(&ks.join("enclaves").join("mcm"));
    enclave_in(&ks.join("enclaves").join("left").join("arm"));
    let chosen = choose(None, &env(Some("true"), None, Some(&ks))).unwrap();
    assert_eq!(chosen.security, Security::Enclave(ks.join("enclaves/mcm")));
    let mut e = env(Some("true"), Some("Enforce"), Some(&ks));
    e.enclave = Some("/left/arm".into());
    let chosen = choose(None, &e).unwrap();
    assert_eq!(
        chosen.security,
        Security::Enclave(ks.join("enclaves/left/arm"))
    );
    for bad in ["/", "mcm", "/../mcm", "/a//b"] {
        e.enclave = Some(bad.into());
        assert_eq!(choose(None, &e), Err(EnclaveError::Name(bad.into())));
    }
}

#[test]
fn permissive_without_the_enclave_runs_unsecured_saying_so() {
    let ks = scratch();
    let chosen = choose(None, &env(Some("true"), None, Some(&ks))).unwrap();
    assert_eq!(chosen.security, Security::Off);
    let warning = chosen.warning.expect("a warning");
    assert!(warning.contains("WITHOUT DDS Security"), "{warning}");
}

#[test]
fn enforce_without_an_enclave_refuses_to_start() {
    let ks = scratch();
    assert!(matches!(
        choose(None, &env(None, Some("Enforce"), None)),
        Err(EnclaveError::EnforceWithout { .. })
    ));
    // A keystore without ROS_SECURITY_ENABLE=true is not used.
    let e = choose(None, &env(Some("false"), Some("Enforce"), Some(&ks))).unwrap_err();
    assert!(
        e.to_string().contains("ROS_SECURITY_ENABLE is not true"),
        "{e}"
    );
    assert!(matches!(
        choose(None, &env(Some("true"), Some("Enforce"), Some(&ks))),
        Err(EnclaveError::EnforceMissing { .. })
    ));
    // With --ros2-enclave, Enforce is satisfied.
    let dir = scratch();
    enclave_in(&dir);
    assert!(choose(Some(&dir), &env(None, Some("Enforce"), None)).is_ok());
}

#[test]
fn unknown_values_of_the_variables_are_refused() {
    assert_eq!(
        choose(None, &env(None, Some("Strict"), None)),
        Err(EnclaveError::Strategy("Strict".into()))
    );
    assert_eq!(
        choose(None, &env(Some("yes"), None, None)),
        Err(EnclaveError::Enable("yes".into()))
    );
}

#[test]
fn files_that_do_not_fit_together_are_refused_by_name() {
    let ks = scratch();
    keystore_in(&ks);
    let other = scratch();
    keystore_in(&other);
    let mcm = ks.join("enclaves/mcm");
    // (the file replaced, where from)
    let cases = [
        ("cert.pem", other.join("enclaves/mcm")),
        ("key.pem", ks.join("enclaves/viewer")),
        ("governance.p7s", other.join("enclaves/mcm")),
        ("permissions.p7s", other.join("enclaves/mcm")),
    ];
    for (name, from) in cases {
        let dir = scratch();
        for (f, _) in FILES {
            std::fs::copy(mcm.join(f), dir.join(f)).unwrap();
        }
        assert_eq!(check_files(&dir), Ok(()));
        std::fs::copy(from.join(name), dir.join(name)).unwrap();
        let e = check_files(&dir).unwrap_err();
        assert!(
            matches!(&e, EnclaveError::Signature { file, .. } if file == &dir.join(name)),
            "{name}: {e}"
        );
    }
}
