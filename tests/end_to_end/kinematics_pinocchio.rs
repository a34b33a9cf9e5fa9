//! The kinematics (`mcm-kinematics`) against Pinocchio, a library nobody here wrote: the URDF
//! the ROS 2 node generates from `deploy/prob2.toml` (`mcm_ros2::urdf::generate`, what
//! `mcm-ros2 --urdf-out` writes) plus a fixed joint to a `tcp` link, and the crate's TCP pose,
//! Jacobian and every IK solution at hundreds of random configurations
//! (`kinematics/examples/pinocchio_cases.rs`), compared by `tests/kinematics/check_pinocchio.py`
//! in a venv with `tests/kinematics/requirements.txt`. Skipped without Python or a network to
//! install Pinocchio (a failure under CI).

use crate::common;

use common::python::{repo_root, requirements_venv_or_skip, run};
use mcm_ros2::urdf::{UrdfOptions, generate};
use mcm_shared::config::RobotConfig;
use std::process::Command;

/// Random configurations (three singular ones come on top).
const CASES: usize = 400;

/// The TCP: 15 cm out of the flange, a little sideways, turned (URDF xyz and rpy).
const TCP_XYZ: [f64; 3] = [0.012, -0.021, 0.15];
const TCP_RPY: [f64; 3] = [0.1, -0.25, 0.4];

/// `urdf` with a link `tcp` on a fixed joint from `flange` at `xyz`/`rpy`.
fn with_tcp(urdf: &str, xyz: [f64; 3], rpy: [f64; 3]) -> String {
    let v = |a: [f64; 3]| format!("{} {} {}", a[0], a[1], a[2]);
    let tcp = format!(
        "  <joint name=\"flange-tcp\" type=\"fixed\">\n    <origin xyz=\"{}\" rpy=\"{}\"/>\n    \
         <parent link=\"flange\"/>\n    <child link=\"tcp\"/>\n  </joint>\n  <link name=\"tcp\"/>\n\
         </robot>",
        v(xyz),
        v(rpy)
    );
    assert!(urdf.trim_end().ends_with("</robot>"), "{urdf}");
    urdf.trim_end().trim_end_matches("</robot>").to_string() + &tcp + "\n"
}

#[test]
fn kinematics_agree_with_pinocchio() {
    let test = "kinematics_pinocchio::kinematics_agree_with_pinocchio";
    let Some(py) =
        requirements_venv_or_skip(test, "kinematics-venv", "tests/kinematics/requirements.txt")
    else {
        return;
    };
    let root = repo_root();
    let config = root.join("deploy/prob2.toml");
    let cfg = RobotConfig::from_file(&config).expect("deploy/prob2.toml");
    let urdf = generate(&cfg, &UrdfOptions::default()).expect("the URDF");
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("kinematics-pinocchio-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let urdf_path = dir.join("prob2-tcp.urdf");
    std::fs::write(&urdf_path, with_tcp(&urdf, TCP_XYZ, TCP_RPY)).unwrap();

    let example = common::built::Executable {
        name: "pinocchio_cases",
        kind: "example",
        test: false,
        manifest: "kinematics/Cargo.toml",
    }
    .path();
    let tcp = TCP_XYZ.iter().chain(&TCP_RPY).map(f64::to_string);
    let cases = run(Command::new(example)
        .arg(&config)
        .arg(CASES.to_string())
        .arg("41")
        .args(tcp))
    .unwrap_or_else(|e| panic!("{e}"));
    let cases_path = dir.join("cases.json");
    std::fs::write(&cases_path, &cases.stdout).unwrap();

    let out = run(Command::new(&py)
        .arg(root.join("tests/kinematics/check_pinocchio.py"))
        .arg(&urdf_path)
        .arg(&cases_path)
        .env("PYTHONDONTWRITEBYTECODE", "1"))
    .unwrap_or_else(|e| panic!("Pinocchio disagrees with mcm-kinematics: {e}"));
    let summary = String::from_utf8_lossy(&out.stdout);
    eprintln!("{summary}");
    let checked = common::number_after(&summary, "checked ");
    assert_eq!(
        checked,
        (CASES + 3) as f64,
        "every configuration checked: {summary}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
