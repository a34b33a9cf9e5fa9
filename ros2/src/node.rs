//! Setting the node up: the DDS participant, the ROS 2 entities, the threads.
//!
//! Threads: the arm loop ([`crate::arm`], the caller's thread), the action server
//! ([`crate::action`], `mcm-ros2-action`) and ros2-client's spinner (discovery and the ROS
//! graph) on the same executor; a read-only node ([`Access::ReadOnly`]) has no action server,
//! its spinner runs alone (`mcm-ros2-spin`). None of them runs real-time: the node is a client
//! of the core like any other, and the core never waits for it.

use crate::access::Access;
use crate::action;
use crate::arm::{Arm, ArmError};
use crate::convert::JointStates;
use crate::distro::RosDistro;
use crate::driver::{Driver, DriverOptions, Event};
use crate::enclave::Security;
use crate::motion::{Motion, ServiceKind, Services, ToArm};
use crate::msgs::std_msgs::StringMsg;
use crate::msgs::trajectory::JointTrajectory;
use crate::trajectory::{Joints, ToleranceDefaults};
use mcm_client::shm::{OpenError, RequestError, ShmClient};
use mcm_shared::config::RobotConfig;
use ros2_client::action::ActionServerQosPolicies;
use ros2_client::action::GoalId;
use ros2_client::dds::rustdds::{DomainParticipantBuilder, DomainParticipantSecurityConfigFiles};
use ros2_client::dds::{Context, ServiceMapping, Subscription};
use ros2_client::qos::{Durability, History, Reliability, WhenFull};
use ros2_client::{
    ActionTypeName, MessageTypeName, Name, Node, NodeName, NodeOptions, QosProfile,
    ServiceTypeName, Spinner,
};
use std::net::IpAddr;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

/// How the node runs.
#[derive(Debug, Clone)]
pub struct Ros2Options {
    pub config: RobotConfig,
    /// The MCM instance (its shared-memory services).
    pub instance: String,
    /// ROS namespace of every name, e.g. `/left`; `/` for none.
    pub namespace: String,
    /// The node's name.
    pub node_name: String,
    pub domain_id: u16,
    /// Prefix of the joint (and URDF link) names, e.g. `left_`.
    pub joint_prefix: String,
    /// Where the URDF is written too.
    pub urdf_out: Option<PathBuf>,
    /// Addresses of the interfaces DDS uses (all when empty).
    pub dds_interfaces: Vec<IpAddr>,
    /// How far points are queued ahead of the arm [s].
    pub lead_s: f64,
    pub service_mapping: ServiceMapping,
    /// The distribution whose peers the node serves (the feedback's layout).
    pub distro: RosDistro,
    /// Whether the motion interface is offered.
    pub access: Access,
    /// DDS Security: off, or the enclave the participant authenticates with.
    pub security: Security,
}

/// Why the node stopped.
#[derive(Debug, thiserror::Error)]
pub enum Ros2Error {
    #[error(
        "cannot open the MCM's shared-memory services (is the MCM running with --instance {instance}?): {source}"
    )]
    Open { instance: String, source: OpenError },
    #[error("cannot ask the MCM for its cycle period: {0}")]
    Info(RequestError),
    #[error("cannot start DDS (domain {domain_id}): {detail}")]
    Dds { domain_id: u16, detail: String },
    #[error("cannot start DDS Security with the enclave {enclave}: {detail}")]
    Security { enclave: PathBuf, detail: String },
    #[error("invalid ROS name {what} {value:?}: {detail}")]
    Name {
        what: &'static str,
        value: String,
        detail: String,
    },
    #[error("{0}")]
    Urdf(String),
    #[error("the configuration does not suit the ROS 2 node: {0}")]
    Config(String),
    #[error(transparent)]
    Arm(#[from] ArmError),
    #[error("cannot start the action server's thread: {0}")]
    Thread(std::io::Error),
}

fn dds_err(domain_id: u16) -> impl Fn(&dyn std::fmt::Display) -> Ros2Error {
    move |e| Ros2Error::Dds {
        domain_id,
        detail: e.to_string(),
    }
}

/// Publishers of the arm loop: reliable, but a full send window drops the sample rather than
/// stopping the loop. RustDDS counts the samples not yet acknowledged by a reliable reader
/// against the history depth (its send window), and readers acknowledge at the writer's
/// heartbeats: at the cycle rate a deep history keeps the window from filling between them.
fn loop_qos(depth: usize) -> QosProfile {
    QosProfile::publisher_default()
        .reliability(Reliability::Reliable {
            when_full: WhenFull::Fail,
        })
        .history(History::KeepLast { depth })
}

