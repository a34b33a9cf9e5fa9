//! Control ownership: at most one client (a gateway connection or a co-located shared-memory
//! client, named by the `client_id` it stamps on its samples) controls the arm's motion.
//!
//! Runs inside the cycle: one `u64`, no allocation.
//!
//! The rules, the same for every client:
//! - `take_control` makes the sender the owner when nobody owns the arm (or it already does);
//!   otherwise it is refused `NotOwner { owner }`.
//! - A command that [`CommandKind::needs_control`] from a client while nobody owns the arm
//!   makes that client the owner first (the implicit take), whatever the command's own answer.
//!   From a client that is not the owner it is refused `NotOwner { owner }` and changes
//!   nothing.
//! - `hold`, `status`, `info`, `sim`, `take_control`, `release_control` and `client_gone` are
//!   open to every client: a stop is never refused for lack of control.
//! - `release_control` from the owner, or `client_gone` from the owner, ends the ownership and
//!   brings whatever the owner drove to HOLD within that cycle: a PVT move or stream, RELEASE and
//!   TORQUE_CONTROL end in the controlled stop `hold` uses; a calibration is aborted like `hold`
//!   aborts it (the axes it was searching keep the calibration they had before: a homing search
//!   nobody watches is a motion like any other); an enabling that was to start a calibration ends
//!   in HOLD instead. OFF, ERROR and HOLD stay as they are. `release_control` while nobody owns the
//!   arm is OK; from another client it is refused `NotOwner`. `client_gone` from a client that does
//!   not own the arm changes nothing.
//! - Client id 0 means "nobody" in the state (`owner_client_id`): a sample with client id 0
//!   never gets control, so its motion commands are refused `NotOwner`.

use super::Controller;
use super::exits::Exit;
use super::state::Caller;
use mcm_shared::command::Request;
use mcm_shared::mode::CommandKind;
use mcm_shared::reply::{Done, Reason};

/// What the ownership rules say about one request.
pub(super) enum Gate {
    /// Serve the request as usual.
    Pass,
    /// The rules answered it (a control command, or a refusal): nothing else to do.
    Answered,
}

impl Controller {
    /// The client that controls the arm's motion (0: nobody).
    pub fn owner(&self) -> u64 {
        self.owner
    }

    /// Apply the ownership rules to `req` from `c`, before the mode logic sees it.
    pub(super) fn gate(&mut self, c: Caller, req: &Request) -> Gate {
        let me = c.client_id;
        match req {
            Request::TakeControl => {
                if CommandKind::may_control(self.owner, me) {
                    self.owner = me;
                    self.done(c, Done::Ack);
                } else {
                    self.refuse(c, Reason::NotOwner { owner: self.owner });
                }
                Gate::Answered
            }
            Request::ReleaseControl => {
                if self.owner == 0 {
                    self.done(c, Done::Ack);
                } else if self.owner == me {
                    self.lose_owner();
                    self.done(c, Done::Ack);
                } else {
                    self.refuse(c, Reason::NotOwner { owner: self.owner });
                }
                Gate::Answered
            }
            Request::ClientGone => {
                if me != 0 && self.owner == me {
                    self.lose_owner();
                }
                self.done(c, Done::Ack);
                Gate::Answered
            }
            _ if c.kind.needs_control() => {
                if CommandKind::may_control(self.owner, me) {
                    self.owner = me;
                    Gate::Pass
                } else {
                    self.refuse(c, Reason::NotOwner { owner: self.owner });
                    Gate::Answered
                }
            }
            _ => Gate::Pass,
        }
    }

    /// The owner released control or is gone: nobody owns the arm, and what it drove comes
    /// to HOLD in this cycle.
    fn lose_owner(&mut self) {
        self.owner = 0;
        self.leave(Exit::OwnerGone);
    }
}

// Scenario tests on the whole simulated robot.
#[cfg(all(test, feature = "sim"))]
mod tests;
