//! # mcm-ros2: the MCM as a ROS 2 node
//!
//! A co-located shared-memory client of the real-time core (through `mcm-client`) that speaks
//! ROS 2 over DDS in pure Rust (ros2-client over RustDDS): no ROS installation is needed to
//! build or run it. `docs/ros2.md` describes every interface with its units.
//!
//! - [`node`] sets up DDS and the threads, offering what [`access`] says (everything, or
//!   read-only); [`arm`] is the loop that reads the core's state every cycle, publishes
//!   `/joint_states` and `/diagnostics` ([`convert`]), and serves the motion interface
//!   ([`motion`]): the services and trajectories ([`driver`], on the PVT stream of [`stream`],
//!   planned by [`trajectory`]); [`action`] serves `follow_joint_trajectory`.
//! - [`urdf`] generates the robot description from the configuration.
//! - [`msgs`] are the ROS 2 messages as serde structs; [`distro`] is the distribution served
//!   and what differs between them.
//! - [`enclave`] chooses and checks the SROS2 enclave of DDS Security.
//! - [`dds_threads`] tells whether DDS still runs in the process.
//! - [`allocator`] gives back the memory of large received samples.

pub mod access;
pub mod action;
pub mod allocator;
pub mod arm;
pub mod cli;
pub mod convert;
pub mod dds_threads;
pub mod distro;
pub mod driver;
pub mod enclave;
pub mod motion;
pub mod msgs;
pub mod node;
pub mod stream;
pub mod trajectory;
pub mod urdf;
