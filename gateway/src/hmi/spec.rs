//! What the HMI knows about each command of the protocol: its arguments in positional order,
//! their kinds, short names, defaults and units, and the modes that accept it. The line
//! parser ([`super::words`]) uses it to turn words into a JSON `arguments` object, and the
//! help ([`super::help`]) to explain the command. Validation itself stays in `crate::cmd`
//! (one parser for both channels); a test checks that this table and `crate::cmd` agree.
//! Not used inside the real-time cycle.

/// How the words of an argument become a JSON value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Number,
    /// An axis number 1..6.
    Axis,
    /// `true`/`false` (also `on`/`off`, `yes`/`no`, `1`/`0`); the bare name means `true`.
    Bool,
    /// Six numbers, one per axis: six words, `a,b,c,d,e,f`, or a JSON array.
    Six,
    /// `ALL`, `ELBOW`, `WRIST` or an axis number.
    Which,
    /// `1` or `-1`.
    Direction,
    /// A JSON array of PVT points (bracketed or quoted).
    Points,
    /// A word taken as text, whatever it looks like (the shared secret).
    Text,
}

impl Kind {
    /// A placeholder for usage lines.
    pub fn placeholder(self) -> &'static str {
        match self {
            Kind::Number => "X",
            Kind::Axis => "1..6",
            Kind::Bool => "true|false",
            Kind::Six => "a,b,c,d,e,f",
            Kind::Which => "ALL|ELBOW|WRIST|1..6",
            Kind::Direction => "1|-1",
            Kind::Points => "[...]",
            Kind::Text => "TEXT",
        }
    }
}

/// One argument of a command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ArgSpec {
    /// The protocol name.
    pub name: &'static str,
    /// A short name accepted in `name=value` ("" for none).
    pub alias: &'static str,
    pub kind: Kind,
    /// May be given by position (in the order of `CommandSpec::args`).
    pub positional: bool,
    /// The default, for people ("" = required).
    pub default: &'static str,
    /// What it is, with its unit and range.
    pub help: &'static str,
}

/// One command of the protocol, for people.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CommandSpec {
    pub name: &'static str,
    pub summary: &'static str,
    pub args: &'static [ArgSpec],
    /// The modes that accept the command.
    pub modes: &'static str,
    /// How to get into such a mode ("" when every mode accepts it).
    pub how: &'static str,
    /// What the command answers.
    pub reply: &'static str,
    pub examples: &'static [&'static str],
    /// Anything else worth knowing ("" for nothing).
    pub notes: &'static str,
}

impl CommandSpec {
    /// The argument called `name` (protocol name or short name, any case).
    pub fn arg(&self, name: &str) -> Option<&'static ArgSpec> {
        let args: &'static [ArgSpec] = self.args;
        args.iter().find(|a| {
            a.name.eq_ignore_ascii_case(name)
                || (!a.alias.is_empty() && a.alias.eq_ignore_ascii_case(name))
        })
    }

    /// Every argument name and short name (for "did you mean").
    pub fn arg_names(&self) -> Vec<&'static str> {
        let args: &'static [ArgSpec] = self.args;
        args.iter()
            .flat_map(|a| [a.name, a.alias])
            .filter(|n| !n.is_empty())
            .collect()
    }

    /// The arguments that may be given by position.
    pub fn positional(&self) -> Vec<&'static ArgSpec> {
        let args: &'static [ArgSpec] = self.args;
        args.iter().filter(|a| a.positional).collect()
    }

    /// One usage line, e.g. `move_axis <axis_index> <target_position> [velocity_factor]`.
    pub fn usage(&self) -> String {
        let mut s = self.name.to_string();
        for a in self.args {
            s.push(' ');
            match (a.positional, a.default.is_empty()) {
                (true, true) if a.kind == Kind::Six => s.push_str(&format!("<{} x6>", a.name)),
                (true, true) => s.push_str(&format!("<{}>", a.name)),
                (true, false) => s.push_str(&format!("[{}]", a.name)),
                (false, _) => s.push_str(&format!("[{}={}]", a.name, a.kind.placeholder())),
            }
        }
        s
    }
}

