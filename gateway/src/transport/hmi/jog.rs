//! `jog AXIS [SPEED]`: drive one axis from the keyboard in VELOCITY_CONTROL. The session
//! enters VELOCITY_CONTROL, shows the axis's position live and sends `set_velocities` every
//! [`JOG_PERIOD`]: the chosen speed while `+` (or Up/Right) or `-` (or Down/Left) is held down,
//! 0 otherwise; `q` (or Ctrl-C, Ctrl-D) stops the axis with `hold` and leaves the screen.
//!
//! A terminal sends nothing while a key is held but its auto-repeat: the first repeat comes
//! after a delay (typically 250 to 660 ms), then about 30 per second. So a key counts as held
//! for [`FIRST_GAP`] after it was pressed and, once it repeats, for [`REPEAT_GAP`] after each
//! repeat; any other key stops at once. If the gateway stops sending, the core's own timeout
//! ([`JOG_TIMEOUT_S`]) stops the axis.
//!
//! This file holds the pure parts (keys, the held-key timing, the speed, the line shown); the
//! screen's loop is part of the HMI session (`session/jog_screen.rs`). Not used inside the
//! real-time cycle.
//!
//! **Cartesian jogging goes here**; the jog screen does not offer it yet (it jogs axes only),
//! though the protocol has `set_cartesian_velocity`: `jog x|y|z|rx|ry|rz [SPEED] [base|tool]`
//! parsed beside `jog AXIS` (`words::parse_jog`), the same keys and [`Held`] timing, the
//! velocity sent on each tick built beside [`velocities`] (a twist along or about the chosen
//! direction in mm/s or deg/s, converted once as `super::cartesian` converts), the loop
//! entering VELOCITY_CONTROL as it does now, and a status line showing the TCP
//! (`super::cartesian`'s millimetres and degrees) beside [`status_line`].

use super::keys::{Decoded, Key, KeyDecoder};
use super::telnet::Input;
use mcm_shared::command::Axis;
use mcm_shared::config::RobotConfig;
use mcm_shared::ranges::{Num, max_velocity_deg_s};
use std::time::{Duration, Instant};

/// Interval of `set_velocities` and of the position shown.
pub const JOG_PERIOD: Duration = Duration::from_millis(50);
/// How long a key press counts as held before its auto-repeat starts.
pub const FIRST_GAP: Duration = Duration::from_millis(700);
/// How long a repeating key counts as held after each repeat.
pub const REPEAT_GAP: Duration = Duration::from_millis(200);
/// The `velocity_control` timeout of a jog [s]: the core stops the axis by itself when the
/// gateway stops sending.
pub const JOG_TIMEOUT_S: f64 = 0.5;
/// The speed of `jog AXIS` without a speed [deg/s] (at most the axis's maximum).
pub const DEFAULT_JOG_SPEED: f64 = 10.0;

/// What a key means on the jog screen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JogKey {
    /// `+`, `=`, Up, Right: towards positive angles.
    Plus,
    /// `-`, `_`, Down, Left: towards negative angles.
    Minus,
    /// `q`, `Q`, Ctrl-C, Ctrl-D: stop and leave.
    Quit,
    /// Any other key: stop.
    Stop,
}

/// Turns the session's inputs into [`JogKey`]s through the HMI's one key decoder
/// ([`super::keys`]): an escape sequence is one key as a whole (the arrows move, any other
/// stops), never a key per byte, so a title string or a terminal's report holding `+` moves
/// nothing.
#[derive(Debug, Default)]
pub struct JogKeys {
    keys: KeyDecoder,
}

