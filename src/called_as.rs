//! `mcm` called by another name: the Debian package's links `mcm-rt`, `mcm-gateway`,
//! `mcm-ros2` and `mcm-virtual-arm` to it (docs/deploy.md) run that program, as `mcm rt ...`,
//! `mcm gateway ...`, `mcm ros2 ...` and `mcm virtual-arm ...` do. The launcher itself starts its children as `mcm rt ...` with the name
//! `mcm-rt` as their argv[0] (for `ps`): there the subcommand follows the name already.

use std::ffi::{OsStr, OsString};
use std::path::Path;

/// The arguments after the program name as `mcm` reads them: for a program called by the name
/// of one of the programs, with that program's subcommand first (unless it is there already).
pub fn arguments(program: &OsStr, mut rest: Vec<OsString>) -> Vec<OsString> {
    let called = Path::new(program).file_name().and_then(|n| n.to_str());
    let subcommand = match called {
        Some("mcm-rt") => "rt",
        Some("mcm-gateway") => "gateway",
        Some("mcm-ros2") => "ros2",
        Some("mcm-virtual-arm") => "virtual-arm",
        _ => return rest,
    };
    if rest.first().and_then(|a| a.to_str()) != Some(subcommand) {
        rest.insert(0, subcommand.into());
    }
    rest
}

#[cfg(test)]
mod tests;
