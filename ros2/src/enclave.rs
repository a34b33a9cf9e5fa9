//! DDS Security for the node: which SROS2 enclave it uses, if any, and whether the enclave's
//! files are there, of their kinds and signed as they should be before DDS reads them.
//!
//! The enclave comes from `--ros2-enclave DIR`, or from the variables SROS2 names:
//! `ROS_SECURITY_ENABLE=true` with `ROS_SECURITY_KEYSTORE` (the keystore) and
//! `ROS_SECURITY_ENCLAVE_OVERRIDE` (the enclave's name, [`DEFAULT_ENCLAVE`] when unset): the
//! directory `KEYSTORE/enclaves/NAME`. `ROS_SECURITY_STRATEGY=Enforce` refuses to run without
//! an enclave; otherwise (`Permissive`, the default, as in ROS 2) a keystore that has no such
//! enclave runs the node without security, saying so. An enclave found but incomplete or
//! unreadable is always refused, naming the file (docs/security.md, docs/ros2.md).

use std::fmt;
use std::path::{Path, PathBuf};

/// The enclave's name when `ROS_SECURITY_ENCLAVE_OVERRIDE` is unset.
pub const DEFAULT_ENCLAVE: &str = "/mcm";

/// The files DDS Security reads from an enclave (SROS2's names), and what each must hold.
pub const FILES: [(&str, Holds); 6] = [
    ("identity_ca.cert.pem", Holds::Certificate),
    ("cert.pem", Holds::Certificate),
    ("key.pem", Holds::PrivateKey),
    ("permissions_ca.cert.pem", Holds::Certificate),
    ("governance.p7s", Holds::Signed),
    ("permissions.p7s", Holds::Signed),
];

/// What an enclave's file holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Holds {
    /// A PEM X.509 certificate.
    Certificate,
    /// A PEM private key (not encrypted: the node has no password to give).
    PrivateKey,
    /// An XML document signed with S/MIME (`openssl smime -sign`).
    Signed,
}

impl Holds {
    /// Whether `text` looks like it, and what it should be.
    fn check(self, text: &str) -> Result<(), &'static str> {
        let ok = match self {
            Holds::Certificate => text.contains("-----BEGIN CERTIFICATE-----"),
            Holds::PrivateKey => {
                text.contains("PRIVATE KEY-----") && !text.contains("ENCRYPTED PRIVATE KEY")
            }
            Holds::Signed => text.contains("MIME-Version") && text.contains("pkcs7-signature"),
        };
        if ok {
            return Ok(());
        }
        Err(match self {
            Holds::Certificate => "a PEM certificate (-----BEGIN CERTIFICATE-----)",
            Holds::PrivateKey => "a PEM private key without a password",
            Holds::Signed => "an S/MIME signed document (openssl smime -sign)",
        })
    }
}

/// The environment variables of SROS2 the node reads.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SecurityEnv {
    /// `ROS_SECURITY_ENABLE`.
    pub enable: Option<String>,
    /// `ROS_SECURITY_STRATEGY`.
    pub strategy: Option<String>,
    /// `ROS_SECURITY_KEYSTORE`.
    pub keystore: Option<String>,
    /// `ROS_SECURITY_ENCLAVE_OVERRIDE`.
    pub enclave: Option<String>,
}

impl SecurityEnv {
    /// The process's environment.
    pub fn from_process() -> SecurityEnv {
        let var = |name| std::env::var(name).ok().filter(|v| !v.trim().is_empty());
        SecurityEnv {
            enable: var("ROS_SECURITY_ENABLE"),
            strategy: var("ROS_SECURITY_STRATEGY"),
            keystore: var("ROS_SECURITY_KEYSTORE"),
            enclave: var("ROS_SECURITY_ENCLAVE_OVERRIDE"),
        }
    }
}

/// Whether the node runs with DDS Security.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Security {
    /// No DDS Security: anyone on the domain may use what the node offers.
    Off,
    /// DDS Security with the enclave in this directory, its files checked.
    Enclave(PathBuf),
}

/// The decision with what the node says about it at start (a fallback to no security).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Chosen {
    pub security: Security,
    /// Said at start when the node runs without security although security was asked for
    /// (`Permissive` and no enclave).
    pub warning: Option<String>,
}

