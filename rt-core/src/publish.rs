//! The one place that composes the published [`StateSample`]: from the controller's view of
//! the cycle (SI units, [`CycleView`]), the simulation's truth (`None` with real drives) and
//! the cycle's timing ([`CycleClock`]). Degrees are produced here, and only here, for the state.
//!
//! The TCP's state is composed last, from the axis values just written
//! ([`crate::cartesian::Cartesian::compose`]).
//!
//! Runs inside the cycle: writes into a sample the caller owns, no allocation. The sample persists
//! from cycle to cycle: `reply_head` counts every reply since start (the replies of this cycle are
//! numbered up to it and published by the edge, [`crate::ipc::RtIpc::publish_replies`]), and the
//! last error record is replaced only when the controller reports a new one, stamped with this
//! cycle's wall clock.
//!
//! ```
//! use mcm_rt_core::cartesian::Cartesian;
//! use mcm_rt_core::controller::CycleView;
//! use mcm_rt_core::publish::{CycleClock, compose};
//! use mcm_shared::mode::Mode;
//! use mcm_shared::sample::{STATE_SIMULATED, StateSample};
//! let mut view = CycleView { cycle: 3, mode: Mode::Hold, ..CycleView::default() };
//! view.axes[1].measured_position = core::f64::consts::FRAC_PI_2;
//! let mut s = StateSample::default();
//! let cartesian = Cartesian::from_config(&mcm_shared::config::RobotConfig::prob2_default())?;
//! compose(&mut s, &view, None, &CycleClock::virtual_time(15_000_000, 5_000_000), &cartesian);
//! assert_eq!((s.seq, s.t_ns, s.mode), (3, 15_000_000, Mode::Hold.to_wire()));
//! assert!((s.measured_position[1] - 90.0).abs() < 1e-12);
//! assert_eq!(s.flags & STATE_SIMULATED, 0);
//! # Ok::<(), mcm_rt_core::cartesian::CartesianSetupError>(())
//! ```

use crate::cartesian::Cartesian;
use crate::controller::CycleView;
use mcm_shared::sample::{
    AXIS_CALIBRATED, AXIS_ENABLED, AXIS_FAULT, AXIS_I2T_DERATED, AXIS_ONLINE, CycleTiming,
    STATE_ALL_CALIBRATED, STATE_ESTOP, STATE_NOT_REALTIME, STATE_PVT_STARVED, STATE_SHUTTING_DOWN,
    STATE_SIM_ESTOP, STATE_SIMULATED, StateSample,
};
use mcm_shared::simulator::SimTruth;
use mcm_shared::units::rad_to_deg;

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

/// Compose `s` for this cycle from the controller's `view`, the simulation's `truth` (yielded
/// by the simulator's edge, [`crate::sim_edge`]; `None` for real drives: the truth fields
/// zero, `STATE_SIMULATED` and `STATE_SIM_ESTOP` clear), the cycle's `clock`, and the TCP's
/// state from the axis values with `cartesian`.
pub fn compose(
    s: &mut StateSample,
    view: &CycleView,
    truth: Option<SimTruth>,
    clock: &CycleClock,
    cartesian: &Cartesian,
) {
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
    s.bus = view.bus;
    s.tool = (&view.tool).into();
    s.command_receive_errors = clock.command_receive_errors;
    s.timing = clock.timing;
    if let Some(e) = view.last_error
        && e.seq != s.last_error.seq
    {
        s.last_error = e.encode();
        s.last_error.unix_ns = clock.unix_ns;
    }
    s.reply_head += view.replies.dropped() + view.replies.replies().len() as u64;
    cartesian.compose(s);
}

/// The sequence number of the first of this cycle's replies, once [`compose`] counted them.
pub fn first_reply_seq(s: &StateSample, view: &CycleView) -> u64 {
    s.reply_head + 1 - view.replies.replies().len() as u64
}

#[cfg(test)]
mod tests;
