//! The virtual arm's process: the CAN socket, the control socket, the log, the loop.
//!
//! One thread runs the loop: wait for a frame until the next deadline (the pace's, or 1 ms so
//! that control requests are answered soon), hand it to the arm, answer the control requests,
//! and every `summary` period print the counters. SIGINT or SIGTERM ends it; the candump log is
//! completed and the last counters printed.

use crate::arm::{Counters, Event, VirtualArm};
use crate::control::{self, ControlError, Request};
use mcm_bus::Bus;
use mcm_bus::candump::{CandumpError, LogOptions, LoggingBus};
use mcm_bus::socketcan::{SocketCanBus, SocketCanError, monotonic_ns};
use mcm_shared::config::RobotConfig;
use mcm_shared::ready::VirtualArmReady;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Receiver;
use std::time::Duration;

/// How long the loop waits at most before it looks at the control requests.
const CONTROL_POLL_NS: u64 = 1_000_000;

/// What the virtual arm runs with.
#[derive(Debug, Clone)]
pub struct Options {
    /// The CAN interface (e.g. `vcan0`).
    pub interface: String,
    /// The robot: the same configuration as the MCM's (node ids, cycle period, drives, arm).
    pub config: RobotConfig,
    /// Where the control socket listens.
    pub control: SocketAddr,
    /// Write every frame seen and sent in candump format to this file.
    pub candump: Option<PathBuf>,
    /// Periods without SYNC before the arm runs on without one.
    pub grace: u64,
    /// How often the counters are printed (never when zero).
    pub summary: Duration,
    /// Run the loop's thread with `SCHED_FIFO` at this priority (1 to 99): on a bench where
    /// the arm shares its CPUs with the MCM and others, so that it answers a SYNC in time.
    pub fifo_priority: Option<u8>,
}

/// Why the virtual arm could not run.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(
        "cannot open CAN interface {interface}: this kernel has no SocketCAN support (os error \
         97, EAFNOSUPPORT); the virtual arm needs a kernel with the can, can-raw and vcan modules \
         (`modprobe vcan can-raw`), e.g. the test guest of docs/virtual-arm.md"
    )]
    NoCan { interface: String },
    #[error("{0}")]
    Can(SocketCanError),
    #[error("{0}")]
    Control(#[from] ControlError),
    #[error("{0}")]
    Candump(#[from] CandumpError),
    #[error("cannot install the SIGINT/SIGTERM handlers: {0}")]
    Signals(#[source] std::io::Error),
    #[error(
        "cannot run with SCHED_FIFO priority {priority}: {reason} (needs root or CAP_SYS_NICE; \
         allowed: 1 to 99, or no --fifo-priority)"
    )]
    Priority { priority: u8, reason: String },
}

/// Give the calling thread `SCHED_FIFO` at `priority`.
fn set_fifo(priority: u8) -> Result<(), RunError> {
    use thread_priority::{
        RealtimeThreadSchedulePolicy, ThreadPriority, ThreadPriorityValue, ThreadSchedulePolicy,
        set_thread_priority_and_policy, thread_native_id,
    };
    let fail = |reason: String| RunError::Priority { priority, reason };
    let value = ThreadPriorityValue::try_from(priority).map_err(|e| fail(e.to_string()))?;
    set_thread_priority_and_policy(
        thread_native_id(),
        ThreadPriority::Crossplatform(value),
        ThreadSchedulePolicy::Realtime(RealtimeThreadSchedulePolicy::Fifo),
    )
    .map_err(|e| fail(format!("{e:?}")))
}

