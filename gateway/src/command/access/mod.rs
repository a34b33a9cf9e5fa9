//! Who may move the arm, seen from the network: the access rules of `[gateway.access]` and
//! the identity of each connection. Runs in the gateway's async tasks, never in the cycle.
//!
//! Control itself (one owner at a time, `hold` open to all, a gone owner's motion stopped)
//! lives in the real-time core, so it binds shared-memory clients as well; the gateway adds
//! what only it can know, the peer's address and the shared secret:
//! - motion commands (those that need control) and `take_control` are accepted only from the
//!   networks of `motion_networks` (default: every network);
//! - when `secret_sha256_file` is set, only after the connection presented the secret
//!   (`authenticate`); the file holds the secret's SHA-256 in hex, the presented secret is
//!   hashed and compared in constant time, and a wrong one is answered after
//!   [`WRONG_SECRET_DELAY`];
//! - `sim` commands only from loopback, unless the gateway runs with `--allow-remote-sim`;
//! - everything else (`hold`, `status`, `info`, `release_control`, `sleep`) is open to all.
//!
//! Every refusal is counted by reason and shown in `status` detail (`detail.access`), next to
//! who controls the arm (`detail.control`).

mod clients;
pub(crate) mod reaper;
pub(crate) mod sha256;
#[cfg(test)]
mod tests;

pub use clients::{Channel, Client, Clients};

use crate::command::{self, Context, Outcome};
use mcm_shared::config::{AccessConfig, Cidr, ConfigError};
use mcm_shared::error_code::ErrorCode;
use mcm_shared::mode::CommandKind;
use mcm_shared::protocol::results::{AccessDetail, Answer, ControlDetail, ErrorOutcome, Generic};
use mcm_shared::protocol::{Command, Secret};
use mcm_shared::reply::{self, Reason};
use std::net::IpAddr;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

/// How long a wrong secret waits for its answer (slows guessing down).
pub const WRONG_SECRET_DELAY: Duration = Duration::from_secs(1);

/// Starting the access rules failed.
#[derive(Debug, thiserror::Error)]
pub enum AccessError {
    #[error(transparent)]
    Config(#[from] ConfigError),
    #[error(
        "gateway.access.secret_sha256_file: cannot use {path}: {reason}; the file must hold the \
         secret's SHA-256 as 64 hex digits, e.g. made with \
         `printf '%s' 'THE SECRET' | sha256sum > {path}`"
    )]
    SecretFile { path: String, reason: String },
}

/// What a command needs of the access rules.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Need {
    /// Open to every client.
    Open,
    /// Moves the arm or takes control: allowed network, and the secret when one is set.
    Motion,
    /// Fault injection: loopback, unless remote `sim` is allowed.
    Sim,
}

/// What a command needs.
pub fn need(cmd: &Command) -> Need {
    match cmd {
        Command::Sim(_) => Need::Sim,
        Command::TakeControl(_) => Need::Motion,
        c if c.def().needs_control() => Need::Motion,
        _ => Need::Open,
    }
}

/// Why the gateway refused an attempt (the counters of `detail.access.refused`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// A motion command from outside the allowed networks.
    Network,
    /// A motion command before the shared secret was presented.
    NotAuthenticated,
    /// `authenticate` with a wrong secret.
    WrongSecret,
    /// `sim` from a non-loopback address.
    RemoteSim,
    /// The core refused: another client controls the arm.
    NotOwner,
}

impl Refusal {
    const ALL: [Refusal; 5] = [
        Refusal::Network,
        Refusal::NotAuthenticated,
        Refusal::WrongSecret,
        Refusal::RemoteSim,
        Refusal::NotOwner,
    ];

    /// Its `error_code`.
    pub fn code(self) -> ErrorCode {
        match self {
            Refusal::Network => ErrorCode::NetworkRefused,
            Refusal::NotAuthenticated => ErrorCode::NotAuthenticated,
            Refusal::WrongSecret => ErrorCode::WrongSecret,
            Refusal::RemoteSim => ErrorCode::RemoteSimRefused,
            Refusal::NotOwner => ErrorCode::NotOwner,
        }
    }

    fn key(self) -> &'static str {
        match self {
            Refusal::Network => "network",
            Refusal::NotAuthenticated => "not_authenticated",
            Refusal::WrongSecret => "wrong_secret",
            Refusal::RemoteSim => "remote_sim",
            Refusal::NotOwner => "not_owner",
        }
    }
}

