//! Results for people: the protocol's typed results ([`mcm_shared::protocol::results`], the same
//! as on the JSON channel) turned into aligned tables with units, modes and errors in words, and
//! hints that say how to fix what went wrong. Output uses `\n`; the session turns it into the
//! terminal's `\r\n`. Not used inside the real-time cycle.
//!
//! Text from outside the HMI (the configuration's robot and axis names, the core's and the
//! gateway's messages, other clients' words) goes in through [`visible`], where it is
//! inserted: its control characters are shown, so it can hold neither a line end nor an escape
//! sequence, not even one of the HMI's own colours.

use super::words::LineError;
use mcm_shared::NUM_AXES;
use mcm_shared::config::RobotConfig;
use mcm_shared::error_code::ErrorCode;
use mcm_shared::mode::Mode;
use mcm_shared::protocol;
use mcm_shared::protocol::results::{
    Answer, Detail, Generic, Info, InverseKinematicsResult, MoveAllResult, MoveLinearResult,
    PayloadResult, SimResult, Status,
};
use mcm_shared::sample::{
    AXIS_CALIBRATED, STATE_ALL_CALIBRATED, STATE_ESTOP, STATE_PVT_STARVED, StateSample,
};
use serde_json::Value;
use std::fmt::Write as _;

/// ANSI: bold red, green, yellow, bold, reset.
pub const RED: &str = "\x1b[1;31m";
pub const GREEN: &str = "\x1b[32m";
pub const YELLOW: &str = "\x1b[33m";
pub const BOLD: &str = "\x1b[1m";
pub const RESET: &str = "\x1b[0m";

/// The mode of a state sample by name ("UNKNOWN" for a value this version does not know).
pub fn mode_name(state: &StateSample) -> &'static str {
    Mode::try_from(state.mode)
        .map(Mode::as_str)
        .unwrap_or("UNKNOWN")
}

/// What a mode means, in words.
pub fn mode_words(mode: &str) -> &'static str {
    match mode {
        "OFF" => "drives powered off; `hold` powers them, `calibrate` homes the axes",
        "ERROR" => {
            "a safety check stopped the robot; `hold` clears the error once its cause is gone"
        }
        "HOLD" => "axes hold their positions",
        "RELEASE" => "the arm can be moved by hand",
        "TORQUE_CONTROL" => "joint torques come from `set_torques`",
        "VELOCITY_CONTROL" => "joint velocities come from `set_velocities` (or `jog`)",
        "PVT" => "position control: `move_axis`, `move_all`, `pvt_points`",
        "CALIBRATION" => "calibration is running",
        _ => "unknown mode",
    }
}

fn mode_color(mode: &str) -> &'static str {
    match mode {
        "ERROR" => RED,
        "OFF" | "CALIBRATION" => YELLOW,
        _ => GREEN,
    }
}

/// The prompt, e.g. `mcm HOLD> ` (the mode coloured).
pub fn prompt(state: Option<&StateSample>) -> String {
    match state {
        Some(s) => {
            let m = mode_name(s);
            format!("mcm {}{m}{RESET}> ", mode_color(m))
        }
        None => format!("mcm {YELLOW}NO-CORE{RESET}> "),
    }
}

/// The greeting of a new session.
pub fn banner(cfg: &RobotConfig, state: Option<&StateSample>, instance: &str) -> String {
    let mut s = format!(
        "{BOLD}MCM {} - Motion Control Module, text HMI{RESET}\nrobot: {}\n",
        mcm_shared::VERSION,
        visible(&cfg.robot.name)
    );
    match state {
        Some(st) => {
            let m = mode_name(st);
            let _ = writeln!(s, "mode:  {}{m}{RESET} - {}", mode_color(m), mode_words(m));
        }
        None => {
            let _ = writeln!(
                s,
                "mode:  unknown - {YELLOW}the real-time core (instance `{}`) is not running{RESET}; commands fail until it starts",
                visible(instance)
            );
        }
    }
    s.push_str("Type `help` for the commands, `help CMD` for one of them, `quit` to leave.\n");
    s
}

/// The replacement shown for a non-ASCII character: the HMI writes only ASCII.
pub const NON_ASCII: char = '?';

/// A control character (0x00-0x1F, 0x7F) in caret notation: ESC as `^[`, BEL as `^G`, a line
/// end as `^J`, DEL as `^?`.
pub fn caret(b: u8) -> [u8; 2] {
    [b'^', b ^ 0x40]
}

