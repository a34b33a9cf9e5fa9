//! The real-time loop: the edges around [`crate::cycle::Cycle`].
//!
//! Set-up runs once on the thread that becomes the cycle thread: it first keeps itself at
//! normal policy off the cycle's CPU ([`realtime::setup_helper_thread`]), opens the bus and
//! starts the flight recorder (their writer threads inherit that placement), and only then
//! turns real-time ([`realtime::setup_current_thread`]) and sets up IPC. Then every period, on
//! absolute deadlines, the loop sleeps until the deadline and runs one cycle of the runner's
//! edge ([`crate::edge::Edge::cycle`]: take in commands, run the cycle ([`run_cycle`]), add
//! timing, record, publish the state), ends it ([`crate::edge::Edge::end`]) and then wakes the
//! state event's listeners ([`crate::edge::Edge::signal_state`], outside the timed work). The
//! first SIGINT or SIGTERM (checked once per cycle) starts the controlled stop
//! ([`crate::process_stop`]): the loop runs on until the arm is at standstill and the drives are
//! disabled, or a second signal ends it at once. [`run_cycle`] runs inside the cycle; the rest
//! is set-up and teardown.
//!
//! The runner builds the bus and so knows its type: with the simulated bus it wires the
//! simulator's edge ([`crate::sim_edge`]) into the loop, and the simulated robot outlives a
//! restart of `mcm-rt` the way real drives that keep their power do (`mcm_sim::snapshot`:
//! resumed at start, saved when the loop stops). Built without the `sim` feature, it refuses
//! `bus.backend = "sim"` ([`RunError::SimNotBuilt`]).

use crate::clock;
use crate::cycle::Cycle;
use crate::edge::{Edge, Figures};
use crate::flight::FlightRecorder;
use crate::ipc::{IpcSetupError, RtIpc};
use crate::line_planner::{LinePlanner, joint_limits};
use crate::params::JointParams;
use crate::process_stop::{StopOutcome, StopSequence};
use crate::publish::{self, CycleClock};
use crate::realtime::{self, RtReport};
use crate::sim_edge::SimEdge;
use mcm_bus::Bus;
use mcm_bus::candump::{LogOptions, LoggingBus};
use mcm_shared::config::{BusBackend, RobotConfig};
use mcm_shared::sample::CommandSample;
use mcm_shared::service::ServiceNames;
#[cfg(feature = "sim")]
use mcm_sim::{SimBus, snapshot};
use std::sync::atomic::{AtomicU64, Ordering};

/// Cycles run by the real-time loops of this process (`mcm-rt` runs one): the heartbeat that
/// [`crate::systemd_notify`] reads, outside the cycle, before it pings systemd's watchdog. The
/// loop adds one per cycle (a relaxed atomic add: no lock, no allocation).
static CYCLES_RUN: AtomicU64 = AtomicU64::new(0);

/// How many cycles the real-time loops of this process ran so far.
pub fn cycles_run() -> u64 {
    CYCLES_RUN.load(Ordering::Relaxed)
}

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
    Setup(#[from] crate::cycle::CycleSetupError),
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
    #[error("cannot start the thread that plans move_linear's lines: {0}")]
    LinePlanner(String),
    #[error("cannot place the helper threads away from the cycle's CPU: {0}")]
    Placement(String),
    #[error(
        "bus.backend = \"sim\" asks for the simulated robot, but this mcm-rt was built without \
         the `sim` feature of mcm-rt-core (build it with `--features sim`, one of its default \
         features), or set bus.backend = \"socketcan\" for real drives"
    )]
    SimNotBuilt,
}

/// What happened during the run.
#[derive(Debug, Clone)]
pub struct RunSummary {
    pub realtime: RtReport,
    /// The loop's figures when it stopped.
    pub figures: Figures,
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
    match (opts.config.bus.backend, candump) {
        (BusBackend::Sim, candump) => {
            require_simulator(cfg!(feature = "sim"))?;
            simulated(opts, on_started, candump)
        }
        (BusBackend::Socketcan, None) => spawn(opts, on_started, socketcan, None, finish_drives),
        (BusBackend::Socketcan, Some(path)) => spawn(
            opts,
            on_started,
            move |cfg| {
                let bus = socketcan(cfg)?;
                logging(bus, &cfg.bus.interface.clone(), &path)
            },
            None,
            finish_drives,
        ),
    }
}

/// `bus.backend = "sim"` needs the simulator built in (`built`: `cfg!(feature = "sim")`);
/// without it the configuration is refused with [`RunError::SimNotBuilt`]. A function of the
/// flag so that the refusal is compiled and tested in every build, not only in the one
/// without the feature.
fn require_simulator(built: bool) -> Result<(), RunError> {
    if built {
        Ok(())
    } else {
        Err(RunError::SimNotBuilt)
    }
}

/// Run the simulated robot (over a candump log when `candump` names one), resumed from the
/// state the last run of this instance saved, and saved again when the loop stops.
#[cfg(feature = "sim")]
fn simulated(
    opts: RunOptions,
    on_started: impl FnOnce(&RtReport) + Send + 'static,
    candump: Option<std::path::PathBuf>,
) -> Result<RunSummary, RunError> {
    match candump {
        None => {
            let state = snapshot::state_path(opts.names.instance());
            let save_to = state.clone();
            spawn(
                opts,
                on_started,
                move |cfg| Ok(snapshot::resume_or_power_up(cfg, &state)),
                Some(SimEdge::new(|bus: &mut SimBus| bus as _)),
                move |bus: &mut SimBus| snapshot::save(bus, &save_to),
            )
        }
        Some(path) => {
            let state = snapshot::state_path(opts.names.instance());
            let save_to = state.clone();
            spawn(
                opts,
                on_started,
                move |cfg| logging(snapshot::resume_or_power_up(cfg, &state), "sim0", &path),
                Some(SimEdge::new(|bus: &mut LoggingBus<SimBus>| {
                    bus.inner_mut() as _
                })),
                move |bus: &mut LoggingBus<SimBus>| snapshot::save(bus.inner(), &save_to),
            )
        }
    }
}

