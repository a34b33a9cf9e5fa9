//! `set_tool` on the whole simulated robot in virtual time: where it is accepted and why it is
//! refused, and the model's new load in force in the cycle the command arrives in.

use super::super::tests::{Robot, move_axis};
use mcm_dynamics::ArmModel;
use mcm_shared::command::{Pvt, Request, SetTool};
use mcm_shared::config::RobotConfig;
use mcm_shared::mode::{CommandKind, Mode, RejectCode, ReplyStatus};
use mcm_shared::reply::{Done, Reason};
use mcm_shared::tool::{Tcp, Tool};

/// 5 kg, 10 cm to the side of the flange, its TCP 15 cm out.
fn heavy() -> Tool {
    let tcp = Tcp {
        position: [0.0, 0.0, 0.15],
        orientation: [0.0, 0.0, 0.0, 1.0],
    };
    Tool::new(tcp, 5.0, [0.1, 0.0, 0.05], None).unwrap()
}

fn set_tool(tool: Tool) -> Request {
    Request::SetTool(SetTool { tool })
}

#[test]
fn the_configured_tool_is_active_at_start() {
    let r = Robot::new();
    let configured = RobotConfig::prob2_default().arm.tool.active();
    assert_eq!(r.cycle.controller().tool(), &configured);
    assert_eq!(Tool::from(&r.cycle.state().tool), configured);
}

#[test]
fn set_tool_is_refused_outside_hold_and_a_pvt_standstill() {
    let mut r = Robot::new();
    let reason = r.refused(set_tool(heavy()), 5);
    assert_eq!(reason, Reason::WrongMode { mode: Mode::Off });
    r.calibrate_all();
    r.ok(Request::Release, 5);
    let reason = r.refused(set_tool(heavy()), 5);
    assert_eq!(
        reason,
        Reason::WrongMode {
            mode: Mode::Release
        }
    );
    r.ok(Request::Hold, 5);
    r.run_until("at rest", 400, Robot::at_rest);
    // Another client than the owner.
    let other = r.command_from(43, set_tool(heavy()), 5);
    assert!(
        matches!(
            other.outcome,
            mcm_shared::reply::Outcome::Refused(Reason::NotOwner { owner: 42 })
        ),
        "{other:?}"
    );
    // Moving in PVT.
    r.ok(Request::Pvt(Pvt { dt_s: 0.01 }), 5);
    r.ok(move_axis(1, 20.0), 5);
    r.run(20);
    assert!(matches!(
        r.refused(set_tool(heavy()), 5),
        Reason::Busy { remaining_s } if remaining_s > 0.0
    ));
    assert_ne!(r.cycle.controller().tool(), &heavy(), "nothing changed");
    // At standstill in PVT.
    r.run_until("arrived", 2000, |r| {
        r.cycle.state().velocity.iter().all(|v| *v == 0.0)
    });
    assert_eq!(r.ok(set_tool(heavy()), 5), Done::Ack);
    assert_eq!(r.cycle.controller().tool(), &heavy());
    // The state sample of that cycle reports it.
    assert_eq!(Tool::from(&r.cycle.state().tool), heavy());
}

#[test]
fn a_tool_that_is_no_tool_is_refused_out_of_range_and_changes_nothing() {
    let mut r = Robot::calibrated();
    let mut s = set_tool(heavy()).encode();
    s.args[7] = 6.0; // the mass, above the rating
    (s.client_id, s.request_id) = (42, 7777);
    r.step(&[s]);
    let reply = r
        .cycle
        .replies()
        .iter()
        .find(|x| x.request_id == 7777)
        .copied()
        .expect("answered in its cycle");
    assert_eq!(reply.kind, CommandKind::SetTool.to_wire());
    assert_eq!(reply.status, ReplyStatus::Rejected.to_wire());
    assert_eq!(reply.code, RejectCode::OutOfRange.to_wire());
    let configured = RobotConfig::prob2_default().arm.tool.active();
    assert_eq!(r.cycle.controller().tool(), &configured);
}

/// In HOLD the drives' gravity feed-forward follows the model's load at a bounded rate: in
/// the cycle `set_tool` arrives in it already moves toward the new tool's load.
#[test]
fn the_new_load_is_in_force_in_the_cycle_the_command_arrives_in() {
    let mut r = Robot::calibrated();
    r.run_until("at rest", 400, Robot::at_rest);
    r.run(200);
    let c = r.cycle.controller();
    let before = c.feed_forward;
    let q = c.cmd.position;
    let cfg = RobotConfig::prob2_default();
    let old_load = ArmModel::from_config(&cfg).gravity_torques(&q);
    let mut model = ArmModel::from_config(&cfg);
    model.set_tool(&heavy());
    let new_load = model.gravity_torques(&q);
    for i in 0..6 {
        assert!((before[i] - old_load[i]).abs() < 1e-6, "steady: {before:?}");
    }
    let axis = (0..6)
        .max_by(|&a, &b| {
            (new_load[a] - old_load[a])
                .abs()
                .total_cmp(&(new_load[b] - old_load[b]).abs())
        })
        .unwrap();
    let change = new_load[axis] - old_load[axis];
    assert!(change.abs() > 2.0, "the tool matters on axis {}", axis + 1);

    assert_eq!(r.ok(set_tool(heavy()), 5), Done::Ack);
    let after = r.cycle.controller().feed_forward;
    let moved = after[axis] - before[axis];
    assert!(
        moved * change > 0.0 && moved.abs() > 0.5,
        "axis {}: the feed-forward moved {moved} Nm toward a change of {change} Nm",
        axis + 1
    );
    r.run(200);
    let settled = r.cycle.controller().feed_forward;
    assert!(
        (settled[axis] - new_load[axis]).abs() < 1e-6,
        "{settled:?} vs {new_load:?}"
    );
}
