//! The pendant's JSON API: `/api/model` (the robot as configured: axes, limits, the DH links
//! for the 3D view, the bus load), `/api/connections` (the gateway's clients now, and which
//! controls the arm) and `/api/flight-records[/NAME]` (this instance's flight-recorder files,
//! docs/safety.md, listed newest first and downloadable).

use mcm_shared::busload::BusLoad;
use mcm_shared::config::RobotConfig;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// `/api/model` of the configuration `cfg` for the MCM instance `instance`.
pub fn model(cfg: &RobotConfig, instance: &str) -> Value {
    let axes: Vec<Value> = cfg
        .axes
        .iter()
        .enumerate()
        .map(|(i, a)| {
            json!({
                "axis": i + 1,
                "name": a.name,
                "min_deg": a.min_deg,
                "max_deg": a.max_deg,
                "limit_margin_deg": cfg.safety.limit_margin_deg,
                "max_velocity_deg_s": a.max_velocity_deg_s,
                "following_error_deg": a.following_error_deg,
            })
        })
        .collect();
    let links: Vec<Value> = cfg
        .arm
        .links
        .iter()
        .map(|l| json!({"d": l.d, "a": l.a, "alpha_deg": l.alpha_deg, "offset_deg": l.offset_deg}))
        .collect();
    let load = BusLoad::of_config(cfg);
    json!({
        "robot": cfg.robot.name,
        "instance": instance,
        "rate_hz": cfg.cycle.rate_hz,
        "axes": axes,
        "links": links,
        "bus": {
            "backend": cfg.bus.backend.to_string(),
            "bitrate": cfg.bus.bitrate,
            "worst_case_load": load.load,
            "load_budget": load.budget,
        },
    })
}

/// `/api/connections`: the gateway's clients `list` (id, channel, peer), and the client id of
/// the arm's `owner` (0: nobody; it may be a shared-memory client, not in the list).
pub fn connections(
    list: &[(u64, crate::command::access::Channel, std::net::SocketAddr)],
    owner: u64,
) -> Value {
    let clients: Vec<Value> = list
        .iter()
        .map(|(id, channel, peer)| {
            json!({
                "client_id": id,
                "channel": channel.words(),
                "peer": peer.to_string(),
                "controls_the_arm": *id == owner,
            })
        })
        .collect();
    json!({"owner_client_id": owner, "clients": clients})
}

/// One flight-recorder file of this instance.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    pub name: String,
    pub check: String,
    pub unix_ms: u64,
    pub bytes: u64,
}

/// The parts of a file name `mcm-<instance>-<unix ms>-<check>.csv` of `instance`, or `None`
/// for any other name (another instance's, a `.tmp` being written, anything else).
pub fn parse_name(name: &str, instance: &str) -> Option<(u64, String)> {
    let rest = name
        .strip_prefix("mcm-")?
        .strip_prefix(instance)?
        .strip_prefix('-')?
        .strip_suffix(".csv")?;
    let (ms, check) = rest.split_once('-')?;
    let valid_check = !check.is_empty()
        && check
            .bytes()
            .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_');
    let ms = ms.parse().ok().filter(|_| valid_check)?;
    Some((ms, check.to_string()))
}

/// This instance's records in `dir`, newest first (an unreadable or missing directory: none).
pub fn records(dir: &Path, instance: &str) -> Vec<Record> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut out: Vec<Record> = entries
        .filter_map(Result::ok)
        .filter_map(|e| {
            let name = e.file_name().into_string().ok()?;
            let (unix_ms, check) = parse_name(&name, instance)?;
            let meta = e.metadata().ok().filter(|m| m.is_file())?;
            Some(Record {
                name,
                check,
                unix_ms,
                bytes: meta.len(),
            })
        })
        .collect();
    out.sort_by(|a, b| b.unix_ms.cmp(&a.unix_ms).then(b.name.cmp(&a.name)));
    out
}

/// `/api/flight-records`.
pub fn records_json(dir: &Path, instance: &str) -> Value {
    let list: Vec<Value> = records(dir, instance)
        .into_iter()
        .map(|r| json!({"name": r.name, "check": r.check, "unix_ms": r.unix_ms, "bytes": r.bytes}))
        .collect();
    json!({"dir": dir.display().to_string(), "records": list})
}

/// The file of record `name`, when it is one of this instance's (never a path elsewhere).
pub fn record_path(dir: &Path, instance: &str, name: &str) -> Option<PathBuf> {
    parse_name(name, instance)?;
    Some(dir.join(name))
}

#[cfg(test)]
mod tests;
