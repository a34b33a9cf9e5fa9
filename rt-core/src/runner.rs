//! The real-time loop: the edges around [`crate::cycle::Cycle`].
//!
//! Set-up (bus, real-time thread, IPC) runs once; then every period, on absolute deadlines:
//! wake, record the wake-up latency, drain commands, run the cycle with its timing
//! ([`run_cycle`], which composes the state sample), publish the state. Stops when SIGINT or
//! SIGTERM arrives (checked once per cycle). [`run_cycle`] runs inside the cycle; the rest is
//! set-up and teardown.
//!
//! The runner builds the bus and so knows its type: with the simulated bus it wires the
//! simulator's edge ([`crate::sim_edge`]) into the loop, and the simulated robot outlives a
//! restart of `mcm-rt` the way real drives that keep their power do
//! ([`mcm_sim::snapshot`]: resumed at start, saved when the loop stops).

use crate::clock;
use crate::cycle::{COMMANDS_PER_CYCLE, Cycle};
use crate::flight::{FlightRecorder, Record};
use crate::histogram::Histogram;
use crate::ipc::{IpcSetupError, RtIpc};
use crate::publish::{self, CycleClock};
use crate::realtime::{self, RtReport};
use crate::sim_edge::{SimAccess, SimEdge};
use mcm_bus::Bus;
use mcm_bus::candump::{LogOptions, LoggingBus};
use mcm_shared::config::{BusBackend, RobotConfig};
use mcm_shared::sample::CommandSample;
use mcm_shared::service::ServiceNames;
use mcm_sim::{SimBus, snapshot};
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
    let state = snapshot::state_path(opts.names.instance());
    let save_to = state.clone();
    match (opts.config.bus.backend, candump) {
        (BusBackend::Sim, None) => spawn(
            opts,
            on_started,
            move |cfg| Ok(snapshot::resume_or_power_up(cfg, &state)),
            Some(|bus: &mut SimBus| bus as _),
            move |bus: &mut SimBus| snapshot::save(bus, &save_to),
        ),
        (BusBackend::Sim, Some(path)) => spawn(
            opts,
            on_started,
            move |cfg| logging(snapshot::resume_or_power_up(cfg, &state), "sim0", &path),
            Some(|bus: &mut LoggingBus<SimBus>| bus.inner_mut() as _),
            move |bus: &mut LoggingBus<SimBus>| snapshot::save(bus.inner(), &save_to),
        ),
        (BusBackend::Socketcan, None) => spawn(opts, on_started, socketcan, None, |_| {}),
        (BusBackend::Socketcan, Some(path)) => spawn(
            opts,
            on_started,
            move |cfg| {
                let bus = socketcan(cfg)?;
                logging(bus, &cfg.bus.interface.clone(), &path)
            },
            None,
            |_| {},
        ),
    }
}

fn socketcan(cfg: &RobotConfig) -> Result<mcm_bus::socketcan::SocketCanBus, RunError> {
    mcm_bus::socketcan::SocketCanBus::open(&cfg.bus.interface)
        .map_err(|e| RunError::Bus(e.to_string()))
}

fn logging<B: Bus>(bus: B, iface: &str, path: &std::path::Path) -> Result<LoggingBus<B>, RunError> {
    LoggingBus::new(bus, path, iface, LogOptions::default()).map_err(|e| RunError::Candump {
        path: path.display().to_string(),
        reason: e.to_string(),
    })
}

/// Run the cycle over the bus `make_bus` opens, with the simulator's edge when `sim` reaches
/// the simulator inside that bus; `finish` gets the bus after the loop stopped (outside the
/// cycle).
fn spawn<B: Bus + 'static>(
    opts: RunOptions,
    on_started: impl FnOnce(&RtReport) + Send + 'static,
    make_bus: impl FnOnce(&RobotConfig) -> Result<B, RunError> + Send + 'static,
    sim: Option<SimAccess<B>>,
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
            let mut edge = sim.map(SimEdge::new);
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
            let summary = cycle_loop(cfg, &mut cycle, edge.as_mut(), &mut ipc, recorder, report);
            finish(cycle.bus_mut());
            writer.stop();
            Ok(summary)
        })
        .expect("spawn the real-time thread");
    handle.join().map_err(|_| RunError::Panicked)?
}

/// One cycle of `cycle` at controller time `now_ns` with `commands`, as the real-time loop
/// runs it: through the simulator's `edge` when there is one, then the state sample composed
/// from the controller's view, the simulation's truth and `clock` ([`publish::compose`]).
pub fn run_cycle<B: Bus>(
    cycle: &mut Cycle<B>,
    edge: Option<&mut SimEdge<B>>,
    now_ns: u64,
    clock: &CycleClock,
    commands: &[CommandSample],
) {
    let truth = match edge {
        Some(edge) => Some(edge.run(cycle, now_ns, commands)),
        None => {
            cycle.run(now_ns, commands);
            None
        }
    };
    let (view, state) = cycle.publish_parts();
    publish::compose(state, view, truth, clock);
}

fn cycle_loop<B: Bus>(
    cfg: &RobotConfig,
    cycle: &mut Cycle<B>,
    mut edge: Option<&mut SimEdge<B>>,
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
    let mut receive_errors = 0u64;
    let mut next = clock::now_ns() + period;
    let stop = crate::signals::stop_flag();
    while !stop.load(Ordering::Relaxed) {
        clock::sleep_until_ns(next);
        let wake = clock::now_ns();
        latency.record(wake.saturating_sub(next));
        let n = ipc.drain(&mut commands).unwrap_or_else(|_| {
            receive_errors += 1;
            0
        });
        let timing = CycleClock {
            t_ns: wake,
            unix_ns: clock::realtime_ns(),
            period_ns: period,
            overruns,
            latency_p50_ns: latency.percentile(0.5),
            latency_p99_ns: latency.percentile(0.99),
            latency_max_ns: latency.max(),
            work_max_ns: work_max,
            not_realtime: !report.is_realtime(),
            command_receive_errors: receive_errors,
        };
        run_cycle(
            cycle,
            edge.as_deref_mut(),
            k * period,
            &timing,
            &commands[..n],
        );
        let s = cycle.state();
        let new_error = s.last_error.seq != error_seq;
        if new_error {
            error_seq = s.last_error.seq;
        }
        let last_command = if n > 0 { commands[n - 1].kind } else { 0 };
        recorder.record(&Record::of(s, last_command));
        if new_error {
            recorder.trigger(&s.last_error);
        }
        ipc.publish(s);
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
