//! Whether DDS still runs in this process: RustDDS ends its threads (its participant's event
//! loop and discovery) when their wait for the network fails for any reason but an interruption
//! by a signal (`vendor/rustdds/MCM-PATCHES.md`). A node whose DDS ended neither hears goals nor
//! answers them: it ends with this error, and the launcher (or systemd) starts it again.

use std::path::Path;

/// The threads that carry DDS, by their thread ids, found when the participant was made.
#[derive(Debug, Clone)]
pub struct DdsThreads {
    tids: Vec<String>,
}

/// DDS's threads ended.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "DDS stopped in this process: {ended} of RustDDS's {total} threads ended (RustDDS ends them when its wait for the network fails)"
)]
pub struct DdsEnded {
    pub ended: usize,
    pub total: usize,
}

const TASKS: &str = "/proc/self/task";

impl DdsThreads {
    /// The process's RustDDS threads now (their names begin with "RustDDS").
    pub fn find() -> DdsThreads {
        let tids = std::fs::read_dir(TASKS)
            .into_iter()
            .flatten()
            .flatten()
            .filter(|t| {
                std::fs::read_to_string(t.path().join("comm"))
                    .is_ok_and(|name| name.starts_with("RustDDS"))
            })
            .map(|t| t.file_name().to_string_lossy().into_owned())
            .collect();
        DdsThreads { tids }
    }

    /// Every thread found at the start still runs.
    pub fn check(&self) -> Result<(), DdsEnded> {
        let ended = self
            .tids
            .iter()
            .filter(|tid| !Path::new(TASKS).join(tid).exists())
            .count();
        match ended {
            0 => Ok(()),
            ended => Err(DdsEnded {
                ended,
                total: self.tids.len(),
            }),
        }
    }
}

#[cfg(test)]
mod tests;
