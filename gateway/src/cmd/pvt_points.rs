//! `pvt_points`: stream position/velocity points in PVT mode, spaced by the `dt` given with
//! `pvt`. A batch is split into samples of `PVT_POINTS_PER_COMMAND` points; the real-time core
//! queues the batch only when its last sample arrived and every point fits, so a batch is
//! queued whole or not at all.

use super::{check_position, sample};
use crate::args::{Args, CommandError, six_numbers};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::CommandKind;
use mcm_shared::sample::{CommandSample, PVT_FLAG_LAST, PVT_POINTS_PER_COMMAND};
use serde_json::Value;

/// Most points in one `pvt_points` command (the real-time queue holds at least this many).
pub const MAX_POINTS_PER_BATCH: usize = 1000;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PvtPoint {
    /// [deg]
    pub position: [f64; 6],
    /// [deg/s]
    pub velocity: [f64; 6],
}

#[derive(Debug, Clone, PartialEq)]
pub struct PvtPoints {
    pub points: Vec<PvtPoint>,
}

impl PvtPoints {
    pub fn parse(arguments: Option<&Value>, cfg: &RobotConfig) -> Result<Self, CommandError> {
        let args = Args::new("pvt_points", arguments, &["points"])?;
        let expected = format!(
            "an array of 1 to {MAX_POINTS_PER_BATCH} points {{\"position\":[6 deg],\"velocity\":[6 deg/s]}}"
        );
        let Some(raw) = args.raw("points") else {
            return Err(CommandError::Missing {
                command: "pvt_points",
                argument: "points",
                expected,
            });
        };
        let list = raw
            .as_array()
            .filter(|a| !a.is_empty() && a.len() <= MAX_POINTS_PER_BATCH)
            .ok_or_else(|| args.invalid("points", raw, expected.clone()))?;
        let mut points = Vec::with_capacity(list.len());
        for (k, p) in list.iter().enumerate() {
            let obj = p
                .as_object()
                .filter(|o| {
                    o.len() == 2 && o.contains_key("position") && o.contains_key("velocity")
                })
                .ok_or_else(|| {
                    args.invalid(
                        &format!("points[{k}]"),
                        p,
                        "an object with exactly \"position\" and \"velocity\"",
                    )
                })?;
            let position = six_numbers(
                &args,
                &format!("points[{k}].position"),
                &obj["position"],
                "positions [deg]",
                |i, x| check_position(cfg, i, x),
            )?;
            let velocity = six_numbers(
                &args,
                &format!("points[{k}].velocity"),
                &obj["velocity"],
                "velocities [deg/s]",
                |i, v| {
                    let max = cfg.axes[i].max_velocity_deg_s;
                    if v.abs() > max {
                        Err(format!("a velocity of axis {} within +-{max} deg/s", i + 1))
                    } else {
                        Ok(())
                    }
                },
            )?;
            points.push(PvtPoint { position, velocity });
        }
        Ok(Self { points })
    }

    pub fn samples(&self) -> Vec<CommandSample> {
        let chunks: Vec<_> = self.points.chunks(PVT_POINTS_PER_COMMAND).collect();
        let last = chunks.len() - 1;
        chunks
            .iter()
            .enumerate()
            .map(|(c, chunk)| {
                let mut s = sample(CommandKind::PvtPoints);
                s.flags = chunk.len() as u32 | if c == last { PVT_FLAG_LAST } else { 0 };
                for (j, p) in chunk.iter().enumerate() {
                    s.args[j * 12..j * 12 + 6].copy_from_slice(&p.position);
                    s.args[j * 12 + 6..j * 12 + 12].copy_from_slice(&p.velocity);
                }
                s
            })
            .collect()
    }
}
