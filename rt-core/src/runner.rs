//! The real-time loop: the edges around [`crate::cycle::Cycle`].
//!
//! Set-up (bus, real-time thread, IPC) runs once; then every period, on absolute deadlines:
//! wake, record the wake-up latency, drain commands, run the cycle, add timing, publish the
//! state. Stops when SIGINT or SIGTERM arrives (checked once per cycle).
//!
//! With the simulated bus, the simulated robot outlives a restart of `mcm-rt` the way real
//! drives that keep their power do: it is resumed from [`sim_state_path`] at start (the file is
//! then deleted) and saved there when the loop stops.

use crate::bus::Bus;
use crate::clock;
use crate::cycle::{COMMANDS_PER_CYCLE, Cycle};
use crate::flight::{FlightRecorder, Record};
use crate::histogram::Histogram;
use crate::ipc::{IpcSetupError, RtIpc};
use crate::realtime::{self, RtReport};
use mcm_shared::config::{BusBackend, RobotConfig};
use mcm_shared::sample::{CommandSample, STATE_NOT_REALTIME};
use mcm_shared::service::ServiceNames;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

/// What the real-time process runs.
#[derive(Debug, Clone)]
pub struct RunOptions {
    pub config: RobotConfig,
    pub names: ServiceNames,
    /// Run even when memory locking, SCHED_FIFO or pinning is not possible.
    pub allow_non_realtime: bool,
    /// Write every bus frame in candump format to this file (overrides `bus.candump_log`).
    pub candump: Option<std::path::PathBuf>,
}

/// Why the real-time process could not run.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error("{0}")]
    MasterSetup(#[from] crate::canopen::MasterSetupError),
    #[error("{0}")]
    Ipc(#[from] IpcSetupError),
    #[error(
        "{report}; refusing to run without real-time scheduling (pass --allow-non-realtime to run anyway, e.g. in simulation)"
    )]
    NotRealtime { report: RtReport },
    #[error("cannot open the CAN bus: {0}")]
    Bus(String),
    #[error("cannot open the candump log {path}: {reason}")]
    Candump { path: String, reason: String },
    #[error("the real-time thread panicked")]
    Panicked,
    #[error("cannot start the flight recorder: {0}")]
    FlightRecorder(String),
}

/// What happened during the run.
#[derive(Debug, Clone)]
pub struct RunSummary {
    pub realtime: RtReport,
    pub cycles: u64,
    pub overruns: u64,
    pub latency_p99_ns: u64,
    pub latency_max_ns: u64,
}

/// Run until stopped. Blocks the calling thread; the cycle runs on its own thread.
pub fn run(
    opts: RunOptions,
    on_started: impl FnOnce(&RtReport) + Send + 'static,
) -> Result<RunSummary, RunError> {
    let candump = opts
        .candump
        .clone()
        .or_else(|| opts.config.bus.candump_log.clone().map(Into::into));
    let state = sim_state_path(opts.names.instance());
    let save_to = state.clone();
    match (opts.config.bus.backend, candump) {
        (BusBackend::Sim, None) => spawn(
            opts,
            on_started,
            move |cfg| Ok(sim_bus(cfg, &state)),
            move |bus: &mut crate::sim::SimBus| save_sim(bus, &save_to),
        ),
        (BusBackend::Sim, Some(path)) => spawn(
            opts,
            on_started,
            move |cfg| logging(sim_bus(cfg, &state), "sim0", &path),
            move |bus: &mut crate::bus::candump::LoggingBus<crate::sim::SimBus>| {
                save_sim(bus.inner(), &save_to)
            },
        ),
        (BusBackend::Socketcan, None) => spawn(opts, on_started, socketcan, |_| {}),
        (BusBackend::Socketcan, Some(path)) => spawn(
            opts,
            on_started,
            move |cfg| {
                let bus = socketcan(cfg)?;
                logging(bus, &cfg.bus.interface.clone(), &path)
            },
            |_| {},
        ),
    }
}

/// Where the simulated robot waits while `mcm-rt` of `instance` restarts: real drives keep
/// their power (encoder counts, stored calibration) when only the MCM restarts, so the
/// simulation is saved here when the loop stops and resumed from here at the next start.
pub fn sim_state_path(instance: &str) -> PathBuf {
    std::env::temp_dir().join(format!("mcm-sim-{instance}.state"))
}

/// The simulated robot: resumed from `state` (which is then deleted) if an earlier run of the
/// same instance saved it, powered up fresh otherwise (also when the file is unreadable).
fn sim_bus(cfg: &RobotConfig, state: &Path) -> crate::sim::SimBus {
    let resumed = crate::sim::SimBus::resume(cfg, state);
    if !matches!(resumed, Ok(None)) {
        let _ = std::fs::remove_file(state);
    }
    match resumed {
        Ok(Some(bus)) => bus,
        Ok(None) => crate::sim::SimBus::new(cfg),
        Err(e) => {
            eprintln!("mcm-rt: WARNING: {e}; the simulated drives power up fresh");
            crate::sim::SimBus::new(cfg)
        }
    }
}

