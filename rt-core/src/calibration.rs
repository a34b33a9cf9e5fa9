//! Calibration (homing) of incremental-encoder axes against their mechanical stops or light
//! barriers.
//!
//! Runs inside the cycle: one small state machine per axis, stepped once per cycle with the
//! axis's feedback; it produces a raw (encoder-frame) position target for the drive (CSP) and
//! a current limit. All axes being calibrated search at the same time.
//!
//! **Mechanical stop**, in the configured direction (reversed by `elbow_direction` /
//! `wrist_direction`): a fast search at the configured search velocity until the motor current
//! departs from its free-motion baseline (contact), a 2-degree back-off, then a slow approach at
//! 1/30 of the search velocity, at a reduced current limit (baseline + search current), until
//! contact again. The stop is where
//! the slow approach touched: joint angle = raw position -
//! (raw at contact - stop angle). The slow approach keeps the contact force, and so the error
//! from the stop's compliance, small.
//!
//! **Light barrier**: a fast search towards the barrier's edge (the barrier input tells which
//! side the axis is on), a back-off to 2 degrees below the edge, then a slow approach in the
//! positive direction until the input switches; the edge is the midpoint of the two samples
//! around the switch.
//!
//! A search that travels further than the whole axis range plus twice the largest possible
//! encoder offset without finding its stop fails; the axis then holds where it is.

use mcm_shared::config::{AxisConfig, RobotConfig};
use mcm_shared::reply::CalibrationFailure;
use mcm_shared::units::rad_to_deg;

/// Back-off distance between the fast search and the slow approach [rad].
const BACKOFF: f64 = 2.0 * core::f64::consts::PI / 180.0;
/// Slow approach speed as a fraction of the search velocity.
const SLOW_FRACTION: f64 = 1.0 / 30.0;
/// Acceleration used to ramp the search velocity [rad/s^2].
const RAMP_ACCEL: f64 = 1.0;
/// Time to let the current settle before a baseline is trusted [s].
const SETTLE: f64 = 0.25;
/// Smoothing factor of the current baseline per cycle; slower during the slow approach, so
/// that the slow rise of a soft contact still stands out.
const BASELINE_ALPHA: f64 = 0.05;
const BASELINE_ALPHA_SLOW: f64 = 0.02;
/// Contact when the current departs from the baseline by this fraction of the search current
/// (fast search / slow approach).
const FAST_THRESHOLD: f64 = 0.5;
const SLOW_THRESHOLD: f64 = 0.2;
/// Cycles in a row the current must stay beyond the threshold to count as contact.
const CONTACT_CYCLES: u32 = 2;

/// How an axis finds its zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// The mechanical stop at `stop` [rad] reached by moving in `direction` (+1/-1).
    Stop { direction: f64, stop: f64 },
    /// The light barrier whose edge is at `edge` [rad] (active on the positive side).
    Barrier { edge: f64 },
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
    /// No stop or no barrier edge within the distance searched (reported in degrees).
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
    baseline: f64,
    baseline_age: f64,
    /// Cycles in a row the current has been beyond the contact threshold.
    over: u32,
    /// Where the current slow approach began (raw).
    approach_start: f64,
    prev: AxisInput,
}

impl AxisCalibration {
    /// Start from the axis's current state.
    pub fn start(s: AxisSettings, now: AxisInput) -> AxisCalibration {
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
            baseline: now.current,
            baseline_age: 0.0,
            over: 0,
            approach_start: now.position,
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
            Phase::Search { search, .. } if search.slow && self.baseline_age >= SETTLE => {
                (self.baseline.abs() + self.s.search_current).min(self.s.max_current)
            }
            _ => self.s.max_current,
        }
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
                self.track_baseline(input.current, dt);
                self.phase = if left <= dt {
                    self.baseline_age = 0.0;
                    self.over = 0;
                    self.approach_start = self.target;
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
                    self.baseline = input.current;
                    self.baseline_age = 0.0;
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
        self.outcome()
    }

    fn track_baseline(&mut self, current: f64, dt: f64) {
        let alpha = match self.phase {
            Phase::Search { search, .. } if search.slow => BASELINE_ALPHA_SLOW,
            _ => BASELINE_ALPHA,
        };
        self.baseline += alpha * (current - self.baseline);
        self.baseline_age += dt;
    }

