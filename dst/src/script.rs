//! A run as a script: every input the world got, in order, with its cycle (the commands of
//! every sender and the bus faults), so that a run can be replayed without the clients, the
//! driver and the fault schedule that made it, and a failing one shrunk ([`crate::shrink`]) to
//! the inputs its failure needs.
//!
//! The world itself (the configuration, the simulated robot's seed, the faulty bus's draws)
//! still comes from the seed: [`seeded`]. The faults the checker is told are under
//! way are derived from the inputs by the world ([`crate::under_way`]), in a run and in a
//! replay alike, so that a replay of the whole script is the run, cycle for cycle.
//!
//! Text form (`Script`'s `Display` and `FromStr`), one input per line after the header:
//!
//! ```text
//! mcm-dst script: seed 37, fault kinds 12, planted braking
//! 4974 command 100 12 6 1 0.5
//! 5000 bus 0.01 0.01 0.0 0.0 0.0 - 0 -
//! ```
//!
//! (`command`: client, request, kind, flags, the arguments up to the last one that is not 0;
//! `bus`: lose_tx, lose_rx, corrupt_rx, duplicate_rx, delay_rx, the node whose heartbeats are
//! lost or `-`, SYNC stuck 0 or 1, the axis index (0-based) whose drive reboots or `-`.)

use crate::faults::Fault;
use crate::faulty_bus::BusFaults;
use crate::invariants::{Checker, Violation, Work};
use crate::run::{PLANTED_BUGS, PlantedBug, planted_name, seeded};
use crate::trace::Trace;
use mcm_shared::sample::{COMMAND_ARGS, CommandSample};
use std::fmt;
use std::str::FromStr;

/// One input to the world, before the step of cycle `cycle`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Event {
    pub cycle: u64,
    pub input: Input,
}

// Nearly every input is a command: boxing them would only add an allocation per input.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Input {
    /// A command arrives (any sender: a client, the driver, the fault injector, the quiet
    /// phase's client).
    Command(CommandSample),
    /// The bus faults from this cycle on.
    Bus(BusFaults),
}

/// A seed's world and the inputs it got.
#[derive(Debug, Clone, PartialEq)]
pub struct Script {
    pub seed: u64,
    /// The fault kinds its world was drawn with ([`crate::run::RunOptions::fault_kinds`]).
    pub fault_kinds: usize,
    pub planted: Option<PlantedBug>,
    pub events: Vec<Event>,
}

/// Replay `script` for at most `cycles` cycles, checking every cycle; the first violation.
pub fn replay(script: &Script, cycles: u64) -> Option<Violation> {
    let (_, _, cfg, mut world) = seeded(script.seed, script.fault_kinds);
    if let Some(bug) = script.planted {
        world.plant(bug);
    }
    let mut checker = Checker::new(&cfg, world.bus().sim());
    let mut next = 0;
    let tracer = Trace::from_env();
    for k in 0..cycles {
        while let Some(e) = script.events.get(next).filter(|e| e.cycle == k) {
            match e.input {
                Input::Command(c) => {
                    checker.asked(&c, k);
                    world.send(c);
                }
                Input::Bus(b) => world.set_bus_faults(b),
            }
            next += 1;
        }
        let before = world.state().mode;
        world.step();
        let work = Work {
            allocations: std::mem::take(&mut world.allocations),
            cpu_ns: world.last_cpu_ns,
        };
        let s = *world.state();
        let k = world.cycle_index();
        tracer.cycle(k, before, &s);
        if let Err(v) = checker.cycle(k, &s, world.replies(), world.served(), work, world.faults())
        {
            return Some(v);
        }
    }
    None
}

impl fmt::Display for Script {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let planted = self.planted.map_or("none", planted_name);
        writeln!(
            f,
            "mcm-dst script: seed {}, fault kinds {}, planted {planted}",
            self.seed, self.fault_kinds
        )?;
        for e in &self.events {
            match e.input {
                Input::Command(c) => {
                    write!(
                        f,
                        "{} command {} {} {} {}",
                        e.cycle, c.client_id, c.request_id, c.kind, c.flags
                    )?;
                    let used = c.args.iter().rposition(|a| *a != 0.0).map_or(0, |i| i + 1);
                    for a in &c.args[..used] {
                        write!(f, " {a:?}")?;
                    }
                    writeln!(f)?;
                }
                Input::Bus(b) => {
                    let hb = b
                        .lose_heartbeats_of
                        .map_or("-".to_string(), |n| n.to_string());
                    let reboot = b.rebooting.map_or("-".to_string(), |a| a.to_string());
                    writeln!(
                        f,
                        "{} bus {:?} {:?} {:?} {:?} {:?} {hb} {} {reboot}",
                        e.cycle,
                        b.lose_tx,
                        b.lose_rx,
                        b.corrupt_rx,
                        b.duplicate_rx,
                        b.delay_rx,
                        u8::from(b.sync_stuck)
                    )?;
                }
            }
        }
        Ok(())
    }
}

