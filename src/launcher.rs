//! The launcher: starts `mcm rt` and `mcm gateway` as two processes, reads their ready lines
//! and says where to connect (the lines are typed: `mcm_shared::ready`), restarts the gateway
//! whenever it dies (it holds no state) with a capped exponential back-off (the one the
//! systemd unit has too: `mcm_shared::restart::GATEWAY_RESTART`), stops everything if the real-time core dies (that is never silently papered
//! over), and on Ctrl-C or SIGTERM stops `mcm-rt` first (its controlled stop: standstill, then
//! the drives disabled; the gateway meanwhile tells its clients) and then the gateway. A second
//! Ctrl-C is passed on (it ends the controlled stop at once).
//!
//! The children die with the launcher: each gets `PR_SET_PDEATHSIG` = SIGTERM, so a launcher
//! killed with SIGKILL still makes `mcm-rt` do its controlled stop and the gateway close.

use clap::Parser;
use mcm_gateway::cli::ListenArgs;
use mcm_rt_core::cli::LogArgs;
use mcm_rt_core::signals;
use mcm_shared::cli::CommonArgs;
use mcm_shared::config::BusBackend;
use mcm_shared::ready::{GatewayReady, McmReady, ReadyLine, Ros2Ready, RtReady};
use mcm_shared::restart::GATEWAY_RESTART;
use mcm_shared::service::ServiceNames;
use std::ffi::OsString;
use std::io::{BufRead, BufReader};
use std::os::unix::process::CommandExt;
use std::process::{Child, ChildStdout, Command, ExitCode, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Run the Motion Control Module: the real-time core (simulated P-Rob2 unless the
/// configuration selects `socketcan`) and the JSON/telnet gateway.
#[derive(Parser, Debug)]
#[command(
    name = "mcm",
    version,
    about,
    after_help = "Subcommands: `mcm rt --help`, `mcm gateway --help` and `mcm ros2 --help` run one process each (so do the links `mcm-rt`, `mcm-gateway` and `mcm-ros2` to this program); `mcm bus-interface --config FILE` prints the CAN interface a configuration's core opens.",
    // An option given twice takes the last value: a harness passes its defaults first (e.g.
    // `mcm_client::launch` passes `--http-port 0`) and a caller's extra arguments override them.
    args_override_self = true
)]
struct Cli {
    #[command(flatten)]
    common: CommonArgs,
    #[command(flatten)]
    listen: ListenArgs,
    #[command(flatten)]
    log: LogArgs,
    /// Require real-time scheduling even in simulation (by default the simulated robot runs
    /// without it when the system does not allow it).
    #[arg(long)]
    require_realtime: bool,
    /// Also run the ROS 2 node (`mcm ros2`, docs/ros2.md): joint states, the robot
    /// description, FollowJointTrajectory, services and diagnostics over DDS.
    #[arg(long)]
    ros2: bool,
    /// An argument for the ROS 2 node (repeatable), e.g. `--ros2-arg=--namespace=/left`; see
    /// `mcm ros2 --help`.
    #[arg(long = "ros2-arg", allow_hyphen_values = true, requires = "ros2")]
    ros2_args: Vec<OsString>,
}

/// How long a child may take to say it is ready.
const READY_TIMEOUT: Duration = Duration::from_secs(20);
/// How long the gateway may take to stop after SIGTERM before it is killed.
const STOP_TIMEOUT: Duration = Duration::from_secs(5);
/// How long `mcm-rt` may take to stop after SIGTERM (its controlled stop is bounded by a few
/// seconds, see `docs/safety.md`) before it is killed.
const RT_STOP_TIMEOUT: Duration = Duration::from_secs(15);

struct Proc {
    name: &'static str,
    child: Child,
}

