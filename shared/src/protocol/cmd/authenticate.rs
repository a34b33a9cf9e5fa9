//! `authenticate`: present the shared secret (`{"command":"authenticate","arguments":
//! {"secret":"..."}}`). When the configuration names a secret (`[gateway.access]
//! secret_sha256_file`), a connection must authenticate before it may take control. Executed
//! by the gateway itself (its access rules); the secret is never echoed or logged.

use super::prelude::*;
use core::fmt;

/// Longest secret accepted [bytes].
pub const MAX_SECRET_BYTES: usize = 1024;

/// A presented secret; its `Debug` form hides it.
#[derive(Clone, PartialEq, Eq)]
pub struct Secret(pub String);

impl fmt::Debug for Secret {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Secret(..)")
    }
}

/// `authenticate`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Authenticate {
    pub secret: Secret,
}

impl Definition for Authenticate {
    const DEF: CommandDef = CommandDef {
        name: "authenticate",
        kind: None,
        sends: None,
        success: Success::Ok,
        group: Group::Control,
        ok_words: "",
        summary: "present the shared secret (needed before taking control when configured)",
        args: &[arg(
            "secret",
            "",
            Kind::Text,
            true,
            "",
            "the shared secret the robot's operator gave you",
        )],
        modes: "every mode",
        how: "",
        reply: "OK, or an error after a second when the secret is wrong",
        examples: &["authenticate s3cret-words"],
        notes: "Holds for this session only. `status detail` shows whether a secret is \
                required and whether this session presented it.",
    };

    fn parse(args: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        let expected = format!("the shared secret as a string of 1 to {MAX_SECRET_BYTES} bytes");
        match args.raw("secret") {
            Some(Value::String(s)) if !s.is_empty() && s.len() <= MAX_SECRET_BYTES => {
                Ok(Authenticate {
                    secret: Secret(s.clone()),
                })
            }
            // Never echo what was given: it may be (a typo of) the secret.
            Some(_) => Err(args.invalid_value("secret", "(not shown)", expected)),
            None => Err(args.missing("secret", &expected)),
        }
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        m.insert("secret".into(), self.secret.0.clone().into());
        m
    }

    fn requests(&self) -> Vec<Request> {
        Vec::new()
    }
}
