//! Cases for the Pinocchio oracle (`tests/end_to_end/kinematics_pinocchio.rs`): joint
//! configurations of the arm of a configuration file, with this crate's TCP pose, Jacobian and
//! inverse-kinematics solutions of each, as JSON on stdout.
//!
//! ```sh
//! cargo run -p mcm-kinematics --example pinocchio_cases -- CONFIG COUNT SEED X Y Z ROLL PITCH YAW
//! ```
//!
//! CONFIG: the robot configuration (TOML); COUNT random configurations within the axes'
//! reachable ranges (from the random seed SEED), after three singular ones (the wrist, the
//! stretched elbow, all axes at zero); the TCP at (X, Y, Z) [m] in the flange frame, turned
//! by ROLL, PITCH, YAW [rad] as a URDF origin is (Rz(yaw) Ry(pitch) Rx(roll)). Each case: `q` [rad], `pose` (the TCP's `position`
//! [m] and `rotation` matrix, rows, in the base frame), `jacobian` (6 rows: linear then angular
//! velocity, base axes, per joint), `solutions` (every IK solution of that pose, seeded with
//! `q`, as joint values [rad]).

use mcm_kinematics::Kinematics;
use mcm_shared::config::RobotConfig;
use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use proptest::prelude::Rng;
use proptest::test_runner::{RngAlgorithm, TestRng};
use serde_json::{Value, json};
use std::process::ExitCode;

fn main() -> ExitCode {
    match run(std::env::args().skip(1).collect()) {
        Ok(out) => {
            println!("{out}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("pinocchio_cases: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: Vec<String>) -> Result<Value, String> {
    let [config, count, seed, tcp @ ..] = args.as_slice() else {
        return Err("usage: pinocchio_cases CONFIG COUNT SEED X Y Z ROLL PITCH YAW".into());
    };
    let cfg = RobotConfig::from_file(config.as_ref()).map_err(|e| e.to_string())?;
    let count: usize = count.parse().map_err(|e| format!("COUNT {count:?}: {e}"))?;
    let seed: u8 = seed.parse().map_err(|e| format!("SEED {seed:?}: {e}"))?;
    let tcp: Vec<f64> = tcp
        .iter()
        .map(|v| v.parse().map_err(|e| format!("TCP value {v:?}: {e}")))
        .collect::<Result<_, String>>()?;
    let [x, y, z, roll, pitch, yaw] = tcp[..] else {
        return Err(format!("the TCP needs 6 numbers, got {}", tcp.len()));
    };
    let mut kin = Kinematics::from_config(&cfg).map_err(|e| e.to_string())?;
    let rotation = UnitQuaternion::from_euler_angles(roll, pitch, yaw);
    let tcp = Isometry3::from_parts(Translation3::new(x, y, z), rotation);
    kin.set_tcp(tcp).map_err(|e| e.to_string())?;

    let d = f64::to_radians;
    let mut configurations = vec![
        [d(10.0), d(20.0), d(-40.0), d(35.0), 0.0, d(-20.0)],
        [d(-15.0), d(25.0), 0.0, d(35.0), d(50.0), d(-20.0)],
        [0.0; 6],
    ];
    let mut rng = TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]);
    for _ in 0..count {
        configurations.push(core::array::from_fn(|i| {
            let r = kin.ranges()[i];
            r.min + (r.max - r.min) * ((rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
        }));
    }
    let mut cases = Vec::with_capacity(configurations.len());
    for q in configurations {
        let pose = kin.tcp_pose(&q);
        let r = pose.rotation.to_rotation_matrix().into_inner();
        let j = kin.tcp_jacobian(&q);
        let solutions = kin
            .inverse(&pose, &q)
            .map_err(|e| format!("no solution for the pose of {q:?}: {e}"))?;
        cases.push(json!({
            "q": q,
            "pose": {
                "position": pose.translation.vector.as_slice(),
                "rotation": (0..3).map(|i| [r[(i, 0)], r[(i, 1)], r[(i, 2)]]).collect::<Vec<_>>(),
            },
            "jacobian": (0..6).map(|i| (0..6).map(|k| j[(i, k)]).collect::<Vec<_>>()).collect::<Vec<_>>(),
            "solutions": solutions.iter().map(|s| s.q).collect::<Vec<_>>(),
        }));
    }
    let c = tcp.rotation.coords;
    Ok(json!({
        "tcp": {
            "position": tcp.translation.vector.as_slice(),
            "orientation": [c.x, c.y, c.z, c.w],
        },
        "cases": cases,
    }))
}
