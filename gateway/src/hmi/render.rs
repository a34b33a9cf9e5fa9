//! Results for people: the protocol's result objects (built by `crate::result`, the same as on
//! the JSON channel) turned into aligned tables with units, modes and errors in words, and
//! hints that say how to fix what went wrong. Output uses `\n`; the session turns it into the
//! terminal's `\r\n`. Not used inside the real-time cycle.
//!
//! ```
//! use mcm_gateway::hmi::render;
//! let cfg = mcm_shared::config::RobotConfig::prob2_default();
//! let text = render::result("hold", &mcm_gateway::result::ok(), &cfg, None);
//! assert!(text.contains("OK"));
//! ```

use super::spec;
use super::words::LineError;
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::Mode;
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
        cfg.robot.name
    );
    match state {
        Some(st) => {
            let m = mode_name(st);
            let _ = writeln!(s, "mode:  {}{m}{RESET} - {}", mode_color(m), mode_words(m));
        }
        None => {
            let _ = writeln!(
                s,
                "mode:  unknown - {YELLOW}the real-time core (instance `{instance}`) is not running{RESET}; commands fail until it starts"
            );
        }
    }
    s.push_str("Type `help` for the commands, `help CMD` for one of them, `quit` to leave.\n");
    s
}

/// The replacement shown for a non-ASCII character: the HMI writes only ASCII.
pub const NON_ASCII: char = '?';

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
    let mut s = crate::json::to_ascii_pretty(v);
    s.push('\n');
    s
}

/// A result of `command` for people. `state` (the reply's, or the newest) adds notes such as
/// uncalibrated axes or the last safety error.
pub fn result(command: &str, v: &Value, cfg: &RobotConfig, state: Option<&StateSample>) -> String {
    match v["result_type"].as_str() {
        Some("status") => status(v, cfg, state),
        Some("move_all") => move_all(v, cfg),
        Some("initialization") => info(v),
        Some("sim") => sim(v, cfg),
        _ if v["error_status"] == "OK" => format!("{GREEN}OK{RESET}{}\n", ok_words(command)),
        _ => error(
            command,
            v["error_message"].as_str().unwrap_or("unknown error"),
            state,
        ),
    }
}

fn ok_words(command: &str) -> &'static str {
    match command {
        "calibrate" => " - calibration finished",
        "move_axis" => " - the axis is moving (`watch` follows it)",
        "pvt_points" => " - points queued",
        "set_torques" => " - torques set",
        "set_velocities" => " - velocities set",
        _ => "",
    }
}

