//! `mcm-ros2`'s command line (also `mcm ros2 ...`, which the launcher starts).

use crate::access::Access;
use crate::distro::RosDistro;
use crate::enclave::{self, SecurityEnv};
use crate::node::{Ros2Options, run};
use clap::Parser;
use mcm_shared::cli::CommonArgs;
use ros2_client::dds::ServiceMapping;
use std::ffi::OsString;
use std::net::IpAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

/// The MCM as a ROS 2 node (docs/ros2.md): /joint_states, /robot_description,
/// follow_joint_trajectory, joint_trajectory, the hold/calibrate/release/take_control/
/// release_control services and /diagnostics, over DDS (with --ros2-read-only only
/// /joint_states, /robot_description and /diagnostics). Runs next to a running MCM (its
/// shared-memory services); needs no ROS installation.
#[derive(Parser, Debug)]
#[command(name = "mcm-ros2", version)]
pub struct Cli {
    #[command(flatten)]
    pub common: CommonArgs,
    /// ROS namespace of the node's names (e.g. `/left` for one of two arms).
    #[arg(long, default_value = "/")]
    pub namespace: String,
    /// The node's name.
    #[arg(long, default_value = "mcm")]
    pub node_name: String,
    /// DDS domain (0..=232); the environment's ROS_DOMAIN_ID when omitted, else 0.
    #[arg(long, value_parser = clap::value_parser!(u16).range(0..=232))]
    pub domain_id: Option<u16>,
    /// Prefix of the joint and link names (e.g. `left_`), for several arms in one ROS graph.
    #[arg(long, default_value = "")]
    pub joint_prefix: String,
    /// Also write the URDF (the robot description) to this file.
    #[arg(long)]
    pub urdf_out: Option<PathBuf>,
    /// Use only the network interface with this address for DDS (repeatable; e.g. 127.0.0.1
    /// keeps DDS on this computer). All interfaces when omitted.
    #[arg(long = "dds-interface")]
    pub dds_interfaces: Vec<IpAddr>,
    /// How far trajectory points are queued ahead of the arm [s] (0.01..=1): a new goal takes
    /// over this late; a node paused longer than this stops the arm.
    #[arg(long, default_value_t = 0.05, value_parser = parse_lead)]
    pub lead: f64,
    /// The DDS implementation's request/reply mapping of the peers: `enhanced` (Fast DDS,
    /// RTI Connext) or `cyclone` (Cyclone DDS).
    #[arg(long, default_value = "enhanced", value_parser = parse_mapping)]
    pub service_mapping: ServiceMapping,
    /// The ROS 2 distribution of the peers: jazzy, kilted or lyrical (the layout of
    /// FollowJointTrajectory's feedback). The environment's ROS_DISTRO when omitted and it
    /// names one of them, else jazzy.
    #[arg(long)]
    pub ros_distro: Option<RosDistro>,
    /// Offer no motion interface: only the joint states, the robot description and the
    /// diagnostics; no follow_joint_trajectory action, joint_trajectory subscription, services
    /// or parameter services. The node then never sends the MCM a command (for a DDS network
    /// where not everyone may move the arm; docs/security.md).
    #[arg(long = "ros2-read-only")]
    pub read_only: bool,
    /// Use DDS Security with this SROS2 enclave (a directory of identity_ca.cert.pem,
    /// cert.pem, key.pem, permissions_ca.cert.pem, governance.p7s and permissions.p7s;
    /// docs/security.md). Without it, ROS_SECURITY_ENABLE=true with ROS_SECURITY_KEYSTORE
    /// (and ROS_SECURITY_ENCLAVE_OVERRIDE, default /mcm) chooses the enclave, as SROS2 does;
    /// ROS_SECURITY_STRATEGY=Enforce refuses to run without one.
    #[arg(long = "ros2-enclave", value_name = "DIR")]
    pub enclave: Option<PathBuf>,
}

fn parse_lead(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|_| format!("lead {s:?} is not a number; allowed: 0.01 to 1 s"))?;
    if (0.01..=1.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("lead {v} s is outside the allowed 0.01 to 1 s"))
    }
}

fn parse_mapping(s: &str) -> Result<ServiceMapping, String> {
    match s {
        "enhanced" => Ok(ServiceMapping::Enhanced),
        "cyclone" => Ok(ServiceMapping::Cyclone),
        "basic" => Ok(ServiceMapping::Basic),
        _ => Err(format!(
            "service mapping {s:?} is not known; allowed: enhanced, cyclone, basic"
        )),
    }
}

/// `ROS_DOMAIN_ID` from the environment (0 when unset or empty), as ROS 2 reads it.
fn domain_from_env() -> Result<u16, String> {
    match std::env::var("ROS_DOMAIN_ID") {
        Err(_) => Ok(0),
        Ok(v) if v.trim().is_empty() => Ok(0),
        Ok(v) => match v.trim().parse::<u16>() {
            Ok(d) if d <= 232 => Ok(d),
            _ => Err(format!(
                "ROS_DOMAIN_ID {v:?} is not a DDS domain id; allowed: 0 to 232"
            )),
        },
    }
}

/// Run `mcm-ros2` with these command-line arguments (the first is the program name).
pub fn main<I, T>(args: I) -> ExitCode
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = Cli::parse_from(args);
    crate::allocator::init();
    let config = match cli.common.load_config() {
        Ok(c) => c,
        Err(e) => {
            eprintln!("mcm-ros2: {e}");
            return ExitCode::FAILURE;
        }
    };
    let domain_id = match cli.domain_id.map_or_else(domain_from_env, Ok) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("mcm-ros2: {e}");
            return ExitCode::FAILURE;
        }
    };
    let distro = cli.ros_distro.unwrap_or_else(|| {
        let (distro, unused) = RosDistro::from_env(std::env::var("ROS_DISTRO").ok().as_deref());
        if let Some(e) = unused {
            eprintln!("mcm-ros2: ROS_DISTRO: {e}; serving {distro}");
        }
        distro
    });
    eprintln!("mcm-ros2: serving ROS 2 {distro}'s peers");
    let security = match enclave::choose(cli.enclave.as_deref(), &SecurityEnv::from_process()) {
        Ok(chosen) => {
            if let Some(w) = chosen.warning {
                eprintln!("mcm-ros2: {w}");
            }
            eprintln!("mcm-ros2: DDS Security: {}", chosen.security);
            chosen.security
        }
        Err(e) => {
            eprintln!("mcm-ros2: {e}");
            return ExitCode::FAILURE;
        }
    };
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGTERM, signal_hook::consts::SIGINT] {
        if let Err(e) = signal_hook::flag::register(sig, Arc::clone(&stop)) {
            eprintln!("mcm-ros2: cannot handle signal {sig}: {e}");
            return ExitCode::FAILURE;
        }
    }
    let opts = Ros2Options {
        config,
        instance: cli.common.instance,
        namespace: cli.namespace,
        node_name: cli.node_name,
        domain_id,
        joint_prefix: cli.joint_prefix,
        urdf_out: cli.urdf_out,
        dds_interfaces: cli.dds_interfaces,
        lead_s: cli.lead,
        service_mapping: cli.service_mapping,
        distro,
        access: Access::from_read_only(cli.read_only),
        security,
    };
    match run(opts, &stop) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("mcm-ros2: {e}");
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests;
