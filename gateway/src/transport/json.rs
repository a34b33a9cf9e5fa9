//! The JSON/TCP protocol (docs/protocol.md): [`framing`] splits a connection's bytes into
//! commands, [`connection`] serves one client (executes its commands one after the other and
//! writes one result line each, with the spontaneous errors and notices in between).

pub mod connection;
pub mod framing;
