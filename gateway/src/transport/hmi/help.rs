//! The HMI's help texts: `help` lists every command with one line each (grouped by the modes
//! that accept them, as in the manual); `help CMD` explains one command: usage, arguments with
//! units and defaults, the modes that accept it, its reply, examples and the allowed ranges per
//! axis of the configured robot (from [`mcm_shared::ranges`]). Built from the commands'
//! definitions ([`mcm_shared::protocol::CommandDef`]). Not used inside the real-time cycle.

use super::render::{BOLD, RESET, visible};
use super::words::SESSION_COMMANDS;
use mcm_shared::config::RobotConfig;
use mcm_shared::protocol::{self, ArgDef, COMMANDS, CommandDef, Group, command_names, suggest};
use mcm_shared::ranges::{Arg, Num};
use std::fmt::Write as _;

const SESSION: &[(&str, &str, &str)] = &[
    (
        "help",
        "help [CMD]",
        "this list, or the details of one command (also `CMD ?`)",
    ),
    (
        "watch",
        "watch [detail]",
        "the status table, refreshed in place until a key is pressed",
    ),
    (
        "jog",
        "jog AXIS [SPEED]",
        "move one axis while `+`/`-` (or an arrow key) is held; `q` leaves (VELOCITY_CONTROL)",
    ),
    (
        "jog",
        "jog x|y|z|rx|ry|rz [SPEED] [base|tool]",
        "move the TCP along or about an axis while `+`/`-` is held (mm/s, deg/s)",
    ),
    (
        "pose",
        "pose",
        "the TCP in the base frame (mm, roll/pitch/yaw deg) and the active tool",
    ),
    (
        "tool",
        "tool [X Y Z ROLL PITCH YAW [mass=KG] [com=X,Y,Z]]",
        "show the tool, or set its TCP (mm, deg, flange frame) and load (com mm) with set_tool",
    ),
    (
        "moveto",
        "moveto X Y Z ROLL PITCH YAW [vf=F]",
        "move the TCP to a pose (mm, deg, base frame) with move_to_pose (PVT)",
    ),
    (
        "movel",
        "movel X Y Z [ROLL PITCH YAW] [v=MM_S]",
        "move the TCP on a straight line (mm, deg, base frame; mm/s) with move_linear (PVT)",
    ),
    ("clear", "clear", "clear the screen"),
    (
        "quit",
        "quit, exit",
        "end the session (also Ctrl-D on an empty line)",
    ),
];

const KEYS: &str = "\
Editing keys (telnet; with nc your terminal edits the line):
  Left/Right, Home/End, Ctrl-A/E   move            Up/Down, Ctrl-P/N   history
  Backspace, Delete, Ctrl-D        erase a char    Ctrl-W              erase a word
  Ctrl-U                           erase the line  Ctrl-K              erase to the end
  Tab                              complete        Ctrl-L              clear the screen
  Ctrl-C                           drop the line, or stop waiting for a command
";

/// The list of commands, one line each.
pub fn overview() -> String {
    let mut s = format!(
        "{BOLD}Robot commands{RESET} - arguments by position or as name=value; `help CMD` explains one\n"
    );
    for group in Group::ALL {
        let _ = writeln!(s, "{}:", group.title());
        for def in COMMANDS.iter().filter(|d| d.group == group) {
            let _ = writeln!(s, "  {:<15} {}", def.name, def.summary);
        }
    }
    let _ = writeln!(s, "{BOLD}Session commands{RESET}:");
    for (_, usage, what) in SESSION {
        let _ = writeln!(s, "  {usage:<15} {what}");
    }
    s.push_str(
        "A line starting with { is a JSON command of the M2M protocol (port 18010); its result \
         is shown as JSON.\n`help keys` lists the editing keys.\n",
    );
    s
}