const fn arg(
    name: &'static str,
    alias: &'static str,
    kind: Kind,
    positional: bool,
    default: &'static str,
    help: &'static str,
) -> ArgSpec {
    ArgSpec {
        name,
        alias,
        kind,
        positional,
        default,
        help,
    }
}

const VELOCITY_FACTOR: ArgSpec = arg(
    "velocity_factor",
    "vf",
    Kind::Number,
    true,
    "0.33333",
    "fraction of each axis's maximum velocity, from 0.001 to 1",
);

/// `dt_status` of `torque_control` and `velocity_control`.
const DT_STATUS: ArgSpec = arg(
    "dt_status",
    "",
    Kind::Number,
    true,
    "0",
    "interval of spontaneous status results [s], 0 to 60 (JSON channel only)",
);

const IN_HOLD: &str = "HOLD, with every axis calibrated";
const TO_HOLD: &str = "`hold` first (and `calibrate` if an axis is not calibrated)";
const TO_PVT: &str = "enter PVT mode first: `hold`, then `pvt`";

/// Every command of the protocol, in the order of `crate::cmd::COMMAND_NAMES`.
pub const COMMANDS: &[CommandSpec] = &[
    CommandSpec {
        name: "status",
        summary: "the mode and every axis's position, velocity and current",
        args: &[arg(
            "detail",
            "",
            Kind::Bool,
            true,
            "false",
            "add commanded and measured position, following error, i2t, calibration, drives and cycle timing",
        )],
        modes: "every mode",
        how: "",
        reply: "the status table",
        examples: &["status", "status detail"],
        notes: "`watch` shows the same table, refreshed until a key is pressed.",
    },
    CommandSpec {
        name: "info",
        summary: "robot, version, cycle time and the limits of every axis",
        args: &[],
        modes: "every mode",
        how: "",
        reply: "a table of the axis limits",
        examples: &["info"],
        notes: "",
    },
    CommandSpec {
        name: "hold",
        summary: "enter HOLD: axes keep their positions; clears errors and powers the drives",
        args: &[],
        modes: "every mode",
        how: "",
        reply: "the status table after the mode change",
        examples: &["hold"],
        notes: "From OFF or ERROR it clears the error and re-enables power; it fails with the \
                reason while the cause persists (e.g. the emergency stop is still pressed).",
    },
    CommandSpec {
        name: "calibrate",
        summary: "home the axes against their mechanical stops or light barriers",
        args: &[
            arg(
                "which",
                "",
                Kind::Which,
                true,
                "ALL",
                "ALL, ELBOW (axes 1-3), WRIST (axes 4-6) or one axis 1..6",
            ),
            arg(
                "elbow_direction",
                "elbow",
                Kind::Direction,
                false,
                "1",
                "1 or -1; -1 reverses the search direction of axis 3",
            ),
            arg(
                "wrist_direction",
                "wrist",
                Kind::Direction,
                false,
                "1",
                "1 or -1; -1 reverses the search direction of axes 4-6",
            ),
            arg(
                "force_mechanical_stop",
                "force",
                Kind::Bool,
                false,
                "false",
                "use the mechanical stops even where light barriers exist",
            ),
        ],
        modes: "OFF and HOLD (the mode is CALIBRATION while it runs)",
        how: "`hold` first",
        reply: "OK when calibration has finished (HOLD), or the reason it failed (ERROR)",
        examples: &["calibrate", "calibrate which=WRIST", "calibrate 3 force"],
        notes: "Needed after every power-up, before any motion. Until then positions are raw \
                encoder positions. Ctrl-C stops waiting for the answer, not the calibration.",
    },
    CommandSpec {
        name: "release",
        summary: "enter RELEASE: move the arm by hand (gravity and friction compensated)",
        args: &[],
        modes: IN_HOLD,
        how: TO_HOLD,
        reply: "the status table after the mode change",
        examples: &["release"],
        notes: "In RELEASE only `hold` and `status` (and `info`, `sleep`) are accepted.",
    },
    CommandSpec {
        name: "torque_control",
        summary: "enter TORQUE_CONTROL: joint torques come from `set_torques`",
        args: &[
            arg(
                "timeout",
                "",
                Kind::Number,
                true,
                "1",
                "longest time between two `set_torques` [s]; negative: no timeout; not 0. \
                 When it passes, the mode falls back to HOLD",
            ),
            DT_STATUS,
            arg(
                "gravity_compensation",
                "gravity",
                Kind::Bool,
                false,
                "true",
                "add the model's gravity and friction torques to the given torques",
            ),
        ],
        modes: IN_HOLD,
        how: TO_HOLD,
        reply: "the status table after the mode change",
        examples: &[
            "torque_control -1",
            "torque_control timeout=0.5 gravity=false",
        ],
        notes: "The HMI does not print spontaneous status results; use `watch`.",
    },
    CommandSpec {
        name: "set_torques",
        summary: "the joint torques of all six axes in TORQUE_CONTROL",
        args: &[arg(
            "torques",
            "",
            Kind::Six,
            true,
            "",
            "six torques [Nm], one per axis, each within the axis's peak torque (see below)",
        )],
        modes: "TORQUE_CONTROL",
        how: "enter TORQUE_CONTROL first: `hold`, then `torque_control`",
        reply: "OK (the JSON channel answers nothing on success)",
        examples: &["set_torques 0 0 0 0 0 0", "set_torques 0,0,1.5,0,0,0"],
        notes: "Zero torques hold the arm still while gravity compensation is on.",
    },
    CommandSpec {
        name: "velocity_control",
        summary: "enter VELOCITY_CONTROL: joint velocities come from `set_velocities`",
        args: &[
            arg(
                "timeout",
                "",
                Kind::Number,
                true,
                "1",
                "longest time between two `set_velocities` [s]; negative: no timeout; not 0. \
                 When it passes, the axes stop (controlled) and the mode falls back to HOLD",
            ),
            DT_STATUS,
        ],
        modes: IN_HOLD,
        how: TO_HOLD,
        reply: "the status table after the mode change",
        examples: &["velocity_control", "velocity_control timeout=-1"],
        notes: "Velocities are ramped within each axis's acceleration and jerk limits, and a \
                joint driven towards its limit brakes and stops before it. `jog AXIS` drives one \
                axis from the keyboard. `hold` stops and leaves the mode.",
    },
    CommandSpec {
        name: "set_velocities",
        summary: "the joint velocities of all six axes in VELOCITY_CONTROL",
        args: &[arg(
            "velocities",
            "",
            Kind::Six,
            true,
            "",
            "six velocities [deg/s], one per axis, each within the axis's maximum velocity \
             (see below)",
        )],
        modes: "VELOCITY_CONTROL",
        how: "enter VELOCITY_CONTROL first: `hold`, then `velocity_control`",
        reply: "OK (the JSON channel answers nothing on success)",
        examples: &["set_velocities 0 10 0 0 0 0", "set_velocities 0,0,-5,0,0,0"],
        notes: "Send them again before the timeout passes, or the axes stop.",
    },
    CommandSpec {
        name: "pvt",
        summary: "enter PVT: smooth position control (move_axis, move_all, pvt_points)",
        args: &[arg(
            "dt",
            "",
            Kind::Number,
            true,
            "0.01",
            "spacing of `pvt_points` [s], from one control cycle to 1",
        )],
        modes: IN_HOLD,
        how: TO_HOLD,
        reply: "the status table after the mode change",
        examples: &["pvt", "pvt 0.02"],
        notes: "",
    },
    CommandSpec {
        name: "move_axis",
        summary: "move one axis to a target position",
        args: &[
            arg("axis_index", "axis", Kind::Axis, true, "", "the axis, 1..6"),
            arg(
                "target_position",
                "target",
                Kind::Number,
                true,
                "",
                "target angle [deg], within the axis's reachable range: its limits less the safety \
                 margin (see below)",
            ),
            VELOCITY_FACTOR,
        ],
        modes: "PVT",
        how: TO_PVT,
        reply: "OK as soon as the motion starts (`watch` follows it)",
        examples: &[
            "move_axis 1 30",
            "move_axis 1 30 0.5",
            "move_axis axis=2 target=-45 vf=0.2",
        ],
        notes: "",
    },
    CommandSpec {
        name: "move_all",
        summary: "move all axes to target positions; from rest they start and arrive together",
        args: &[
            arg(
                "target_positions",
                "targets",
                Kind::Six,
                true,
                "",
                "six target angles [deg], one per axis, each within its reachable range: its limits \
                 less the safety margin (see below)",
            ),
            VELOCITY_FACTOR,
        ],
        modes: "PVT",
        how: TO_PVT,
        reply: "the velocity of every axis [deg/s], the axis that takes longest and the time to target [s]",
        examples: &[
            "move_all 0 10 20 0 0 0",
            "move_all 0 10 20 0 0 0 vf=0.5",
            "move_all targets=0,10,20,0,0,0",
        ],
        notes: "",
    },
    CommandSpec {
        name: "pvt_points",
        summary: "queue position/velocity points, spaced by the `dt` given with `pvt`",
        args: &[arg(
            "points",
            "",
            Kind::Points,
            true,
            "",
            "a JSON array of 1 to 1000 points {\"position\":[6 deg],\"velocity\":[6 deg/s]}, \
             bracketed or quoted",
        )],
        modes: "PVT",
        how: TO_PVT,
        reply: "OK when every point was queued; on ERROR nothing of the batch is queued",
        examples: &[
            "pvt_points [{\"position\":[0,0,0,0,0,0],\"velocity\":[0,0,0,0,0,0]}]",
            "pvt_points '[{\"position\":[1,0,0,0,0,0],\"velocity\":[0,0,0,0,0,0]}]'",
        ],
        notes: "The reference passes through each point at its time (cubic Hermite between \
                points). When the queue runs dry the axes stop smoothly and hold.",
    },
    CommandSpec {
        name: "sleep",
        summary: "wait before the next command of this session",
        args: &[arg(
            "duration",
            "",
            Kind::Number,
            true,
            "",
            "seconds, 0 to 3600",
        )],
        modes: "every mode",
        how: "",
        reply: "OK when the time has passed (Ctrl-C stops waiting)",
        examples: &["sleep 1.5"],
        notes: "Other sessions are not delayed.",
    },
    CommandSpec {
        name: "sim",
        summary: "fault injection into the simulated robot",
        args: &[
            arg(
                "emergency_stop",
                "estop",
                Kind::Bool,
                false,
                "",
                "press (true) or release (false) the emergency switch",
            ),
            arg(
                "disconnect_axis",
                "",
                Kind::Axis,
                false,
                "",
                "drive 1..6 goes silent on the bus",
            ),
            arg(
                "reconnect_axis",
                "",
                Kind::Axis,
                false,
                "",
                "drive 1..6 comes back",
            ),
            arg(
                "block_axis",
                "",
                Kind::Axis,
                false,
                "",
                "a rigid obstacle holds axis 1..6 where it is",
            ),
            arg(
                "unblock_axis",
                "",
                Kind::Axis,
                false,
                "",
                "remove the obstacle of axis 1..6",
            ),
            arg(
                "external_torques",
                "torques",
                Kind::Six,
                false,
                "",
                "six torques [Nm] of a hand pushing on the joints, until set back to zeros",
            ),
            arg(
                "power_cycle",
                "",
                Kind::Bool,
                false,
                "false",
                "the drives lose power and reboot: calibration is lost",
            ),
        ],
        modes: "every mode; simulated robot only",
        how: "",
        reply: "the simulation's ground truth: true positions and velocities, emergency switch",
        examples: &[
            "sim estop=true",
            "sim block_axis=2",
            "sim external_torques=0,5,0,0,0,0",
            "sim power_cycle",
        ],
        notes: "Any combination of arguments in one command. Refused on real hardware.",
    },
    CommandSpec {
        name: "take_control",
        summary: "make this session the one that controls the arm's motion",
        args: &[],
        modes: "every mode",
        how: "",
        reply: "OK, or who controls the arm when another client does",
        examples: &["take_control"],
        notes: "Only one client (JSON, HMI or shared memory) controls the arm at a time; the \
                first motion command of a client takes control implicitly when nobody has it. \
                Others may read the state and always `hold`. Control ends with \
                `release_control` or when the session closes: what it drove stops in HOLD. \
                Needs an allowed network and, when configured, `authenticate` first.",
    },
    CommandSpec {
        name: "release_control",
        summary: "give up control of the arm's motion (what this session drove stops in HOLD)",
        args: &[],
        modes: "every mode",
        how: "",
        reply: "OK (also when nobody controls the arm)",
        examples: &["release_control"],
        notes: "A move, PVT stream, RELEASE, TORQUE_CONTROL or calibration of this session \
                ends with the controlled stop to HOLD.",
    },
    CommandSpec {
        name: "authenticate",
        summary: "present the shared secret (needed before taking control when configured)",
        args: &[arg(
            "secret",
            "",
            Kind::Text,
            true,
            "",
            "the shared secret the robot's operator gave you",
        )],
        modes: "every mode",
        how: "",
        reply: "OK, or an error after a second when the secret is wrong",
        examples: &["authenticate s3cret-words"],
        notes: "Holds for this session only. `status detail` shows whether a secret is \
                required and whether this session presented it.",
    },
];

