//! `pvt_points`: stream position/velocity points in PVT mode, spaced by the `dt` given with
//! `pvt`. The bridge sends a batch as chunks ([`mcm_shared::command::PvtChunk::batch`]); the
//! real-time core queues the batch only when its last chunk arrived and every point fits, so a
//! batch is queued whole or not at all.

use super::check_position;
use crate::args::{Args, CommandError, six_numbers};
use mcm_shared::command::PvtPoint;
use mcm_shared::config::RobotConfig;
use serde_json::Value;

/// Most points in one `pvt_points` command (the real-time queue holds at least this many).
pub const MAX_POINTS_PER_BATCH: usize = 1000;

/// A whole `pvt_points` batch, 1 to [`MAX_POINTS_PER_BATCH`] points.
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
            let position_deg = six_numbers(
                &args,
                &format!("points[{k}].position"),
                &obj["position"],
                "positions [deg]",
                |i, x| check_position(cfg, i, x),
            )?;
            let velocity_deg_s = six_numbers(
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
            points.push(PvtPoint {
                position_deg,
                velocity_deg_s,
            });
        }
        Ok(Self { points })
    }
}