impl JogKeys {
    /// The key that `input` completes, if any.
    pub fn feed(&mut self, input: Input) -> Option<JogKey> {
        let b = match input {
            Input::Byte(b) => b,
            Input::Interrupt | Input::EndOfFile => {
                self.keys.reset();
                return Some(JogKey::Quit);
            }
            Input::Enter | Input::EraseChar | Input::EraseLine => {
                self.keys.reset();
                return Some(JogKey::Stop);
            }
        };
        let Decoded { dropped, key } = self.keys.byte(b);
        match key {
            Some(Key::Typed(b'+' | b'=')) => Some(JogKey::Plus),
            Some(Key::Typed(b'-' | b'_')) => Some(JogKey::Minus),
            Some(Key::Typed(b'q' | b'Q' | 0x03 | 0x04)) => Some(JogKey::Quit),
            Some(Key::Typed(_)) => Some(JogKey::Stop),
            // Up and Right, Down and Left (with modifiers too, e.g. `ESC [ 1 ; 5 C`).
            Some(Key::Csi(k)) => Some(match k.last {
                b'A' | b'C' => JogKey::Plus,
                b'B' | b'D' => JogKey::Minus,
                _ => JogKey::Stop,
            }),
            // Another sequence is another key: it stops.
            None if dropped => Some(JogKey::Stop),
            None => None,
        }
    }
}

/// Which direction is held, from the key presses and their timing.
#[derive(Debug, Clone, Copy, Default)]
pub struct Held {
    direction: i8,
    last: Option<Instant>,
    repeating: bool,
}

impl Held {
    /// A direction key (`+1` or `-1`) was pressed at `now`.
    pub fn press(&mut self, direction: i8, now: Instant) {
        self.repeating = self.direction == direction && self.last.is_some();
        self.direction = direction;
        self.last = Some(now);
    }

    /// Stop at once (another key).
    pub fn stop(&mut self) {
        *self = Held::default();
    }

    /// The direction held at `now`: `+1`, `-1` or `0` once the key was let go.
    pub fn direction(&mut self, now: Instant) -> i8 {
        let gap = if self.repeating {
            REPEAT_GAP
        } else {
            FIRST_GAP
        };
        match self.last {
            Some(t) if now.saturating_duration_since(t) <= gap => self.direction,
            _ => {
                self.stop();
                0
            }
        }
    }
}

/// The six velocities [deg/s] of a jog of `axis` at `speed` in `direction`.
pub fn velocities(axis: Axis, speed: f64, direction: i8) -> [f64; 6] {
    let mut v = [0.0; 6];
    v[axis.index()] = speed * f64::from(direction);
    v
}

/// The speed of `jog AXIS` without one: [`DEFAULT_JOG_SPEED`], at most the axis's maximum.
pub fn default_speed(cfg: &RobotConfig, axis: Axis) -> f64 {
    DEFAULT_JOG_SPEED.min(max_velocity_deg_s(cfg, axis.index()))
}

/// Check the speed of a jog: above 0, at most the axis's maximum velocity (the figure of
/// [`mcm_shared::ranges`] that bounds `set_velocities`; a jog speed is not a protocol argument,
/// so it has no row of its own, and its numbers are written as the table's are).
pub fn check_speed(cfg: &RobotConfig, axis: Axis, speed: f64) -> Result<f64, String> {
    let max = max_velocity_deg_s(cfg, axis.index());
    if speed > 0.0 && speed <= max {
        Ok(speed)
    } else {
        Err(format!(
            "jog: speed = {} is not allowed; expected a speed above 0 and at most {} deg/s \
             (the maximum velocity of axis {axis})",
            Num(speed),
            Num(max)
        ))
    }
}

/// The status line of the jog screen (one row, redrawn in place).
pub fn status_line(
    axis: Axis,
    name: &str,
    position_deg: f64,
    velocity_deg_s: f64,
    speed: f64,
    direction: i8,
) -> String {
    let arrow = match direction {
        1 => "  >>> +",
        -1 => "  - <<<",
        _ => "  stop ",
    };
    format!(
        "jog axis {axis} {name:<9} position {position_deg:>9.3} deg  velocity {velocity_deg_s:>8.3} \
         deg/s  {arrow} ({speed} deg/s)"
    )
}

#[cfg(test)]
mod tests;