/// The action's services keep the requests of a burst and their answers
/// ([`action::GOAL_REQUESTS_DEPTH`], [`action::REQUESTS_DEPTH`]); no publish of the action
/// server waits for a client to acknowledge: an answer or a status that does not fit is dropped
/// rather than holding up the answers to every other goal. The goal statuses supersede each
/// other, and feedback is sent every 20 ms.
fn action_qos() -> ActionServerQosPolicies {
    let service = |depth| {
        QosProfile::publisher_default()
            .durability(Durability::Volatile)
            .reliability(Reliability::Reliable {
                when_full: WhenFull::Fail,
            })
            .history(History::KeepLast { depth })
    };
    ActionServerQosPolicies {
        goal_service: service(action::GOAL_REQUESTS_DEPTH),
        result_service: service(action::REQUESTS_DEPTH),
        cancel_service: service(action::REQUESTS_DEPTH),
        feedback_publisher: loop_qos(100),
        status_publisher: loop_qos(16).durability(Durability::TransientLocal),
    }
}

/// History of `/joint_states`: about 5 s of cycles at 200 Hz.
const JOINT_STATES_DEPTH: usize = 1000;

/// Run the node until `stop` is set (or the MCM goes away).
pub fn run(opts: Ros2Options, stop: &AtomicBool) -> Result<(), Ros2Error> {
    let id = opts.domain_id;
    let de = dds_err(id);
    let mut client = ShmClient::connect(&opts.instance).map_err(|source| Ros2Error::Open {
        instance: opts.instance.clone(),
        source,
    })?;
    let info = client.info().map_err(Ros2Error::Info)?;
    let dt = info.period_s;

    let mut builder = DomainParticipantBuilder::new(id);
    if !opts.dds_interfaces.is_empty() {
        builder = builder.with_only_networks(opts.dds_interfaces.iter().copied());
    }
    if let Security::Enclave(dir) = &opts.security {
        // The enclave's key has no password (enclave::check_files refuses an encrypted one).
        builder = builder.builtin_security(
            DomainParticipantSecurityConfigFiles::with_ros_default_names(dir, String::new()),
        );
    }
    let participant = builder.build().map_err(|e| match &opts.security {
        Security::Enclave(dir) => Ros2Error::Security {
            enclave: dir.clone(),
            detail: e.to_string(),
        },
        Security::Off => de(&e),
    })?;
    let dds = crate::dds_threads::DdsThreads::find();
    let context = Context::from_domain_participant(participant).map_err(|e| de(&e))?;
    let name_err = |what: &'static str, value: &str| {
        let value = value.to_string();
        move |e: ros2_client::names::NameError| Ros2Error::Name {
            what,
            value: value.clone(),
            detail: format!("{e:?}"),
        }
    };
    let ns = opts.namespace.as_str();
    let mut node = context
        .new_node(
            NodeName::new(ns, &opts.node_name).map_err(name_err("node", &opts.node_name))?,
            NodeOptions::new()
                .enable_rosout(false)
                .start_parameter_services(opts.access.offers_motion()),
        )
        .map_err(|e| de(&e))?;
    let name = |base: &str| Name::new(ns, base).map_err(name_err("name", base));

    // /robot_description, latched.
    let urdf = crate::urdf::generate(
        &opts.config,
        &crate::urdf::UrdfOptions {
            prefix: opts.joint_prefix.clone(),
        },
    )
    .map_err(|e| Ros2Error::Urdf(e.to_string()))?;
    if let Some(path) = &opts.urdf_out {
        crate::urdf::write(path, &urdf).map_err(|e| Ros2Error::Urdf(e.to_string()))?;
    }
    let latched = QosProfile::publisher_default()
        .durability(Durability::TransientLocal)
        .history(History::KeepLast { depth: 1 });
    let topic = node
        .create_topic(
            &name("robot_description")?,
            MessageTypeName::new("std_msgs", "String"),
            &latched,
        )
        .map_err(|e| de(&e))?;
    let description = node
        .create_publisher::<StringMsg>(&topic, None)
        .map_err(|e| de(&e))?;
    description
        .publish(StringMsg { data: urdf })
        .map_err(|e| de(&format!("{e:?}")))?;

    let topic = node
        .create_topic(
            &name("joint_states")?,
            MessageTypeName::new("sensor_msgs", "JointState"),
            &loop_qos(JOINT_STATES_DEPTH),
        )
        .map_err(|e| de(&e))?;
    let joint_state_pub = node.create_publisher(&topic, None).map_err(|e| de(&e))?;
    // /diagnostics is one topic for the whole system (absolute).
    let topic = node
        .create_topic(
            &Name::new("/", "diagnostics").map_err(name_err("name", "diagnostics"))?,
            MessageTypeName::new("diagnostic_msgs", "DiagnosticArray"),
            &loop_qos(10),
        )
        .map_err(|e| de(&e))?;
    let diagnostics_pub = node.create_publisher(&topic, None).map_err(|e| de(&e))?;
    let motion = match opts.access {
        Access::Motion => Some(MotionEntities::create(&mut node, &opts, &name)?),
        Access::ReadOnly => None,
    };
    let spinner = node.spinner().map_err(|e| de(&e))?;
    let joints = Joints::from_config(&opts.config, &opts.joint_prefix)
        .map_err(|e| Ros2Error::Config(e.to_string()))?;
    let names = joints.names().to_vec();
    let motion = match motion {
        Some(entities) => Some(entities.start(spinner, &opts, joints, dt)?),
        None => {
            spawn_spinner_alone(spinner)?;
            None
        }
    };
    eprintln!("{}", opts.access.start_line());
    let bus = mcm_shared::busload::BusLoad::of_config(&opts.config);
    let arm = Arm {
        joint_states: JointStates::new(names, &opts.config),
        client,
        joint_state_pub,
        diagnostics_pub,
        motion,
        hardware_id: format!(
            "{} (MCM instance {})",
            opts.config.robot.name, opts.instance
        ),
        bus,
        diagnostics_every: ((1.0 / dt).round() as u64).max(1),
        dds,
    };
    let ready = mcm_shared::ready::Ros2Ready {
        node: if ns.ends_with('/') {
            format!("{ns}{}", opts.node_name)
        } else {
            format!("{ns}/{}", opts.node_name)
        },
        domain: id,
        instance: opts.instance.clone(),
    };
    println!("{ready}");
    arm.run(stop)?;
    drop(node);
    Ok(())
}

