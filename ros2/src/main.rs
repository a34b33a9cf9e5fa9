//! `mcm-ros2`: the MCM's ROS 2 node (see the library's docs and `docs/ros2.md`).

fn main() -> std::process::ExitCode {
    mcm_ros2::cli::main(std::env::args_os())
}
