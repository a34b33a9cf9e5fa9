//! The torque loop over TCP: `torque_control` with `dt_status` = one period, every status
//! result answered with a `set_torques`; [`crate::loopmatch`] tells from the next status in
//! which cycle each answer was applied.

use crate::client::{Client, HOLD, is_error, line, status_of};
use crate::error::BenchError;
use crate::loopmatch::{Answer, LEVELS_NM, Observation, Tally, classify, cycle_numbers, level_of};
use mcm_shared::command::{SetTorques, TorqueControl};
use mcm_shared::mode::Mode;
use mcm_shared::protocol;
use std::net::SocketAddr;
use std::time::{Duration, Instant};

/// Timeout of the torque session [s]: a loop that stops answering falls back to HOLD.
pub const SESSION_TIMEOUT_S: f64 = 0.2;
/// How long the loop tries to enter TORQUE_CONTROL (or take control) while refused.
pub const OWNER_WAIT: Duration = Duration::from_secs(2);
/// States read with zero torques to measure the compensation on axis 6.
const BASELINE_STATES: usize = 10;
/// States read after the last answer, to see where it was applied.
const TAIL_STATES: usize = 3;

/// What one torque loop saw.
#[derive(Debug, Clone, Default)]
pub struct LoopOutcome {
    pub tally: Tally,
    /// Answers refused (ERROR results or refused replies).
    pub errors: u64,
    /// The same state seen twice (TCP: a status result of a cycle already answered).
    pub repeats: u64,
    /// Why the loop ended before its count, if it did.
    pub ended_early: Option<String>,
    /// Axis-6 torque with zero `set_torques` (the compensation) [Nm].
    pub baseline_nm: f64,
    /// How the loop waited for a new state (shared memory only).
    pub wait_mode: &'static str,
}

/// The `set_torques` line for `axis6_nm` on axis 6 and none on the others.
fn set_torques_line(axis6_nm: f64) -> String {
    line(SetTorques {
        torques_nm: [0.0, 0.0, 0.0, 0.0, 0.0, axis6_nm],
    })
}

/// The `set_torques` line of every level of [`LEVELS_NM`], encoded once: answer `k` sends
/// `levels[level_of(k)]`.
pub fn set_torques_lines() -> Vec<String> {
    LEVELS_NM.iter().map(|&nm| set_torques_line(nm)).collect()
}

/// Median of a non-empty list.
pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Run the loop for `cycles` answers on a new connection; `kt6`: axis 6's torque per ampere.
pub fn tcp_loop(
    addr: SocketAddr,
    cycles: u64,
    period_s: f64,
    kt6: f64,
) -> Result<LoopOutcome, BenchError> {
    let mut c = Client::connect(addr)?;
    c.ok(&HOLD)?;
    let enter = line(protocol::TorqueControl {
        request: TorqueControl {
            timeout_s: Some(SESSION_TIMEOUT_S),
            gravity_compensation: true,
        },
        dt_status: period_s,
    });
    let zeros = set_torques_line(0.0);
    let answers = set_torques_lines();
    // The client of an earlier phase may still own motion for a moment after it closed its
    // connection: try again for a bounded time.
    let deadline = Instant::now() + OWNER_WAIT;
    loop {
        let r = c.request(&enter)?;
        if status_of(&r).is_some_and(|s| s.mode == Mode::TorqueControl) {
            break;
        }
        if Instant::now() > deadline {
            return Err(BenchError::Protocol {
                command: enter,
                answer: r.to_value().to_string(),
            });
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let mut out = LoopOutcome {
        wait_mode: "status results (dt_status)",
        ..LoopOutcome::default()
    };
    // The compensation alone: zero torques, then the axis-6 current of a few states.
    c.send(&zeros)?;
    let mut last_t = f64::NEG_INFINITY;
    let mut base = Vec::with_capacity(BASELINE_STATES);
    while base.len() < BASELINE_STATES {
        let v = c.recv()?;
        if is_error(&v) {
            return Err(BenchError::Protocol {
                command: "set_torques (zeros)".into(),
                answer: v.to_value().to_string(),
            });
        }
        if let Some(s) = status_of(&v)
            && s.time() > last_t
        {
            last_t = s.time();
            base.push(s.axis_states.current[5] * kt6);
            // Keep the session alive while measuring.
            c.send(&zeros)?;
        }
    }
    out.baseline_nm = median(&mut base);

    let mut times = Vec::with_capacity(cycles as usize + TAIL_STATES);
    let mut levels = Vec::with_capacity(cycles as usize + TAIL_STATES);
    let mut answered = Vec::with_capacity(cycles as usize);
    let mut k = 0u64;
    let mut tail = 0;
    while tail < TAIL_STATES {
        let v = c.recv()?;
        if is_error(&v) {
            out.errors += 1;
            continue;
        }
        let Some(s) = status_of(&v) else {
            continue;
        };
        let (t, i) = (s.time(), s.axis_states.current[5]);
        if s.mode != Mode::TorqueControl {
            out.ended_early = Some(format!("left TORQUE_CONTROL after {k} answers: {}", s.mode));
            break;
        }
        if t <= last_t {
            out.repeats += 1;
            continue;
        }
        last_t = t;
        times.push(t);
        levels.push(classify(i * kt6 - out.baseline_nm));
        if k < cycles {
            c.send(&answers[level_of(k)])?;
            answered.push((times.len() - 1, level_of(k)));
            k += 1;
        } else {
            tail += 1;
        }
    }
    c.send(&HOLD)?;
    let numbers = cycle_numbers(&times, period_s);
    let observations: Vec<Observation> = numbers
        .iter()
        .zip(&levels)
        .map(|(&cycle, &level)| Observation { cycle, level })
        .collect();
    let answers: Vec<Answer> = answered
        .iter()
        .map(|&(idx, level)| Answer {
            cycle: numbers[idx],
            level,
        })
        .collect();
    out.tally = crate::loopmatch::tally(&observations, &answers);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn answers_step_through_the_levels() {
        let cfg = mcm_shared::config::RobotConfig::prob2_default();
        let lines = set_torques_lines();
        assert_eq!(lines.len(), LEVELS_NM.len());
        let cmd = protocol::Command::from_json(&lines[level_of(1)], &cfg).unwrap();
        let protocol::Command::SetTorques(t) = cmd else {
            panic!("{cmd:?}")
        };
        assert_eq!(
            t.torques_nm,
            [0.0, 0.0, 0.0, 0.0, 0.0, LEVELS_NM[level_of(1)]]
        );
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
    }
}
