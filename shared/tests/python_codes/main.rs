//! The Python package's `python/src/mcm/codes.py` is generated from the contract: the wire
//! codes (`mcm_shared::mode`), the protocol's commands (`mcm_shared::protocol::COMMANDS`: their
//! names, the result each answers on success, those that answer nothing, those that need
//! control), the numeric arguments (`mcm_shared::ranges::ARGS`), the words of every refusal
//! (`Reason`'s and `ArgRefusal`'s `Display` in `mcm_shared::reply` and `mcm_shared::ranges`) and
//! every error code (`mcm_shared::error_code::ErrorCode`, the Python `ErrorCode` enum) and the
//! `outcome` of an ERROR result (`mcm_shared::protocol::results::ErrorOutcome`, the Python
//! `Outcome` enum).
//! This test fails when the checked-in file differs from what it generates now;
//! `MCM_UPDATE_PYTHON=1 cargo test -p mcm-shared --test python_codes` writes it anew.
//!
//! The words are not copied: each reason is rendered by Rust with sentinel figures (axis 5,
//! 11.123456789, ...), and the rendering of each figure is replaced by a placeholder the Python
//! side fills from the reason's wire form (`code`, `axis`, `values`) in the same format. A figure
//! whose rendering is not found (Rust's words changed their format) fails here.
//! `tests/end_to_end/python_layout.rs` then checks the generated `reason_text` against Rust's words
//! for sample reasons of every kind.
//!
//! `python/src/mcm/encoding.py` is generated the same way, and checked the same way: where the
//! samples carry each argument and answer ([`encoding`]).

mod encoding;
mod text;

use mcm_shared::command::Axis;
use mcm_shared::error_code::ErrorCode;
use mcm_shared::mode::{CommandKind, Mode, RejectCode, ReplyStatus};
use mcm_shared::protocol::results::ErrorOutcome;
use mcm_shared::protocol::{COMMANDS, Success};
use mcm_shared::ranges::{ARGS, ArgRefusal, Num};
use mcm_shared::reply::{CalibrationFailure, LineFault, PvtQuantity, Reason, Singularity};
use std::fmt::Write;
use std::path::Path;
use text::{FUNCTIONS, PRELUDE};

/// Sentinel figures: distinct, and no rendering of one is part of another's.
const S: [f64; 4] = [11.123456789, 22.234567891, 33.345678912, 44.456789123];
const AXIS: u8 = 5;

/// How Rust writes a figure, and the same in Python.
#[derive(Clone, Copy)]
enum Fmt {
    /// `{:.3}`
    F3,
    /// `{:.2}`
    F2,
    /// `{:.1}`
    F1,
    /// `Num` (12 significant digits)
    Num,
    /// an integer
    Int,
    /// `{:04X}`
    Hex4,
}

/// A piece of the words replaced by a placeholder: what Rust wrote, the placeholder's text
/// and the Python expression that gives it.
struct Slot {
    needle: String,
    replacement: String,
    key: String,
    py: String,
}

/// One way a code is worded: a Python condition (besides the code) and a reason with
/// sentinels.
struct Case {
    code: RejectCode,
    guard: String,
    reason: Reason,
    slots: Vec<Slot>,
}

fn axis() -> Axis {
    Axis::new(AXIS).expect("axis 1..6")
}

/// The wire slot of reason `r` that holds `x`.
fn wire_slot(r: &Reason, x: f64) -> usize {
    r.to_wire()
        .values
        .iter()
        .position(|&v| v == x)
        .unwrap_or_else(|| panic!("{r:?}: no wire value {x}"))
}

