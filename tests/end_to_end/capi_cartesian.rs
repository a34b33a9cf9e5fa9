//! End to end (real launcher, simulated arm): the C API's Cartesian functions over TCP, called
//! through the `mcm_c` library as a C program calls them: `mcm_tcp_set_tool` seen in
//! `mcm_tcp_status_detail`'s `tool`, the TCP's state in `cartesian`, `mcm_tcp_inverse_kinematics`
//! (the present pose gives the present position first, a seed its nearest first, an
//! unreachable pose refused with `MCM_CODE_UNREACHABLE`) and `mcm_tcp_move_to_pose`, whose
//! arrival is checked on the simulation's ground truth through the MCM's own kinematics with
//! the same tool.

use crate::common;

use common::{Mcm, max_diff};
use mcm_c::*;
use mcm_kinematics::Kinematics;
use mcm_shared::config::RobotConfig;
use std::ffi::{CStr, CString};

/// The tool set through C: its TCP 15 cm out along the flange's z axis, turned 90 degrees
/// about it; 1 kg 5 cm out.
fn tool() -> mcm_tool_t {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    mcm_tool_t {
        tcp_position: [0.02, 0.0, 0.15],
        tcp_orientation: [0.0, 0.0, h, h],
        mass: 1.0,
        center_of_mass: [0.0, 0.0, 0.05],
        inertia: [0.0; 6],
    }
}

/// The P-Rob2's kinematics with the TCP of [`tool`].
fn kinematics() -> Kinematics {
    let t = tool();
    let mut kin = Kinematics::from_config(&RobotConfig::prob2_default()).unwrap();
    kin.set_tcp(mcm_kinematics::tcp_transform(&mcm_shared::tool::Tcp {
        position: t.tcp_position,
        orientation: t.tcp_orientation,
    }))
    .unwrap();
    kin
}

/// The TCP pose of `q_deg` as the C API takes it.
fn pose(kin: &Kinematics, q_deg: &[f64; 6]) -> mcm_pose_t {
    let p = kin.tcp_pose(&q_deg.map(f64::to_radians));
    let (t, q) = (p.translation.vector, p.rotation.coords);
    mcm_pose_t {
        position: [t.x, t.y, t.z],
        orientation: [q.x, q.y, q.z, q.w],
    }
}

fn distance(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
}

/// The handle's last error, for a failure's message.
///
/// # Safety
/// `h` is a live handle.
unsafe fn last_error(h: *const mcm_tcp_client_t) -> String {
    // SAFETY: a live handle's message is a NUL-terminated string it owns.
    unsafe { CStr::from_ptr(mcm_tcp_last_error(h)) }
        .to_string_lossy()
        .into_owned()
}

