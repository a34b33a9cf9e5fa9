//! Calibration (homing) of incremental-encoder axes against their mechanical stops or light
//! barriers.
//!
//! Runs inside the cycle: one small state machine per axis, stepped once per cycle with the
//! axis's feedback; it produces a raw (encoder-frame) position target for the drive (CSP) and
//! a current limit. Plain `Copy` data, no allocation. All axes being calibrated search at the
//! same time.
//!
//! **Mechanical stop**, in the configured direction (reversed by `elbow_direction` /
//! `wrist_direction`): a fast search at the configured search velocity until contact, a
//! 2-degree back-off, then a slow approach at 1/30 of the search velocity, at a reduced current
//! limit (baseline + search current), until contact again. Contact is decided by
//! [`contact::ContactDetector`] from currents and positions over many cycles (current beyond
//! the baseline in the search direction, a following error, the axis no longer advancing),
//! never from one sample: another axis hitting its stop (the swing it puts into this axis
//! starts a quiet time), a load that changes as the other axes move, a late cycle or a current
//! spike does not make a contact. The stop is where the slow approach touched: joint angle = raw
//! position - (raw at contact - stop angle).
//!
//! **Light barrier**: a fast search towards the barrier's edge (the barrier input tells which
//! side the axis is on), a back-off to 2 degrees below the edge, then a slow approach in the
//! positive direction until the input switches; the edge is the midpoint of the two samples
//! around the switch.
//!
//! **Plausibility** ([`AxisSettings::tolerance`]): the slow approach must find the stop or edge
//! where the approach before it did (within the tolerance); when they disagree the axis backs
//! off and approaches again, up to [`MAX_APPROACHES`] slow approaches, and then fails with
//! [`CalibrationFailure::Inconsistent`]. An axis that had a valid calibration must find its
//! stop or edge, in that calibration's frame, within the tolerance of the configured position,
//! else [`CalibrationFailure::Implausible`]; the controller then drops that previous
//! calibration (one of the two is wrong), so that the next calibration can put it right.
//!
//! A search that travels further than the whole axis range plus twice the largest possible
//! encoder offset without finding its stop fails; the axis then holds where it is.
//!
//! **Lead** ([`lead`]): a search's target never runs further ahead of the measured position
//! than the axis's following-error band plus what the contact detector needs to confirm a
//! contact at the search speed. An axis that falls further behind stops its target; it is in
//! contact if its current pushes in the search direction while it stands, it is waited for
//! while it still advances (it lags, loaded by the other axes' searches), else the calibration
//! fails with [`CalibrationFailure::Blocked`] (an obstacle whose push the current cannot show,
//! e.g. an axis derated by i2t).

pub mod contact;
pub mod lead;

use contact::{ContactDetector, ContactParams, Sample};
use lead::{LeadGuard, Verdict};
use mcm_shared::config::{AxisConfig, RobotConfig};
use mcm_shared::reply::CalibrationFailure;
use mcm_shared::units::rad_to_deg;

/// Back-off distance between the fast search and the slow approach [rad].
const BACKOFF: f64 = 2.0 * core::f64::consts::PI / 180.0;
/// Slow approach speed as a fraction of the search velocity.
const SLOW_FRACTION: f64 = 1.0 / 30.0;
/// Acceleration used to ramp the search velocity [rad/s^2].
const RAMP_ACCEL: f64 = 1.0;
/// Time to hold still before a search starts [s].
const SETTLE: f64 = contact::SETTLE;
/// Slow approaches at most, each compared with the contact before it.
pub const MAX_APPROACHES: u32 = 3;
/// Contact in the fast search: current beyond half the search current for 4 cycles, at least
/// 0.2 deg behind the target, the axis advancing less than half as fast as its target.
const FAST_CONTACT: (f64, u32, f64) = (0.5, 4, 0.2);
/// Contact in the slow approach: 0.2 of the search current for 30 cycles (0.15 s at 200 Hz:
/// a jolt from another axis is over by then), at least 0.05 deg behind the target.
const SLOW_CONTACT: (f64, u32, f64) = (0.2, 30, 0.05);
/// Largest share of its target's advance an axis in contact may still make (a compliant
/// stop gives a little; free motion follows the target).
const STALL_FRACTION: f64 = 0.5;

/// How an axis finds its zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// The mechanical stop at `stop` [rad] reached by moving in `direction` (+1/-1).
    Stop { direction: f64, stop: f64 },
    /// The light barrier whose edge is at `edge` [rad] (active on the positive side).
    Barrier { edge: f64 },
}