/// An error of `command` with a hint on how to fix it.
pub fn error(command: &str, message: &str, state: Option<&StateSample>) -> String {
    let mut s = format!("{RED}error:{RESET} {message}\n");
    let spec = spec::find(command);
    let hint = if message.contains("is not running") {
        Some(
            "the real-time core (mcm-rt) is not running: start it (the `mcm` launcher starts both \
             processes), then try again"
                .to_string(),
        )
    } else if message.contains("not allowed in mode")
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
    } else if message.contains("no reply from the real-time core") {
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
    let mut s = format!("{RED}error:{RESET} {e}\n");
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

/// A spontaneous safety error (`crate::result::safety_error`).
pub fn safety(v: &Value) -> String {
    format!(
        "{RED}*** {}{RESET}\n  hint: once the cause is gone, `hold` clears the error\n",
        v["error_message"]
            .as_str()
            .unwrap_or("safety check tripped")
    )
}

fn six(v: &Value) -> [f64; 6] {
    let mut out = [f64::NAN; 6];
    if let Some(a) = v.as_array() {
        for (o, x) in out.iter_mut().zip(a) {
            *o = x.as_f64().unwrap_or(f64::NAN);
        }
    }
    out
}

fn bools(v: &Value) -> [Option<bool>; 6] {
    let mut out = [None; 6];
    if let Some(a) = v.as_array() {
        for (o, x) in out.iter_mut().zip(a) {
            *o = x.as_bool();
        }
    }
    out
}

fn name(cfg: &RobotConfig, i: usize) -> &str {
    cfg.axes.get(i).map_or("", |a| a.name.as_str())
}

fn num(x: f64, width: usize, decimals: usize) -> String {
    if x.is_finite() {
        format!("{x:>width$.decimals$}")
    } else {
        format!("{:>width$}", "-")
    }
}

/// The status result as a table.
pub fn status(v: &Value, cfg: &RobotConfig, state: Option<&StateSample>) -> String {
    let mode = v["operating_mode"].as_str().unwrap_or("UNKNOWN");
    let axes = &v["axis_states"];
    let t = six(&axes["time"])[0];
    let mut s = format!(
        "mode {}{mode}{RESET} - {}   (t = {} s)\n",
        mode_color(mode),
        mode_words(mode),
        num(t, 0, 3)
    );
    let (pos, vel, cur) = (
        six(&axes["position"]),
        six(&axes["velocity"]),
        six(&axes["current"]),
    );
    let d = &v["detail"];
    let detail = d.is_object();
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
        if detail {
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
    let (cmd, meas, fe, i2t, cal) = (
        six(&d["commanded_position"]),
        six(&d["measured_position"]),
        six(&d["following_error"]),
        six(&d["i2t"]),
        bools(&d["calibrated"]),
    );
    for i in 0..6 {
        let _ = write!(
            s,
            "{:>4}  {:<9} {} {} {}",
            i + 1,
            name(cfg, i),
            num(pos[i], 11, 3),
            num(vel[i], 11, 3),
            num(cur[i], 11, 3)
        );
        if detail {
            let c = match cal[i] {
                Some(true) => "yes",
                Some(false) => "NO",
                None => "-",
            };
            let _ = write!(
                s,
                " {} {} {} {}  {c:>10}",
                num(cmd[i], 11, 3),
                num(meas[i], 11, 3),
                num(fe[i], 10, 3),
                num(i2t[i] * 100.0, 7, 1)
            );
        }
        s.push('\n');
    }
    if detail {
        detail_lines(&mut s, v);
    }
    if let Some(st) = state {
        notes(&mut s, st);
    }
    s
}

fn detail_lines(s: &mut String, v: &Value) {
    let d = &v["detail"];
    if let Some(h) = v["hardware_status"].as_str() {
        let _ = writeln!(s, "hardware:  {h}");
    }
    let a = &d["access"];
    if a.is_object() {
        let refused = a["refused"]
            .as_object()
            .map(|m| {
                m.iter()
                    .map(|(k, n)| format!("{k} {n}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            })
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "access:    motion from {}{}; secret {}; refused so far: {refused}",
            a["motion_networks"].as_str().unwrap_or("?"),
            if a["motion_allowed_here"] == false {
                " (NOT from this session's address)"
            } else {
                ""
            },
            match (a["secret_required"] == true, a["authenticated"] == true) {
                (false, _) => "not required",
                (true, true) => "required, presented by this session",
                (true, false) => "required, NOT presented by this session (`authenticate`)",
            },
        );
    }
    let q = &d["pvt_queue"];
    let _ = writeln!(
        s,
        "PVT queue: {} of {} points{}",
        q["queued"],
        q["capacity"],
        if q["starved"] == true {
            " (ran dry: the axes stopped and hold)"
        } else {
            ""
        }
    );
    let tm = &d["timing"];
    let period = tm["period_s"].as_f64().unwrap_or(f64::NAN);
    let us = |k: &str| {
        tm[k]
            .as_f64()
            .map_or("-".to_string(), |x| format!("{x:.0}"))
    };
    let _ = writeln!(
        s,
        "cycle:     {} ms ({} Hz), wake-up latency p50 {} us, p99 {} us, max {} us; longest work {} us; overruns {}{}",
        num(period * 1e3, 0, 3),
        num(1.0 / period, 0, 0),
        us("latency_p50_us"),
        us("latency_p99_us"),
        us("latency_max_us"),
        us("work_max_us"),
        tm["overruns"],
        if tm["realtime"] == false {
            format!(" {YELLOW}(NOT real-time){RESET}")
        } else {
            String::new()
        }
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
        && let Some(e) = crate::result::last_error(&st.last_error)
    {
        let _ = writeln!(
            s,
            "{RED}last error:{RESET} {}",
            e["error_message"].as_str().unwrap_or("")
        );
    }
    if st.mode == Mode::Pvt.to_wire() && st.flags & STATE_PVT_STARVED != 0 {
        let _ = writeln!(s, "PVT queue ran dry: the axes stopped and hold");
    }
}

/// The move_all result: timing and velocity of each axis.
pub fn move_all(v: &Value, cfg: &RobotConfig) -> String {
    let longest = v["longest"].as_u64().unwrap_or(0) as usize;
    let mut s = format!(
        "{GREEN}OK{RESET} - every axis arrives within {} s; axis {longest} ({}) takes longest\n",
        num(v["max_time_to_target"].as_f64().unwrap_or(f64::NAN), 0, 3),
        name(cfg, longest.wrapping_sub(1))
    );
    let _ = writeln!(s, "{:>4}  {:<9} {:>11}", "axis", "name", "velocity");
    let _ = writeln!(s, "{:>4}  {:<9} {:>11}", "", "", "deg/s");
    for (i, vel) in six(&v["velocities"]).iter().enumerate() {
        let mark = if i + 1 == longest { "  <- longest" } else { "" };
        let _ = writeln!(
            s,
            "{:>4}  {:<9} {}{mark}",
            i + 1,
            name(cfg, i),
            num(*vel, 11, 3)
        );
    }
    s
}

/// The initialization result (`info`).
pub fn info(v: &Value) -> String {
    let cycle = v["cycle_time"].as_f64().unwrap_or(f64::NAN);
    let mut s = format!(
        "{}, MCM {}, {} axes, cycle {} ms ({} Hz), {}\n",
        v["robot"].as_str().unwrap_or("robot"),
        v["version"].as_str().unwrap_or("?"),
        v["num_axes"],
        num(cycle * 1e3, 0, 3),
        num(1.0 / cycle, 0, 0),
        if v["simulated"] == true {
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
    for a in v["axes"].as_array().into_iter().flatten() {
        let f = |k: &str, w: usize, d: usize| num(a[k].as_f64().unwrap_or(f64::NAN), w, d);
        let _ = writeln!(
            s,
            "{:>4}  {:<9} {} {} {} {} {}  {}",
            a["axis"].as_u64().unwrap_or(0),
            a["name"].as_str().unwrap_or(""),
            f("min_position", 8, 1),
            f("max_position", 9, 1),
            f("max_velocity", 10, 1),
            f("max_acceleration", 10, 1),
            f("max_torque", 11, 1),
            if a["light_barrier"] == true {
                "yes"
            } else {
                "no"
            }
        );
    }
    s
}

/// The sim result: the simulation's ground truth.
pub fn sim(v: &Value, cfg: &RobotConfig) -> String {
    let mut s = format!(
        "{GREEN}OK{RESET} - simulation ground truth; emergency switch {}\n",
        if v["emergency_stop"] == true {
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
    let (p, vel) = (six(&v["true_position"]), six(&v["true_velocity"]));
    for i in 0..6 {
        let _ = writeln!(
            s,
            "{:>4}  {:<9} {} {}",
            i + 1,
            name(cfg, i),
            num(p[i], 13, 3),
            num(vel[i], 14, 3)
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
            status(&crate::result::status(st, detail), cfg, Some(st))
        ),
        None => format!(
            "{head}{YELLOW}the real-time core (instance `{instance}`) is not running{RESET}; waiting for it ...\n"
        ),
    }
}

/// Remove ANSI escape sequences (for tests and logs).
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