/// Text from outside the HMI as it is shown: every control character in caret notation
/// ([`caret`]), line ends and ESC included, every non-ASCII character as [`NON_ASCII`].
pub fn visible(s: &str) -> std::borrow::Cow<'_, str> {
    if s.bytes().all(|b| (0x20..0x7F).contains(&b)) {
        return s.into();
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        match u8::try_from(c) {
            Ok(b) if b < 0x20 || b == 0x7F => out.extend(caret(b).map(char::from)),
            Ok(b) if b < 0x80 => out.push(c),
            _ => out.push(NON_ASCII),
        }
    }
    out.into()
}

/// `s` with every non-ASCII character shown as [`NON_ASCII`] (one column each, as the line
/// editor counts them).
pub fn ascii(s: &str) -> std::borrow::Cow<'_, str> {
    if s.is_ascii() {
        s.into()
    } else {
        s.chars()
            .map(|c| if c.is_ascii() { c } else { NON_ASCII })
            .collect::<String>()
            .into()
    }
}

/// Pretty JSON (for lines typed as JSON), pure ASCII.
pub fn pretty(v: &Value) -> String {
    let mut s = mcm_shared::protocol::json::to_ascii_pretty(v);
    s.push('\n');
    s
}

/// A result of `command` for people. `state` (the reply's, or the newest) adds notes such as
/// uncalibrated axes or the last safety error.
pub fn answer(command: &str, v: &Answer, cfg: &RobotConfig, state: Option<&StateSample>) -> String {
    match v {
        Answer::Status(st) => status(st, cfg, state),
        Answer::MoveAll(m) => move_all(m, cfg),
        Answer::MoveLinear(m) => move_linear(m),
        Answer::Initialization(i) => info(i),
        Answer::Sim(r) => sim(r, cfg),
        Answer::InverseKinematics(r) => inverse_kinematics(r),
        Answer::Payload(p) => payload(p),
        Answer::Generic(g) if g.is_ok() => {
            let words = protocol::find(command).map_or("", |d| d.ok_words);
            format!("{GREEN}OK{RESET}{words}\n")
        }
        Answer::Generic(g) => error(command, g, state),
    }
}

/// The start of an error line: `error` and its code in brackets (`error [wrong_mode]:`).
fn error_head(code: Option<&str>) -> String {
    match code {
        Some(c) => format!("{RED}error [{}]:{RESET}", visible(c)),
        None => format!("{RED}error:{RESET}"),
    }
}

/// An ERROR result `g` of `command`, with its code and a hint on how to fix it.
pub fn error(command: &str, g: &Generic, state: Option<&StateSample>) -> String {
    let mut s = format!(
        "{} {}\n",
        error_head(g.error_code.as_deref()),
        visible(g.message())
    );
    let spec = protocol::find(command);
    let hint = if g.code() == Some(ErrorCode::CoreUnavailable) {
        Some(
            "the real-time core (mcm-rt) is not running: start it (the `mcm` launcher starts both \
             processes), then try again"
                .to_string(),
        )
    } else if g.code() == Some(ErrorCode::WrongMode)
        && let Some(spec) = spec
    {
        let now = state.map(mode_name).unwrap_or("unknown");
        let how = if now == "HOLD" {
            spec.how.replace("`hold`, then ", "")
        } else {
            spec.how.to_string()
        };
        Some(format!(
            "`{command}` is accepted in {}; the mode is {now}. {}",
            spec.modes,
            capitalise(&how)
        ))
    } else if g.code() == Some(ErrorCode::OutcomeUnknown) {
        Some("the real-time core did not answer in time; `status` shows whether it runs".into())
    } else {
        None
    };
    if let Some(h) = hint {
        let _ = writeln!(s, "  hint: {h}");
    }
    s
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_uppercase().chain(c).collect::<String>() + ".",
        None => String::new(),
    }
}

/// A line the parser refused, with the usage of its command.
pub fn line_error(e: &LineError) -> String {
    let mut s = format!(
        "{} {}\n",
        error_head(Some(e.code().as_str())),
        visible(&e.to_string())
    );
    if let Some(spec) = e.command() {
        let _ = writeln!(
            s,
            "  usage: {}\n  (`help {}` explains the arguments)",
            spec.usage(),
            spec.name
        );
    }
    s
}

