//! Decoding command samples into typed requests.
//!
//! Runs inside the cycle: plain data in, plain data out, no allocation. The gateway validates
//! arguments before publishing, but co-located controllers publish samples directly, so every
//! value is checked again here; a bad value becomes a rejection naming it.

use mcm_shared::mode::{CommandKind, RejectCode};
use mcm_shared::sample::{
    CALIBRATE_FLAG_FORCE_STOP, CommandSample, PVT_FLAG_LAST, PVT_POINTS_PER_COMMAND,
    SIM_FLAG_POWER_CYCLE, TORQUE_FLAG_NO_GRAVITY,
};
use mcm_sim::SimCommand;

/// Which axes a calibration covers (0-based axis bit mask).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AxisSet(pub u8);

impl AxisSet {
    pub const ALL: AxisSet = AxisSet(0b11_1111);
    pub fn contains(self, axis: usize) -> bool {
        self.0 & (1 << axis) != 0
    }
}

/// A decoded command.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Request {
    Status,
    Hold,
    Info,
    Calibrate {
        axes: AxisSet,
        elbow_direction: f64,
        wrist_direction: f64,
        force_mechanical_stop: bool,
    },
    Release,
    TorqueControl {
        /// [s]; `None`: no timeout.
        timeout: Option<f64>,
        gravity_compensation: bool,
    },
    Pvt {
        dt: f64,
    },
    MoveAxis {
        axis: usize,
        target_deg: f64,
        velocity_factor: f64,
    },
    MoveAll {
        target_deg: [f64; 6],
        velocity_factor: f64,
    },
    PvtPoints {
        count: usize,
        last: bool,
    },
    SetTorques {
        torques: [f64; 6],
    },
    Sim(SimCommand),
}

/// Why a sample could not be decoded: the reject code, the axis (1-based, 0 for none) and the
/// values for its message.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DecodeError {
    pub code: RejectCode,
    pub axis: u32,
    pub values: [f64; 3],
}

fn out_of_range(axis: u32, value: f64, min: f64, max: f64) -> DecodeError {
    DecodeError {
        code: RejectCode::OutOfRange,
        axis,
        values: [value, min, max],
    }
}

fn axis_arg(x: f64) -> Result<usize, DecodeError> {
    if x.fract() == 0.0 && (1.0..=6.0).contains(&x) {
        Ok(x as usize - 1)
    } else {
        Err(out_of_range(0, x, 1.0, 6.0))
    }
}

fn factor(x: f64) -> Result<f64, DecodeError> {
    if x > 0.0 && x <= 1.0 {
        Ok(x)
    } else {
        Err(out_of_range(0, x, 0.0, 1.0))
    }
}

fn finite6(args: &[f64]) -> Result<[f64; 6], DecodeError> {
    let mut v = [0.0; 6];
    for (i, x) in args[..6].iter().enumerate() {
        if !x.is_finite() {
            return Err(out_of_range(i as u32 + 1, *x, f64::MIN, f64::MAX));
        }
        v[i] = *x;
    }
    Ok(v)
}

/// Decode one sample.
pub fn decode(s: &CommandSample) -> Result<Request, DecodeError> {
    let kind =
        CommandKind::try_from(s.kind).map_err(|_| out_of_range(0, f64::from(s.kind), 1.0, 12.0))?;
    let a = &s.args;
    Ok(match kind {
        CommandKind::Status => Request::Status,
        CommandKind::Hold => Request::Hold,
        CommandKind::Info => Request::Info,
        CommandKind::Release => Request::Release,
        CommandKind::Calibrate => {
            let axes = match a[0] {
                0.0 => AxisSet::ALL,
                7.0 => AxisSet(0b00_0111),
                8.0 => AxisSet(0b11_1000),
                x => AxisSet(1 << axis_arg(x)?),
            };
            let dir = |x: f64| {
                if x == 1.0 || x == -1.0 {
                    Ok(x)
                } else {
                    Err(out_of_range(0, x, -1.0, 1.0))
                }
            };
            Request::Calibrate {
                axes,
                elbow_direction: dir(a[1])?,
                wrist_direction: dir(a[2])?,
                force_mechanical_stop: s.flags & CALIBRATE_FLAG_FORCE_STOP != 0,
            }
        }
        CommandKind::TorqueControl => {
            let t = a[0];
            if !t.is_finite() || t == 0.0 {
                return Err(out_of_range(0, t, -1.0, 3600.0));
            }
            Request::TorqueControl {
                timeout: (t > 0.0).then_some(t),
                gravity_compensation: s.flags & TORQUE_FLAG_NO_GRAVITY == 0,
            }
        }
        CommandKind::Pvt => {
            if !(a[0] > 0.0 && a[0] <= 1.0) {
                return Err(out_of_range(0, a[0], 0.0, 1.0));
            }
            Request::Pvt { dt: a[0] }
        }
        CommandKind::MoveAxis => {
            let axis = axis_arg(a[0])?;
            if !a[1].is_finite() {
                return Err(out_of_range(axis as u32 + 1, a[1], f64::MIN, f64::MAX));
            }
            Request::MoveAxis {
                axis,
                target_deg: a[1],
                velocity_factor: factor(a[2])?,
            }
        }
        CommandKind::MoveAll => Request::MoveAll {
            target_deg: finite6(a)?,
            velocity_factor: factor(a[6])?,
        },
        CommandKind::PvtPoints => {
            let count = (s.flags & 0xFF) as usize;
            if count == 0 || count > PVT_POINTS_PER_COMMAND {
                return Err(out_of_range(
                    0,
                    count as f64,
                    1.0,
                    PVT_POINTS_PER_COMMAND as f64,
                ));
            }
            Request::PvtPoints {
                count,
                last: s.flags & PVT_FLAG_LAST != 0,
            }
        }
        CommandKind::SetTorques => Request::SetTorques {
            torques: finite6(a)?,
        },
        CommandKind::Sim => Request::Sim(decode_sim(s)?),
    })
}