/// The figure `x` of reason `r`, written as `fmt`, as the placeholder `key`.
fn figure(r: &Reason, key: &str, x: f64, fmt: Fmt) -> Slot {
    let k = wire_slot(r, x);
    let (needle, py) = match fmt {
        Fmt::F3 => (format!("{x:.3}"), format!("\"%.3f\" % v[{k}]")),
        Fmt::F2 => (format!("{x:.2}"), format!("\"%.2f\" % v[{k}]")),
        Fmt::F1 => (format!("{x:.1}"), format!("\"%.1f\" % v[{k}]")),
        Fmt::Num => (Num(x).to_string(), format!("num(v[{k}])")),
        Fmt::Int => (format!("{}", x as u64), format!("str(int(v[{k}]))")),
        Fmt::Hex4 => (
            format!("{:04X}", x as u64),
            format!("\"%04X\" % int(v[{k}])"),
        ),
    };
    custom(needle, key, py)
}

/// The axis, as the words write it ("axis 5").
fn axis_slot() -> Slot {
    Slot {
        needle: format!("axis {AXIS}"),
        replacement: "axis %(axis)s".into(),
        key: "axis".into(),
        py: "str(axis)".into(),
    }
}

/// A piece with its own Python expression.
fn custom(needle: String, key: &str, py: String) -> Slot {
    Slot {
        needle,
        replacement: format!("%({key})s"),
        key: key.into(),
        py,
    }
}

fn case(reason: Reason, guard: &str, slots: impl FnOnce(&Reason) -> Vec<Slot>) -> Case {
    Case {
        code: reason.code(),
        guard: guard.into(),
        slots: slots(&reason),
        reason,
    }
}

