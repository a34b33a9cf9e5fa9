//! The typed answers of the real-time core: a [`Response`] to each request, the [`Reason`]
//! of every refusal, failure or safety trip, and the [`SafetyError`] record; each with the one
//! `encode`/`decode` pair that maps it onto the wire structs of [`crate::sample`].
//!
//! Nothing outside this module reads `Reply::values` or `ErrorRecord::values` by position.
//! Decoding checks every number, so an answer from another MCM version is a [`DecodeError`]
//! naming what was unknown, never a silent "no error". Encoding and decoding never allocate.
//!
//! ```
//! use mcm_shared::command::Axis;
//! use mcm_shared::mode::CommandKind;
//! use mcm_shared::reply::{Outcome, Reason, Response};
//! let r = Response {
//!     client_id: 1,
//!     request_id: 9,
//!     kind: CommandKind::MoveAxis,
//!     outcome: Outcome::Refused(Reason::Busy { remaining_s: 0.25 }),
//! };
//! assert_eq!(Response::decode(&r.encode()), Ok(r));
//! assert_eq!(
//!     Reason::NotCalibrated { axis: Axis::new(3).unwrap() }.to_string(),
//!     "axis 3 is not calibrated; run `calibrate` first"
//! );
//! ```

use crate::NUM_AXES;
use crate::command::{Axis, DecodeError};
use crate::mode::{CommandKind, ReplyStatus};
use crate::ranges::{Arg, ArgRefusal};
use crate::sample::{CommandSample, ErrorRecord, Reply};

mod reason;
pub use reason::{CalibrationFailure, LineFault, PvtQuantity, Reason, Singularity, WireReason};

/// The move a `move_all` planned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveAllPlan {
    /// Peak velocity of each axis [deg/s].
    pub velocities_deg_s: [f64; NUM_AXES],
    /// The axis that needs the longest (it sets the pace of the others).
    pub longest: Axis,
    /// Time from now to arrival [s].
    pub duration_s: f64,
}

/// The line a `move_linear` planned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveLinearPlan {
    /// Time from now to arrival [s].
    pub duration_s: f64,
    /// Each axis's position at the end of the line [deg].
    pub joint_target_deg: [f64; NUM_AXES],
}

/// What the core says about itself in answer to `info`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InfoReply {
    pub num_axes: u32,
    /// Cycle period [s].
    pub period_s: f64,
}

/// What `identify_payload` found: the load on the flange.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PayloadReply {
    /// [kg]
    pub mass_kg: f64,
    /// Flange frame [m] (zeros for a load too light to place).
    pub center_of_mass_m: [f64; 3],
    /// RMS of the holding torque the estimate does not explain, over every axis and pose [N·m].
    pub residual_nm: f64,
}

/// What a command that succeeded answers: most say only "done" ([`Done::Ack`]); `info`,
/// `move_all` and `identify_payload` carry figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Done {
    Ack,
    Info(InfoReply),
    MoveAll(MoveAllPlan),
    Payload(PayloadReply),
    MoveLinear(MoveLinearPlan),
}

/// How the core answered a request.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Outcome {
    /// Done (or accepted, for commands that start a motion).
    Done(Done),
    /// Refused; nothing changed.
    Refused(Reason),
    /// Accepted, but failed while running (e.g. a calibration that found no stop).
    Failed(Reason),
}

/// The answer to one request.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Response {
    pub client_id: u64,
    pub request_id: u64,
    /// The kind of the request answered.
    pub kind: CommandKind,
    pub outcome: Outcome,
}

impl Response {
    /// The wire form (`seq` 0: the reply ring numbers it).
    pub fn encode(&self) -> Reply {
        let mut r = Reply {
            client_id: self.client_id,
            request_id: self.request_id,
            kind: self.kind.to_wire(),
            ..Reply::default()
        };
        let reason = match self.outcome {
            Outcome::Done(done) => {
                r.status = ReplyStatus::Ok.to_wire();
                match done {
                    Done::Ack => {}
                    Done::Info(i) => {
                        r.values[0] = f64::from(i.num_axes);
                        r.values[1] = i.period_s;
                    }
                    Done::MoveAll(p) => {
                        r.values[..NUM_AXES].copy_from_slice(&p.velocities_deg_s);
                        r.values[NUM_AXES] = f64::from(p.longest.number());
                        r.values[NUM_AXES + 1] = p.duration_s;
                    }
                    Done::Payload(p) => {
                        r.values[0] = p.mass_kg;
                        r.values[1..4].copy_from_slice(&p.center_of_mass_m);
                        r.values[4] = p.residual_nm;
                    }
                    Done::MoveLinear(p) => {
                        r.values[..NUM_AXES].copy_from_slice(&p.joint_target_deg);
                        r.values[NUM_AXES] = p.duration_s;
                    }
                }
                return r;
            }
            Outcome::Refused(reason) => {
                r.status = ReplyStatus::Rejected.to_wire();
                reason
            }
            Outcome::Failed(reason) => {
                r.status = ReplyStatus::Failed.to_wire();
                reason
            }
        };
        let w = reason.to_wire();
        r.code = w.code.to_wire();
        r.axis = w.axis;
        r.values[..4].copy_from_slice(&w.values);
        r
    }

