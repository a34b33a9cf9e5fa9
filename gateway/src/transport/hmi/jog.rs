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
//! `jog x|y|z|rx|ry|rz [SPEED] [base|tool]` jogs the TCP the same way, with
//! `set_cartesian_velocity`: along (mm/s) or about (deg/s) one axis of the base or the tool
//! frame. On its screen `x`, `y`, `z` choose a direction to move along, `X`, `Y`, `Z` one to
//! turn about, `f` switches between the base and the tool frame (each of them stops first).
//!
//! This file holds the pure parts (keys, the held-key timing, the speeds, the velocity sent on
//! each tick, the line shown); the screen's loop is part of the HMI session
//! (`session/jog_screen.rs`). Not used inside the real-time cycle.

use super::cartesian::three;
use super::keys::{Decoded, Key, KeyDecoder};
use super::telnet::Input;
use mcm_kinematics::rpy_deg_from_quaternion;
use mcm_shared::command::{Axis, CartesianFrame, SetCartesianVelocity};
use mcm_shared::config::RobotConfig;
use mcm_shared::ranges::{Arg, Num, max_velocity_deg_s};
use mcm_shared::sample::{STATE_CARTESIAN, StateSample};
use std::time::{Duration, Instant};

/// What `help jog` adds: both forms, the keys of the screen.
pub const HELP: &str = "\
        jog x|y|z|rx|ry|rz [SPEED] [base|tool]
Hold `+` or `-` (or the arrow keys) to move; letting go stops, any other key stops at once,
`q` stops and leaves in HOLD. An axis moves at SPEED deg/s (default 10, at most its maximum
velocity). The TCP moves along x, y or z at SPEED mm/s (default 20, at most 1000) or turns
about it (rx, ry, rz) at SPEED deg/s (default 10, at most 180), in the axes of the base frame
(the default) or of the tool frame (the TCP's own, as it turns). On the TCP's screen `x` `y`
`z` choose a direction to move along, `X` `Y` `Z` one to turn about, `f` switches the frame.
examples:
  jog 2 20
  jog z 50 tool
  jog rz 15
";

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
/// The TCP's speed of `jog x|y|z` without a speed [mm/s].
pub const DEFAULT_TCP_SPEED_MM_S: f64 = 20.0;
/// The TCP's turning speed of `jog rx|ry|rz` without a speed [deg/s].
pub const DEFAULT_TCP_TURN_DEG_S: f64 = 10.0;
/// Millimetres per metre.
const MM: f64 = 1000.0;

/// A direction the TCP is jogged in: along (`Along`) or about (`About`) the x (0), y (1) or
/// z (2) axis of the jog's frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TcpDirection {
    Along(usize),
    About(usize),
}

impl TcpDirection {
    /// Every direction, in the order of the words `x y z rx ry rz`.
    pub const ALL: [TcpDirection; 6] = [
        TcpDirection::Along(0),
        TcpDirection::Along(1),
        TcpDirection::Along(2),
        TcpDirection::About(0),
        TcpDirection::About(1),
        TcpDirection::About(2),
    ];

    /// The word of `jog WORD`: `x`, `y`, `z`, `rx`, `ry`, `rz`.
    pub fn word(self) -> &'static str {
        match self {
            TcpDirection::Along(i) => ["x", "y", "z"][i],
            TcpDirection::About(i) => ["rx", "ry", "rz"][i],
        }
    }

    /// The direction of `word` (any case).
    pub fn from_word(word: &str) -> Option<TcpDirection> {
        let w = word.to_ascii_lowercase();
        Self::ALL.into_iter().find(|d| d.word() == w)
    }
}

/// A jog of the TCP: its direction, frame and speeds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TcpJog {
    pub direction: TcpDirection,
    pub frame: CartesianFrame,
    /// Along a direction [mm/s].
    pub linear_mm_s: f64,
    /// About a direction [deg/s].
    pub angular_deg_s: f64,
}

impl TcpJog {
    /// The speed of the present direction and its unit.
    pub fn speed(&self) -> (f64, &'static str) {
        match self.direction {
            TcpDirection::Along(_) => (self.linear_mm_s, "mm/s"),
            TcpDirection::About(_) => (self.angular_deg_s, "deg/s"),
        }
    }

