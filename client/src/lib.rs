//! # mcm-client: drive the MCM from Rust
//!
//! Two transports, one vocabulary (the typed requests and answers of [`mcm_shared`]):
//!
//! - [`tcp::TcpClient`]: the JSON protocol of `docs/protocol.md` over TCP (port 18010), for
//!   programs on another computer. Blocking (`std::net`): one call sends one command and
//!   returns its typed result; spontaneous messages (safety errors, the status ticks of a
//!   TORQUE_CONTROL session, shutdown notices) are kept apart and read with
//!   [`tcp::TcpClient::next_event`].
//! - [`shm::ShmClient`]: the shared-memory services of the real-time core (iceoryx2), for
//!   programs on the robot's computer: [`shm::ShmClient::wait_state`] wakes on each cycle's
//!   state, commands go straight to the core, and [`shm::ShmClient::control`] runs a control
//!   loop at the cycle rate (a callback gets each state and returns the next torques).
//!
//! Both are ordinary clients of the MCM's ownership rules: one client at a time controls the
//! arm's motion (`take_control`, or its first motion command); `hold` and state reads are open
//! to all. `docs/clients.md` explains both transports, the timing contract and every field of
//! the shared-memory samples.
//!
//! The arm's kinematics (forward kinematics of the TCP, its Jacobian, every inverse kinematics
//! solution) are [`mcm_kinematics`], the ones the MCM uses: a client computes a pose for
//! `move_to_pose`, or checks where a joint position puts the TCP, with the same code.
//!
//! Why blocking: a controller's loop is sequential (read the state, compute, send), and the
//! real-time work is done by the MCM; a blocking client needs no runtime, adds no thread, and
//! its calls are easy to bound with timeouts. A program that already runs tokio can call it
//! from `spawn_blocking`.

pub mod launch;
pub mod placement;
pub mod shm;
pub mod tcp;

pub use mcm_kinematics;
pub use mcm_shared;
pub use mcm_shared::NUM_AXES;
pub use mcm_shared::command::{Axis, Direction, PvtPoint, SimCommand, Which};
pub use mcm_shared::error_code::ErrorCode;
pub use mcm_shared::mode::{Mode, RejectCode};

/// `CLOCK_MONOTONIC` now [ns], the clock of `StateSample::t_ns`.
pub fn monotonic_ns() -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; CLOCK_MONOTONIC always exists on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut ts) };
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}