/// The access rules in force and the refusals counted so far.
#[derive(Debug, Default)]
pub struct Access {
    /// `None`: motion from every network.
    networks: Option<Vec<Cidr>>,
    secret: Option<[u8; 32]>,
    allow_remote_sim: bool,
    refused: [AtomicU64; 5],
}

impl Access {
    /// The rules of `cfg` (reads the secret's hash file); `allow_remote_sim` from the flag.
    pub fn from_config(cfg: &AccessConfig, allow_remote_sim: bool) -> Result<Access, AccessError> {
        let networks = cfg.networks()?;
        let secret = match &cfg.secret_sha256_file {
            None => None,
            Some(path) => Some(read_secret_hash(path)?),
        };
        Ok(Access::new(networks, secret, allow_remote_sim))
    }

    /// Rules from their parts (the hash of the secret, not the secret).
    pub fn new(
        networks: Option<Vec<Cidr>>,
        secret: Option<[u8; 32]>,
        allow_remote_sim: bool,
    ) -> Access {
        Access {
            networks,
            secret,
            allow_remote_sim,
            refused: Default::default(),
        }
    }

    /// Whether motion is accepted from `ip`.
    pub fn motion_allowed_from(&self, ip: IpAddr) -> bool {
        self.networks
            .as_ref()
            .is_none_or(|nets| nets.iter().any(|n| n.contains(ip)))
    }

    /// The decision for a command that `needs` this, from `peer`, by a connection that has
    /// (or has not) presented the secret.
    pub fn decide(&self, needs: Need, peer: IpAddr, authenticated: bool) -> Result<(), Refusal> {
        match needs {
            Need::Open => Ok(()),
            Need::Sim if self.allow_remote_sim || peer.to_canonical().is_loopback() => Ok(()),
            Need::Sim => Err(Refusal::RemoteSim),
            Need::Motion if !self.motion_allowed_from(peer) => Err(Refusal::Network),
            Need::Motion if self.secret.is_some() && !authenticated => {
                Err(Refusal::NotAuthenticated)
            }
            Need::Motion => Ok(()),
        }
    }

    /// Whether `presented` is the secret (always true when none is configured).
    pub fn secret_matches(&self, presented: &str) -> bool {
        match &self.secret {
            None => true,
            Some(hash) => sha256::equal_constant_time(hash, &sha256::digest(presented.as_bytes())),
        }
    }

    pub fn count(&self, r: Refusal) {
        self.refused[r as usize].fetch_add(1, Ordering::Relaxed);
    }

    /// Refusals of `r` so far.
    pub fn refused(&self, r: Refusal) -> u64 {
        self.refused[r as usize].load(Ordering::Relaxed)
    }

    /// The words of a refusal by the gateway: what was refused, why, and how to get access.
    pub fn refusal_text(&self, command: &str, r: Refusal, peer: IpAddr) -> String {
        let open = "`hold`, `status` and `info` stay open to every client";
        match r {
            Refusal::Network => format!(
                "{command} refused: motion commands are not accepted from {peer} (allowed \
                 networks: {}); connect from an allowed network or add yours to \
                 [gateway.access] motion_networks; {open}",
                self.networks_words()
            ),
            Refusal::NotAuthenticated => format!(
                "{command} refused: this MCM requires the shared secret before a client may \
                 take control; send {{\"command\":\"authenticate\",\"arguments\":{{\"secret\":\
                 \"...\"}}}} first (HMI: authenticate SECRET); {open}"
            ),
            Refusal::WrongSecret => format!(
                "{command} refused: the secret is wrong; ask the robot's operator for the \
                 shared secret (its hash is in [gateway.access] secret_sha256_file)"
            ),
            Refusal::RemoteSim => format!(
                "{command} refused: fault injection is accepted only from loopback and this \
                 connection is from {peer}; connect from the robot's computer, or start the \
                 MCM with --allow-remote-sim"
            ),
            Refusal::NotOwner => format!("{command} refused: another client controls the arm"),
        }
    }

    fn networks_words(&self) -> String {
        match &self.networks {
            None => "any".to_string(),
            Some(n) if n.is_empty() => "none".to_string(),
            Some(n) => n.iter().map(Cidr::to_string).collect::<Vec<_>>().join(", "),
        }
    }

    /// `detail.access` for the connection `client`.
    pub fn detail(&self, client: &Client) -> AccessDetail {
        AccessDetail {
            peer: client.peer.to_string(),
            motion_networks: self.networks_words(),
            motion_allowed_here: self.motion_allowed_from(client.peer.ip()),
            secret_required: self.secret.is_some(),
            authenticated: client.authenticated(),
            remote_sim: self.allow_remote_sim,
            refused: Refusal::ALL
                .iter()
                .map(|r| (r.key().to_string(), self.refused(*r)))
                .collect(),
        }
    }
}

