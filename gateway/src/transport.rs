//! The four ways clients reach the gateway, each turning its bytes into commands for
//! [`crate::command`] and its results back into bytes. Runs in the gateway's async tasks (and,
//! for ZeroMQ, two threads of its own), never in the real-time cycle.
//!
//! - [`json`]: the JSON/TCP machine-to-machine protocol (default port 18010): one JSON object
//!   per line each way;
//! - [`hmi`]: the telnet text HMI for people (default port 18011);
//! - [`zmq`]: the optional ZeroMQ interface (commands over a ROUTER socket, state and errors
//!   over a PUB socket);
//! - [`web`]: the browser pendant (default port 18014): a page, and per page a WebSocket that
//!   carries the JSON protocol and the state.
//!
//! What they share: [`server`] accepts the TCP connections of the JSON, HMI and web ports within the
//! limits of `[gateway.connections]` and stops them on [`shutdown`]; [`heavy`] parses long
//! lines off the async workers, for every transport; [`http_line`] recognises HTTP sent to the
//! JSON and HMI ports, which close such a connection.

pub(crate) mod heavy;
pub(crate) mod hmi;
pub(crate) mod http_line;
pub(crate) mod json;
pub(crate) mod server;
pub(crate) mod shutdown;
pub(crate) mod web;
pub(crate) mod zmq;