/// Why a script's text does not read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ScriptError {
    #[error("line 1 must be `mcm-dst script: seed N, fault kinds K, planted NAME|none`, not {0:?}")]
    Header(String),
    #[error("line {line}: {what} in {text:?}")]
    Line {
        line: usize,
        what: &'static str,
        text: String,
    },
    #[error("line {line}: cycle {cycle} comes before the cycle {before} of the line above")]
    Order {
        line: usize,
        cycle: u64,
        before: u64,
    },
}

impl FromStr for Script {
    type Err = ScriptError;

    fn from_str(text: &str) -> Result<Script, ScriptError> {
        let mut lines = text.lines();
        let header = lines.next().unwrap_or("");
        let (seed, fault_kinds, planted) = header
            .strip_prefix("mcm-dst script: seed ")
            .and_then(|rest| rest.split_once(", fault kinds "))
            .and_then(|(seed, rest)| {
                let (kinds, name) = rest.split_once(", planted ")?;
                let seed = seed.parse::<u64>().ok()?;
                let kinds = kinds
                    .parse::<usize>()
                    .ok()
                    .filter(|k| *k <= Fault::ALL.len())?;
                let planted = match name.trim() {
                    "none" => None,
                    n => Some(PLANTED_BUGS.iter().find(|(_, m)| *m == n)?.0),
                };
                Some((seed, kinds, planted))
            })
            .ok_or_else(|| ScriptError::Header(header.to_string()))?;
        let mut events = Vec::new();
        for (n, line) in lines.enumerate() {
            let line_no = n + 2;
            if line.trim().is_empty() {
                continue;
            }
            let bad = |what| ScriptError::Line {
                line: line_no,
                what,
                text: line.to_string(),
            };
            let words: Vec<&str> = line.split_whitespace().collect();
            let cycle: u64 = words[0].parse().map_err(|_| bad("no cycle number"))?;
            let input = match words.get(1).copied() {
                Some("command") if (6..=6 + COMMAND_ARGS).contains(&words.len()) => {
                    let n = |i: usize| words[i].parse::<u64>().map_err(|_| bad("not a number"));
                    let mut args = [0.0; COMMAND_ARGS];
                    for (a, w) in args.iter_mut().zip(&words[6..]) {
                        *a = w.parse().map_err(|_| bad("an argument is not a number"))?;
                    }
                    Input::Command(CommandSample {
                        client_id: n(2)?,
                        request_id: n(3)?,
                        kind: u32::try_from(n(4)?).map_err(|_| bad("kind beyond u32"))?,
                        flags: u32::try_from(n(5)?).map_err(|_| bad("flags beyond u32"))?,
                        args,
                    })
                }
                Some("bus") if words.len() == 10 => {
                    let p = |i: usize| {
                        words[i]
                            .parse::<f64>()
                            .map_err(|_| bad("a chance is not a number"))
                    };
                    Input::Bus(BusFaults {
                        lose_tx: p(2)?,
                        lose_rx: p(3)?,
                        corrupt_rx: p(4)?,
                        duplicate_rx: p(5)?,
                        delay_rx: p(6)?,
                        lose_heartbeats_of: match words[7] {
                            "-" => None,
                            w => Some(w.parse().map_err(|_| bad("not a node id or -"))?),
                        },
                        sync_stuck: match words[8] {
                            "0" => false,
                            "1" => true,
                            _ => return Err(bad("SYNC stuck is not 0 or 1")),
                        },
                        rebooting: match words[9] {
                            "-" => None,
                            w => Some(w.parse().map_err(|_| bad("not an axis index or -"))?),
                        },
                    })
                }
                _ => {
                    return Err(bad(
                        "not `CYCLE command CLIENT REQUEST KIND FLAGS ARGS...` or `CYCLE bus ...`",
                    ));
                }
            };
            if let Some(before) = events.last().map(|e: &Event| e.cycle)
                && cycle < before
            {
                return Err(ScriptError::Order {
                    line: line_no,
                    cycle,
                    before,
                });
            }
            events.push(Event { cycle, input });
        }
        Ok(Script {
            seed,
            fault_kinds,
            planted,
            events,
        })
    }
}

#[cfg(test)]
mod tests;