/// A notice about the MCM's own life (`crate::core_link::lifecycle::Notice`): the words the
/// JSON/TCP and ZeroMQ clients get as a `generic` ERROR result, as an ERROR line.
pub fn notice(code: ErrorCode, text: &str) -> String {
    format!("{RED}ERROR [{code}]: {text}{RESET}\n")
}

/// A spontaneous safety error ([`Generic::safety_event`]).
pub fn safety(e: &Generic) -> String {
    let words = match e.message() {
        "" => "safety check tripped",
        m => m,
    };
    format!(
        "{RED}*** {}{RESET}\n  hint: once the cause is gone, `hold` clears the error\n",
        visible(words)
    )
}

/// The name of axis `i + 1` in the configuration, as shown.
pub fn axis_name(cfg: &RobotConfig, i: usize) -> std::borrow::Cow<'_, str> {
    visible(cfg.axes.get(i).map_or("", |a| a.name.as_str()))
}

fn num(x: f64, width: usize, decimals: usize) -> String {
    if x.is_finite() {
        format!("{x:>width$.decimals$}")
    } else {
        format!("{:>width$}", "-")
    }
}

/// The status result as a table.
pub fn status(v: &Status, cfg: &RobotConfig, state: Option<&StateSample>) -> String {
    let mode = v.mode.as_str();
    let axes = &v.axis_states;
    let mut s = format!(
        "mode {}{mode}{RESET} - {}   (t = {} s)\n",
        mode_color(mode),
        mode_words(mode),
        num(v.time(), 0, 3)
    );
    let d = v.detail.as_ref();
    for (i, row) in [
        ["axis", "name", "position", "velocity", "current"],
        ["", "", "deg", "deg/s", "A"],
    ]
    .iter()
    .enumerate()
    {
        let mut line = format!(
            "{:>4}  {:<9} {:>11} {:>11} {:>11}",
            row[0], row[1], row[2], row[3], row[4]
        );
        if d.is_some() {
            let extra = [
                ["commanded", "measured", "foll. err", "i2t", "calibrated"],
                ["deg", "deg", "deg", "%", ""],
            ][i];
            let _ = write!(
                line,
                " {:>11} {:>11} {:>10} {:>7}  {:>10}",
                extra[0], extra[1], extra[2], extra[3], extra[4]
            );
        }
        s.push_str(line.trim_end());
        s.push('\n');
    }
    for i in 0..6 {
        let _ = write!(
            s,
            "{:>4}  {:<9} {} {} {}",
            i + 1,
            axis_name(cfg, i),
            num(axes.position[i], 11, 3),
            num(axes.velocity[i], 11, 3),
            num(axes.current[i], 11, 3)
        );
        if let Some(d) = d {
            let c = if d.calibrated[i] { "yes" } else { "NO" };
            let _ = write!(
                s,
                " {} {} {} {}  {c:>10}",
                num(d.commanded_position[i], 11, 3),
                num(d.measured_position[i], 11, 3),
                num(d.following_error[i], 10, 3),
                num(d.i2t[i] * 100.0, 7, 1)
            );
        }
        s.push('\n');
    }
    if let Some(d) = d {
        detail_lines(&mut s, v.hardware_status.as_deref(), d);
    }
    if let Some(st) = state {
        notes(&mut s, st);
    }
    s
}

fn detail_lines(s: &mut String, hardware: Option<&str>, d: &Detail) {
    if let Some(h) = hardware {
        let _ = writeln!(s, "hardware:  {}", visible(h));
    }
    if let Some(a) = &d.access {
        let refused = a
            .refused
            .iter()
            .map(|(k, n)| format!("{k} {n}"))
            .collect::<Vec<_>>()
            .join(", ");
        let _ = writeln!(
            s,
            "access:    motion from {}{}; secret {}; refused so far: {refused}",
            visible(&a.motion_networks),
            if a.motion_allowed_here {
                ""
            } else {
                " (NOT from this session's address)"
            },
            match (a.secret_required, a.authenticated) {
                (false, _) => "not required",
                (true, true) => "required, presented by this session",
                (true, false) => "required, NOT presented by this session (`authenticate`)",
            },
        );
    }
    let q = &d.pvt_queue;
    let _ = writeln!(
        s,
        "PVT queue: {} of {} points{}",
        q.queued,
        q.capacity,
        if q.starved {
            " (ran dry: the axes stopped and hold)"
        } else {
            ""
        }
    );
    let tm = &d.timing;
    let period = tm.period_s;
    let us = |x: f64| {
        if x.is_finite() {
            format!("{x:.0}")
        } else {
            "-".to_string()
        }
    };
    let _ = writeln!(
        s,
        "cycle:     {} ms ({} Hz), wake-up latency p50 {} us, p99 {} us, max {} us; longest work {} us; overruns {}{}",
        num(period * 1e3, 0, 3),
        num(1.0 / period, 0, 0),
        us(tm.latency_p50_us),
        us(tm.latency_p99_us),
        us(tm.latency_max_us),
        us(tm.work_max_us),
        tm.overruns,
        if tm.realtime {
            String::new()
        } else {
            format!(" {YELLOW}(NOT real-time){RESET}")
        }
    );
    let b = &d.bus;
    let lost = b.bad_frames + b.frames_dropped + b.events_dropped + b.bus_errors;
    let (on, off) = if lost > 0 { (YELLOW, RESET) } else { ("", "") };
    let _ = writeln!(
        s,
        "bus:       {on}bad frames {}, frames dropped {}, events dropped {}, bus errors {}{off}",
        b.bad_frames, b.frames_dropped, b.events_dropped, b.bus_errors
    );
}