impl Proc {
    fn spawn(
        name: &'static str,
        args: &[OsString],
    ) -> Result<(Proc, mpsc::Receiver<String>), String> {
        let exe =
            std::env::current_exe().map_err(|e| format!("cannot find the mcm executable: {e}"))?;
        let mut cmd = Command::new(exe);
        cmd.arg0(name)
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::piped());
        // Children ignore Ctrl-C from the terminal: the launcher stops them in order. They
        // die with the launcher: SIGTERM when it goes (the parent-death signal is tied to the
        // thread that forks; the launcher spawns from its main thread, which lives as long as
        // it does). If the launcher died before prctl, the child's parent is already someone
        // else: then it does not run at all.
        let launcher = std::process::id() as libc::pid_t;
        // SAFETY: setpgid, prctl and getppid are async-signal-safe and only affect the child
        // being spawned; nothing is allocated between fork and exec.
        unsafe {
            cmd.pre_exec(move || {
                libc::setpgid(0, 0);
                if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGTERM as libc::c_ulong) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                if libc::getppid() != launcher {
                    // No allocation between fork and exec: a plain errno.
                    return Err(std::io::Error::from_raw_os_error(libc::ESRCH));
                }
                Ok(())
            });
        }
        let mut child = cmd
            .spawn()
            .map_err(|e| format!("cannot start {name}: {e}"))?;
        let stdout = child.stdout.take().expect("piped stdout");
        Ok((Proc { name, child }, forward_lines(name, stdout)))
    }

    fn pid(&self) -> u32 {
        self.child.id()
    }

    /// SIGTERM, wait at most `timeout`, then SIGKILL. Each further stop signal the launcher
    /// receives meanwhile is passed on (for `mcm-rt`: end the controlled stop at once).
    fn stop(&mut self, timeout: Duration) {
        if let Ok(Some(_)) = self.child.try_wait() {
            return;
        }
        self.signal(libc::SIGTERM);
        let mut signals = signals::count();
        let deadline = Instant::now() + timeout;
        while Instant::now() < deadline {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            let now = signals::count();
            if now > signals {
                signals = now;
                eprintln!("mcm: stop signal again: passing it on to {}", self.name);
                self.signal(libc::SIGTERM);
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        eprintln!(
            "mcm: {} did not stop within {timeout:?}; killing it",
            self.name
        );
        let _ = self.child.kill();
        let _ = self.child.wait();
    }

    fn signal(&self, sig: libc::c_int) {
        // SAFETY: kill with the pid of our own child, not yet reaped (try_wait said so).
        unsafe { libc::kill(self.child.id() as i32, sig) };
    }
}

/// Copy a child's stdout to ours, and hand its lines to the launcher until it stops listening.
fn forward_lines(name: &'static str, stdout: ChildStdout) -> mpsc::Receiver<String> {
    let (tx, rx) = mpsc::channel();
    std::thread::Builder::new()
        .name(format!("{name}-stdout"))
        .spawn(move || {
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if tx.send(line.clone()).is_err() {
                    println!("{line}");
                }
            }
        })
        .expect("spawn a stdout thread");
    rx
}

/// Wait for the child's ready line `T`; fail if the child exits first, or if its ready line
/// cannot be read.
fn wait_ready<T: ReadyLine>(p: &mut Proc, lines: &mpsc::Receiver<String>) -> Result<T, String> {
    let deadline = Instant::now() + READY_TIMEOUT;
    loop {
        if signals::stop_requested() {
            return Err("stopped before start-up finished".into());
        }
        match lines.recv_timeout(Duration::from_millis(50)) {
            Ok(line) if line.starts_with(T::PREFIX) => {
                return line.parse().map_err(|e| {
                    format!(
                        "{} said it is ready, but {e}; is it from the same MCM version as this launcher?",
                        p.name
                    )
                });
            }
            Ok(line) => println!("{line}"),
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                let status = p.child.wait().map(|s| s.to_string()).unwrap_or_default();
                return Err(format!(
                    "{} exited during start-up ({status}); see its message above",
                    p.name
                ));
            }
        }
        if let Ok(Some(status)) = p.child.try_wait() {
            return Err(format!(
                "{} exited during start-up ({status}); see its message above",
                p.name
            ));
        }
        if Instant::now() > deadline {
            return Err(format!(
                "{} did not become ready within {READY_TIMEOUT:?}",
                p.name
            ));
        }
    }
}

