//! The command line of `mcm-dst`: what to run, every value checked, a refusal naming the
//! option, the value and what is allowed.

use crate::run::{PLANTED_BUGS, PlantedBug};

pub const USAGE: &str = "usage: mcm-dst [--seed N | --replay FILE] [--seconds S] [--hours H] [--jobs J] [--first-seed N] [--planted-bug braking|soft-stop] [--shrink-replays R] [--keep-going]
  --seed N        run seed N alone (twice, comparing the hashes of every state) and print what it did;
                  a broken invariant is shrunk to the inputs it needs, written to mcm-dst-seed-N.script
  --replay FILE   replay a script (what --seed writes) for S simulated seconds past its last input
  --shrink-replays R  replays the shrinking may make at most (default 400)
  --seconds S     simulated seconds of each run's chaos phase (default 60)
  --hours H       without --seed: a campaign of H simulated hours over seeds from --first-seed (default 0.1)
  --jobs J        threads of the campaign (default 1; with 1 a campaign is reproducible)
  --first-seed N  the campaign's first seed (default 0)
  --keep-going    a campaign goes on past a run that breaks a per-cycle invariant and lists
                  every failing seed at the end (without it, it stops at the first)
  --planted-bug NAME  plant a bug to see the campaign catch it: braking (the braking-distance
                  check never trips) or soft-stop (the stop after a trip brakes at a tenth of
                  the maximum deceleration)";

/// What the command line asks for.
#[derive(Debug, Clone, PartialEq)]
pub struct Args {
    /// Run this seed alone; `None`: a campaign.
    pub seed: Option<u64>,
    /// Replay this script file.
    pub replay: Option<String>,
    pub shrink_replays: u32,
    pub seconds: f64,
    pub hours: f64,
    pub jobs: usize,
    pub first_seed: u64,
    pub planted: Option<PlantedBug>,
    /// `--keep-going`: a campaign does not stop at a run that breaks a per-cycle invariant.
    pub keep_going: bool,
    /// `--help`: print the usage and nothing else.
    pub help: bool,
}

impl Default for Args {
    fn default() -> Self {
        Args {
            seed: None,
            replay: None,
            shrink_replays: 400,
            seconds: 60.0,
            hours: 0.1,
            jobs: 1,
            first_seed: 0,
            planted: None,
            keep_going: false,
            help: false,
        }
    }
}

/// A command line `mcm-dst` refuses.
#[derive(Debug, Clone, PartialEq)]
pub enum ArgError {
    /// An option without its value.
    Missing { option: &'static str },
    /// A value the option does not allow.
    Invalid {
        option: &'static str,
        value: String,
        allowed: &'static str,
    },
    /// Not an option of `mcm-dst`.
    Unknown { arg: String },
}

impl std::fmt::Display for ArgError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ArgError::Missing { option } => write!(f, "{option} needs a value"),
            ArgError::Invalid {
                option,
                value,
                allowed,
            } => write!(f, "{option} {value:?}: allowed is {allowed}"),
            ArgError::Unknown { arg } => write!(f, "unknown argument {arg:?}"),
        }
    }
}

impl std::error::Error for ArgError {}

const SEED: &str = "an integer from 0 to 18446744073709551615";
const POSITIVE: &str = "a finite number above 0";
const JOBS: &str = "an integer from 1";
const REPLAYS: &str = "an integer from 1 to 4294967295";
const PLANTED: &str = "`braking` or `soft-stop`";

/// `value` of `option` as a `T`, else refused with `allowed`.
fn number<T: std::str::FromStr>(
    option: &'static str,
    value: &str,
    allowed: &'static str,
    ok: impl Fn(&T) -> bool,
) -> Result<T, ArgError> {
    value
        .parse()
        .ok()
        .filter(|v| ok(v))
        .ok_or_else(|| ArgError::Invalid {
            option,
            value: value.to_string(),
            allowed,
        })
}

fn positive(x: &f64) -> bool {
    x.is_finite() && *x > 0.0
}

/// The arguments after the program's name.
pub fn parse(args: impl IntoIterator<Item = String>) -> Result<Args, ArgError> {
    let mut out = Args::default();
    let mut args = args.into_iter();
    while let Some(a) = args.next() {
        let option: &'static str = match a.as_str() {
            "-h" | "--help" => {
                out.help = true;
                continue;
            }
            "--keep-going" => {
                out.keep_going = true;
                continue;
            }
            "--seed" => "--seed",
            "--seconds" => "--seconds",
            "--hours" => "--hours",
            "--jobs" => "--jobs",
            "--first-seed" => "--first-seed",
            "--planted-bug" => "--planted-bug",
            "--replay" => "--replay",
            "--shrink-replays" => "--shrink-replays",
            _ => return Err(ArgError::Unknown { arg: a }),
        };
        let value = args.next().ok_or(ArgError::Missing { option })?;
        match option {
            "--seed" => out.seed = Some(number(option, &value, SEED, |_| true)?),
            "--seconds" => out.seconds = number(option, &value, POSITIVE, positive)?,
            "--hours" => out.hours = number(option, &value, POSITIVE, positive)?,
            "--jobs" => out.jobs = number(option, &value, JOBS, |j| *j >= 1)?,
            "--first-seed" => out.first_seed = number(option, &value, SEED, |_| true)?,
            "--replay" => out.replay = Some(value),
            "--shrink-replays" => {
                out.shrink_replays = number(option, &value, REPLAYS, |r| *r >= 1)?;
            }
            _ => {
                out.planted = Some(
                    PLANTED_BUGS
                        .into_iter()
                        .find(|(_, name)| *name == value)
                        .map(|(bug, _)| bug)
                        .ok_or(ArgError::Invalid {
                            option,
                            value,
                            allowed: PLANTED,
                        })?,
                )
            }
        }
    }
    if out.seed.is_some() && out.replay.is_some() {
        return Err(ArgError::Invalid {
            option: "--replay",
            value: out.replay.unwrap_or_default(),
            allowed: "a script without --seed (a script names its own seed)",
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests;
