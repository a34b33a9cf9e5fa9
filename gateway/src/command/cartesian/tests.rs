//! The Cartesian commands against a gateway whose real-time core is not running: the solutions
//! and the refusals come from the gateway alone.

use super::*;
use crate::command::execute;
use mcm_shared::sample::STATE_ALL_CALIBRATED;

fn context() -> (Context, crate::core_link::bridge::BridgeThread) {
    let (ctx, thread, _) =
        crate::test_support::offline_context("cartesian", RobotConfig::prob2_default());
    (ctx, thread)
}

/// A configuration [deg] away from the singularities and within every axis's range.
const Q_DEG: [f64; 6] = [20.0, 30.0, 60.0, -40.0, 50.0, 10.0];

/// The TCP pose of `q_deg` (the TCP on the flange), as the protocol writes it.
fn pose_of(ctx: &Context, q_deg: &[f64; 6]) -> Pose {
    let kin = ctx.kinematics.as_ref().unwrap();
    let p = kin.tcp_pose(&q_deg.map(f64::to_radians));
    let t = p.translation.vector;
    let q = p.rotation.coords;
    Pose {
        position: [t.x, t.y, t.z],
        orientation: [q.x, q.y, q.z, q.w],
    }
}

fn calibrated_at(q_deg: [f64; 6]) -> StateSample {
    StateSample {
        position: q_deg,
        axis_flags: [AXIS_CALIBRATED; 6],
        flags: STATE_ALL_CALIBRATED,
        ..StateSample::default()
    }
}

fn assert_near(a: &[f64; 6], b: &[f64; 6], tol: f64) {
    assert!(
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < tol),
        "{a:?} != {b:?}"
    );
}

#[test]
fn the_seed_comes_back_first_and_every_solution_reaches_the_pose() {
    let (ctx, thread) = context();
    let pose = pose_of(&ctx, &Q_DEG);
    let seed = Some(Q_DEG);
    let solutions = solve(&ctx, &pose, seed, None).unwrap();
    thread.stop();
    assert!(solutions.len() > 1, "{solutions:?}");
    assert_near(&solutions[0], &Q_DEG, 1e-9);
    for s in &solutions {
        let p = pose_of(&ctx, s);
        let d: f64 = (0..3)
            .map(|i| (p.position[i] - pose.position[i]).powi(2))
            .sum();
        assert!(d.sqrt() < 1e-9, "{s:?}: {p:?}");
    }
}

/// Without a seed the present position is the seed, which needs every axis calibrated.
#[test]
fn without_a_seed_the_present_position_is_the_seed_once_calibrated() {
    let (ctx, thread) = context();
    let pose = pose_of(&ctx, &Q_DEG);
    let state = calibrated_at(Q_DEG);
    let solutions = solve(&ctx, &pose, None, Some(&state)).unwrap();
    assert_near(&solutions[0], &Q_DEG, 1e-9);

    let mut state = calibrated_at(Q_DEG);
    state.axis_flags[2] = 0;
    state.flags = 0;
    let refusal = solve(&ctx, &pose, None, Some(&state)).unwrap_err();
    thread.stop();
    let refused = refusal.answer("inverse_kinematics");
    assert_eq!(refused.code(), Some(ErrorCode::NotCalibrated));
    assert_eq!(refused.outcome(), Some(ErrorOutcome::Refused));
    assert_eq!(
        refused.message(),
        "inverse_kinematics refused: axis 3 is not calibrated; run `calibrate` first (the \
         present position is the seed), or give a `seed`"
    );
    // `move_to_pose` has no seed to give.
    assert_eq!(
        refusal.answer("move_to_pose").message(),
        "move_to_pose refused: axis 3 is not calibrated; run `calibrate` first (the present \
         position is the seed)"
    );
}

#[test]
fn an_unreachable_pose_is_refused_saying_why() {
    let (ctx, thread) = context();
    let pose = Pose {
        position: [3.0, 0.0, 0.5],
        orientation: [0.0, 0.0, 0.0, 1.0],
    };
    let refused = solve(&ctx, &pose, Some([0.0; 6]), None)
        .unwrap_err()
        .answer("move_to_pose");
    thread.stop();
    assert_eq!(refused.code(), Some(ErrorCode::Unreachable));
    assert!(
        refused.message().starts_with(
            "move_to_pose refused: position [3, 0, 0.5] m, orientation [0, 0, 0, 1]: \
             unreachable: the wrist centre would be "
        ),
        "{}",
        refused.message()
    );
}

/// `inverse_kinematics` with a seed needs no core: executed, it answers the solutions.
#[tokio::test]
async fn inverse_kinematics_with_a_seed_is_answered_without_the_core() {
    let (ctx, thread) = context();
    let ik = InverseKinematics {
        pose: pose_of(&ctx, &Q_DEG),
        seed_deg: Some(Q_DEG),
    };
    let outcome = execute(&ctx, 7, &Command::InverseKinematics(ik)).await;
    thread.stop();
    let Some(Answer::InverseKinematics(r)) = &outcome.result else {
        panic!("{outcome:?}");
    };
    assert_near(&r.solutions[0], &Q_DEG, 1e-5);
}

/// Without a state, `move_to_pose` cannot know the present position: nothing is sent.
#[tokio::test]
async fn move_to_pose_without_the_core_says_the_core_is_unavailable() {
    let (ctx, thread) = context();
    let m = MoveToPose {
        pose: pose_of(&ctx, &Q_DEG),
        velocity_factor: 0.5,
    };
    let outcome = execute(&ctx, 7, &Command::MoveToPose(m)).await;
    thread.stop();
    let Some(Answer::Generic(g)) = &outcome.result else {
        panic!("{outcome:?}");
    };
    assert_eq!(g.code(), Some(ErrorCode::CoreUnavailable), "{g:?}");
    assert!(g.message().starts_with("move_to_pose failed: "), "{g:?}");
}
