//! `sim`: fault injection into the simulated robot (refused on real hardware by the real-time
//! core). Any combination of arguments; the reply is a `sim` result with the ground truth.

use super::sample;
use crate::args::{Args, CommandError};
use mcm_shared::mode::CommandKind;
use mcm_shared::sample::{CommandSample, SIM_FLAG_POWER_CYCLE};
use serde_json::Value;

#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sim {
    pub emergency_stop: Option<bool>,
    pub disconnect_axis: Option<usize>,
    pub reconnect_axis: Option<usize>,
    pub block_axis: Option<usize>,
    pub unblock_axis: Option<usize>,
    pub external_torques: Option<[f64; 6]>,
    pub power_cycle: bool,
}

impl Sim {
    pub fn parse(arguments: Option<&Value>) -> Result<Self, CommandError> {
        let args = Args::new(
            "sim",
            arguments,
            &[
                "emergency_stop",
                "disconnect_axis",
                "reconnect_axis",
                "block_axis",
                "unblock_axis",
                "external_torques",
                "power_cycle",
            ],
        )?;
        Ok(Self {
            emergency_stop: args.boolean("emergency_stop")?,
            disconnect_axis: args.axis("disconnect_axis")?,
            reconnect_axis: args.axis("reconnect_axis")?,
            block_axis: args.axis("block_axis")?,
            unblock_axis: args.axis("unblock_axis")?,
            external_torques: args.six("external_torques", "torques [Nm]", |_, t| {
                if t.abs() <= 1000.0 {
                    Ok(())
                } else {
                    Err("a torque within +-1000 Nm".into())
                }
            })?,
            power_cycle: args.boolean("power_cycle")?.unwrap_or(false),
        })
    }

    pub fn sample(&self) -> CommandSample {
        let mut s = sample(CommandKind::Sim);
        let mut set = |bit: usize, value: f64| {
            s.args[bit] = value;
            s.flags |= 1 << bit;
        };
        if let Some(e) = self.emergency_stop {
            set(0, f64::from(u8::from(e)));
        }
        for (bit, axis) in [
            (1, self.disconnect_axis),
            (2, self.reconnect_axis),
            (3, self.block_axis),
            (4, self.unblock_axis),
        ] {
            if let Some(a) = axis {
                set(bit, a as f64);
            }
        }
        if let Some(t) = self.external_torques {
            s.args[5..11].copy_from_slice(&t);
            s.flags |= 1 << 5;
        }
        if self.power_cycle {
            s.flags |= SIM_FLAG_POWER_CYCLE;
        }
        s
    }
}
