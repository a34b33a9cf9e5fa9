//! The one place that composes the published [`StateSample`]: from the controller's view of
//! the cycle (SI units, [`CycleView`]), the simulation's truth (`None` with real drives) and
//! the cycle's timing ([`CycleClock`]). Degrees are produced here, and only here, for the state.
//!
//! Runs inside the cycle: writes into a sample the caller owns, no allocation. The sample
//! persists from cycle to cycle: `reply_head` counts every reply since start (the replies of
//! this cycle are numbered up to it and published by the edge, [`crate::ipc::RtIpc::publish_replies`]),
//! and the last error record is replaced only when the controller reports a new one, stamped
//! with this cycle's wall clock.
//!
//! ```
//! use mcm_rt_core::controller::CycleView;
//! use mcm_rt_core::publish::{CycleClock, compose};
//! use mcm_shared::mode::Mode;
//! use mcm_shared::sample::{STATE_SIMULATED, StateSample};
//! let mut view = CycleView { cycle: 3, mode: Mode::Hold, ..CycleView::default() };
//! view.axes[1].measured_position = core::f64::consts::FRAC_PI_2;
//! let mut s = StateSample::default();
//! compose(&mut s, &view, None, &CycleClock::virtual_time(15_000_000, 5_000_000));
//! assert_eq!((s.seq, s.t_ns, s.mode), (3, 15_000_000, Mode::Hold.to_wire()));
//! assert!((s.measured_position[1] - 90.0).abs() < 1e-12);
//! assert_eq!(s.flags & STATE_SIMULATED, 0);
//! ```

use crate::controller::CycleView;
use mcm_shared::sample::{
    AXIS_CALIBRATED, AXIS_ENABLED, AXIS_FAULT, AXIS_I2T_DERATED, AXIS_ONLINE, CycleTiming,
    STATE_ALL_CALIBRATED, STATE_ESTOP, STATE_NOT_REALTIME, STATE_PVT_STARVED, STATE_SHUTTING_DOWN,
    STATE_SIM_ESTOP, STATE_SIMULATED, StateSample,
};
use mcm_shared::units::rad_to_deg;

/// What only a simulated robot knows, as the state publishes it (`sim_true_position`,
/// `sim_true_velocity`, `STATE_SIM_ESTOP`); yielded by the simulator's edge
/// ([`crate::sim_edge`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Truth {
    /// True joint angles [rad].
    pub position: [f64; 6],
    /// True joint velocities [rad/s].
    pub velocity: [f64; 6],
    /// The simulated emergency switch is pressed.
    pub emergency_stop: bool,
}

/// The timing of one cycle, as the real-time loop measured it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CycleClock {
    /// The robot's clock at the start of the cycle [ns]: `CLOCK_MONOTONIC` at wake-up in the
    /// real-time loop; the virtual time in deterministic tests.
    pub t_ns: u64,
    /// `CLOCK_REALTIME` at the start of the cycle [ns since the Unix epoch], stamped on a
    /// safety error reported in this cycle (0 in deterministic tests).
    pub unix_ns: u64,
    /// The loop's timing figures, published as they are.
    pub timing: CycleTiming,
    /// The loop runs without real-time scheduling.
    pub not_realtime: bool,
    /// Receiving commands failed this many times since start.
    pub command_receive_errors: u64,
}

impl CycleClock {
    /// The clock of a deterministic run: `t_ns` virtual time, every measurement zero.
    pub fn virtual_time(t_ns: u64, period_ns: u64) -> CycleClock {
        CycleClock {
            t_ns,
            timing: CycleTiming {
                period_ns,
                ..CycleTiming::default()
            },
            ..CycleClock::default()
        }
    }
}

/// Compose `s` for this cycle from the controller's `view`, the simulation's `truth` (`None`
/// for real drives: the truth fields zero, `STATE_SIMULATED` and `STATE_SIM_ESTOP` clear) and
/// the cycle's `clock`.
pub fn compose(s: &mut StateSample, view: &CycleView, truth: Option<Truth>, clock: &CycleClock) {
    s.seq = view.cycle;
    s.t_ns = clock.t_ns;
    s.mode = view.mode.to_wire();
    let flag = |on: bool, bit: u32| if on { bit } else { 0 };
    let t = truth.unwrap_or_default();
    s.flags = flag(view.estop, STATE_ESTOP)
        | flag(view.all_calibrated, STATE_ALL_CALIBRATED)
        | flag(view.pvt_starved, STATE_PVT_STARVED)
        | flag(view.shutting_down, STATE_SHUTTING_DOWN)
        | flag(clock.not_realtime, STATE_NOT_REALTIME)
        | flag(truth.is_some(), STATE_SIMULATED)
        | flag(t.emergency_stop, STATE_SIM_ESTOP);
    for (i, a) in view.axes.iter().enumerate() {
        s.position[i] = rad_to_deg(a.position);
        s.velocity[i] = rad_to_deg(a.velocity);
        s.acceleration[i] = rad_to_deg(a.acceleration);
        s.current[i] = a.current;
        s.measured_position[i] = rad_to_deg(a.measured_position);
        s.commanded_position[i] = rad_to_deg(a.commanded_position);
        s.following_error[i] = rad_to_deg(a.following_error);
        s.i2t[i] = a.i2t;
        s.sim_true_position[i] = rad_to_deg(t.position[i]);
        s.sim_true_velocity[i] = rad_to_deg(t.velocity[i]);
        s.axis_flags[i] = flag(a.online, AXIS_ONLINE)
            | flag(a.enabled, AXIS_ENABLED)
            | flag(a.fault, AXIS_FAULT)
            | flag(a.calibrated, AXIS_CALIBRATED)
            | flag(a.derated, AXIS_I2T_DERATED);
    }
    s.pvt_queued = view.pvt_queued;
    s.pvt_capacity = view.pvt_capacity;
    s.owner_client_id = view.owner_client_id;
    s.command_receive_errors = clock.command_receive_errors;
    s.timing = clock.timing;
    if let Some(e) = view.last_error
        && e.seq != s.last_error.seq
    {
        s.last_error = e.encode();
        s.last_error.unix_ns = clock.unix_ns;
    }
    s.reply_head += view.replies.dropped() + view.replies.replies().len() as u64;
}