/// Every way a reason is worded, in the order the Python side tries them per code.
fn cases() -> Vec<Case> {
    let a = axis();
    let [s0, s1, s2, s3] = S;
    let mode = Mode::VelocityControl;
    let mut out = vec![
        case(Reason::WrongMode { mode }, "", |r| {
            let k = wire_slot(r, f64::from(mode.to_wire()));
            vec![custom(
                mode.as_str().into(),
                "mode",
                format!("MODES.get(int(v[{k}]), \"?\")"),
            )]
        }),
        case(Reason::NotCalibrated { axis: a }, "", |_| vec![axis_slot()]),
        case(Reason::EmergencyStop, "", |_| vec![]),
    ];
    out.extend(line_cases());
    // One drive, or several (the others in a mask).
    let several = Reason::DriveDisconnected {
        axis: Axis::new(1).expect("axis 1"),
        also: 0b110,
    };
    let k = wire_slot(&several, 6.0);
    out.push(case(
        Reason::DriveDisconnected { axis: a, also: 0 },
        &format!("len(_lost_axes(axis, v[{k}])) <= 1"),
        |_| vec![axis_slot()],
    ));
    out.push(case(several, "", |_| {
        vec![custom(
            "1, 2 and 3".into(),
            "axes",
            format!("_axes_words(_lost_axes(axis, v[{k}]))"),
        )]
    }));
    let code = 0xBEEF;
    out.push(case(
        Reason::DriveFault {
            axis: Some(a),
            code,
        },
        "axis != 0",
        |r| vec![axis_slot(), figure(r, "code", f64::from(code), Fmt::Hex4)],
    ));
    out.push(case(Reason::DriveFault { axis: None, code }, "", |r| {
        vec![figure(r, "code", f64::from(code), Fmt::Hex4)]
    }));
    // Out of range: a value whose range is every finite number, else a range; each with or
    // without an axis.
    for (guard, axis, min, max) in [
        (
            "axis != 0 and _every_finite_number(v)",
            Some(a),
            f64::MIN,
            f64::MAX,
        ),
        ("_every_finite_number(v)", None, f64::MIN, f64::MAX),
        ("axis != 0", Some(a), s1, s2),
        ("", None, s1, s2),
    ] {
        let reason = Reason::OutOfRange {
            axis,
            value: s0,
            min,
            max,
        };
        out.push(case(reason, guard, |r| {
            let mut slots = vec![figure(r, "value", s0, Fmt::Num)];
            if axis.is_some() {
                slots.push(axis_slot());
            }
            if min != f64::MIN {
                slots.push(figure(r, "lo", s1, Fmt::Num));
                slots.push(figure(r, "hi", s2, Fmt::Num));
            }
            slots
        }));
    }
    for reason in [Reason::NotAvailable, Reason::NotSimulated] {
        out.push(case(reason, "", |_| vec![]));
    }
    let queue = Reason::QueueFull {
        offered: 4101,
        free: 4202,
    };
    out.push(case(queue, "", |r| {
        vec![
            figure(r, "offered", 4101.0, Fmt::Int),
            figure(r, "free", 4202.0, Fmt::Int),
        ]
    }));
    let limit = |r: &Reason| {
        vec![
            axis_slot(),
            figure(r, "value", s0, Fmt::F3),
            figure(r, "limit", s1, Fmt::F3),
        ]
    };
    for reason in [
        Reason::PositionLimit {
            axis: a,
            position_deg: s0,
            limit_deg: s1,
        },
        Reason::VelocityLimit {
            axis: a,
            velocity_deg_s: s0,
            limit_deg_s: s1,
        },
        Reason::BrakingDistance {
            axis: a,
            stop_deg: s0,
            limit_deg: s1,
        },
        Reason::FollowingError {
            axis: a,
            error_deg: s0,
            band_deg: s1,
        },
    ] {
        out.push(case(reason, "", limit));
    }
    let overload = Reason::Overload {
        axis: a,
        current_a: s0,
        limit_a: s1,
    };
    out.push(case(overload, "", |r| {
        vec![
            axis_slot(),
            figure(r, "current", s0, Fmt::F2),
            figure(r, "limit", s1, Fmt::F2),
        ]
    }));
    let not_identifiable = Reason::NotIdentifiable {
        condition: s0,
        limit: s1,
    };
    out.push(case(not_identifiable, "", |r| {
        vec![
            figure(r, "condition", s0, Fmt::Num),
            figure(r, "limit", s1, Fmt::Num),
        ]
    }));
    // Calibration: the cause is the first value.
    for cause in [
        CalibrationFailure::NoStop { searched_deg: s1 },
        CalibrationFailure::NoEdge { searched_deg: s1 },
        CalibrationFailure::DriveLost,
        CalibrationFailure::Inconsistent {
            first_deg: s1,
            second_deg: s2,
            tolerance_deg: s3,
        },
        CalibrationFailure::Implausible {
            found_deg: s1,
            configured_deg: s2,
            tolerance_deg: s3,
        },
        CalibrationFailure::Blocked {
            lag_deg: s1,
            bound_deg: s2,
        },
    ] {
        let reason = Reason::CalibrationFailed { axis: a, cause };
        let which = reason.to_wire().values[0];
        out.push(case(reason, &format!("int(v[0]) == {which}"), |r| {
            let mut slots = vec![axis_slot()];
            match cause {
                CalibrationFailure::NoStop { .. } | CalibrationFailure::NoEdge { .. } => {
                    slots.push(figure(r, "searched", s1, Fmt::F1));
                }
                CalibrationFailure::DriveLost => {}
                CalibrationFailure::Inconsistent { .. }
                | CalibrationFailure::Implausible { .. } => {
                    slots.push(figure(r, "first", s1, Fmt::F3));
                    slots.push(figure(r, "second", s2, Fmt::F3));
                    slots.push(figure(r, "tolerance", s3, Fmt::F3));
                }
                CalibrationFailure::Blocked { .. } => {
                    slots.push(figure(r, "lag", s1, Fmt::F3));
                    slots.push(figure(r, "bound", s2, Fmt::F3));
                }
            }
            slots
        }));
    }
    out.push(case(Reason::Aborted, "", |_| vec![]));
    out.push(case(Reason::Busy { remaining_s: s0 }, "", |r| {
        vec![figure(r, "left", s0, Fmt::F3)]
    }));
    // A PVT point: the quantity is the second value.
    for quantity in [
        PvtQuantity::Position,
        PvtQuantity::Velocity,
        PvtQuantity::Acceleration,
    ] {
        let reason = Reason::PvtPoint {
            axis: a,
            point: 4101,
            quantity,
            value: s0,
            limit: s1,
        };
        let which = reason.to_wire().values[1];
        out.push(case(reason, &format!("int(v[1]) == {which}"), |r| {
            vec![
                axis_slot(),
                figure(r, "point", 4101.0, Fmt::Int),
                figure(r, "value", s0, Fmt::Num),
                figure(r, "limit", s1, Fmt::Num),
            ]
        }));
    }
    let unreachable = Reason::Unreachable {
        axis: a,
        target_deg: s0,
        min_deg: s1,
        max_deg: s2,
    };
    out.push(case(unreachable, "", |r| {
        vec![
            axis_slot(),
            figure(r, "target", s0, Fmt::Num),
            figure(r, "lo", s1, Fmt::Num),
            figure(r, "hi", s2, Fmt::Num),
        ]
    }));
    let owner = 0x1a2b_0000_0003_u64;
    out.push(case(Reason::NotOwner { owner }, "", |r| {
        let high = wire_slot(r, (owner >> 32) as f64);
        let low = wire_slot(r, (owner & 0xFFFF_FFFF) as f64);
        vec![custom(
            format!("{owner:#x}"),
            "owner",
            format!("\"%#x\" % ((int(v[{high}]) << 32) | int(v[{low}]))"),
        )]
    }));
    out.push(case(Reason::ShuttingDown, "", |_| vec![]));
    out
}

