//! `mcm`: the Motion Control Module.
//!
//! With no arguments (`cargo run --release`) it starts the simulated P-Rob2: the real-time
//! core and the gateway as two processes, prints where to connect, and stops both on Ctrl-C
//! or SIGTERM. `mcm rt ...`, `mcm gateway ...` and `mcm ros2 ...` run one process each (the same
//! programs as `mcm-rt`, `mcm-gateway` and `mcm-ros2`); the launcher starts its children that way
//! (the ROS 2 node only with `--ros2`). `mcm virtual-arm ...` is `mcm-virtual-arm`, the simulated
//! arm on a CAN interface (docs/virtual-arm.md). Called by the name `mcm-rt`, `mcm-gateway`,
//! `mcm-ros2` or `mcm-virtual-arm` (a link, as the Debian package installs them) it is that
//! program ([`called_as`]). `mcm bus-interface --config FILE` names the CAN interface a
//! configuration's core opens (for the systemd unit's start, [`bus_interface`]).

mod bus_interface;
mod called_as;
mod launcher;

use std::process::ExitCode;

fn main() -> ExitCode {
    let mut args = std::env::args_os();
    let program = args.next().unwrap_or_else(|| "mcm".into());
    let rest: Vec<_> = args.collect();
    let rest = called_as::arguments(&program, rest);
    match rest.first().and_then(|a| a.to_str()) {
        Some("rt") => {
            mcm_rt_core::cli::main(std::iter::once("mcm-rt".into()).chain(rest.into_iter().skip(1)))
        }
        Some("gateway") => mcm_gateway::cli::main(
            std::iter::once("mcm-gateway".into()).chain(rest.into_iter().skip(1)),
        ),
        Some("ros2") => {
            mcm_ros2::cli::main(std::iter::once("mcm-ros2".into()).chain(rest.into_iter().skip(1)))
        }
        Some("virtual-arm") => mcm_virtual_arm::cli::main(
            std::iter::once("mcm-virtual-arm".into()).chain(rest.into_iter().skip(1)),
        ),
        Some("bus-interface") => bus_interface::main(
            std::iter::once("mcm bus-interface".into()).chain(rest.into_iter().skip(1)),
        ),
        _ => launcher::main(std::iter::once(program).chain(rest)),
    }
}