/// Why the node does not start.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EnclaveError {
    #[error(
        "ROS_SECURITY_STRATEGY is {0:?}; allowed: Enforce (refuse to run without an enclave) or Permissive"
    )]
    Strategy(String),
    #[error("ROS_SECURITY_ENABLE is {0:?}; allowed: true or false")]
    Enable(String),
    #[error(
        "ROS_SECURITY_STRATEGY=Enforce but no enclave: give --ros2-enclave DIR, or ROS_SECURITY_ENABLE=true with ROS_SECURITY_KEYSTORE (now {keystore})"
    )]
    EnforceWithout { keystore: String },
    #[error(
        "ROS_SECURITY_STRATEGY=Enforce but the enclave {enclave} is not in the keystore: {dir} is not a directory"
    )]
    EnforceMissing { enclave: String, dir: PathBuf },
    #[error("ROS_SECURITY_ENCLAVE_OVERRIDE {0:?} is not an enclave name like /mcm")]
    Name(String),
    #[error("the enclave {dir} is not a directory: {detail}")]
    Dir { dir: PathBuf, detail: String },
    #[error("the enclave's file {file} cannot be read: {detail}")]
    Unreadable { file: PathBuf, detail: String },
    #[error("the enclave's file {file} is not {expected}")]
    Content {
        file: PathBuf,
        expected: &'static str,
    },
    #[error("the enclave's file {file} {problem}")]
    Signature { file: PathBuf, problem: String },
}

/// The enclave to use: `--ros2-enclave` (`flag`) first, else SROS2's variables (`env`).
/// Checks the enclave's files ([`check_files`]).
pub fn choose(flag: Option<&Path>, env: &SecurityEnv) -> Result<Chosen, EnclaveError> {
    let enforce = match env.strategy.as_deref().map(str::trim) {
        None => false,
        Some(s) if s.eq_ignore_ascii_case("enforce") => true,
        Some(s) if s.eq_ignore_ascii_case("permissive") => false,
        Some(s) => return Err(EnclaveError::Strategy(s.to_string())),
    };
    if let Some(dir) = flag {
        check_files(dir)?;
        return Ok(Chosen {
            security: Security::Enclave(dir.to_path_buf()),
            warning: None,
        });
    }
    let enabled = match env.enable.as_deref().map(str::trim) {
        None => false,
        Some(v) if v.eq_ignore_ascii_case("true") => true,
        Some(v) if v.eq_ignore_ascii_case("false") => false,
        Some(v) => return Err(EnclaveError::Enable(v.to_string())),
    };
    let keystore = env.keystore.as_deref().filter(|_| enabled);
    let Some(keystore) = keystore else {
        if enforce {
            return Err(EnclaveError::EnforceWithout {
                keystore: match (&env.keystore, enabled) {
                    (None, _) => "unset".into(),
                    (Some(k), false) => format!("{k:?}, but ROS_SECURITY_ENABLE is not true"),
                    (Some(k), true) => format!("{k:?}"),
                },
            });
        }
        return Ok(Chosen {
            security: Security::Off,
            warning: None,
        });
    };
    let name = env.enclave.as_deref().unwrap_or(DEFAULT_ENCLAVE);
    let relative = name.strip_prefix('/').unwrap_or("");
    let valid = !relative.is_empty()
        && relative
            .split('/')
            .all(|p| !p.is_empty() && p != "." && p != "..");
    if !valid {
        return Err(EnclaveError::Name(name.to_string()));
    }
    let dir = Path::new(keystore).join("enclaves").join(relative);
    if !dir.is_dir() {
        if enforce {
            return Err(EnclaveError::EnforceMissing {
                enclave: name.to_string(),
                dir,
            });
        }
        return Ok(Chosen {
            security: Security::Off,
            warning: Some(format!(
                "no enclave {name} in the keystore ({} is not a directory): running WITHOUT DDS \
                 Security (ROS_SECURITY_STRATEGY=Permissive; Enforce refuses to run)",
                dir.display()
            )),
        });
    }
    check_files(&dir)?;
    Ok(Chosen {
        security: Security::Enclave(dir),
        warning: None,
    })
}