    fn search(&mut self, search: Search, speed: f64, input: AxisInput, prev: AxisInput, dt: f64) {
        let top = if search.slow {
            self.s.velocity * SLOW_FRACTION
        } else {
            self.s.velocity
        };
        let speed = (speed + RAMP_ACCEL * dt).min(top);
        let at_speed = speed >= top;
        match self.s.method {
            Method::Stop { stop, .. } => {
                let threshold = if search.slow {
                    SLOW_THRESHOLD
                } else {
                    FAST_THRESHOLD
                } * self.s.search_current;
                let settled = at_speed && self.baseline_age >= SETTLE;
                // A stop holds the axis still; a jolt from another axis does not.
                let speed_now = (input.position - prev.position).abs() / dt;
                let still = search.slow || speed_now < 0.5 * top;
                if settled && still && (input.current - self.baseline).abs() > threshold {
                    self.over += 1;
                } else {
                    self.over = 0;
                }
                if self.over >= CONTACT_CYCLES {
                    if search.slow {
                        self.target = input.position;
                        self.phase = Phase::Done {
                            offset: input.position - stop,
                        };
                    } else {
                        self.target = input.position;
                        self.phase = Phase::Backoff {
                            goal: input.position - search.direction * BACKOFF,
                            direction: -search.direction,
                        };
                    }
                    return;
                }
                self.track_baseline(input.current, dt);
                if search.slow && (self.target - self.approach_start).abs() > 3.0 * BACKOFF {
                    // The fast search's contact was not the stop: search fast again.
                    self.phase = Phase::Search {
                        search: Search {
                            slow: false,
                            ..search
                        },
                        speed,
                    };
                    self.baseline_age = 0.0;
                    return;
                }
            }
            Method::Barrier { edge } => {
                if input.light_barrier != prev.light_barrier && self.baseline_age > 0.0 {
                    let at = 0.5 * (input.position + prev.position);
                    if search.slow {
                        self.target = input.position;
                        self.phase = Phase::Done { offset: at - edge };
                    } else {
                        self.target = at;
                        let goal = at - BACKOFF;
                        self.phase = Phase::Backoff {
                            goal,
                            direction: if goal < at { -1.0 } else { 1.0 },
                        };
                    }
                    return;
                }
                self.baseline_age += dt;
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
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A crude axis: follows the target exactly until it meets a wall at `wall`, where the
    /// current rises with the target's push.
    fn run(
        settings: AxisSettings,
        start: f64,
        wall: Option<f64>,
        barrier: Option<f64>,
    ) -> (Outcome, u32) {
        let dt = 0.005;
        let read = |target: f64| {
            let (pos, current) = match wall {
                Some(w) if (target - w) * settings_dir(&settings) > 0.0 => {
                    (w, 0.3 + 1000.0 * (target - w).abs())
                }
                _ => (target, 0.3),
            };
            AxisInput {
                position: pos,
                current,
                light_barrier: barrier.is_some_and(|e| pos >= e),
            }
        };
        let mut c = AxisCalibration::start(settings, read(start));
        for k in 0..100_000 {
            let out = c.step(read(c.target()), dt);
            if out != Outcome::Running {
                return (out, k);
            }
        }
        panic!("did not finish");
    }

    fn settings_dir(s: &AxisSettings) -> f64 {
        match s.method {
            Method::Stop { direction, .. } => direction,
            Method::Barrier { .. } => 1.0,
        }
    }

    fn settings(method: Method) -> AxisSettings {
        AxisSettings {
            method,
            velocity: 30f64.to_radians(),
            search_current: 3.0,
            max_current: 10.0,
            range: 4.0,
        }
    }

    #[test]
    fn finds_a_mechanical_stop_and_the_offset() {
        // Raw frame: the wall at raw 1.3 rad is the stop at joint 2.0 rad, so offset = -0.7.
        let s = settings(Method::Stop {
            direction: 1.0,
            stop: 2.0,
        });
        let (out, _) = run(s, 0.2, Some(1.3), None);
        let Outcome::Found { offset } = out else {
            panic!("{out:?}")
        };
        assert!(
            (offset + 0.7).abs() < 0.05f64.to_radians(),
            "offset {offset}"
        );
    }

    #[test]
    fn finds_a_stop_in_the_negative_direction() {
        let s = settings(Method::Stop {
            direction: -1.0,
            stop: -2.0,
        });
        let (out, _) = run(s, 0.0, Some(-1.5), None);
        let Outcome::Found { offset } = out else {
            panic!("{out:?}")
        };
        assert!(
            (offset - 0.5).abs() < 0.05f64.to_radians(),
            "offset {offset}"
        );
    }

    #[test]
    fn finds_a_light_barrier_edge_from_either_side() {
        for start in [-0.3, 0.4] {
            let s = settings(Method::Barrier { edge: 0.0 });
            // Raw edge at 0.1 => offset 0.1.
            let (out, _) = run(s, start, None, Some(0.1));
            let Outcome::Found { offset } = out else {
                panic!("{out:?}")
            };
            assert!(
                (offset - 0.1).abs() < 0.01f64.to_radians(),
                "start {start}: offset {offset}"
            );
        }
    }

    #[test]
    fn no_stop_fails_after_the_search_range() {
        let s = settings(Method::Stop {
            direction: 1.0,
            stop: 2.0,
        });
        let (out, _) = run(s, 0.0, None, None);
        let Outcome::Failed {
            cause: CalibrationFailure::NoStop { searched_deg },
        } = out
        else {
            panic!("{out:?}")
        };
        assert!(searched_deg > 4f64.to_degrees(), "{searched_deg}");
    }

    #[test]
    fn reverse_mirrors_the_stop() {
        let cfg = RobotConfig::prob2_default();
        let s = AxisSettings::from_config(&cfg, 2, true, false);
        let Method::Stop { direction, stop } = s.method else {
            panic!()
        };
        assert_eq!(direction, -1.0);
        assert!((stop + 140f64.to_radians()).abs() < 1e-12);
        let b = AxisSettings::from_config(&cfg, 0, false, false);
        assert!(matches!(b.method, Method::Barrier { .. }));
        let f = AxisSettings::from_config(&cfg, 0, false, true);
        assert!(matches!(f.method, Method::Stop { .. }));
    }
}