/// The motion interface's DDS entities, made before the node's spinner (which announces them).
struct MotionEntities {
    trajectory_sub: Subscription<JointTrajectory>,
    servers: Services,
    action_server: action::Server,
}

impl MotionEntities {
    fn create(
        node: &mut Node,
        opts: &Ros2Options,
        name: &dyn Fn(&str) -> Result<Name, Ros2Error>,
    ) -> Result<MotionEntities, Ros2Error> {
        let de = dds_err(opts.domain_id);
        let sub_qos = QosProfile::publisher_default().history(History::KeepLast { depth: 10 });
        let topic = node
            .create_topic(
                &name("joint_trajectory")?,
                MessageTypeName::new("trajectory_msgs", "JointTrajectory"),
                &sub_qos,
            )
            .map_err(|e| de(&e))?;
        let trajectory_sub = node.create_subscription(&topic, None).map_err(|e| de(&e))?;

        let service_qos = QosProfile::publisher_default()
            .durability(Durability::Volatile)
            .history(History::KeepLast { depth: 10 });
        let mut servers = Vec::new();
        for kind in ServiceKind::ALL {
            let server = node
                .create_server(
                    opts.service_mapping,
                    &name(kind.name())?,
                    &ServiceTypeName::new("std_srvs", "Trigger"),
                    service_qos.clone(),
                    service_qos.clone(),
                )
                .map_err(|e| de(&e))?;
            servers.push((kind, server));
        }

        let action_server = action::Server::new(
            node.create_action_server(
                opts.service_mapping,
                &name("follow_joint_trajectory")?,
                &ActionTypeName::new("control_msgs", "FollowJointTrajectory"),
                action_qos(),
            )
            .map_err(|e| de(&e))?,
        );
        Ok(MotionEntities {
            trajectory_sub,
            servers,
            action_server,
        })
    }

    /// Start the action server's thread (with the spinner) and make the arm loop's part.
    fn start(
        self,
        spinner: Spinner,
        opts: &Ros2Options,
        joints: Joints,
        dt: f64,
    ) -> Result<Motion<GoalId>, Ros2Error> {
        let distro = opts.distro;
        let action_server = self.action_server;
        let (to_arm, from_action) = std::sync::mpsc::channel::<ToArm<_>>();
        let (to_action, from_arm) = futures::channel::mpsc::unbounded::<Event<_>>();
        std::thread::Builder::new()
            .name("mcm-ros2-action".into())
            .spawn(move || {
                futures::executor::block_on(async move {
                    let spin = spinner.spin();
                    futures::pin_mut!(spin);
                    let serve = action::serve(action_server, distro, to_arm, from_arm);
                    futures::pin_mut!(serve);
                    futures::future::select(spin, serve).await;
                })
            })
            .map_err(Ros2Error::Thread)?;
        let driver = Driver::new(
            DriverOptions {
                dt,
                lead_s: opts.lead_s,
                feedback_every: ((0.02 / dt).round() as u64).max(1),
                tolerances: ToleranceDefaults::default(),
            },
            joints,
        );
        Ok(Motion::new(
            driver,
            self.servers,
            self.trajectory_sub,
            from_action,
            to_action,
        ))
    }
}

/// A read-only node's spinner (discovery, the ROS graph) on a thread of its own.
fn spawn_spinner_alone(spinner: Spinner) -> Result<(), Ros2Error> {
    std::thread::Builder::new()
        .name("mcm-ros2-spin".into())
        .spawn(move || {
            futures::executor::block_on(async move {
                let _ = spinner.spin().await;
            })
        })
        .map(drop)
        .map_err(Ros2Error::Thread)
}
