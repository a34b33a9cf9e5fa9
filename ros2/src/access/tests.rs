use super::Access;

#[test]
fn read_only_offers_no_motion_and_says_what_it_leaves_out() {
    let a = Access::from_read_only(true);
    assert_eq!(a, Access::ReadOnly);
    assert!(!a.offers_motion());
    assert_eq!(
        a.start_line(),
        "mcm-ros2: read-only (--ros2-read-only): offering joint_states, robot_description, \
         /diagnostics; no motion interface: none of follow_joint_trajectory, joint_trajectory, \
         the services hold, calibrate, release, take_control, release_control and the \
         parameter services"
    );
    assert_eq!(a.diagnostics_value(), "none (--ros2-read-only)");
}

#[test]
fn by_default_every_interface_is_offered() {
    let a = Access::from_read_only(false);
    assert_eq!(a, Access::Motion);
    assert!(a.offers_motion());
    assert_eq!(
        a.start_line(),
        "mcm-ros2: offering joint_states, robot_description, /diagnostics, \
         follow_joint_trajectory, joint_trajectory, the services hold, calibrate, release, \
         take_control, release_control and the parameter services"
    );
    assert_eq!(a.diagnostics_value(), "offered");
}