/// The faults of a `move_linear` line (before the other reasons of their codes): told apart by
/// their kind in the last figure.
fn line_cases() -> Vec<Case> {
    let a = axis();
    let [s0, s1, s2, _] = S;
    let fraction = s0 / 100.0;
    let at = || {
        custom(
            Num(fraction * 100.0).to_string(),
            "at",
            "num(v[0] * 100.0)".into(),
        )
    };
    let mut out = Vec::new();
    let mut push = |reason: Reason, slots: fn(&Reason) -> Vec<Slot>| {
        let kind = reason.to_wire().values[3];
        out.push(case(reason, &format!("v[3] == {kind:.1}"), |r| {
            let mut all = vec![at()];
            all.extend(slots(r));
            all
        }));
    };
    push(
        Reason::LineUnreachable {
            axis: None,
            fault: LineFault::NoSolution { fraction },
        },
        |_| vec![],
    );
    for singularity in [
        Singularity::Wrist,
        Singularity::Elbow,
        Singularity::Shoulder,
    ] {
        push(
            Reason::LineUnreachable {
                axis: None,
                fault: LineFault::Singular {
                    fraction,
                    singularity,
                    value: s1,
                    margin: s2,
                },
            },
            |r| {
                vec![
                    figure(r, "value", S[1], Fmt::Num),
                    figure(r, "margin", S[2], Fmt::Num),
                ]
            },
        );
    }
    push(
        Reason::LineUnreachable {
            axis: Some(a),
            fault: LineFault::JointJump {
                fraction,
                step_deg: s1,
                allowed_deg: s2,
            },
        },
        |r| {
            vec![
                axis_slot(),
                figure(r, "step", S[1], Fmt::Num),
                figure(r, "allowed", S[2], Fmt::Num),
            ]
        },
    );
    push(
        Reason::LineOutOfRange {
            axis: a,
            fault: LineFault::OutOfRange {
                fraction,
                value_deg: s1,
                limit_deg: s2,
            },
        },
        |r| {
            vec![
                axis_slot(),
                figure(r, "value", S[1], Fmt::Num),
                figure(r, "limit", S[2], Fmt::Num),
            ]
        },
    );
    out
}

