//! `mcm-rt`'s notifications to systemd (`Type=notify`, `deploy/systemd/mcm-rt.service`), from a
//! helper thread of its own. Not in the cycle: the thread runs at normal policy off the cycle's
//! CPU (it is spawned after the main thread placed itself there) and only reads two counters
//! the cycle loop and the signal handlers keep ([`runner::cycles_run`], [`signals::count`]).
//!
//! - `READY=1` with the ready line as `STATUS=`, when the runner calls its `on_started` (the
//!   bus open, the IPC services up, the line printed);
//! - `STOPPING=1` when the first SIGTERM/SIGINT after that starts the controlled stop;
//! - `WATCHDOG=1` every half of the unit's `WatchdogSec=`, only while the cycle counter
//!   advanced since the last ping: a cycle that hangs stops the pings, and systemd ends the
//!   process (`WatchdogSignal=`, SIGABRT by default). Never from the cycle thread.
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
    let mut progress = Progress::new(runner::cycles_run());
    let mut next_ping = Instant::now();
    let mut stopping = false;
    loop {
        if !stopping && signals::count() > baseline {
            stopping = true;
            notifier.stopping(STOPPING_STATUS);
        }
        if let Some(every) = every {
            let now = Instant::now();
            if now >= next_ping {
                let cycles = runner::cycles_run();
                if progress.advanced(cycles) {
                    notifier.watchdog();
                } else {
                    notifier.status(&format!(
                        "the real-time cycle has not advanced for {every:?} (at cycle {cycles}): \
                         no watchdog ping"
                    ));
                }
                next_ping = now + every;
            }
        }
        std::thread::sleep(tick);
    }
}
