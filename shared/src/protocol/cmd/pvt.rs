//! `pvt`: enter PVT (from HOLD, every axis calibrated) with `dt`, the spacing of the streamed
//! points, from one cycle to [`Pvt::MAX_DT_S`] ([`Arg::Dt`]). Answers the status after the mode
//! change.

use super::prelude::*;
use crate::command::Pvt;

/// Default spacing of PVT points [s].
pub const DEFAULT_PVT_DT: f64 = 0.01;

impl Definition for Pvt {
    const DEF: CommandDef = CommandDef {
        name: "pvt",
        kind: Some(CommandKind::Pvt),
        sends: None,
        success: Success::Status,
        group: Group::ModeChange,
        ok_words: "",
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
    };

    fn parse(args: &Args<'_>, cfg: &RobotConfig) -> Result<Self, CommandError> {
        Ok(Pvt {
            dt_s: args
                .ranged(Arg::Dt, Arg::Dt.bounds(cfg, None))?
                .unwrap_or(DEFAULT_PVT_DT),
        })
    }

    fn arguments(&self) -> Map<String, Value> {
        let mut m = Map::new();
        m.insert("dt".into(), self.dt_s.into());
        m
    }

    fn requests(&self) -> Vec<Request> {
        vec![Request::Pvt(*self)]
    }
}