    /// The typed answer a wire reply stands for.
    pub fn decode(r: &Reply) -> Result<Response, DecodeError> {
        let kind = CommandKind::try_from(r.kind).map_err(|_| DecodeError::UnknownKind(r.kind))?;
        let status = ReplyStatus::try_from(r.status).map_err(|e| DecodeError::Unknown {
            what: e.what,
            value: e.value,
        })?;
        let reason = || {
            let v = &r.values;
            Reason::from_wire(r.code, r.axis, &[v[0], v[1], v[2], v[3]])
        };
        let outcome = match status {
            ReplyStatus::Ok => Outcome::Done(match kind {
                CommandKind::Info => Done::Info(InfoReply {
                    num_axes: r.values[0] as u32,
                    period_s: r.values[1],
                }),
                CommandKind::MoveAll => {
                    let v = &r.values;
                    let longest = v[NUM_AXES];
                    let longest = (longest.fract() == 0.0 && (1.0..=6.0).contains(&longest))
                        .then(|| Axis::new(longest as u8))
                        .flatten()
                        .ok_or(DecodeError::Mismatch {
                            kind,
                            problem: "the longest axis is not 1 to 6",
                        })?;
                    let mut velocities_deg_s = [0.0; NUM_AXES];
                    velocities_deg_s.copy_from_slice(&v[..NUM_AXES]);
                    Done::MoveAll(MoveAllPlan {
                        velocities_deg_s,
                        longest,
                        duration_s: v[NUM_AXES + 1],
                    })
                }
                CommandKind::IdentifyPayload => {
                    let v = &r.values;
                    Done::Payload(PayloadReply {
                        mass_kg: v[0],
                        center_of_mass_m: [v[1], v[2], v[3]],
                        residual_nm: v[4],
                    })
                }
                CommandKind::MoveLinear => {
                    let mut joint_target_deg = [0.0; NUM_AXES];
                    joint_target_deg.copy_from_slice(&r.values[..NUM_AXES]);
                    Done::MoveLinear(MoveLinearPlan {
                        duration_s: r.values[NUM_AXES],
                        joint_target_deg,
                    })
                }
                _ => Done::Ack,
            }),
            ReplyStatus::Rejected => Outcome::Refused(reason()?),
            ReplyStatus::Failed => Outcome::Failed(reason()?),
        };
        Ok(Response {
            client_id: r.client_id,
            request_id: r.request_id,
            kind,
            outcome,
        })
    }
}

/// The wire reply refusing a sample that did not decode: the sample's own (possibly unknown)
/// kind and ids, status `REJECTED`, and the fault as `OutOfRange` naming the value and the
/// allowed bounds (an unknown kind as its number against the known range); a value of a
/// protocol argument out of its range ([`crate::ranges`]) as [`Reason::InvalidArgument`].
pub fn refuse_undecodable(sample: &CommandSample, e: &DecodeError) -> Reply {
    if let DecodeError::Invalid {
        field,
        value,
        allowed,
        ..
    } = *e
        && let Some(arg) = Arg::by_name(field.name)
        && !matches!(allowed, crate::command::Allowed::Finite)
    {
        let (min, max) = allowed.bounds();
        let axis = field.axis();
        return refusal_reply(
            sample,
            Reason::InvalidArgument {
                refusal: ArgRefusal {
                    arg,
                    axis,
                    value,
                    min,
                    max,
                },
            },
        );
    }
    let (axis, value, (min, max)) = match *e {
        DecodeError::Invalid {
            field,
            value,
            allowed,
            ..
        } => (field.axis(), value, allowed.bounds()),
        DecodeError::UnknownKind(kind) => (
            None,
            f64::from(kind),
            (
                f64::from(CommandKind::ALL[0].to_wire()),
                f64::from(CommandKind::ALL[CommandKind::ALL.len() - 1].to_wire()),
            ),
        ),
        DecodeError::Unknown { value, .. } => (None, f64::from(value), (0.0, 0.0)),
        DecodeError::Mismatch { .. } => (None, 0.0, (0.0, 0.0)),
    };
    refusal_reply(
        sample,
        Reason::OutOfRange {
            axis,
            value,
            min,
            max,
        },
    )
}

fn refusal_reply(sample: &CommandSample, reason: Reason) -> Reply {
    let w = reason.to_wire();
    let mut r = Reply {
        client_id: sample.client_id,
        request_id: sample.request_id,
        kind: sample.kind,
        status: ReplyStatus::Rejected.to_wire(),
        code: w.code.to_wire(),
        axis: w.axis,
        ..Reply::default()
    };
    r.values[..4].copy_from_slice(&w.values);
    r
}

/// A safety violation or drive error, as the core reports it to every client once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SafetyError {
    /// Increments with every new error (1, 2, ...).
    pub seq: u64,
    /// Cycle in which it tripped.
    pub cycle: u64,
    /// `CLOCK_REALTIME` of that cycle [ns since the Unix epoch].
    pub unix_ns: u64,
    /// The check that tripped and its figures.
    pub reason: Reason,
}

impl SafetyError {
    /// The wire record.
    pub fn encode(&self) -> ErrorRecord {
        let w = self.reason.to_wire();
        ErrorRecord {
            seq: self.seq,
            cycle: self.cycle,
            unix_ns: self.unix_ns,
            code: w.code.to_wire(),
            axis: w.axis,
            values: w.values,
        }
    }

    /// The error a wire record stands for; `Ok(None)` for the empty record (`seq` 0: no error
    /// since start).
    pub fn decode(e: &ErrorRecord) -> Result<Option<SafetyError>, DecodeError> {
        if e.seq == 0 {
            return Ok(None);
        }
        Ok(Some(SafetyError {
            seq: e.seq,
            cycle: e.cycle,
            unix_ns: e.unix_ns,
            reason: Reason::from_wire(e.code, e.axis, &e.values)?,
        }))
    }
}

mod words;
pub use words::OutcomeWords;

#[cfg(test)]
pub(crate) mod tests;