fn read_secret_hash(path: &str) -> Result<[u8; 32], AccessError> {
    let bad = |reason: String| AccessError::SecretFile {
        path: path.to_string(),
        reason,
    };
    let text = std::fs::read_to_string(path).map_err(|e| bad(e.to_string()))?;
    // `sha256sum` prints "HASH  -": the first word is the hash.
    let word = text.split_whitespace().next().unwrap_or_default();
    sha256::from_hex(word).ok_or_else(|| {
        bad(format!(
            "its first word is {} characters long, not 64 hex digits",
            word.len()
        ))
    })
}

/// `detail.control`: who controls the arm, and whether it is this connection.
pub fn control_detail(ctx: &Context, client: &Client, owner: u64) -> ControlDetail {
    ControlDetail {
        owner: (owner != 0).then(|| ctx.clients.who(owner)),
        owner_client_id: owner,
        this_connection: owner != 0 && owner == client.id,
    }
}

/// The ERROR result of a refused or failed reply; a `not_owner` refusal names the owner in
/// words and is counted.
pub fn reply_error(ctx: &Context, kind: CommandKind, outcome: &reply::Outcome) -> Generic {
    match outcome {
        reply::Outcome::Refused(Reason::NotOwner { owner }) => {
            ctx.access.count(Refusal::NotOwner);
            Generic::answer_error(
                ErrorOutcome::Refused,
                Refusal::NotOwner.code(),
                format!(
                    "{kind} refused: the arm is controlled by {} (client id {owner:#x}); only \
                     `hold`, `status` and `info` are open to others until it sends \
                     `release_control` or disconnects",
                    ctx.clients.who(*owner)
                ),
            )
        }
        other => Generic::reply_error(kind, other),
    }
}

fn only(result: Answer) -> Outcome {
    Outcome {
        result: Some(result),
        state: None,
        mode_session: None,
    }
}

/// Execute `cmd` for the connection `client` under the access rules: `authenticate` here,
/// refusals here, everything else through [`command::execute`]; `status` detail gains
/// `detail.control` and `detail.access`. An ERROR result names `cmd` (`command`).
pub async fn run_command(ctx: &Context, client: &Client, cmd: &Command) -> Outcome {
    let mut out = run(ctx, client, cmd).await;
    out.result = out.result.map(|r| r.answering(cmd.name()));
    out
}

async fn run(ctx: &Context, client: &Client, cmd: &Command) -> Outcome {
    if let Command::Authenticate(a) = cmd {
        let secret = &a.secret;
        return authenticate(ctx, client, secret).await;
    }
    let needs = need(cmd);
    if let Err(r) = ctx
        .access
        .decide(needs, client.peer.ip(), client.authenticated())
    {
        ctx.access.count(r);
        return only(Answer::answer_error(
            ErrorOutcome::Invalid,
            r.code(),
            ctx.access.refusal_text(cmd.name(), r, client.peer.ip()),
        ));
    }
    if needs == Need::Motion {
        client.may_own();
    }
    let mut out = command::execute(ctx, client.id, cmd).await;
    if let (Command::Status(_), Some(Answer::Status(s)), Some(state)) =
        (cmd, &mut out.result, &out.state)
        && let Some(detail) = s.detail.as_mut()
    {
        detail.control = Some(control_detail(ctx, client, state.owner_client_id));
        detail.access = Some(ctx.access.detail(client));
    }
    out
}

async fn authenticate(ctx: &Context, client: &Client, secret: &Secret) -> Outcome {
    if ctx.access.secret_matches(&secret.0) {
        client.set_authenticated();
        return only(Answer::ok());
    }
    ctx.access.count(Refusal::WrongSecret);
    tokio::time::sleep(WRONG_SECRET_DELAY).await;
    only(Answer::answer_error(
        ErrorOutcome::Invalid,
        Refusal::WrongSecret.code(),
        ctx.access
            .refusal_text("authenticate", Refusal::WrongSecret, client.peer.ip()),
    ))
}

/// Who controls the arm, for people: the HMI's status view adds this line.
pub fn control_words(ctx: &Context, client: &Client, owner: u64) -> String {
    match owner {
        0 => "control:   nobody controls the arm (the first motion command takes control)"
            .to_string(),
        o if o == client.id => "control:   this session controls the arm".to_string(),
        o => format!(
            "control:   the arm is controlled by {}; only `hold` and reading are open to this \
             session",
            ctx.clients.who(o)
        ),
    }
}