/// The sequence number of the first of this cycle's replies, once [`compose`] counted them.
pub fn first_reply_seq(s: &StateSample, view: &CycleView) -> u64 {
    s.reply_head + 1 - view.replies.replies().len() as u64
}

#[cfg(test)]
mod tests {
    use super::*;
    use mcm_shared::command::Axis;
    use mcm_shared::mode::{CommandKind, Mode};
    use mcm_shared::reply::{Done, Outcome, Reason, Response, SafetyError};
    use mcm_shared::sample::REPLIES_PER_CYCLE;

    fn ack(request_id: u64) -> mcm_shared::sample::Reply {
        Response {
            client_id: 1,
            request_id,
            kind: CommandKind::Status,
            outcome: Outcome::Done(Done::Ack),
        }
        .encode()
    }

    #[test]
    fn truth_sets_the_sim_fields_and_none_clears_them() {
        let view = CycleView::default();
        let mut s = StateSample::default();
        let truth = Truth {
            position: [0.5; 6],
            velocity: [-1.0; 6],
            emergency_stop: true,
        };
        compose(&mut s, &view, Some(truth), &CycleClock::default());
        assert_eq!(s.flags, STATE_SIMULATED | STATE_SIM_ESTOP);
        assert!((s.sim_true_position[5] - 0.5f64.to_degrees()).abs() < 1e-12);
        assert!((s.sim_true_velocity[0] + 1f64.to_degrees()).abs() < 1e-12);
        compose(&mut s, &view, None, &CycleClock::default());
        assert_eq!(s.flags, 0);
        assert_eq!(s.sim_true_position, [0.0; 6]);
        assert_eq!(s.sim_true_velocity, [0.0; 6]);
    }

    #[test]
    fn timing_and_flags_come_from_the_clock_and_the_view() {
        let mut view = CycleView {
            mode: Mode::Pvt,
            estop: true,
            pvt_starved: true,
            pvt_queued: 7,
            pvt_capacity: 100,
            ..CycleView::default()
        };
        view.axes[2].calibrated = true;
        view.axes[2].derated = true;
        let clock = CycleClock {
            t_ns: 42,
            timing: CycleTiming {
                period_ns: 5,
                overruns: 2,
                since_start: mcm_shared::sample::LatencyFigures {
                    p99_ns: 9,
                    ..Default::default()
                },
                work_max_ns: 11,
                ..CycleTiming::default()
            },
            not_realtime: true,
            command_receive_errors: 3,
            ..CycleClock::default()
        };
        let mut s = StateSample::default();
        compose(&mut s, &view, None, &clock);
        assert_eq!(s.t_ns, 42);
        assert_eq!(
            s.flags,
            STATE_ESTOP | STATE_PVT_STARVED | STATE_NOT_REALTIME
        );
        assert_eq!(s.axis_flags[2], AXIS_CALIBRATED | AXIS_I2T_DERATED);
        assert_eq!((s.pvt_queued, s.pvt_capacity), (7, 100));
        assert_eq!(s.command_receive_errors, 3);
        assert_eq!(
            (
                s.timing.overruns,
                s.timing.since_start.p99_ns,
                s.timing.work_max_ns
            ),
            (2, 9, 11)
        );
    }

    #[test]
    fn replies_are_counted_and_a_new_error_is_stamped_once() {
        let mut view = CycleView::default();
        let mut s = StateSample::default();
        view.replies.push(ack(1));
        view.replies.push(ack(2));
        view.last_error = Some(SafetyError {
            seq: 1,
            cycle: 4,
            unix_ns: 0,
            reason: Reason::NotCalibrated { axis: Axis::ALL[0] },
        });
        let clock = CycleClock {
            unix_ns: 1000,
            ..CycleClock::default()
        };
        compose(&mut s, &view, None, &clock);
        assert_eq!(s.reply_head, 2);
        assert_eq!(first_reply_seq(&s, &view), 1);
        assert_eq!((s.last_error.seq, s.last_error.unix_ns), (1, 1000));
        // Next cycle: no replies, the same error; the stamp stays.
        view.replies.clear();
        let later = CycleClock {
            unix_ns: 2000,
            ..CycleClock::default()
        };
        compose(&mut s, &view, None, &later);
        assert_eq!(s.reply_head, 2);
        assert_eq!(s.last_error.unix_ns, 1000);
        // More replies than a cycle may give: the head counts them all, the kept ones are the
        // newest and numbered last (the dropped ones leave a gap readers see).
        for n in 0..REPLIES_PER_CYCLE as u64 + 3 {
            view.replies.push(ack(100 + n));
        }
        compose(&mut s, &view, None, &later);
        assert_eq!(s.reply_head, 2 + REPLIES_PER_CYCLE as u64 + 3);
        assert_eq!(first_reply_seq(&s, &view), 2 + 3 + 1);
        assert_eq!(view.replies.replies()[0].request_id, 103);
    }
}