pub fn main(args: impl IntoIterator<Item = OsString>) -> ExitCode {
    let cli = Cli::parse_from(args);
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("mcm: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<(), String> {
    // Validate what the children will read, so errors show before anything starts.
    let cfg = cli.common.load_config().map_err(|e| e.to_string())?;
    let mut zmq = cfg.gateway.zmq.clone();
    cli.listen.apply_zmq(&mut zmq).map_err(|e| e.to_string())?;
    ServiceNames::new(&cli.common.instance).map_err(|e| e.to_string())?;
    signals::install().map_err(|e| format!("cannot install the SIGINT/SIGTERM handlers: {e}"))?;

    let common = cli.common.to_args();
    let mut rt_args = common.clone();
    if !cli.require_realtime && cfg.bus.backend == BusBackend::Sim {
        rt_args.push("--allow-non-realtime".into());
    }
    rt_args.extend(cli.log.to_args());
    let mut gw_args = common;
    gw_args.extend(cli.listen.to_args());

    let (mut rt, rt_lines) = Proc::spawn("mcm-rt", &prepend("rt", &rt_args))?;
    let rt_ready = wait_ready::<RtReady>(&mut rt, &rt_lines).and_then(|r| {
        if r.instance == cli.common.instance {
            Ok(r)
        } else {
            Err(format!(
                "mcm-rt says it serves instance `{}`, not `{}`",
                r.instance, cli.common.instance
            ))
        }
    });
    if let Err(e) = rt_ready {
        rt.stop(RT_STOP_TIMEOUT);
        return Err(e);
    }
    drop(rt_lines);

    let mut ros2 = match cli.ros2 {
        false => None,
        true => {
            let mut args = cli.common.to_args();
            args.extend(cli.ros2_args.iter().cloned());
            match Ros2::start(args) {
                Ok(r) => Some(r),
                Err(e) => {
                    rt.stop(RT_STOP_TIMEOUT);
                    return Err(e);
                }
            }
        }
    };

    let robot = match cfg.bus.backend {
        BusBackend::Sim => format!("simulated {}", cfg.robot.name),
        BusBackend::Socketcan => format!("{} on {}", cfg.robot.name, cfg.bus.interface),
    };
    let mut backoff = Backoff::new();
    let mut first = true;
    let result = loop {
        let gw = Proc::spawn("mcm-gateway", &prepend("gateway", &gw_args)).and_then(
            |(mut gw, gw_lines)| match wait_ready::<GatewayReady>(&mut gw, &gw_lines) {
                Ok(line) => Ok((gw, line)),
                Err(e) => {
                    gw.stop(STOP_TIMEOUT);
                    Err(e)
                }
            },
        );
        let (mut gw, ready) = match gw {
            Ok(x) => x,
            // The first start fails loudly (a port in use, a bad address): nothing runs yet
            // that a restart would keep alive.
            Err(e) if first || signals::stop_requested() => break Err(e),
            Err(e) => {
                let wait = backoff.next(Duration::ZERO);
                eprintln!(
                    "mcm: mcm-gateway did not start ({e}); mcm-rt keeps running; restarting the gateway in {wait:?}"
                );
                match wait_watching(&mut rt, wait) {
                    Ok(true) => continue,
                    Ok(false) => break Ok(()),
                    Err(e) => break Err(e),
                }
            }
        };
        first = false;
        let started = Instant::now();
        let line = McmReady {
            robot: robot.clone(),
            instance: cli.common.instance.clone(),
            gateway: ready,
            rt_pid: rt.pid(),
            gateway_pid: gw.pid(),
        };
        println!("{line}");
        // Supervise.
        let outcome = loop {
            if signals::stop_requested() {
                break Ok(false);
            }
            if let Ok(Some(status)) = rt.child.try_wait() {
                break Err(format!(
                    "mcm-rt exited unexpectedly ({status}); stopping the gateway and the MCM (a dead real-time core is not restarted silently; see its message above)"
                ));
            }
            if let Some(r) = ros2.as_mut() {
                r.supervise();
            }
            if let Ok(Some(status)) = gw.child.try_wait() {
                let wait = backoff.next(started.elapsed());
                eprintln!(
                    "mcm: mcm-gateway exited unexpectedly ({status}) after {:.1} s; mcm-rt keeps running; restarting the gateway in {wait:?} (back-off {GATEWAY_RESTART})",
                    started.elapsed().as_secs_f64()
                );
                break wait_watching(&mut rt, wait);
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        match outcome {
            Ok(true) => {}
            Ok(false) => {
                // mcm-rt first: its controlled stop shows in the state, and the gateway and the
                // ROS 2 node tell their clients (a running goal ends with why); then they.
                rt.stop(RT_STOP_TIMEOUT);
                if let Some(mut r) = ros2.take() {
                    r.proc.stop(STOP_TIMEOUT);
                }
                gw.stop(STOP_TIMEOUT);
                break Ok(());
            }
            Err(e) => {
                gw.stop(STOP_TIMEOUT);
                break Err(e);
            }
        }
    };
    rt.stop(RT_STOP_TIMEOUT);
    if let Some(mut r) = ros2.take() {
        r.proc.stop(STOP_TIMEOUT);
    }
    if result.is_ok() {
        eprintln!("mcm: stopped");
    }
    result
}

/// Wait `wait` before a restart while watching `mcm-rt` and the stop signals: `Ok(true)` to
/// restart, `Ok(false)` when a stop was asked for, `Err` when `mcm-rt` died.
fn wait_watching(rt: &mut Proc, wait: Duration) -> Result<bool, String> {
    let until = Instant::now() + wait;
    loop {
        if signals::stop_requested() {
            return Ok(false);
        }
        if let Ok(Some(status)) = rt.child.try_wait() {
            return Err(format!(
                "mcm-rt exited unexpectedly ({status}); stopping (a dead real-time core is not restarted silently; see its message above)"
            ));
        }
        if Instant::now() >= until {
            return Ok(true);
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The capped exponential back-off of gateway restarts ([`GATEWAY_RESTART`]).
#[derive(Debug, Clone, Copy)]
struct Backoff {
    /// Restarts since the start or the last healthy run.
    restarts: u32,
}

impl Backoff {
    fn new() -> Self {
        Self { restarts: 0 }
    }

    /// The wait before the next restart of a gateway that ran for `ran`: the first wait after
    /// a healthy run, otherwise the next step of the policy.
    fn next(&mut self, ran: Duration) -> Duration {
        if ran >= GATEWAY_RESTART.healthy_run {
            self.restarts = 0;
        }
        self.restarts = self.restarts.saturating_add(1);
        GATEWAY_RESTART.delay(self.restarts)
    }
}

/// The ROS 2 node (`mcm ros2`), restarted when it dies: it is a client of the core like any
/// other, so its death ends what it drove (the core holds) and nothing else.
struct Ros2 {
    proc: Proc,
    args: Vec<OsString>,
    /// When it died, if it is dead.
    died: Option<Instant>,
}

/// Wait before restarting a ROS 2 node that died.
/// (`mcm_shared::restart::ROS2_RESTART`, which deploy/systemd/mcm-ros2.service carries too.)
const ROS2_RESTART: Duration = mcm_shared::restart::ROS2_RESTART.first;

impl Ros2 {
    fn start(args: Vec<OsString>) -> Result<Ros2, String> {
        let (mut proc, lines) = Proc::spawn("mcm-ros2", &prepend("ros2", &args))?;
        match wait_ready::<Ros2Ready>(&mut proc, &lines) {
            Ok(ready) => {
                println!("{ready}");
                Ok(Ros2 {
                    proc,
                    args,
                    died: None,
                })
            }
            Err(e) => {
                proc.stop(STOP_TIMEOUT);
                Err(e)
            }
        }
    }

    /// Restart the node when it died (after [`ROS2_RESTART`]).
    fn supervise(&mut self) {
        match self.died {
            None => {
                if let Ok(Some(status)) = self.proc.child.try_wait() {
                    eprintln!(
                        "mcm: mcm-ros2 exited unexpectedly ({status}); the core holds what it drove; restarting it in {ROS2_RESTART:?}"
                    );
                    self.died = Some(Instant::now());
                }
            }
            Some(t) if t.elapsed() >= ROS2_RESTART => match Ros2::start(self.args.clone()) {
                Ok(r) => *self = r,
                Err(e) => {
                    eprintln!(
                        "mcm: mcm-ros2 did not start again ({e}); retrying in {ROS2_RESTART:?}"
                    );
                    self.died = Some(Instant::now());
                }
            },
            Some(_) => {}
        }
    }
}

fn prepend(sub: &str, args: &[OsString]) -> Vec<OsString> {
    std::iter::once(OsString::from(sub))
        .chain(args.iter().cloned())
        .collect()
}

#[cfg(test)]
mod tests;
