//! `mcm-ros2`: the MCM's ROS 2 node (see the library's docs and `docs/ros2.md`).

fn main() -> std::process::ExitCode {
    eprintln!("mcm-ros2: not finished yet");
    std::process::ExitCode::FAILURE
}
