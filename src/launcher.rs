//! The launcher: starts `mcm rt` and `mcm gateway` as two processes, says where to connect,
//! restarts the gateway if it dies (it holds no state), stops everything if the real-time core
//! dies (that is never silently papered over), and stops both cleanly on Ctrl-C or SIGTERM.

use clap::Parser;
use mcm_gateway::cli::ListenArgs;
use mcm_rt_core::cli::LogArgs;
use mcm_rt_core::signals;
use mcm_shared::cli::CommonArgs;
use mcm_shared::config::{BusBackend, RobotConfig};
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
    after_help = "Subcommands: `mcm rt --help` and `mcm gateway --help` run one process each."
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
}

/// How long a child may take to say it is ready.
const READY_TIMEOUT: Duration = Duration::from_secs(20);
/// How long a child may take to stop after SIGTERM before it is killed.
const STOP_TIMEOUT: Duration = Duration::from_secs(5);

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
        // Children ignore Ctrl-C from the terminal: the launcher stops them in order.
        // SAFETY: setpgid is async-signal-safe and only affects the child being spawned.
        unsafe {
            cmd.pre_exec(|| {
                libc::setpgid(0, 0);
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

    /// SIGTERM, wait, then SIGKILL.
    fn stop(&mut self) {
        if let Ok(Some(_)) = self.child.try_wait() {
            return;
        }
        // SAFETY: kill with a valid pid of our own child.
        unsafe { libc::kill(self.child.id() as i32, libc::SIGTERM) };
        let deadline = Instant::now() + STOP_TIMEOUT;
        while Instant::now() < deadline {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        eprintln!(
            "mcm: {} did not stop within {STOP_TIMEOUT:?}; killing it",
            self.name
        );
        let _ = self.child.kill();
        let _ = self.child.wait();
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

/// Wait for a line starting with `prefix`; fail if the child exits first.
fn wait_ready(
    p: &mut Proc,
    lines: &mpsc::Receiver<String>,
    prefix: &str,
) -> Result<String, String> {
    let deadline = Instant::now() + READY_TIMEOUT;
    loop {
        if signals::stop_requested() {
            return Err("stopped before start-up finished".into());
        }
        match lines.recv_timeout(Duration::from_millis(50)) {
            Ok(line) if line.starts_with(prefix) => return Ok(line),
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

fn field<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    line.split_whitespace()
        .find_map(|w| w.strip_prefix(key).and_then(|r| r.strip_prefix('=')))
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
    let cfg = match &cli.common.config {
        Some(p) => RobotConfig::from_file(p).map_err(|e| e.to_string())?,
        None => RobotConfig::prob2_default(),
    };
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
    if let Err(e) = wait_ready(&mut rt, &rt_lines, "mcm-rt ready") {
        rt.stop();
        return Err(e);
    }
    drop(rt_lines);

    let robot = match cfg.bus.backend {
        BusBackend::Sim => format!("simulated {}", cfg.robot.name),
        BusBackend::Socketcan => format!("{} on {}", cfg.robot.name, cfg.bus.interface),
    };
    let mut restarts = 0u32;
    let mut last_start = Instant::now();
    let result = loop {
        let (mut gw, gw_lines) = match Proc::spawn("mcm-gateway", &prepend("gateway", &gw_args)) {
            Ok(x) => x,
            Err(e) => break Err(e),
        };
        let ready = match wait_ready(&mut gw, &gw_lines, "mcm-gateway ready") {
            Ok(line) => line,
            Err(e) => {
                gw.stop();
                break Err(e);
            }
        };
        drop(gw_lines);
        let json = field(&ready, "json").unwrap_or("?");
        let hmi = field(&ready, "hmi").unwrap_or("?");
        println!(
            "MCM ready ({robot}, instance {}): JSON on {json}, telnet HMI on {hmi}; Ctrl-C stops. [json={json} hmi={hmi} rt_pid={} gateway_pid={}]",
            cli.common.instance,
            rt.pid(),
            gw.pid()
        );
        // Supervise.
        let outcome = loop {
            if signals::stop_requested() {
                break Ok(false);
            }
            if let Ok(Some(status)) = rt.child.try_wait() {
                break Err(format!("mcm-rt exited unexpectedly ({status}); stopping"));
            }
            if let Ok(Some(status)) = gw.child.try_wait() {
                eprintln!("mcm: mcm-gateway exited unexpectedly ({status}); restarting it");
                break Ok(true);
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        match outcome {
            Ok(true) => {
                // Back off if it keeps dying at once.
                restarts = if last_start.elapsed() < Duration::from_secs(10) {
                    restarts + 1
                } else {
                    0
                };
                if restarts > 5 {
                    break Err("mcm-gateway keeps exiting; giving up".into());
                }
                std::thread::sleep(Duration::from_millis(200 * u64::from(restarts)));
                last_start = Instant::now();
            }
            Ok(false) => {
                gw.stop();
                break Ok(());
            }
            Err(e) => {
                gw.stop();
                break Err(e);
            }
        }
    };
    rt.stop();
    if result.is_ok() {
        eprintln!("mcm: stopped");
    }
    result
}

fn prepend(sub: &str, args: &[OsString]) -> Vec<OsString> {
    std::iter::once(OsString::from(sub))
        .chain(args.iter().cloned())
        .collect()
}
