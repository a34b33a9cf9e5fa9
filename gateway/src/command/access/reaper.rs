//! Control held by a client whose process is gone. A connection's `client_gone` reaches the
//! core when the connection closes; but when a whole gateway dies (killed, crashed) its
//! connections never say goodbye, and the arm would stay controlled by a ghost until `mcm-rt`
//! restarts: nobody could take control, and a torque session with no timeout would go on.
//!
//! Client ids are `(pid << 32) | n` (`Bridge::new_client_id`; co-located controllers are
//! asked to stamp theirs the same way). Every [`CHECK_PERIOD`] the gateway looks at the owner
//! in the newest state; when its pid is neither this process nor a live process, it sends
//! `client_gone` on that client's behalf: the ownership ends and what it drove stops in HOLD.
//! Ids whose upper half is 0 name no process and are never reaped. Nor is anything reaped while
//! the core is shutting down: its controlled stop already ends every owner's motion, and the
//! clients (the ROS 2 node, the gateway's own) stop with it, so a release would only wait for
//! a core that is gone. Runs in the gateway's async tasks.

use crate::core_link::bridge::Bridge;
use mcm_shared::command::Request;
use std::time::Duration;

/// How often the owner is checked.
pub const CHECK_PERIOD: Duration = Duration::from_millis(200);

/// Whether control held by `owner` is orphaned: its process (the id's upper half) is neither
/// `me` nor alive.
pub fn orphaned(owner: u64, me: u32, alive: impl Fn(u32) -> bool) -> bool {
    let pid = (owner >> 32) as u32;
    owner != 0 && pid != 0 && pid != me && !alive(pid)
}

/// Whether a process `pid` exists (Linux: its `/proc` entry).
pub fn process_alive(pid: u32) -> bool {
    std::path::Path::new(&format!("/proc/{pid}")).exists()
}

/// Check the owner every [`CHECK_PERIOD`] and release a ghost's control, until dropped.
pub async fn run(bridge: Bridge) {
    let me = std::process::id();
    let mut tick = tokio::time::interval(CHECK_PERIOD);
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
    loop {
        tick.tick().await;
        let owner = bridge.owner();
        if orphaned(owner, me, process_alive) && !bridge.core_shutting_down() {
            eprintln!(
                "mcm-gateway: the arm was controlled by client {owner:#x}, whose process \
                 {} is gone; releasing its control (what it drove stops in HOLD)",
                owner >> 32
            );
            let gone = vec![Request::ClientGone];
            if let Err(e) = bridge
                .request(owner, gone, crate::command::REPLY_TIMEOUT)
                .await
            {
                eprintln!("mcm-gateway: releasing the control of client {owner:#x} failed: {e}");
            }
        }
    }
}

#[cfg(test)]
mod tests;
