//! What a run or a replay prints on stderr for a person diagnosing it, chosen by environment
//! variables (nothing is printed without them):
//!
//! - `MCM_DST_TRACE` set: every mode change (cycle, the last error's code, axis and values, the
//!   true angles and speeds), and the quiet phase's client's answers;
//! - `MCM_DST_TRACE_AXIS=N` (1 to 6): axis N's state every cycle, from
//!   `MCM_DST_TRACE_FROM=K` on (default 0): mode, true angle and speed, the measured angle and
//!   speed, the following error, current, i2t level and flags.

use mcm_shared::NUM_AXES;
use mcm_shared::mode::Mode;
use mcm_shared::sample::StateSample;

/// What to print, read once from the environment.
#[derive(Debug, Clone, Copy, Default)]
pub struct Trace {
    pub modes: bool,
    /// The axis (0-based) to print every cycle, and the first cycle.
    pub axis: Option<(usize, u64)>,
}

impl Trace {
    pub fn from_env() -> Trace {
        let axis = std::env::var("MCM_DST_TRACE_AXIS")
            .ok()
            .and_then(|a| a.parse::<usize>().ok())
            .filter(|a| (1..=NUM_AXES).contains(a));
        let from = std::env::var("MCM_DST_TRACE_FROM")
            .ok()
            .and_then(|k| k.parse().ok())
            .unwrap_or(0);
        Trace {
            modes: std::env::var_os("MCM_DST_TRACE").is_some(),
            axis: axis.map(|a| (a - 1, from)),
        }
    }

    /// After cycle `k`, whose state is `s`, the mode before it having been `before`.
    pub fn cycle(&self, k: u64, before: u32, s: &StateSample) {
        if self.modes && s.mode != before {
            eprintln!(
                "cycle {k}: mode {} -> {} (last error: code {} axis {} values {:?}), true angles {:?} deg, velocities {:?} deg/s",
                mode_name(before),
                mode_name(s.mode),
                s.last_error.code,
                s.last_error.axis,
                s.last_error.values,
                s.sim_true_position.map(|x| (x * 100.0).round() / 100.0),
                s.sim_true_velocity.map(|x| (x * 10.0).round() / 10.0),
            );
        }
        if let Some((i, from)) = self.axis
            && k >= from
        {
            eprintln!(
                "cycle {k} {} axis {}: true {:.3} deg {:.2} deg/s, measured {:.3} deg {:.2} deg/s, following error {:.3} deg, current {:.2} A, i2t {:.3}, flags {}",
                mode_name(s.mode),
                i + 1,
                s.sim_true_position[i],
                s.sim_true_velocity[i],
                s.position[i],
                s.velocity[i],
                s.following_error[i],
                s.current[i],
                s.i2t[i],
                s.axis_flags[i],
            );
        }
    }
}

pub fn mode_name(m: u32) -> String {
    Mode::try_from(m).map_or_else(|_| format!("mode {m}"), |m| m.to_string())
}
