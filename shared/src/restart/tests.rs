use super::*;

#[test]
fn the_gateway_waits_double_from_a_tenth_of_a_second_to_the_cap() {
    let waits: Vec<u64> = (1..=10)
        .map(|n| GATEWAY_RESTART.delay(n).as_millis() as u64)
        .collect();
    assert_eq!(
        waits,
        [100, 200, 400, 800, 1600, 3200, 6400, 12_800, 12_800, 12_800]
    );
    assert_eq!(
        GATEWAY_RESTART.systemd_lines(),
        [
            "RestartSec=100ms",
            "RestartSteps=7",
            "RestartMaxDelaySec=12800ms"
        ]
    );
}

#[test]
fn the_ros2_node_waits_the_same_two_seconds_every_time() {
    let waits: Vec<Duration> = (1..=5).map(|n| ROS2_RESTART.delay(n)).collect();
    assert_eq!(waits, [Duration::from_secs(2); 5]);
    assert_eq!(ROS2_RESTART.systemd_lines(), ["RestartSec=2000ms"]);
}