impl Method {
    /// The configured joint angle of the reference [rad].
    pub fn reference(&self) -> f64 {
        match *self {
            Method::Stop { stop, .. } => stop,
            Method::Barrier { edge } => edge,
        }
    }
}

/// Static per-axis calibration settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisSettings {
    pub method: Method,
    /// Search velocity [rad/s].
    pub velocity: f64,
    /// Extra current allowed above the free-motion baseline [A].
    pub search_current: f64,
    pub max_current: f64,
    /// Longest distance searched before giving up [rad].
    pub range: f64,
    /// How far two approaches (or the reference and the previous calibration) may disagree
    /// [rad].
    pub tolerance: f64,
    /// The axis's following-error band [rad]: the base of how far the search's target may
    /// lead the measured position (see [`lead`]).
    pub following_band: f64,
}

impl AxisSettings {
    /// Settings of `axis` (0-based); `reverse` flips a mechanical-stop search to the other
    /// stop; `force_stop` ignores a light barrier.
    pub fn from_config(
        cfg: &RobotConfig,
        axis: usize,
        reverse: bool,
        force_stop: bool,
    ) -> AxisSettings {
        let a: &AxisConfig = &cfg.axes[axis];
        let c = &a.calibration;
        let method = match c.light_barrier_deg {
            Some(lb) if !force_stop => Method::Barrier {
                edge: lb.to_radians(),
            },
            _ => {
                let (direction, stop) = if reverse {
                    // The opposite stop mirrors the configured one across the range's centre.
                    (-f64::from(c.direction), a.min_deg + a.max_deg - c.stop_deg)
                } else {
                    (f64::from(c.direction), c.stop_deg)
                };
                Method::Stop {
                    direction,
                    stop: stop.to_radians(),
                }
            }
        };
        let range = (a.max_deg - a.min_deg + 2.0 * cfg.sim.max_encoder_offset_deg.max(20.0) + 10.0)
            .to_radians();
        AxisSettings {
            method,
            velocity: c.search_velocity_deg_s.to_radians(),
            search_current: c.search_current_a,
            max_current: a.max_current_a,
            range,
            tolerance: c.tolerance_deg.to_radians(),
            following_band: a.following_error_deg.to_radians(),
        }
    }

    fn contact_params(&self, slow: bool) -> ContactParams {
        let (share, confirm_cycles, lag_deg) = if slow { SLOW_CONTACT } else { FAST_CONTACT };
        ContactParams {
            threshold: share * self.search_current,
            confirm_cycles,
            min_lag: lag_deg.to_radians(),
            stall_fraction: STALL_FRACTION,
        }
    }
}

/// Feedback of one axis, as the calibration needs it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisInput {
    /// Raw (encoder-frame) position [rad].
    pub position: f64,
    pub current: f64,
    pub light_barrier: bool,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    /// Hold and let the current settle.
    Settle {
        left: f64,
        next: Search,
    },
    /// Move at `speed` in `direction` (ramping up), watching for contact or the barrier edge.
    Search {
        search: Search,
        speed: f64,
    },
    /// Move back to `goal`.
    Backoff {
        goal: f64,
        direction: f64,
    },
    Done {
        offset: f64,
    },
    Failed {
        cause: CalibrationFailure,
    },
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Search {
    direction: f64,
    slow: bool,
}

/// The outcome of one axis's calibration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Outcome {
    Running,
    /// Joint angle = raw position - offset.
    Found {
        offset: f64,
    },
    /// No stop or edge found, or the one found is not plausible (figures in degrees).
    Failed {
        cause: CalibrationFailure,
    },
}

/// Calibration of one axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisCalibration {
    s: AxisSettings,
    phase: Phase,
    target: f64,
    start: f64,
    detector: ContactDetector,
    /// Keeps the target within its bound of the measured position.
    lead: LeadGuard,
    /// The targets of the last two cycles, `[k-1, k-2]`: the position measured in cycle k
    /// answers the target of cycle k-2.
    sent: [f64; 2],
    /// Time since the current search began [s].
    searching: f64,
    /// Where the current slow approach began (raw).
    approach_start: f64,
    /// The raw position of the last contact or edge (fast search or earlier slow approach).
    last_contact: Option<f64>,
    /// Slow approaches so far.
    approaches: u32,
    /// The offset of the axis's previous, valid calibration, if it had one.
    previous: Option<f64>,
    prev: AxisInput,
}