    /// The `set_cartesian_velocity` of one tick, `direction` held (`+1`, `-1`, `0`).
    pub fn velocity(&self, direction: i8) -> SetCartesianVelocity {
        let sign = f64::from(direction);
        let (mut linear_m_s, mut angular_deg_s) = ([0.0; 3], [0.0; 3]);
        match self.direction {
            TcpDirection::Along(i) => linear_m_s[i] = sign * self.linear_mm_s / MM,
            TcpDirection::About(i) => angular_deg_s[i] = sign * self.angular_deg_s,
        }
        SetCartesianVelocity {
            linear_m_s,
            angular_deg_s,
            frame: self.frame,
        }
    }

    /// The other frame.
    pub fn toggle_frame(&mut self) {
        self.frame = match self.frame {
            CartesianFrame::Base => CartesianFrame::Tool,
            CartesianFrame::Tool => CartesianFrame::Base,
        };
    }
}

/// What a jog moves: one axis at `speed` [deg/s], or the TCP.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Jogged {
    Axis { axis: Axis, speed: f64 },
    Tcp(TcpJog),
}

/// What a key means on the jog screen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JogKey {
    /// `+`, `=`, Up, Right: towards positive angles.
    Plus,
    /// `-`, `_`, Down, Left: towards negative angles.
    Minus,
    /// `q`, `Q`, Ctrl-C, Ctrl-D: stop and leave.
    Quit,
    /// `x`, `y`, `z` (along), `X`, `Y`, `Z` (about): jog the TCP in this direction (stops
    /// first; an axis jog just stops).
    Choose(TcpDirection),
    /// `f`, `F`: jog the TCP in the other frame (stops first; an axis jog just stops).
    Frame,
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
            Some(Key::Typed(b @ b'x'..=b'z')) => {
                Some(JogKey::Choose(TcpDirection::Along(usize::from(b - b'x'))))
            }
            Some(Key::Typed(b @ b'X'..=b'Z')) => {
                Some(JogKey::Choose(TcpDirection::About(usize::from(b - b'X'))))
            }
            Some(Key::Typed(b'f' | b'F')) => Some(JogKey::Frame),
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

/// The arrow of the held direction.
fn arrow(direction: i8) -> &'static str {
    match direction {
        1 => "  >>> +",
        -1 => "  - <<<",
        _ => "  stop ",
    }
}

/// The status line of the jog screen of an axis (one row, redrawn in place).
pub fn status_line(
    axis: Axis,
    name: &str,
    position_deg: f64,
    velocity_deg_s: f64,
    speed: f64,
    direction: i8,
) -> String {
    let arrow = arrow(direction);
    format!(
        "jog axis {axis} {name:<9} position {position_deg:>9.3} deg  velocity {velocity_deg_s:>8.3} \
         deg/s  {arrow} ({speed} deg/s)"
    )
}

/// Check the speed of a TCP jog in `direction` (mm/s along, deg/s about): above 0, at most
/// what `set_cartesian_velocity` takes for one component ([`Arg::Linear`] in mm/s,
/// [`Arg::Angular`]).
pub fn check_tcp_speed(direction: TcpDirection, speed: f64) -> Result<f64, String> {
    let (max, unit, what) = match direction {
        TcpDirection::Along(_) => (Arg::Linear.fixed_bounds().1 * MM, "mm/s", "along"),
        TcpDirection::About(_) => (Arg::Angular.fixed_bounds().1, "deg/s", "about"),
    };
    if speed > 0.0 && speed <= max {
        Ok(speed)
    } else {
        Err(format!(
            "jog: speed = {} is not allowed; expected a speed above 0 and at most {} {unit} \
             (the TCP's speed {what} one axis)",
            Num(speed),
            Num(max)
        ))
    }
}

/// The status line of the jog screen of the TCP: its pose in the base frame [mm, deg], the
/// direction, the frame and the speed.
pub fn tcp_status_line(jog: &TcpJog, state: &StateSample, direction: i8) -> String {
    let (speed, unit) = jog.speed();
    let what = match jog.direction {
        TcpDirection::Along(i) => format!("along {} ", ["X", "Y", "Z"][i]),
        TcpDirection::About(i) => format!("about {}", ["X", "Y", "Z"][i]),
    };
    let pose = if state.flags & STATE_CARTESIAN == 0 {
        "no TCP pose (not calibrated)".to_string()
    } else {
        let c = &state.cartesian;
        format!(
            "TCP{} mm{} deg",
            three(c.position.map(|x| x * MM), 2),
            three(rpy_deg_from_quaternion(c.orientation), 3)
        )
    };
    format!(
        "jog TCP {what} {} frame  {pose}  {} ({speed} {unit})",
        jog.frame.as_str(),
        arrow(direction)
    )
}

#[cfg(test)]
mod tests;
