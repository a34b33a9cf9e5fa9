//! `pvt_points`: stream position/velocity points in PVT mode, spaced by the `dt` given with
//! `pvt`. The bridge sends a batch as chunks ([`PvtChunk::batch`]); the
//! real-time core queues the batch only when its last chunk arrived and every point fits, so a
//! batch is queued whole or not at all.
//!
//! Before any chunk is sent, [`PvtPoints::check`] refuses what the core would surely refuse,
//! as the core would word it, from the configuration and the newest state: a mode other than
//! PVT, a batch larger than the free room of the queue, and any point outside the reachable
//! range or faster than its axis may go (the core's own check, [`check_point`]).
//! What needs the core's queue (the segments between points, a move under way) is checked by
//! the core when the last chunk arrives.

use super::prelude::*;
use crate::command::{Axis, PvtChunk, PvtPoint};
use crate::mode::Mode;
use crate::protocol::args::six_numbers;
use crate::pvt::{PointLimits, check_point};
use crate::reply::Reason;
use crate::sample::StateSample;
use crate::units::{deg_to_rad6, rad_to_deg};

/// Most points in one `pvt_points` command (the real-time queue holds at least this many).
pub const MAX_POINTS_PER_BATCH: usize = 1000;

/// A whole `pvt_points` batch, 1 to [`MAX_POINTS_PER_BATCH`] points.
#[derive(Debug, Clone, PartialEq)]
pub struct PvtPoints {
    pub points: Vec<PvtPoint>,
}

impl Definition for PvtPoints {
    const DEF: CommandDef = CommandDef {
        name: "pvt_points",
        kind: Some(CommandKind::PvtPoints),
        sends: None,
        success: Success::Ok,
        group: Group::Pvt,
        ok_words: " - points queued",
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
    };

    fn parse(args: &Args<'_>, _: &RobotConfig) -> Result<Self, CommandError> {
        let expected = format!(
            "an array of 1 to {MAX_POINTS_PER_BATCH} points {{\"position\":[6 deg],\"velocity\":[6 deg/s]}}"
        );
        let Some(raw) = args.raw("points") else {
            return Err(args.missing("points", &expected));
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
            // Positions and speeds are checked against the limits by [`PvtPoints::check`],
            // the core's own check, so a point out of range reads as the core words it.
            let position_deg = six_numbers(
                args,
                &format!("points[{k}].position"),
                &obj["position"],
                "positions [deg]",
            )?;
            let velocity_deg_s = six_numbers(
                args,
                &format!("points[{k}].velocity"),
                &obj["velocity"],
                "velocities [deg/s]",
            )?;
            points.push(PvtPoint {
                position_deg,
                velocity_deg_s,
            });
        }
        Ok(Self { points })
    }

    fn arguments(&self) -> Map<String, Value> {
        let points: Vec<Value> = self
            .points
            .iter()
            .map(|p| {
                let mut o = Map::new();
                o.insert("position".into(), p.position_deg.to_vec().into());
                o.insert("velocity".into(), p.velocity_deg_s.to_vec().into());
                Value::Object(o)
            })
            .collect();
        let mut m = Map::new();
        m.insert("points".into(), points.into());
        m
    }

    fn requests(&self) -> Vec<Request> {
        PvtChunk::batch(&self.points)
            .map(Request::PvtPoints)
            .collect()
    }
}

impl PvtPoints {
    /// What the core would refuse of this batch, known from the configuration's `limits` (built
    /// once per gateway) and the newest `state`: the refusal the core would give, or `Ok` when
    /// the batch may be sent.
    pub fn check(&self, limits: &PointLimits, state: &StateSample) -> Result<(), Reason> {
        // (A mode unknown to this gateway is left to the core.)
        if let Ok(mode) = Mode::try_from(state.mode)
            && mode != Mode::Pvt
        {
            return Err(Reason::WrongMode { mode });
        }
        let offered = u32::try_from(self.points.len()).unwrap_or(u32::MAX);
        let free = state.pvt_capacity.saturating_sub(state.pvt_queued);
        if offered > free {
            return Err(Reason::QueueFull { offered, free });
        }
        for (index, p) in self.points.iter().enumerate() {
            let position = deg_to_rad6(&p.position_deg);
            let velocity = deg_to_rad6(&p.velocity_deg_s);
            if let Err(e) = check_point(&position, &velocity, limits) {
                return Err(Reason::PvtPoint {
                    axis: Axis::ALL[e.axis],
                    point: u32::try_from(index + 1).unwrap_or(u32::MAX),
                    quantity: e.what,
                    value: rad_to_deg(e.value),
                    limit: rad_to_deg(e.limit),
                });
            }
        }
        Ok(())
    }
}