/// The help for `topic`: a command, a session command, or `keys`.
pub fn topic(topic: &str, cfg: &RobotConfig) -> String {
    let t = topic.to_ascii_lowercase();
    if t == "keys" {
        return KEYS.to_string();
    }
    if let Some(spec) = protocol::find(&t) {
        return command(spec, cfg);
    }
    if let Some((name, usage, what)) = SESSION
        .iter()
        .find(|(n, _, _)| *n == t || (*n == "quit" && t == "exit"))
    {
        let mut s = format!("{BOLD}{name}{RESET} - {what}\nusage:  {usage}\n");
        if matches!(*name, "pose" | "tool" | "moveto" | "movel") {
            s.push_str(super::cartesian::HELP);
        }
        if *name == "jog" {
            s.push_str(super::jog::HELP);
        }
        return s;
    }
    let words = command_names()
        .chain(SESSION_COMMANDS.iter().copied())
        .chain(["keys"]);
    format!(
        "no help for \"{}\"{}; `help` lists the commands\n",
        topic.chars().take(40).collect::<String>(),
        suggest(&t, words)
            .map(|s| format!(" (did you mean \"{s}\"?)"))
            .unwrap_or_default()
    )
}

/// The full help of one command.
pub fn command(spec: &CommandDef, cfg: &RobotConfig) -> String {
    let mut s = format!("{BOLD}{}{RESET} - {}\n\n", spec.name, spec.summary);
    let _ = writeln!(s, "usage:       {}", spec.usage());
    if !spec.args.is_empty() {
        s.push_str(
            "             arguments by position, or as name=value in any order\n\narguments:\n",
        );
        let label = |a: &ArgDef| match a.alias {
            "" => a.name.to_string(),
            alias => format!("{} ({alias})", a.name),
        };
        let width = spec.args.iter().map(|a| label(a).len()).max().unwrap_or(0);
        for a in spec.args {
            let need = match (a.default, a.positional) {
                ("", true) => "required".to_string(),
                ("", false) => "optional".to_string(),
                (d, _) => format!("default {d}"),
            };
            let _ = writeln!(s, "  {:<width$}  {need:<16}  {}", label(a), a.help);
        }
    }
    s.push('\n');
    let _ = write!(s, "accepted in: {}", spec.modes);
    if !spec.how.is_empty() {
        let _ = write!(s, " ({})", spec.how);
    }
    let _ = writeln!(s, "\nreply:       {}", spec.reply);
    if !spec.notes.is_empty() {
        let _ = writeln!(s, "note:        {}", spec.notes);
    }
    s.push_str("examples:\n");
    for e in spec.examples {
        let _ = writeln!(s, "  {e}");
    }
    limits(&mut s, spec.name, cfg);
    s
}

/// The configured robot's ranges that matter for the command, per axis, from the table of
/// ranges the gateway and the core check arguments against ([`mcm_shared::ranges`]).
fn limits(s: &mut String, command: &str, cfg: &RobotConfig) {
    let per_axis = |arg: Arg| {
        cfg.axes
            .iter()
            .enumerate()
            .map(|(i, a)| {
                let (min, max) = arg.bounds(cfg, Some(i));
                format!("{} {} {}..{}", i + 1, visible(&a.name), Num(min), Num(max))
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let range = |s: &mut String, title: &str, arg: Arg| {
        let _ = writeln!(s, "{title}: {}", per_axis(arg));
    };
    if matches!(command, "move_axis" | "move_all" | "pvt_points") {
        let _ = writeln!(
            s,
            "reachable positions [deg] (the axis limits less the {} deg safety margin): {}",
            Num(cfg.safety.limit_margin_deg),
            per_axis(Arg::TargetPosition)
        );
        range(
            s,
            "max velocity [deg/s] (velocity_factor 1)",
            Arg::Velocities,
        );
    }
    if command == "set_torques" {
        range(s, "peak torque [Nm]", Arg::Torques);
    }
    if command == "set_velocities" {
        range(s, "max velocity [deg/s]", Arg::Velocities);
    }
}

#[cfg(test)]
mod tests;
