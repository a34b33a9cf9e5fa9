//! `mcm-rt`'s notifications to systemd (`Type=notify`, `deploy/systemd/mcm-rt.service`), from a
//! helper thread of its own. Not in the cycle: the thread runs at normal policy off the cycle's
//! CPU (it is spawned after the main thread placed itself there) and only reads two counters
//! the cycle loop and the signal handlers keep ([`runner::cycles_run`], [`signals::count`]).
//!
//! - `READY=1` with the ready line as `STATUS=`, when the runner calls its `on_started` (the
//!   bus open, the IPC services up, the line printed);
//! - `STOPPING=1` when the first SIGTERM/SIGINT after that starts the controlled stop;
//! - `WATCHDOG=1` every half of the unit's `WatchdogSec=`, only while the cycle counter
//!   advanced since the last look (the first look one period after `READY=1`): a cycle that
//!   hangs stops the pings, and systemd ends the process (`WatchdogSignal=`, SIGABRT by
//!   default). While it stalls `STATUS=` says so; when it runs again, the ready line is back.
//!   Never from the cycle thread.
//!
//! Without `NOTIFY_SOCKET` (run by hand, by the `mcm` launcher) no thread is started.

use crate::{runner, signals};
use mcm_shared::notify::{Notifier, Progress};
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

/// How often the thread looks at the signal count (and the watchdog's schedule).
const POLL: Duration = Duration::from_millis(50);

/// What systemd is told when the controlled stop begins.
pub const STOPPING_STATUS: &str =
    "controlled stop: to standstill, hold, drives disabled (docs/safety.md \"Shutdown\")";

/// Start the notifying thread when systemd listens: it waits for the ready line on `ready` (the
/// runner's `on_started` sends it; the sender dropped without one means the run ended first),
/// then notifies as the module says until the process ends.
pub fn start(ready: Receiver<String>) -> std::io::Result<()> {
    if !Notifier::listening() {
        return Ok(());
    }
    let notifier = Notifier::from_env("mcm-rt");
    std::thread::Builder::new()
        .name("mcm-rt-systemd".into())
        .spawn(move || watch(&notifier, &ready))?;
    Ok(())
}

fn watch(notifier: &Notifier, ready: &Receiver<String>) {
    let Ok(status) = ready.recv() else {
        return; // the run ended before it served
    };
    let baseline = signals::count();
    notifier.ready(&status);
    let every = notifier.watchdog_every();
    let tick = every.map_or(POLL, |e| e.min(POLL));
    let mut schedule =
        every.map(|e| WatchdogSchedule::new(e, Instant::now(), runner::cycles_run()));
    let mut stopping = false;
    loop {
        if !stopping && signals::count() > baseline {
            stopping = true;
            notifier.stopping(STOPPING_STATUS);
        }
        if let Some(schedule) = &mut schedule {
            match schedule.look(Instant::now(), runner::cycles_run()) {
                None => {}
                Some(Tell::Ping) => notifier.watchdog(),
                Some(Tell::PingAgain) => {
                    notifier.watchdog();
                    if !stopping {
                        notifier.status(&status);
                    }
                }
                Some(Tell::Stalled { cycles }) => notifier.status(&format!(
                    "the real-time cycle has not advanced for {:?} (at cycle {cycles}): no \
                     watchdog ping",
                    schedule.every
                )),
            }
        }
        std::thread::sleep(tick);
    }
}

/// What the watchdog tells systemd after a look at the cycle counter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Tell {
    /// The cycle advanced: `WATCHDOG=1`.
    Ping,
    /// The cycle advanced again after a stall: `WATCHDOG=1`, and the status back to the ready
    /// line.
    PingAgain,
    /// The cycle did not advance since the last look: no ping, the status says so.
    Stalled { cycles: u64 },
}

/// When to look at the cycle counter and what to tell: plain data, so the schedule is tested
/// without systemd. The first look is one period after `READY=1` (the first cycle runs just
/// after it), then one every period.
#[derive(Debug)]
struct WatchdogSchedule {
    every: Duration,
    next: Instant,
    progress: Progress,
    stalled: bool,
}

impl WatchdogSchedule {
    fn new(every: Duration, now: Instant, cycles: u64) -> Self {
        Self {
            every,
            next: now + every,
            progress: Progress::new(cycles),
            stalled: false,
        }
    }

    /// At `now`, with the cycle counter at `cycles`: what to tell, when a look is due.
    fn look(&mut self, now: Instant, cycles: u64) -> Option<Tell> {
        if now < self.next {
            return None;
        }
        self.next = now + self.every;
        if self.progress.advanced(cycles) {
            Some(if std::mem::take(&mut self.stalled) {
                Tell::PingAgain
            } else {
                Tell::Ping
            })
        } else {
            self.stalled = true;
            Some(Tell::Stalled { cycles })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const EVERY: Duration = Duration::from_secs(1);

    #[test]
    fn the_first_look_is_one_period_after_ready_so_a_cycle_about_to_start_is_no_stall() {
        let t0 = Instant::now();
        let mut s = WatchdogSchedule::new(EVERY, t0, 0);
        // Right at READY=1 and until a period passed, nothing is due: no stall reported at
        // cycle 0 before the first cycle could run.
        assert_eq!(s.look(t0, 0), None);
        assert_eq!(s.look(t0 + EVERY / 2, 0), None);
        assert_eq!(s.look(t0 + EVERY, 50), Some(Tell::Ping));
        assert_eq!(s.look(t0 + EVERY + EVERY / 2, 60), None);
        assert_eq!(s.look(t0 + 2 * EVERY, 100), Some(Tell::Ping));
    }

    #[test]
    fn a_stall_stops_the_pings_and_the_next_advance_restores_the_status() {
        let t0 = Instant::now();
        let mut s = WatchdogSchedule::new(EVERY, t0, 0);
        assert_eq!(s.look(t0 + EVERY, 50), Some(Tell::Ping));
        assert_eq!(
            s.look(t0 + 2 * EVERY, 50),
            Some(Tell::Stalled { cycles: 50 })
        );
        assert_eq!(
            s.look(t0 + 3 * EVERY, 50),
            Some(Tell::Stalled { cycles: 50 })
        );
        assert_eq!(s.look(t0 + 4 * EVERY, 51), Some(Tell::PingAgain));
        assert_eq!(s.look(t0 + 5 * EVERY, 52), Some(Tell::Ping));
    }
}
