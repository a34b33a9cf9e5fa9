//! `authenticate`: present the shared secret (`{"command":"authenticate","arguments":
//! {"secret":"..."}}`). When the configuration names a secret (`[gateway.access]
//! secret_sha256_file`), a connection must authenticate before it may take control. Executed
//! by the gateway itself (`crate::access`); the secret is never echoed or logged.

use crate::args::{Args, CommandError};
use core::fmt;
use serde_json::Value;

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

pub fn parse(arguments: Option<&Value>) -> Result<Secret, CommandError> {
    let args = Args::new("authenticate", arguments, &["secret"])?;
    let expected = format!("the shared secret as a string of 1 to {MAX_SECRET_BYTES} bytes");
    match args.raw("secret") {
        Some(Value::String(s)) if !s.is_empty() && s.len() <= MAX_SECRET_BYTES => {
            Ok(Secret(s.clone()))
        }
        // Never echo what was given: it may be (a typo of) the secret.
        Some(_) => Err(args.invalid_value("secret", "(not shown)", expected)),
        None => Err(args.invalid_value("secret", "(missing)", expected)),
    }
}
