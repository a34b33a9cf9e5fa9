//! The relax of the axes whose calibration search ended without success (aborted, failed,
//! `blocked`), so that an axis a search pressed into its mechanical stop does not press there
//! for good ([`SearchRelax`]).
//!
//! Runs inside the cycle: plain `Copy` data, no allocation.

use super::Controller;
use super::trips::RELAX_CYCLES;
use mcm_shared::NUM_AXES;

impl Controller {
    /// A calibration's searches end without completing (aborted, failed or blocked): every
    /// axis that was searching its mechanical stop relaxes ([`SearchRelax`]). Called before
    /// the state changes; nothing happens outside the searches.
    pub(super) fn relax_searched_axes(&mut self) {
        let Some(axes) = self.searches() else {
            return;
        };
        for (i, cal) in axes.iter().enumerate() {
            let Some(cal) = cal else {
                continue;
            };
            if let Some(direction) = cal.stop_direction() {
                let restart = cal.may_press_its_stop();
                self.search_relax.start(i, direction, restart);
                if restart {
                    // The stop that follows re-seeds the reference at the measured position in
                    // this very cycle, while the relax's own restart comes a cycle later (a
                    // search that fails in the cycle's motion) or once that stop is over. Sent
                    // without a restart, the step back by the search's lead (up to 3 deg) is a
                    // velocity reference to the drive for a period, which kicks the axis off
                    // its stop.
                    self.master.restart_position_loop(i);
                }
            }
        }
    }

    /// One cycle of the relax of the axes whose search ended without success, once `stopping`
    /// (a stop under way) is over: a stop plans every axis back to where it was, so a relax
    /// during it would end with the axis pressing again.
    pub(super) fn relax_searched(&mut self, stopping: bool) {
        if stopping || !self.search_relax.any() {
            return;
        }
        let fb = *self.master.feedback();
        let measured = self.measured();
        for (i, f) in fb.iter().enumerate() {
            let Some((shift, restart)) = self.search_relax.step(i, f.position_rad) else {
                continue;
            };
            self.cmd.position[i] = measured[i] + shift;
            self.cmd.velocity[i] = 0.0;
            self.cmd.acceleration[i] = 0.0;
            if restart {
                self.master.restart_position_loop(i);
            }
        }
    }
}

/// How far an axis relaxing after its search may move back from its stop [rad]: the depth a
/// drive presses it into the stop's spring (20 000 Nm/rad: 0.1 deg at 4 A, 0.4 deg at the
/// search's 10 A) with some margin. An axis that did not press (its weight pulls it away from
/// its stop) sags no further than this.
const RELAX_BAND_RAD: f64 = 0.5 * core::f64::consts::PI / 180.0;

/// The relax of the axes whose calibration search ended without success (aborted, failed,
/// blocked): a search may have pressed an axis into its mechanical stop's spring, or started on
/// an axis already pressing there; held at its measured position, the drive would press with
/// its full current for good, derate the motor by i2t and keep every later search from
/// reaching its contact current. For [`RELAX_CYCLES`] such an axis's reference follows its
/// measured position, but only on the side away from its stop and by at most
/// [`RELAX_BAND_RAD`] from where the relax began (an axis its weight pulls elsewhere stays
/// held there); then it holds where it came to rest. The drive's loop of an axis the search
/// drove towards its stop (moving, backing off, or ended there) restarts at the start and at
/// the end of its relax, so that a loop wound up against the stop stops pressing. An axis
/// still settling before its approach keeps its loop: its integral carries the axis's weight
/// (an uncalibrated axis gets no gravity feed-forward), and clearing it would let the axis
/// sag. The relax waits for any stop under way, goes on through ERROR, an enabling and HOLD,
/// and ends in any other mode (`motion.rs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct SearchRelax {
    /// Cycles left per axis (0: not relaxing).
    left: [u8; NUM_AXES],
    /// The direction of each axis's stop (+1/-1).
    toward_stop: [f64; NUM_AXES],
    /// The raw position where each axis's relax began [rad].
    from: [f64; NUM_AXES],
    /// Whether each axis's drive loop restarts at the start and the end of its relax.
    restart: [bool; NUM_AXES],
}

impl SearchRelax {
    pub const NONE: SearchRelax = SearchRelax {
        left: [0; NUM_AXES],
        toward_stop: [0.0; NUM_AXES],
        from: [0.0; NUM_AXES],
        restart: [false; NUM_AXES],
    };

    fn start(&mut self, axis: usize, toward_stop: f64, restart: bool) {
        self.left[axis] = RELAX_CYCLES;
        self.toward_stop[axis] = toward_stop;
        self.restart[axis] = restart;
    }

    /// An axis relaxes.
    pub fn any(&self) -> bool {
        self.left.iter().any(|&c| c > 0)
    }

    /// The relax ends (a mode with a motion of its own, OFF).
    pub fn end(&mut self) {
        self.left = [0; NUM_AXES];
    }

    /// One cycle of `axis`'s relax at raw position `raw`: `None` when it does not relax, else
    /// how far its reference is from its measured position (0 within the band, else back to
    /// the band's edge) and whether its drive's loop restarts this cycle.
    fn step(&mut self, axis: usize, raw: f64) -> Option<(f64, bool)> {
        let left = self.left[axis];
        if left == 0 {
            return None;
        }
        if left == RELAX_CYCLES {
            self.from[axis] = raw;
        }
        self.left[axis] = left - 1;
        // How far the axis moved away from its stop since the relax began.
        let back = -self.toward_stop[axis] * (raw - self.from[axis]);
        let allowed = back.clamp(0.0, RELAX_BAND_RAD);
        let shift = -self.toward_stop[axis] * (allowed - back);
        let edge = left == RELAX_CYCLES || left == 1;
        Some((shift, self.restart[axis] && edge))
    }
}