/// The command called `name` (any case).
pub fn find(name: &str) -> Option<&'static CommandSpec> {
    COMMANDS.iter().find(|c| c.name.eq_ignore_ascii_case(name))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::args::CommandError;
    use crate::cmd::{COMMAND_NAMES, Command};
    use mcm_shared::config::RobotConfig;
    use serde_json::json;

    #[test]
    fn every_gateway_command_is_described_in_order() {
        let names: Vec<_> = COMMANDS.iter().map(|c| c.name).collect();
        assert_eq!(names, COMMAND_NAMES);
    }

    #[test]
    fn every_argument_is_known_to_the_gateway() {
        let cfg = RobotConfig::prob2_default();
        for c in COMMANDS {
            for a in c.args {
                let args = json!({ a.name: null });
                let r = Command::parse(c.name, Some(&args), &cfg);
                assert!(
                    !matches!(r, Err(CommandError::UnknownArgument { .. })),
                    "{}.{}: {r:?}",
                    c.name,
                    a.name
                );
            }
            // And nothing else is accepted.
            let args = json!({ "no_such_argument": 1 });
            assert!(matches!(
                Command::parse(c.name, Some(&args), &cfg),
                Err(CommandError::UnknownArgument { .. })
            ));
        }
    }

    #[test]
    fn usage_lines() {
        assert_eq!(
            find("move_axis").unwrap().usage(),
            "move_axis <axis_index> <target_position> [velocity_factor]"
        );
        assert_eq!(
            find("MOVE_ALL").unwrap().usage(),
            "move_all <target_positions x6> [velocity_factor]"
        );
        assert!(
            find("sim")
                .unwrap()
                .usage()
                .contains("[power_cycle=true|false]")
        );
        assert_eq!(
            find("move_axis").unwrap().arg("VF").unwrap().name,
            "velocity_factor"
        );
    }
}