/// Whether `dir` holds the six files of an enclave ([`FILES`]), each readable and of its kind.
/// DDS Security checks their signatures and chains when the participant is made.
pub fn check_files(dir: &Path) -> Result<(), EnclaveError> {
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => {
            return Err(EnclaveError::Dir {
                dir: dir.to_path_buf(),
                detail: "it is a file".into(),
            });
        }
        Err(e) => {
            return Err(EnclaveError::Dir {
                dir: dir.to_path_buf(),
                detail: e.to_string(),
            });
        }
    }
    for (name, holds) in FILES {
        let file = dir.join(name);
        let text = std::fs::read(&file).map_err(|e| EnclaveError::Unreadable {
            file: file.clone(),
            detail: e.to_string(),
        })?;
        holds
            .check(&String::from_utf8_lossy(&text))
            .map_err(|expected| EnclaveError::Content { file, expected })?;
    }
    check_signatures(dir)
}

/// Whether the enclave's files fit together: `cert.pem` signed by `identity_ca.cert.pem`,
/// `key.pem` the key of `cert.pem`, `governance.p7s` and `permissions.p7s` signed by
/// `permissions_ca.cert.pem`. DDS Security checks the same when the participant is made, but
/// without naming the file.
fn check_signatures(dir: &Path) -> Result<(), EnclaveError> {
    use openssl::pkcs7::{Pkcs7, Pkcs7Flags};
    use openssl::pkey::PKey;
    use openssl::stack::Stack;
    use openssl::x509::X509;
    use openssl::x509::store::X509StoreBuilder;
    let bad = |name: &str, problem: String| EnclaveError::Signature {
        file: dir.join(name),
        problem,
    };
    // The files were read and checked for their kind just before: a failure now is a file
    // that looks right and is not.
    let read = |name: &str| std::fs::read(dir.join(name)).map_err(|e| bad(name, e.to_string()));
    let cert = |name: &str| X509::from_pem(&read(name)?).map_err(|e| bad(name, e.to_string()));
    let identity_ca = cert("identity_ca.cert.pem")?;
    let own = cert("cert.pem")?;
    let signed_by_ca = identity_ca
        .public_key()
        .and_then(|k| own.verify(&k))
        .map_err(|e| bad("identity_ca.cert.pem", e.to_string()))?;
    if !signed_by_ca {
        return Err(bad(
            "cert.pem",
            "is not signed by the identity CA (identity_ca.cert.pem)".into(),
        ));
    }
    let key =
        PKey::private_key_from_pem(&read("key.pem")?).map_err(|e| bad("key.pem", e.to_string()))?;
    let cert_key = own
        .public_key()
        .map_err(|e| bad("cert.pem", e.to_string()))?;
    if !cert_key.public_eq(&key) {
        return Err(bad(
            "key.pem",
            "is not the key of the certificate cert.pem".into(),
        ));
    }
    let permissions_ca = cert("permissions_ca.cert.pem")?;
    for name in ["governance.p7s", "permissions.p7s"] {
        let (pkcs7, content) =
            Pkcs7::from_smime(&read(name)?).map_err(|e| bad(name, e.to_string()))?;
        let mut store = X509StoreBuilder::new().map_err(|e| bad(name, e.to_string()))?;
        store
            .add_cert(permissions_ca.clone())
            .map_err(|e| bad("permissions_ca.cert.pem", e.to_string()))?;
        let no_more = Stack::new().map_err(|e| bad(name, e.to_string()))?;
        pkcs7
            .verify(
                &no_more,
                &store.build(),
                content.as_deref(),
                None,
                Pkcs7Flags::empty(),
            )
            .map_err(|e| {
                bad(
                    name,
                    format!("is not signed by the permissions CA (permissions_ca.cert.pem): {e}"),
                )
            })?;
    }
    Ok(())
}

impl fmt::Display for Security {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Security::Off => f.write_str("off"),
            Security::Enclave(dir) => write!(f, "enclave {}", dir.display()),
        }
    }
}

#[cfg(test)]
mod tests;