/// Notes from the state: emergency stop, uncalibrated axes, the last safety error.
fn notes(s: &mut String, st: &StateSample) {
    if st.flags & STATE_ESTOP != 0 {
        let _ = writeln!(
            s,
            "{RED}emergency stop PRESSED{RESET}: release it, then `hold`"
        );
    }
    if st.flags & STATE_ALL_CALIBRATED == 0 {
        let axes: Vec<String> = (0..6)
            .filter(|i| st.axis_flags[*i] & AXIS_CALIBRATED == 0)
            .map(|i| (i + 1).to_string())
            .collect();
        if !axes.is_empty() {
            let _ = writeln!(
                s,
                "{YELLOW}not calibrated:{RESET} {} {} (positions are raw encoder positions; run `calibrate`)",
                if axes.len() == 1 { "axis" } else { "axes" },
                axes.join(", ")
            );
        }
    }
    if st.mode == Mode::Error.to_wire()
        && let Some(e) = Generic::last_error(&st.last_error)
    {
        let _ = writeln!(s, "{RED}last error:{RESET} {}", visible(e.message()));
    }
    if st.mode == Mode::Pvt.to_wire() && st.flags & STATE_PVT_STARVED != 0 {
        let _ = writeln!(s, "PVT queue ran dry: the axes stopped and hold");
    }
}

/// The move_all result: timing and velocity of each axis.
pub fn move_all(v: &MoveAllResult, cfg: &RobotConfig) -> String {
    let longest = usize::from(v.longest);
    let mut s = format!(
        "{GREEN}OK{RESET} - every axis arrives within {} s; axis {longest} ({}) takes longest\n",
        num(v.max_time_to_target, 0, 3),
        axis_name(cfg, longest.wrapping_sub(1))
    );
    let _ = writeln!(s, "{:>4}  {:<9} {:>11}", "axis", "name", "velocity");
    let _ = writeln!(s, "{:>4}  {:<9} {:>11}", "", "", "deg/s");
    for (i, vel) in v.velocities.iter().enumerate() {
        let mark = if i + 1 == longest { "  <- longest" } else { "" };
        let _ = writeln!(
            s,
            "{:>4}  {:<9} {}{mark}",
            i + 1,
            axis_name(cfg, i),
            num(*vel, 11, 3)
        );
    }
    s
}

/// The move_linear result: when the TCP arrives, and each axis's position there.
pub fn move_linear(v: &MoveLinearResult) -> String {
    let mut s = format!(
        "{GREEN}OK{RESET} - the TCP arrives in {} s; the axes there [deg]:",
        num(v.duration, 0, 3)
    );
    for x in &v.joint_target {
        let _ = write!(s, " {}", num(*x, 0, 3));
    }
    s.push('\n');
    s
}

/// The inverse_kinematics result: one row per solution, the nearest to the seed first, one
/// column per axis.
pub fn inverse_kinematics(v: &InverseKinematicsResult) -> String {
    let n = v.solutions.len();
    let mut s = format!(
        "{GREEN}OK{RESET} - {n} solution{} within the axis limits, the nearest to the seed first\n",
        if n == 1 { "" } else { "s" }
    );
    let _ = write!(s, "{:>8}", "solution");
    for i in 1..=NUM_AXES {
        let _ = write!(s, " {:>9}", format!("axis {i}"));
    }
    let _ = write!(s, "\n{:>8}", "");
    for _ in 0..NUM_AXES {
        let _ = write!(s, " {:>9}", "deg");
    }
    s.push('\n');
    for (k, q) in v.solutions.iter().enumerate() {
        let _ = write!(s, "{:>8}", k + 1);
        for x in q {
            let _ = write!(s, " {}", num(*x, 9, 3));
        }
        s.push('\n');
    }
    s
}

