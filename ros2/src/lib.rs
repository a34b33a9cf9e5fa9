//! # mcm-ros2: the MCM as a ROS 2 node
//!
//! A co-located shared-memory client of the real-time core (through `mcm-client`) that speaks
//! ROS 2 over DDS in pure Rust (ros2-client over RustDDS): no ROS installation is needed to
//! build or run it. `docs/ros2.md` describes every interface with its units.

pub mod msgs;
pub mod trajectory;