fn save_sim(bus: &crate::sim::SimBus, state: &Path) {
    if let Err(e) = bus.save(state) {
        eprintln!(
            "mcm-rt: WARNING: cannot save the simulation to {}: {e}; the next start powers the drives up fresh",
            state.display()
        );
    }
}

fn socketcan(cfg: &RobotConfig) -> Result<crate::bus::socketcan::SocketCanBus, RunError> {
    crate::bus::socketcan::SocketCanBus::open(&cfg.bus.interface)
        .map_err(|e| RunError::Bus(e.to_string()))
}

fn logging<B: Bus>(
    bus: B,
    iface: &str,
    path: &std::path::Path,
) -> Result<crate::bus::candump::LoggingBus<B>, RunError> {
    crate::bus::candump::LoggingBus::new(
        bus,
        path,
        iface,
        crate::bus::candump::LogOptions::default(),
    )
    .map_err(|e| RunError::Candump {
        path: path.display().to_string(),
        reason: e.to_string(),
    })
}

/// Run the cycle over the bus `make_bus` opens; `finish` gets the bus after the loop stopped
/// (outside the cycle).
fn spawn<B: Bus + 'static>(
    opts: RunOptions,
    on_started: impl FnOnce(&RtReport) + Send + 'static,
    make_bus: impl FnOnce(&RobotConfig) -> Result<B, RunError> + Send + 'static,
    finish: impl FnOnce(&mut B) + Send + 'static,
) -> Result<RunSummary, RunError> {
    let handle = std::thread::Builder::new()
        .name("mcm-rt-cycle".into())
        .spawn(move || -> Result<RunSummary, RunError> {
            let cfg = &opts.config;
            let report = realtime::setup_current_thread(cfg.cycle.priority, cfg.cycle.cpu);
            // Open the bus first: a missing CAN interface is the more useful message.
            let bus = make_bus(cfg)?;
            if !report.is_realtime() && !opts.allow_non_realtime {
                return Err(RunError::NotRealtime { report });
            }
            let mut cycle = Cycle::new(cfg, bus)?;
            let mut ipc = RtIpc::create(&opts.names)?;
            let records =
                (cfg.safety.flight_recorder_seconds * f64::from(cfg.cycle.rate_hz)).ceil() as usize;
            let (recorder, writer) = FlightRecorder::start(
                records,
                &cfg.safety.flight_recorder_dir,
                opts.names.instance(),
            )
            .map_err(|e| RunError::FlightRecorder(e.to_string()))?;
            on_started(&report);
            let summary = cycle_loop(cfg, &mut cycle, &mut ipc, recorder, report);
            finish(cycle.bus_mut());
            writer.stop();
            Ok(summary)
        })
        .expect("spawn the real-time thread");
    handle.join().map_err(|_| RunError::Panicked)?
}

fn cycle_loop<B: Bus>(
    cfg: &RobotConfig,
    cycle: &mut Cycle<B>,
    ipc: &mut RtIpc,
    mut recorder: FlightRecorder,
    report: RtReport,
) -> RunSummary {
    let period = cfg.cycle_period_ns();
    let mut latency = Histogram::new();
    let mut work_max = 0u64;
    let mut overruns = 0u64;
    let mut commands = [CommandSample::default(); COMMANDS_PER_CYCLE];
    let mut k: u64 = 0;
    let mut error_seq = 0u64;
    let mut next = clock::now_ns() + period;
    let not_rt = if report.is_realtime() {
        0
    } else {
        STATE_NOT_REALTIME
    };
    let stop = crate::signals::stop_flag();
    while !stop.load(Ordering::Relaxed) {
        clock::sleep_until_ns(next);
        let wake = clock::now_ns();
        latency.record(wake.saturating_sub(next));
        let n = ipc.drain(&mut commands).unwrap_or(0);
        cycle.run(k * period, &commands[..n]);
        let s = cycle.controller_mut().state_mut();
        s.t_ns = wake;
        s.flags |= not_rt;
        s.timing.period_ns = period;
        s.timing.overruns = overruns;
        s.timing.latency_p50_ns = latency.percentile(0.5);
        s.timing.latency_p99_ns = latency.percentile(0.99);
        s.timing.latency_max_ns = latency.max();
        s.timing.work_max_ns = work_max;
        let new_error = s.last_error.seq != error_seq;
        if new_error {
            error_seq = s.last_error.seq;
            s.last_error.unix_ns = clock::realtime_ns();
        }
        let last_command = if n > 0 { commands[n - 1].kind } else { 0 };
        recorder.record(&Record::of(s, last_command));
        if new_error {
            recorder.trigger(&s.last_error);
        }
        ipc.publish(cycle.controller().state());
        k += 1;
        let end = clock::now_ns();
        work_max = work_max.max(end - wake);
        next += period;
        if end > next {
            // Missed one or more deadlines: count them and start again from now.
            overruns += (end - next) / period + 1;
            next = end + period - (end - next) % period;
        }
    }
    RunSummary {
        realtime: report,
        cycles: k,
        overruns,
        latency_p99_ns: latency.percentile(0.99),
        latency_max_ns: latency.max(),
    }
}
