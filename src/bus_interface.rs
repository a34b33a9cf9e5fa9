//! `mcm bus-interface --config FILE`: print the SocketCAN interface that the configuration's
//! core opens (`bus.interface` when `bus.backend = "socketcan"`), or nothing for the simulated
//! bus. The systemd unit's start waits for that interface (`deploy/wait-for-bus`, run by the
//! drop-in `mcm-rt.service.d/bus.conf`), so the interface is named once, in the configuration.

use clap::Parser;
use mcm_shared::config::{BusBackend, RobotConfig};
use std::ffi::OsString;
use std::path::PathBuf;
use std::process::ExitCode;

/// Print the SocketCAN interface mcm-rt opens with this configuration (nothing for the
/// simulated bus).
#[derive(Parser, Debug)]
#[command(name = "mcm bus-interface")]
struct Cli {
    /// Robot configuration file (TOML), as given to mcm-rt.
    #[arg(long)]
    config: PathBuf,
}

/// The interface to wait for with `config`: `None` for the simulated bus.
pub fn interface(config: &RobotConfig) -> Option<&str> {
    match config.bus.backend {
        BusBackend::Socketcan => Some(&config.bus.interface),
        BusBackend::Sim => None,
    }
}

/// Run `mcm bus-interface` with these arguments (the first is the program name).
pub fn main(args: impl IntoIterator<Item = OsString>) -> ExitCode {
    let cli = Cli::parse_from(args);
    match RobotConfig::from_file(&cli.config) {
        Ok(config) => {
            if let Some(iface) = interface(&config) {
                println!("{iface}");
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("mcm bus-interface: {e}");
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests;