impl AxisCalibration {
    /// Start from the axis's current state; `previous` is the offset of the axis's valid
    /// calibration, if it has one (the reference found is checked against it).
    pub fn start(s: AxisSettings, now: AxisInput, previous: Option<f64>) -> AxisCalibration {
        let direction = match s.method {
            Method::Stop { direction, .. } => direction,
            // Towards the edge: the barrier is active on its positive side.
            Method::Barrier { .. } => {
                if now.light_barrier {
                    -1.0
                } else {
                    1.0
                }
            }
        };
        AxisCalibration {
            s,
            phase: Phase::Settle {
                left: SETTLE,
                next: Search {
                    direction,
                    slow: false,
                },
            },
            target: now.position,
            start: now.position,
            detector: ContactDetector::new(now.current),
            lead: LeadGuard::default(),
            sent: [now.position; 2],
            searching: 0.0,
            approach_start: now.position,
            last_contact: None,
            approaches: 0,
            previous,
            prev: now,
        }
    }

    /// The raw position target for the drive.
    pub fn target(&self) -> f64 {
        self.target
    }

    /// The current limit for the drive [A].
    pub fn current_limit(&self) -> f64 {
        match self.phase {
            Phase::Search { search, .. } if search.slow && self.detector.settled() => {
                (self.detector.baseline().abs() + self.s.search_current).min(self.s.max_current)
            }
            _ => self.s.max_current,
        }
    }

    /// The offset of the axis's previous, valid calibration, if it had one: the reference
    /// found is checked against it, and it comes back if the calibration does not complete.
    pub fn previous(&self) -> Option<f64> {
        self.previous
    }

    /// The direction (+1/-1) in which the axis's search finds its mechanical stop; `None` for
    /// a light barrier (nothing to press into).
    pub fn stop_direction(&self) -> Option<f64> {
        match self.s.method {
            Method::Stop { direction, .. } => Some(direction),
            Method::Barrier { .. } => None,
        }
    }

    /// Whether this search may have pressed the axis into its mechanical stop: it backed off
    /// from it, ended (a reference found implausible leaves the axis pressed into its stop),
    /// or in its fast search or slow approach its current pushes beyond the baseline in the
    /// search direction by that contact's share of the search current (a contact not yet
    /// confirmed). An axis still settling, or searching in free air, has not been driven into
    /// the stop: its loop's integral carries its weight, and restarting that loop would let the
    /// axis sag.
    pub fn may_press_its_stop(&self) -> bool {
        match self.phase {
            Phase::Settle { .. } => false,
            Phase::Search {
                search: Search { slow, direction },
                ..
            } => {
                let share = if slow { SLOW_CONTACT.0 } else { FAST_CONTACT.0 };
                (self.prev.current - self.detector.baseline()) * direction
                    >= share * self.s.search_current
            }
            _ => true,
        }
    }

    /// The axis's drive rebooted (its encoder reference may be gone): its previous calibration
    /// is no longer valid.
    pub fn forget_previous(&mut self) {
        self.previous = None;
    }

    pub fn outcome(&self) -> Outcome {
        match self.phase {
            Phase::Done { offset } => Outcome::Found { offset },
            Phase::Failed { cause } => Outcome::Failed { cause },
            _ => Outcome::Running,
        }
    }

    /// One cycle of `dt` seconds with this cycle's feedback.
    pub fn step(&mut self, input: AxisInput, dt: f64) -> Outcome {
        let prev = self.prev;
        self.prev = input;
        match self.phase {
            Phase::Settle { left, next } => {
                self.detector.track(input.current, dt);
                self.phase = if left <= dt {
                    self.detector.restart();
                    self.lead = LeadGuard::default();
                    self.searching = 0.0;
                    self.approach_start = self.target;
                    if next.slow {
                        self.approaches += 1;
                    }
                    Phase::Search {
                        search: next,
                        speed: 0.0,
                    }
                } else {
                    Phase::Settle {
                        left: left - dt,
                        next,
                    }
                };
            }
            Phase::Search { search, speed } => self.search(search, speed, input, prev, dt),
            Phase::Backoff { goal, direction } => {
                let step = self.s.velocity * dt;
                if (goal - self.target) * direction <= step {
                    self.target = goal;
                    self.detector.rebase(input.current);
                    let approach = match self.s.method {
                        Method::Stop { direction, .. } => direction,
                        Method::Barrier { .. } => 1.0,
                    };
                    self.phase = Phase::Settle {
                        left: SETTLE,
                        next: Search {
                            direction: approach,
                            slow: true,
                        },
                    };
                } else {
                    self.target += direction * step;
                }
            }
            Phase::Done { .. } | Phase::Failed { .. } => {}
        }
        self.sent = [self.target, self.sent[0]];
        self.outcome()
    }