/// Built without the simulator there is none to run; [`require_simulator`] refuses the
/// configuration before this is reached, and this refuses it the same way.
#[cfg(not(feature = "sim"))]
fn simulated(
    _opts: RunOptions,
    _on_started: impl FnOnce(&RtReport) + Send + 'static,
    _candump: Option<std::path::PathBuf>,
) -> Result<RunSummary, RunError> {
    Err(RunError::SimNotBuilt)
}

/// The last frames to real drives, after the loop stopped (the controlled stop left them
/// disabled): NMT "enter pre-operational" to every node, so that no drive acts on a process
/// data object any more; then nothing more is sent.
fn finish_drives<B: Bus>(bus: &mut B) {
    let frame =
        crate::canopen::nmt::nmt_frame(crate::canopen::nmt::NmtCommand::EnterPreOperational, 0);
    if let Err(e) = bus.send(&frame) {
        eprintln!("mcm-rt: the final NMT frame (enter pre-operational) was not sent: {e}");
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

/// Run the cycle over the bus `make_bus` opens, with the simulator's edge `sim` when that bus
/// is (or wraps) the simulator; `finish` gets the bus after the loop stopped (outside the
/// cycle).
fn spawn<B: Bus + 'static>(
    opts: RunOptions,
    on_started: impl FnOnce(&RtReport) + Send + 'static,
    make_bus: impl FnOnce(&RobotConfig) -> Result<B, RunError> + Send + 'static,
    sim: Option<SimEdge<B>>,
    finish: impl FnOnce(&mut B) + Send + 'static,
) -> Result<RunSummary, RunError> {
    // Signals from here on stop this run, also those that come while it starts up (opening the
    // bus, the services): the loop's first cycle then begins the controlled stop.
    let signals_before = crate::signals::count();
    let handle = std::thread::Builder::new()
        .name("mcm-rt-cycle".into())
        .spawn(move || -> Result<RunSummary, RunError> {
            let cfg = &opts.config;
            // Helper threads start from here before it turns real-time, and inherit this.
            realtime::setup_helper_thread(cfg.cycle.cpu).map_err(RunError::Placement)?;
            // Open the bus first: a missing CAN interface is the more useful message.
            let bus = make_bus(cfg)?;
            let records =
                (cfg.safety.flight_recorder_seconds * f64::from(cfg.cycle.rate_hz)).ceil() as usize;
            let (recorder, writer) = FlightRecorder::start(
                records,
                &cfg.safety.flight_recorder_dir,
                opts.names.instance(),
            )
            .map_err(|e| RunError::FlightRecorder(e.to_string()))?;
            // The lines' planner thread, started here so that it stays at normal policy away
            // from the cycle's CPU.
            let planner = LinePlanner::thread(joint_limits(&JointParams::from_config(cfg)))
                .map_err(|e| RunError::LinePlanner(e.to_string()))?;
            let report = realtime::setup_current_thread(cfg.cycle.priority, cfg.cycle.cpu);
            if !report.is_realtime() && !opts.allow_non_realtime {
                return Err(RunError::NotRealtime { report });
            }
            let mut cycle = Box::new(Cycle::new(cfg, bus)?);
            cycle.plan_lines_with(planner);
            let ipc = RtIpc::create(&opts.names)?;
            let mut edge = Edge::new(
                cycle,
                sim,
                ipc,
                recorder,
                cfg.cycle_period_ns(),
                cfg.work_budget_ns(),
                report.is_realtime(),
            );
            on_started(&report);
            let (figures, stop) = cycle_loop(&mut edge, signals_before);
            eprintln!("mcm-rt: {stop}");
            finish(edge.cycle_mut().bus_mut());
            writer.stop();
            Ok(RunSummary {
                realtime: report,
                figures,
            })
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
    let (view, state, cartesian) = cycle.publish_parts();
    publish::compose(state, view, truth, clock, cartesian);
}

/// Run the edge's cycles on absolute deadlines until the controlled stop that the first SIGINT
/// or SIGTERM starts has finished, or a second one ends it ([`StopSequence`], polled once per
/// cycle): sleep until the deadline, read the clock, run [`Edge::cycle`], read the clock,
/// [`Edge::end`] gives the next deadline, then [`Edge::signal_state`] wakes the listeners.
/// Signals counted beyond `signals_before` (the count when the run began) stop it.
fn cycle_loop<B: Bus>(edge: &mut Edge<B>, signals_before: usize) -> (Figures, StopOutcome) {
    let mut stop = StopSequence::new(signals_before);
    let mut next = edge.start(clock::now_ns());
    let outcome = loop {
        clock::sleep_until_ns(next);
        edge.cycle(clock::now_ns());
        next = edge.end(clock::now_ns());
        edge.signal_state();
        CYCLES_RUN.fetch_add(1, Ordering::Relaxed);
        let controller = edge.cycle_mut().parts_mut().0;
        if let Some(outcome) = stop.poll(controller, crate::signals::count(), clock::now_ns()) {
            break outcome;
        }
    };
    (edge.figures(), outcome)
}

#[cfg(test)]
mod tests;