/// Run until SIGINT or SIGTERM; the counters at the end.
pub fn run(opts: &Options) -> Result<Counters, RunError> {
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(sig, Arc::clone(&stop)).map_err(RunError::Signals)?;
    }
    let socket = SocketCanBus::open(&opts.interface).map_err(|e| match e {
        SocketCanError::NoKernelSupport { interface } => RunError::NoCan { interface },
        e => RunError::Can(e),
    })?;
    let (control, requests) = control::serve(opts.control, opts.config.clone())?;
    // After the control thread started: only this thread runs real-time.
    if let Some(p) = opts.fifo_priority {
        set_fifo(p)?;
    }
    let ready = VirtualArmReady {
        interface: opts.interface.clone(),
        control,
    };
    match &opts.candump {
        Some(path) => {
            let options = LogOptions {
                capacity: 1 << 16,
                ..LogOptions::default()
            };
            let wire = LoggingBus::new(socket, path, &opts.interface, options)?;
            let arm = VirtualArm::new(&opts.config, wire, opts.grace, monotonic_ns());
            let (counters, wire) = drive(arm, &ready, &requests, &stop, opts.summary);
            let log = wire.finish()?;
            eprintln!(
                "mcm-virtual-arm: candump log {}: {} frames written, {} dropped",
                path.display(),
                log.written,
                log.dropped
            );
            Ok(counters)
        }
        None => {
            let arm = VirtualArm::new(&opts.config, socket, opts.grace, monotonic_ns());
            Ok(drive(arm, &ready, &requests, &stop, opts.summary).0)
        }
    }
}

fn drive<W: Bus>(
    mut arm: VirtualArm<W>,
    ready: &VirtualArmReady,
    requests: &Receiver<Request>,
    stop: &AtomicBool,
    summary: Duration,
) -> (Counters, W) {
    let summary_ns = summary.as_nanos() as u64;
    let started = monotonic_ns();
    let mut next_summary = started.saturating_add(summary_ns);
    let mut log = |e: Event| match e {
        Event::FirstSync => eprintln!("mcm-virtual-arm: first SYNC from the master"),
        Event::SyncLost { periods } => {
            eprintln!("mcm-virtual-arm: no SYNC for {periods} periods; the arm runs on without it")
        }
        Event::SyncBack { periods } => {
            eprintln!("mcm-virtual-arm: SYNC back after {periods} periods without it")
        }
        Event::WireError(e) => eprintln!("mcm-virtual-arm: {e}"),
    };
    arm.poll(started, &mut log);
    println!("{ready}");
    while !stop.load(Ordering::Relaxed) {
        let now = monotonic_ns();
        let deadline = arm.deadline_ns().min(now + CONTROL_POLL_NS);
        arm.wait_and_poll(deadline, monotonic_ns, &mut log);
        while let Ok(r) = requests.try_recv() {
            let answer = arm.apply(&r.command, &mut log);
            if let Ok(truth) = answer
                && r.command != mcm_sim::SimCommand::default()
            {
                let shown = mcm_shared::protocol::Command::Sim(r.command).to_json();
                let position = mcm_shared::units::rad_to_deg6(&truth.position);
                eprintln!("mcm-virtual-arm: applied {shown}; true position [deg] {position:.3?}");
            }
            let _ = r.answer.send(answer);
        }
        if summary_ns > 0 && monotonic_ns() >= next_summary {
            next_summary = next_summary.saturating_add(summary_ns);
            print_counters(&arm);
        }
    }
    print_counters(&arm);
    let counters = arm.counters();
    (counters, arm.into_wire())
}

fn print_counters<W: Bus>(arm: &VirtualArm<W>) {
    let (c, d) = (arm.counters(), arm.drive_counters());
    eprintln!(
        "mcm-virtual-arm: arm time {:.3} s; frames in {} out {}; SYNC {}; periods without SYNC {}; \
         frames lost on send {}; wire errors {}; fault injections {}; as the drives saw it: \
         setpoints missing at SYNC {}, SDO aborts {}, heartbeat timeouts {}, SYNC losses {}, \
         connection aborts {}",
        arm.sim().now_ns() as f64 * 1e-9,
        c.frames_in,
        c.frames_out,
        c.syncs,
        c.periods_without_sync,
        c.tx_dropped,
        c.wire_errors,
        c.faults,
        d.rpdo1_missing,
        d.sdo_aborts,
        d.heartbeat_timeouts,
        d.sync_losses,
        d.connection_aborts
    );
}