    fn search(&mut self, search: Search, speed: f64, input: AxisInput, prev: AxisInput, dt: f64) {
        let top = if search.slow {
            self.s.velocity * SLOW_FRACTION
        } else {
            self.s.velocity
        };
        let speed = (speed + RAMP_ACCEL * dt).min(top);
        let at_speed = speed >= top;
        self.searching += dt;
        let params = self.s.contact_params(search.slow);
        match self.s.method {
            Method::Stop { .. } => {
                let lagged = self.sent[1];
                let sample = Sample {
                    position: input.position,
                    current: input.current,
                    target: lagged,
                };
                if let Some(at) =
                    self.detector
                        .step(&params, search.direction, sample, at_speed, dt)
                {
                    // Hold where the axis is (pressed against the stop).
                    self.target = input.position;
                    self.found(search, at);
                    return;
                }
                if search.slow && (self.target - self.approach_start).abs() > 3.0 * BACKOFF {
                    // The contact before was not the stop: search fast again.
                    self.last_contact = None;
                    self.detector.restart();
                    self.phase = Phase::Search {
                        search: Search {
                            slow: false,
                            ..search
                        },
                        speed,
                    };
                    return;
                }
            }
            Method::Barrier { .. } => {
                if input.light_barrier != prev.light_barrier && self.searching > dt {
                    let at = 0.5 * (input.position + prev.position);
                    self.target = if search.slow { input.position } else { at };
                    self.found(search, at);
                    return;
                }
            }
        }
        // The target stays within its bound of the position it is answered by (see `lead`).
        let lag = search.direction * (self.sent[1] - input.position);
        let bound = lead::bound(self.s.following_band, top, params.confirm_cycles, dt);
        // Only a stop is pushed against; a barrier search has nothing to push.
        let push = matches!(self.s.method, Method::Stop { .. })
            && search.direction * (input.current - self.detector.baseline()) > params.threshold;
        match self
            .lead
            .step(lag, bound, input.position, search.direction, push, &params)
        {
            Verdict::Advance => {}
            Verdict::Stay => {
                self.phase = Phase::Search { search, speed };
                return;
            }
            Verdict::Contact(at) => {
                self.target = input.position;
                self.found(search, at);
                return;
            }
            Verdict::Blocked(lag) => {
                // Hold where the axis is, not where the target went.
                self.target = input.position;
                self.phase = Phase::Failed {
                    cause: CalibrationFailure::Blocked {
                        lag_deg: rad_to_deg(lag),
                        bound_deg: rad_to_deg(bound),
                    },
                };
                return;
            }
        }
        let searched = (self.target - self.start).abs();
        if searched > self.s.range {
            self.target = input.position;
            let searched_deg = rad_to_deg(searched);
            let cause = match self.s.method {
                Method::Stop { .. } => CalibrationFailure::NoStop { searched_deg },
                Method::Barrier { .. } => CalibrationFailure::NoEdge { searched_deg },
            };
            self.phase = Phase::Failed { cause };
            return;
        }
        self.target += search.direction * speed * dt;
        self.phase = Phase::Search { search, speed };
    }

    /// The search found its stop or edge at the raw position `at`: back off and approach
    /// slowly, or (slow approach) accept it if it agrees with the contact before it and with
    /// the previous calibration.
    fn found(&mut self, search: Search, at: f64) {
        let reference = self.s.method.reference();
        let tolerance = self.s.tolerance;
        let before = self.last_contact;
        self.last_contact = Some(at);
        if search.slow
            && let Some(first) = before
        {
            let apart = at - first;
            if apart.abs() <= tolerance {
                self.phase = match self.previous {
                    Some(old) if (at - old - reference).abs() > tolerance => Phase::Failed {
                        cause: CalibrationFailure::Implausible {
                            found_deg: rad_to_deg(at - old),
                            configured_deg: rad_to_deg(reference),
                            tolerance_deg: rad_to_deg(tolerance),
                        },
                    },
                    _ => Phase::Done {
                        offset: at - reference,
                    },
                };
                return;
            }
            if self.approaches >= MAX_APPROACHES {
                self.phase = Phase::Failed {
                    cause: CalibrationFailure::Inconsistent {
                        first_deg: rad_to_deg(reference),
                        second_deg: rad_to_deg(reference + apart),
                        tolerance_deg: rad_to_deg(tolerance),
                    },
                };
                return;
            }
        }
        // Back off against the search direction of the method (barrier: below the edge).
        let back = match self.s.method {
            Method::Stop { .. } => -search.direction,
            Method::Barrier { .. } => -1.0,
        };
        self.phase = Phase::Backoff {
            goal: at + back * BACKOFF,
            direction: back,
        };
    }
}

#[cfg(test)]
mod tests;
