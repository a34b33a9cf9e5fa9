use super::*;

#[test]
fn arguments_are_checked_with_words_that_name_them() {
    let e = axis(7, "mcm_tcp_move_axis").unwrap_err();
    assert_eq!(e.code, MCM_ERR_ARGUMENT);
    assert!(
        e.message.contains("`axis` = 7") && e.message.contains("1 to 6"),
        "{}",
        e.message
    );
    let bad = mcm_calibrate_t {
        which: 9,
        ..Default::default()
    };
    // SAFETY: a valid struct.
    let e = unsafe { calibrate(&bad, "f") }.unwrap_err();
    assert!(e.message.contains("`which` = 9"), "{}", e.message);
    let bad = mcm_calibrate_t {
        elbow_direction: 2,
        ..Default::default()
    };
    // SAFETY: a valid struct.
    assert!(unsafe { calibrate(&bad, "f") }.is_err());
    // SAFETY: NULL is allowed.
    let c = unsafe { calibrate(std::ptr::null(), "f") }.unwrap();
    assert_eq!(c.which, Which::All);
    assert_eq!(frame(0, "f").unwrap(), CartesianFrame::Base);
    assert_eq!(frame(1, "f").unwrap(), CartesianFrame::Tool);
    assert_eq!(
        frame(2, "mcm_shm_set_cartesian_velocity")
            .unwrap_err()
            .message,
        "mcm_shm_set_cartesian_velocity: argument `frame` = 2 is not allowed; expected 0 (base) \
         or 1 (tool)"
    );
    assert!(seconds(-1.0, "f", "timeout_s").is_err());
    assert_eq!(timeout(-1.0), None);
    // SAFETY: NULL is refused before any read.
    let e = unsafe { six(std::ptr::null(), "mcm_shm_set_torques", "torques") }.unwrap_err();
    assert_eq!(
        e.message,
        "mcm_shm_set_torques: argument `torques` is NULL; pass a valid pointer"
    );
}

#[test]
fn solutions_fill_the_struct_in_order_and_too_many_are_refused() {
    assert_eq!(
        MCM_MAX_IK_SOLUTIONS,
        mcm_client::mcm_kinematics::MAX_SOLUTIONS
    );
    let two = InverseKinematicsResult {
        solutions: vec![[1.0; 6], [2.0; 6]],
    };
    let s = ik_solutions(&two, "f").unwrap();
    assert_eq!(s.count, 2);
    assert_eq!(&s.solutions[..3], &[[1.0; 6], [2.0; 6], [0.0; 6]]);
    let nine = InverseKinematicsResult {
        solutions: vec![[0.0; 6]; 9],
    };
    let e = ik_solutions(&nine, "mcm_tcp_inverse_kinematics").unwrap_err();
    assert_eq!(e.code, MCM_ERR_PROTOCOL);
    assert!(e.message.contains("9 solutions"), "{}", e.message);
    // SAFETY: NULL is allowed for the seed, refused for the pose, before any read.
    assert_eq!(
        unsafe { optional_six(std::ptr::null(), "f", "seed_deg") }.unwrap(),
        None
    );
    // SAFETY: as above.
    let e = unsafe { pose(std::ptr::null(), "mcm_tcp_move_to_pose") }.unwrap_err();
    assert!(
        e.message.contains("argument `pose` is NULL"),
        "{}",
        e.message
    );
}
