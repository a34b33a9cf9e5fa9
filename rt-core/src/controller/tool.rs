//! The active tool: `set_tool` replaces the tool of the arm's model, the one model every use
//! in the core reads (the gravity feed-forward in HOLD and the motion modes, gravity and
//! friction compensation in RELEASE and TORQUE_CONTROL, the braking check's accelerations),
//! so all of them see it from the cycle the command arrives in, and the TCP of the kinematics
//! (the published TCP state, VELOCITY_CONTROL's TCP velocity) follows it in the same cycle.
//! The configuration's `[arm.tool]` is the tool at start.
//!
//! Runs inside the cycle: the tool is plain `Copy` data, checked when its sample was decoded.

use super::Controller;
use super::state::{Caller, PvtMotion, State};
use crate::cartesian::Cartesian;
use mcm_kinematics::Kinematics;
use mcm_shared::command::SetTool;
use mcm_shared::reply::{Done, Reason};
use mcm_shared::tool::Tool;

impl Controller {
    /// The active tool: TCP and load.
    pub fn tool(&self) -> &Tool {
        self.model.tool()
    }

    /// The kinematics with the active tool's TCP, as the published TCP state uses them.
    pub fn cartesian(&self) -> &Cartesian {
        &self.cartesian
    }

    /// The kinematics with the active tool's TCP.
    pub(super) fn kinematics(&self) -> &Kinematics {
        self.cartesian.kinematics()
    }

    /// Make `tool` the active tool, from this cycle on (`set_tool`, `identify_payload` with
    /// `apply`): the model's load and the kinematics' TCP.
    pub(super) fn use_tool(&mut self, tool: &Tool) {
        self.model.set_tool(tool);
        // A tool is checked when its sample is decoded (`Tool::new`), so its TCP is a
        // transform and never refused here; were it refused, the sample's `cartesian` would
        // not be the kinematics of the `tool` it reports, which the simulation tester checks
        // every cycle.
        let _ = self.cartesian.follow_tool(&tool.tcp);
    }

    /// `set_tool`: in HOLD, or in PVT with the arm at standstill (no move, stop or stream
    /// under way); refused `busy` while the arm moves, `wrong_mode` elsewhere.
    pub(super) fn on_set_tool(&mut self, c: Caller, t: SetTool) {
        match self.state {
            State::Hold { stop: None }
            | State::Pvt {
                motion: PvtMotion::Hold,
                ..
            } => {
                self.use_tool(&t.tool);
                self.done(c, Done::Ack);
            }
            State::Pvt {
                motion: PvtMotion::Stream,
                ..
            } => {
                let remaining_s = self.stream.queued() as f64 * self.stream.dt();
                self.refuse(c, Reason::Busy { remaining_s });
            }
            State::Hold { stop: Some(_) } | State::Pvt { .. } => self.busy(c),
            _ => self.wrong_mode(c),
        }
    }
}

#[cfg(all(test, feature = "sim"))]
mod tests;
