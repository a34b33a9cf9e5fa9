//! The gateway's link to the real-time core (`mcm-rt`): [`bridge`] is the one thread that owns
//! the iceoryx2 ports (commands out, replies, state and safety errors in), [`lifecycle`] turns
//! what is known of the core into the notices a client gets (the core stopping or gone, the
//! gateway stopping), and [`latency`] asks the kernel for a short scheduling slice for the
//! threads that answer clients. Not used inside the real-time cycle.

pub(crate) mod bridge;
pub(crate) mod latency;
pub(crate) mod lifecycle;