#[test]
fn the_c_api_sets_the_tool_solves_poses_and_moves_to_one() {
    let kin = kinematics();
    let mcm = Mcm::start("capi-cartesian");
    let mut truth = mcm.client();
    truth.wait_drives_online();
    let addr = CString::new(mcm.json.to_string()).unwrap();
    let mut h: *mut mcm_tcp_client_t = std::ptr::null_mut();
    // SAFETY: valid C strings, structs and out-pointers; the handle is closed once at the end.
    unsafe {
        let code = mcm_tcp_connect(addr.as_ptr(), &mut h);
        assert_eq!(code, mcm_error_t::MCM_OK, "connect");
        let ok = move |what: &str, code: mcm_error_t| {
            assert_eq!(code, mcm_error_t::MCM_OK, "{what}: {}", last_error(h));
        };
        let mut calibrated = false;
        ok(
            "calibrate_if_needed",
            mcm_tcp_calibrate_if_needed(h, &mut calibrated),
        );

        // The tool: set in HOLD, read back in the status's detail.
        let mut s = mcm_status_t::default();
        ok("status_detail", mcm_tcp_status_detail(h, &mut s));
        assert_eq!(s.tool.mass, 3.8, "the configuration's tool at start: {s:?}");
        ok("set_tool", mcm_tcp_set_tool(h, &tool()));
        ok("status_detail", mcm_tcp_status_detail(h, &mut s));
        let (set, got) = (tool(), s.tool);
        assert_eq!(got.tcp_position, set.tcp_position, "{got:?}");
        assert!(
            (0..4).all(|i| (got.tcp_orientation[i] - set.tcp_orientation[i]).abs() < 1e-6),
            "{got:?}"
        );
        assert_eq!(
            (got.mass, got.center_of_mass),
            (set.mass, set.center_of_mass)
        );
        // The TCP's state is that tool's TCP (rounded to 6 decimals in the status).
        assert!(s.has_cartesian, "{s:?}");
        let present = pose(&kin, &s.position);
        assert!(
            distance(&s.cartesian.position, &present.position) < 2e-6,
            "{:?} vs {present:?}",
            s.cartesian
        );

        // The present pose: the present position first, every solution of that pose.
        let mut ik = mcm_ik_solutions_t::default();
        ok(
            "inverse_kinematics",
            mcm_tcp_inverse_kinematics(h, &present, std::ptr::null(), &mut ik),
        );
        assert!((2..=8).contains(&ik.count), "{ik:?}");
        assert!(max_diff(&ik.solutions[0], &s.position) < 1e-3, "{ik:?}");
        for q in &ik.solutions[..ik.count as usize] {
            let p = pose(&kin, q);
            assert!(distance(&p.position, &present.position) < 1e-6, "{q:?}");
        }
        assert!(
            ik.solutions[ik.count as usize..]
                .iter()
                .all(|q| *q == [0.0; 6]),
            "{ik:?}"
        );
        // With a seed: the solution nearest it first.
        let second = ik.solutions[1];
        let mut seeded = mcm_ik_solutions_t::default();
        ok(
            "inverse_kinematics with a seed",
            mcm_tcp_inverse_kinematics(h, &present, second.as_ptr(), &mut seeded),
        );
        assert!(max_diff(&seeded.solutions[0], &second) < 1e-3, "{seeded:?}");

        // Out of reach: refused with its code, the MCM's words.
        let far = mcm_pose_t {
            position: [3.0, 0.0, 0.5],
            orientation: [0.0, 0.0, 0.0, 1.0],
        };
        let code = mcm_tcp_inverse_kinematics(h, &far, std::ptr::null(), &mut ik);
        assert_ne!(code, mcm_error_t::MCM_OK);
        assert_eq!(
            mcm_tcp_last_reject(h),
            mcm_error_code_t::MCM_CODE_UNREACHABLE as u32,
            "{code:?}: {}",
            last_error(h)
        );
        assert!(last_error(h).contains("wrist centre"), "{}", last_error(h));
        let code = mcm_tcp_inverse_kinematics(h, std::ptr::null(), std::ptr::null(), &mut ik);
        assert_eq!(code, mcm_error_t::MCM_ERR_NULL_POINTER, "{}", last_error(h));

        // A move to a pose: the true TCP arrives.
        let goal_q = [-25.0, 15.0, 75.0, 30.0, -45.0, 60.0];
        let goal = pose(&kin, &goal_q);
        ok("pvt", mcm_tcp_pvt(h, 0.01, std::ptr::null_mut()));
        let mut plan = mcm_move_all_result_t::default();
        ok(
            "move_to_pose",
            mcm_tcp_move_to_pose(h, &goal, 1.0, &mut plan),
        );
        assert!(plan.max_time_to_target > 0.1, "{plan:?}");
        truth.wait_truth("the true TCP at the pose, at rest", |q, v| {
            distance(&pose(&kin, q).position, &goal.position) < 1e-3
                && v.iter().all(|x| x.abs() < 0.1)
        });
        mcm_tcp_close(h);
    }
}
