//! # mcm-shared: the contract between the MCM processes
//!
//! Everything two MCM processes (or a co-located controller) must agree on lives here:
//!
//! - [`sample`]: the fixed-size `#[repr(C)]` IPC samples (commands in, state and replies out),
//!   with versioned iceoryx2 type names;
//! - [`service`]: the iceoryx2 service names, derived from an instance name so that several
//!   MCMs (and parallel tests) can run side by side on one machine;
//! - [`command`]: the typed requests, and the one encoding of each into a command sample;
//! - [`protocol`]: the JSON contract: every command of the JSON protocol defined once (parsing,
//!   writing, help, what it answers) and the typed results;
//! - [`reply`]: the typed responses, refusal reasons and safety errors, and their encoding;
//! - [`mode`]: the operating modes and the wire codes of command kinds and reasons;
//! - [`error_code`]: every error code of every interface (`error_code`), defined once;
//! - [`config`]: the robot configuration file;
//! - [`pvt`]: the per-point checks of `pvt_points` the gateway and the core share;
//! - [`ranges`]: the allowed range of every numeric argument and the words of a refusal,
//!   read by the gateway's parsing and the core's checks alike;
//! - [`cli`]: the command-line arguments the MCM programs share;
//! - [`ready`]: the ready line each program prints when it serves, and how it is read;
//! - [`restart`]: how a gateway that dies is restarted (the launcher and the systemd unit);
//! - [`notify`]: systemd's readiness, stop and watchdog notifications (`Type=notify` units);
//! - [`tool`]: the tool the arm carries (TCP and load), checked in one place;
//! - [`units`]: the unit conventions at the boundary (degrees outside, radians inside).
//! - [`alloc_count`]: a counting global allocator, for the tests that prove a path allocates
//!   nothing.
//!
//! ```
//! use mcm_shared::{service::ServiceNames, sample::StateSample, NUM_AXES};
//! let names = ServiceNames::new("robot1").unwrap();
//! assert_eq!(names.state(), "mcm/robot1/state");
//! let s = StateSample::default();
//! assert_eq!(s.position.len(), NUM_AXES);
//! ```

pub mod alloc_count;
pub mod busload;
pub mod cli;
pub mod command;
pub mod config;
pub mod error_code;
pub mod mode;
pub mod notify;
pub mod protocol;
pub mod pvt;
pub mod ranges;
pub mod ready;
pub mod reply;
pub mod restart;
pub mod sample;
pub mod service;
pub mod simulator;
pub mod tool;
pub mod units;

/// Number of axes of the arm. The samples are sized for exactly this many.
pub const NUM_AXES: usize = 6;

/// The MCM version reported by `info` and the HMI banner.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