fn decode_sim(s: &CommandSample) -> Result<SimCommand, DecodeError> {
    let a = &s.args;
    let has = |bit: u32| s.flags & (1 << bit) != 0;
    let axis = |bit: u32| -> Result<Option<usize>, DecodeError> {
        if has(bit) {
            axis_arg(a[bit as usize]).map(Some)
        } else {
            Ok(None)
        }
    };
    Ok(SimCommand {
        emergency_stop: has(0).then(|| a[0] != 0.0),
        disconnect_axis: axis(1)?,
        reconnect_axis: axis(2)?,
        block_axis: axis(3)?,
        unblock_axis: axis(4)?,
        external_torques: if has(5) {
            Some(finite6(&a[5..])?)
        } else {
            None
        },
        power_cycle: s.flags & SIM_FLAG_POWER_CYCLE != 0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(kind: CommandKind, args: &[f64], flags: u32) -> CommandSample {
        let mut s = CommandSample {
            kind: kind.to_wire(),
            flags,
            ..CommandSample::default()
        };
        s.args[..args.len()].copy_from_slice(args);
        s
    }

    #[test]
    fn decodes_move_axis_and_rejects_bad_axis() {
        let r = decode(&sample(CommandKind::MoveAxis, &[2.0, 30.0, 0.5], 0)).unwrap();
        assert_eq!(
            r,
            Request::MoveAxis {
                axis: 1,
                target_deg: 30.0,
                velocity_factor: 0.5
            }
        );
        let e = decode(&sample(CommandKind::MoveAxis, &[7.0, 30.0, 0.5], 0)).unwrap_err();
        assert_eq!(e.code, RejectCode::OutOfRange);
        assert_eq!(e.values, [7.0, 1.0, 6.0]);
        assert!(decode(&sample(CommandKind::MoveAxis, &[1.0, f64::NAN, 0.5], 0)).is_err());
        assert!(decode(&sample(CommandKind::MoveAxis, &[1.0, 3.0, 0.0], 0)).is_err());
    }

    #[test]
    fn decodes_calibrate_sets() {
        let r = decode(&sample(
            CommandKind::Calibrate,
            &[8.0, 1.0, -1.0],
            CALIBRATE_FLAG_FORCE_STOP,
        ))
        .unwrap();
        let Request::Calibrate {
            axes,
            wrist_direction,
            force_mechanical_stop,
            ..
        } = r
        else {
            panic!()
        };
        assert!(!axes.contains(2) && axes.contains(3) && axes.contains(5));
        assert_eq!(wrist_direction, -1.0);
        assert!(force_mechanical_stop);
    }

    #[test]
    fn decodes_sim_fields_by_flag() {
        let mut s = sample(
            CommandKind::Sim,
            &[1.0, 0.0, 0.0, 3.0],
            (1 << 0) | (1 << 3) | SIM_FLAG_POWER_CYCLE,
        );
        s.args[5] = 2.0;
        let Request::Sim(c) = decode(&s).unwrap() else {
            panic!()
        };
        assert_eq!(c.emergency_stop, Some(true));
        assert_eq!(c.block_axis, Some(2));
        assert_eq!(c.disconnect_axis, None);
        assert_eq!(c.external_torques, None);
        assert!(c.power_cycle);
    }

    #[test]
    fn unknown_kind_is_rejected() {
        let s = CommandSample {
            kind: 99,
            ..CommandSample::default()
        };
        assert_eq!(decode(&s).unwrap_err().values[0], 99.0);
    }
}