/// `s` as a Python string literal.
fn py_str(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// `text` with each slot's needle replaced (and a literal `%` doubled for Python's `%`).
fn template(text: &str, slots: &[Slot], what: &str) -> String {
    let mut t = text.replace('%', "%%");
    for s in slots {
        assert!(
            t.contains(&s.needle),
            "{what}: `{}` is not in the words {text:?}; did their format change?",
            s.needle
        );
        t = t.replace(&s.needle, &s.replacement);
    }
    for x in S {
        assert!(
            !t.contains(&format!("{x:.1}")),
            "{what}: a sentinel figure is left in {t:?}"
        );
    }
    t
}

/// `reason_text`: per code, its cases in order.
fn reason_text() -> String {
    let mut out = String::from(
        "def reason_text(code: int, axis: int, v: Sequence[float]) -> str:
    \"\"\"The words for a refusal, failure or safety trip, as the core's ``Reason`` gives them.\"\"\"
    name = REJECT_CODES.get(code)
    if name == \"out_of_range\" and 0 < int(v[3]) < 256:
        return argument_text(int(v[3]), axis, v[0], v[1], v[2])
",
    );
    for c in cases() {
        let text = c.reason.to_string();
        let t = template(&text, &c.slots, &format!("{:?}", c.reason));
        let guard = if c.guard.is_empty() {
            String::new()
        } else {
            format!(" and {}", c.guard)
        };
        let _ = writeln!(out, "    if name == \"{}\"{guard}:", c.code.as_str());
        if c.slots.is_empty() {
            let _ = writeln!(out, "        return {}", py_str(&t));
        } else {
            let _ = writeln!(out, "        return {} % {{", py_str(&t));
            for s in &c.slots {
                let _ = writeln!(out, "            \"{}\": {},", s.key, s.py);
            }
            let _ = writeln!(out, "        }}");
        }
    }
    out.push_str("    return \"reason code %d is not known to this client version\" % code\n");
    out
}

/// `_ARG_WORDS`: per argument code, its refusal's words without and with the array index.
fn arg_words() -> String {
    let [s0, s1, s2, _] = S;
    let mut out = String::from(
        "# The words of an argument refusal (``ArgRefusal``'s), per argument code
# (``mcm_shared::ranges::ARGS``): without the element's index, and with it for the per-axis
# arrays (\"\" for the others).
_ARG_WORDS: Dict[int, Tuple[str, str]] = {
",
    );
    for spec in ARGS {
        let words = |axis: Option<Axis>| {
            let r = ArgRefusal {
                arg: spec.arg,
                axis,
                value: s0,
                min: s1,
                max: s2,
            };
            let text = r.to_string();
            let mut slots = vec![custom(Num(s0).to_string(), "value", String::new())];
            for (x, key) in [(s1, "lo"), (s2, "hi")] {
                // An argument that is "other than 0, at most ..." has no lower bound in words.
                if text.contains(&Num(x).to_string()) {
                    slots.push(custom(Num(x).to_string(), key, String::new()));
                }
            }
            if axis.is_some() {
                slots.push(Slot {
                    needle: format!("[{}]", AXIS - 1),
                    replacement: "[%(index)s]".into(),
                    key: "index".into(),
                    py: String::new(),
                });
            }
            template(&text, &slots, spec.name)
        };
        let with_index = if spec.arg.per_axis_array() {
            py_str(&words(Some(axis())))
        } else {
            "\"\"".into()
        };
        let _ = writeln!(
            out,
            "    {}: (\n        {},\n        {},\n    ),",
            spec.arg as u32,
            py_str(&words(None)),
            with_index
        );
    }
    out.push_str("}\n");
    out
}

/// `NAME: TYPE = {...}` of (key, value) rows, with its `#:` doc.
fn table(
    name: &str,
    ty: &str,
    doc: &str,
    rows: impl IntoIterator<Item = (String, String)>,
) -> String {
    let mut out = format!("#: {doc}\n{name}: {ty} = {{\n");
    for (k, v) in rows {
        let _ = writeln!(out, "    {k}: {v},");
    }
    out.push_str("}\n");
    out
}

/// `rows` as the lines of a Python list or tuple, one string literal a line.
fn str_rows<'a>(rows: impl IntoIterator<Item = &'a str>, indent: &str) -> String {
    rows.into_iter()
        .map(|r| format!("{indent}{},\n", py_str(r)))
        .collect()
}

/// The protocol's commands (`mcm_shared::protocol::COMMANDS`): their names in order, the
/// `result_type` each answers on success, those that answer nothing and those that need
/// control.
fn commands() -> String {
    let names = || COMMANDS.iter().map(|c| c.name);
    let mut out = format!(
        "#: The protocol's commands, in the order ``help`` lists them\n\
         #: (``mcm_shared::protocol::COMMANDS``).\nCOMMANDS: Tuple[str, ...] = (\n{})\n\n",
        str_rows(names(), "    ")
    );
    out.push_str(&table(
        "RESULT_TYPES",
        "Dict[str, Optional[str]]",
        "The ``result_type`` of each command's result on success (``CommandDef::success``);\n\
         #: None: it answers nothing on success.",
        COMMANDS.iter().map(|c| {
            let ty = c.success.result_type().map_or("None".into(), py_str);
            (py_str(c.name), ty)
        }),
    ));
    let nothing = COMMANDS.iter().filter(|c| c.success == Success::Nothing);
    let _ = write!(
        out,
        "\n#: Commands that answer nothing on success (``Success::Nothing``): a refusal comes \
         later,\n#: as an ERROR whose ``command`` names the command.\n\
         NO_RESULT: Tuple[str, ...] = (\n{})\n\n",
        str_rows(nothing.map(|c| c.name), "    ")
    );
    let control = COMMANDS.iter().filter(|c| c.needs_control());
    let _ = write!(
        out,
        "#: Commands only the client that controls the arm may send \
         (``CommandDef::needs_control``).\nNEEDS_CONTROL = frozenset(\n    [\n{}    ]\n)\n",
        str_rows(control.map(|c| c.name), "        ")
    );
    out
}

fn render() -> String {
    let mut out = String::from(PRELUDE);
    out.push('\n');
    out.push_str(&table(
        "MODES",
        "Dict[int, str]",
        "Operating modes by wire value.",
        Mode::ALL
            .iter()
            .map(|m| (m.to_wire().to_string(), py_str(m.as_str()))),
    ));
    out.push('\n');
    out.push_str(&table(
        "KINDS",
        "Dict[str, int]",
        "Command kinds by protocol name (``CommandSample.kind``).",
        CommandKind::ALL
            .iter()
            .map(|k| (py_str(k.as_str()), k.to_wire().to_string())),
    ));
    out.push_str("KIND_NAMES: Dict[int, str] = {v: k for k, v in KINDS.items()}\n\n");
    out.push_str(&commands());
    out.push_str("\n#: ``Reply.status`` values.\n");
    for s in ReplyStatus::ALL {
        let _ = writeln!(out, "REPLY_{} = {}", s.as_str().to_uppercase(), s.to_wire());
    }
    out.push('\n');
    out.push_str(&table(
        "REJECT_CODES",
        "Dict[int, str]",
        "Reject codes by wire value (``RejectCode``); also the ``check`` of a safety error.",
        RejectCode::ALL
            .iter()
            .map(|c| (c.to_wire().to_string(), py_str(c.as_str()))),
    ));
    out.push('\n');
    out.push_str(&arg_words());
    out.push_str(FUNCTIONS);
    out.push_str("\n\n");
    out.push_str(&reason_text());
    out.push_str("\n\n");
    out.push_str(&error_codes());
    out.push_str("\n\n");
    out.push_str(&outcomes());
    out
}

/// Every `outcome` of an ERROR result ([`ErrorOutcome`]) as a Python enum of the same names,
/// and the reading of a result's outcome.
fn outcomes() -> String {
    let mut s = String::from(
        "class Outcome(str, Enum):\n    \
         \"\"\"The ``outcome`` of an ERROR result that answers a command \
         (``shared/src/protocol/results/outcome.rs``):\n    how the command ended, never read \
         from the words. A ``str``: ``Outcome.REFUSED == \"refused\"``.\"\"\"\n\n",
    );
    for o in ErrorOutcome::ALL {
        let _ = writeln!(s, "    #: {}", o.meaning());
        let _ = writeln!(
            s,
            "    {} = {}",
            o.as_str().to_uppercase(),
            py_str(o.as_str())
        );
    }
    s.push_str(
        "\n\ndef outcome(result: Dict[str, Any]) -> Optional[Outcome]:\n    \
         \"\"\"The ``outcome`` of an ERROR result; None when it has none (a spontaneous error, \
         an MCM too\n    old to send it) or one this version does not know (a newer MCM).\"\"\"\n    \
         try:\n        return Outcome(result.get(\"outcome\"))\n    \
         except ValueError:\n        return None\n",
    );
    s
}

/// Every error code ([`ErrorCode`]) as a Python enum of the same names, the spontaneous ones,
/// and the reading of a result's code.
fn error_codes() -> String {
    let mut s = String::from(
        "class ErrorCode(str, Enum):\n    \
         \"\"\"The ``error_code`` of an ERROR result (``shared/src/error_code.rs``; the list with \
         what\n    each means and what to do: ``docs/protocol.md``, \"Error codes\"): what a \
         program decides on,\n    never the words. A ``str``: \
         ``ErrorCode.BUSY == \"busy\"``.\"\"\"\n\n",
    );
    for c in ErrorCode::ALL {
        let _ = writeln!(
            s,
            "    {} = {}",
            c.as_str().to_uppercase(),
            py_str(c.as_str())
        );
    }
    s.push_str(
        "\n\n#: The codes of ERROR results that answer no command (notices about the MCM's life, \
         the\n#: connection's timeouts, lost events); a safety error names its ``check`` besides.\n\
         SPONTANEOUS: FrozenSet[ErrorCode] = frozenset({\n",
    );
    for c in ErrorCode::ALL.iter().filter(|c| c.is_spontaneous()) {
        let _ = writeln!(s, "    ErrorCode.{},", c.as_str().to_uppercase());
    }
    s.push_str(
        "})\n\n\ndef error_code(result: Dict[str, Any]) -> Optional[ErrorCode]:\n    \
         \"\"\"The ``error_code`` of an ERROR result; None when it has none, or one this version \
         does not\n    know (a newer MCM).\"\"\"\n    \
         try:\n        return ErrorCode(result.get(\"error_code\"))\n    \
         except ValueError:\n        return None\n",
    );
    s
}

/// Compare `python/src/mcm/<file>` with what the contract generates (writing it first under
/// `MCM_UPDATE_PYTHON`).
fn check_generated(file: &str, generated: &str) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../python/src/mcm")
        .join(file);
    if std::env::var_os("MCM_UPDATE_PYTHON").is_some() {
        // Under CI the file is compared, never written: a CI run that set both would check a
        // file it had just written.
        assert!(
            std::env::var_os("CI").is_none(),
            "MCM_UPDATE_PYTHON is set together with CI: CI compares python/src/mcm/{file}, it never writes it"
        );
        std::fs::write(&path, generated)
            .unwrap_or_else(|e| panic!("write {}: {e}", path.display()));
    }
    let checked_in = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        checked_in == generated,
        "python/src/mcm/{file} differs from what the contract generates; regenerate it with \
         `MCM_UPDATE_PYTHON=1 cargo test -p mcm-shared --test python_codes` and commit it"
    );
}

#[test]
fn the_checked_in_codes_py_is_what_the_contract_generates() {
    check_generated("codes.py", &render());
}

#[test]
fn the_checked_in_encoding_py_is_what_the_contract_generates() {
    check_generated("encoding.py", &encoding::render());
}

#[test]
fn every_reject_code_has_words() {
    let cases = cases();
    for code in RejectCode::ALL {
        // `none` is no refusal.
        assert!(
            *code == RejectCode::None || cases.iter().any(|c| c.code == *code),
            "reject code {code} has no words in the generated reason_text"
        );
    }
}
