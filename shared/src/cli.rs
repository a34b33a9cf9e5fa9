//! Command-line arguments that `mcm`, `mcm rt` and `mcm gateway` share: defined once, so that
//! the launcher passes on exactly what the processes it starts accept.

use crate::service::ServiceNames;
use std::ffi::OsString;
use std::path::PathBuf;

/// Which robot and which MCM instance.
#[derive(clap::Args, Debug, Clone, PartialEq, Eq)]
pub struct CommonArgs {
    /// Robot configuration file (TOML); the embedded P-Rob2 configuration (simulated) when
    /// omitted.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Instance name: prefix of the shared-memory services, so that several MCMs can run side
    /// by side on one machine.
    #[arg(long, default_value = ServiceNames::DEFAULT_INSTANCE)]
    pub instance: String,
}

impl CommonArgs {
    /// The robot configuration these arguments name: `--config`'s file, or the embedded P-Rob2
    /// configuration without it.
    pub fn load_config(&self) -> Result<crate::config::RobotConfig, crate::config::ConfigError> {
        match &self.config {
            Some(p) => crate::config::RobotConfig::from_file(p),
            None => Ok(crate::config::RobotConfig::prob2_default()),
        }
    }

    /// The same arguments as a command line.
    pub fn to_args(&self) -> Vec<OsString> {
        let mut args: Vec<OsString> = vec!["--instance".into(), self.instance.clone().into()];
        if let Some(c) = &self.config {
            args.extend(["--config".into(), c.clone().into_os_string()]);
        }
        args
    }
}

#[cfg(test)]
mod tests;
