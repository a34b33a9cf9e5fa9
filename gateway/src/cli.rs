//! The command line of `mcm-gateway` (also `mcm gateway`).

use crate::{DEFAULT_HMI_PORT, DEFAULT_JSON_PORT, DEFAULT_WEB_PORT, GatewayOptions};
use clap::Parser;
use mcm_shared::cli::CommonArgs;
use mcm_shared::service::ServiceNames;
use std::ffi::OsString;
use std::net::{IpAddr, SocketAddr};
use std::process::ExitCode;

/// Serve the MCM's JSON protocol and pass commands to the real-time core (mcm-rt).
#[derive(Parser, Debug)]
#[command(name = "mcm-gateway", version, about)]
struct Cli {
    #[command(flatten)]
    common: CommonArgs,
    #[command(flatten)]
    listen: ListenArgs,
}

/// Where the gateway listens (also arguments of the `mcm` launcher, which passes them on).
#[derive(clap::Args, Debug, Clone, PartialEq, Eq)]
pub struct ListenArgs {
    /// Address the gateway listens on.
    #[arg(long, default_value = "0.0.0.0")]
    pub bind: IpAddr,
    /// TCP port of the JSON protocol (0: any free port, printed at start).
    #[arg(long, default_value_t = DEFAULT_JSON_PORT)]
    pub json_port: u16,
    /// TCP port of the telnet text HMI (0: any free port, printed at start).
    #[arg(long, default_value_t = DEFAULT_HMI_PORT)]
    pub hmi_port: u16,
    /// TCP port of the browser pendant, page and WebSocket (0: any free port, printed at
    /// start; `[gateway.web] enabled = false` switches it off).
    #[arg(long, default_value_t = DEFAULT_WEB_PORT)]
    pub http_port: u16,
    /// Accept `sim` fault injection from other hosts too (default: from loopback only).
    #[arg(long)]
    pub allow_remote_sim: bool,
    /// Serve the ZeroMQ interface (`[gateway.zmq]`: commands on a ROUTER socket, default
    /// tcp://127.0.0.1:18012; state and errors on a PUB socket, default tcp://127.0.0.1:18013).
    #[arg(long)]
    pub zmq: bool,
    /// Endpoint of the ZeroMQ ROUTER socket (e.g. tcp://0.0.0.0:18012; port * for any free
    /// port); switches the ZeroMQ interface on.
    #[arg(long, value_name = "ENDPOINT")]
    pub zmq_router: Option<String>,
    /// Endpoint of the ZeroMQ PUB socket; switches the ZeroMQ interface on.
    #[arg(long, value_name = "ENDPOINT")]
    pub zmq_publish: Option<String>,
}

impl ListenArgs {
    /// The same arguments as a command line.
    pub fn to_args(&self) -> Vec<OsString> {
        let mut args: Vec<OsString> = vec![
            "--bind".into(),
            self.bind.to_string().into(),
            "--json-port".into(),
            self.json_port.to_string().into(),
            "--hmi-port".into(),
            self.hmi_port.to_string().into(),
            "--http-port".into(),
            self.http_port.to_string().into(),
        ];
        if self.allow_remote_sim {
            args.push("--allow-remote-sim".into());
        }
        if self.zmq {
            args.push("--zmq".into());
        }
        for (flag, v) in [
            ("--zmq-router", &self.zmq_router),
            ("--zmq-publish", &self.zmq_publish),
        ] {
            if let Some(v) = v {
                args.extend([flag.into(), v.into()]);
            }
        }
        args
    }

    /// Apply the ZeroMQ options to `cfg` (they override `[gateway.zmq]`), checked as the
    /// configuration file's keys are.
    pub fn apply_zmq(
        &self,
        cfg: &mut mcm_shared::config::ZmqConfig,
    ) -> Result<(), mcm_shared::config::ConfigError> {
        if self.zmq || self.zmq_router.is_some() || self.zmq_publish.is_some() {
            cfg.enabled = true;
        }
        if let Some(r) = &self.zmq_router {
            cfg.router = r.clone();
        }
        if let Some(p) = &self.zmq_publish {
            cfg.publish = p.clone();
        }
        cfg.validate()
    }
}

/// Run `mcm-gateway` with these command-line arguments (the first is the program name).
pub fn main<I, T>(args: I) -> ExitCode
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = Cli::parse_from(args);
    match mcm_gateway_main(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("mcm-gateway: {e}");
            ExitCode::FAILURE
        }
    }
}

fn mcm_gateway_main(cli: Cli) -> Result<(), Box<dyn std::error::Error>> {
    let mut config = cli.common.load_config()?;
    cli.listen.apply_zmq(&mut config.gateway.zmq)?;
    let names = ServiceNames::new(&cli.common.instance)?;
    let opts = GatewayOptions {
        config,
        names,
        json_addr: SocketAddr::new(cli.listen.bind, cli.listen.json_port),
        hmi_addr: SocketAddr::new(cli.listen.bind, cli.listen.hmi_port),
        web_addr: SocketAddr::new(cli.listen.bind, cli.listen.http_port),
        allow_remote_sim: cli.listen.allow_remote_sim,
    };
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .on_thread_start(crate::core_link::latency::on_thread_start)
        .enable_all()
        .build()?;
    // systemd's notifications (`Type=notify`, deploy/systemd/mcm-gateway.service): READY=1 once
    // it listens and has the core's first state (or `READY_STATE_WAIT` passed), STOPPING=1 at a stop signal, the watchdog from a task of the runtime (a
    // runtime that no longer runs its tasks stops the pings). Nothing without NOTIFY_SOCKET.
    let notifier = std::sync::Arc::new(mcm_shared::notify::Notifier::from_env("mcm-gateway"));
    rt.block_on(async move {
        if let Some(every) = notifier.watchdog_every() {
            let n = notifier.clone();
            tokio::spawn(async move {
                let mut tick = tokio::time::interval(every);
                loop {
                    tick.tick().await;
                    n.watchdog();
                }
            });
        }
        let on_ready = notifier.clone();
        let ready = move |r: crate::Ready| {
            // The line the launcher reads (`mcm_shared::ready`).
            let line = mcm_shared::ready::GatewayReady {
                json: r.json,
                hmi: r.hmi,
                web: r.web,
                zmq: r
                    .zmq
                    .map(|(router, publish)| mcm_shared::ready::ZmqEndpoints { router, publish }),
            };
            println!("{line}");
            on_ready.ready(&line.to_string());
        };
        let shutdown = async move {
            shutdown_signal().await;
            notifier.stopping("stopping: telling the clients, then closing the listeners");
        };
        crate::run(opts, ready, shutdown).await
    })?;
    Ok(())
}

async fn shutdown_signal() {
    use tokio::signal::unix::{SignalKind, signal};
    let mut term = signal(SignalKind::terminate()).expect("install the SIGTERM handler");
    tokio::select! {
        _ = tokio::signal::ctrl_c() => {}
        _ = term.recv() => {}
    }
}

#[cfg(test)]
mod tests;