/// The `payload` result (`identify_payload`).
pub fn payload(p: &PayloadResult) -> String {
    let [x, y, z] = p.center_of_mass.map(|v| v * 1000.0);
    format!(
        "{GREEN}OK{RESET} - payload {} kg, centre of mass ({}, {}, {}) mm in the flange frame, residual {} N m\n",
        num(p.mass, 0, 3).trim(),
        num(x, 0, 1).trim(),
        num(y, 0, 1).trim(),
        num(z, 0, 1).trim(),
        num(p.residual, 0, 3).trim()
    )
}

/// The initialization result (`info`).
pub fn info(v: &Info) -> String {
    let cycle = v.cycle_time;
    let mut s = format!(
        "{}, MCM {}, {} axes, cycle {} ms ({} Hz), {}\n",
        visible(&v.robot),
        v.version,
        v.num_axes,
        num(cycle * 1e3, 0, 3),
        num(1.0 / cycle, 0, 0),
        if v.simulated {
            "simulated robot"
        } else {
            "real hardware"
        }
    );
    for row in [
        [
            "axis",
            "name",
            "min",
            "max",
            "max vel",
            "max acc",
            "max torque",
            "light",
        ],
        ["", "", "deg", "deg", "deg/s", "deg/s2", "Nm", "barrier"],
    ] {
        let _ = writeln!(
            s,
            "{:>4}  {:<9} {:>8} {:>9} {:>10} {:>10} {:>11}  {}",
            row[0], row[1], row[2], row[3], row[4], row[5], row[6], row[7]
        );
    }
    for a in &v.axes {
        let _ = writeln!(
            s,
            "{:>4}  {:<9} {} {} {} {} {}  {}",
            a.axis,
            visible(&a.name),
            num(a.min_position, 8, 1),
            num(a.max_position, 9, 1),
            num(a.max_velocity, 10, 1),
            num(a.max_acceleration, 10, 1),
            num(a.max_torque, 11, 1),
            if a.light_barrier { "yes" } else { "no" }
        );
    }
    s
}

/// The sim result: the simulation's ground truth.
pub fn sim(v: &SimResult, cfg: &RobotConfig) -> String {
    let mut s = format!(
        "{GREEN}OK{RESET} - simulation ground truth; emergency switch {}\n",
        if v.emergency_stop {
            "PRESSED"
        } else {
            "released"
        }
    );
    for row in [
        ["axis", "name", "true position", "true velocity"],
        ["", "", "deg", "deg/s"],
    ] {
        let _ = writeln!(
            s,
            "{:>4}  {:<9} {:>13} {:>14}",
            row[0], row[1], row[2], row[3]
        );
    }
    for i in 0..6 {
        let _ = writeln!(
            s,
            "{:>4}  {:<9} {} {}",
            i + 1,
            axis_name(cfg, i),
            num(v.true_position[i], 13, 3),
            num(v.true_velocity[i], 14, 3)
        );
    }
    s
}

/// One frame of `watch`: the status table of the newest state.
pub fn watch_frame(
    state: Option<&StateSample>,
    detail: bool,
    cfg: &RobotConfig,
    instance: &str,
) -> String {
    let head = "watch: refreshed 5 times a second; press any key (Enter with nc) to stop\n";
    match state {
        Some(st) => format!(
            "{head}{}",
            answer(
                "status",
                &crate::command::result::status_answer("status", st, detail),
                cfg,
                Some(st)
            )
        ),
        None => format!(
            "{head}{YELLOW}the real-time core (instance `{}`) is not running{RESET}; waiting for it ...\n",
            visible(instance)
        ),
    }
}

/// Remove ANSI escape sequences (for the tests, which read the text a person sees).
#[cfg(test)]
pub fn strip_ansi(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut chars = s.chars();
    while let Some(c) = chars.next() {
        if c == '\x1b' {
            if chars.next() == Some('[') {
                for c in chars.by_ref() {
                    if ('\x40'..='\x7e').contains(&c) {
                        break;
                    }
                }
            }
        } else {
            out.push(c);
        }
    }
    out
}

#[cfg(test)]
mod tests;
