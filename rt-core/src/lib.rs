//! # mcm-rt-core: the real-time core of the Motion Control Module
//!
//! A deterministic controller over plain data, with all I/O at the edges (clock, bus, IPC).
//! Each module says at its top whether it runs inside the cycle. The drive bus, the arm's
//! dynamics and the simulated robot are the crates `mcm-bus`, `mcm-dynamics` and `mcm-sim`;
//! the simulator reaches the cycle only through [`sim_edge`], which the runner wires in for
//! `bus.backend = "sim"`. `mcm-sim` comes with the feature `sim` (on by default); built
//! without it, the core runs real drives only and refuses a configuration that asks for the
//! simulator ([`runner::RunError::SimNotBuilt`]).

pub mod calibration;
pub mod canopen;
pub mod cartesian;
pub mod cli;
pub mod clock;
pub mod controller;
pub mod cycle;
pub mod edge;
pub mod flight;
pub mod histogram;
pub mod intake;
pub mod ipc;
pub mod line_planner;
pub mod params;
pub mod preflight;
pub mod process_stop;
pub mod publish;
pub mod pvt;
pub mod realtime;
pub mod runner;
pub mod safety;
pub mod signals;
pub mod sim_edge;
pub mod systemd_notify;
pub mod timing;
pub mod trajectory;
