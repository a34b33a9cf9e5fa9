//! What can stop the benchmark.

use mcm_client::shm::ports::{OpenError, SendError};

/// An error of the benchmark tool; each message says what was wrong and where.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    #[error("starting the MCM under test: {0}")]
    Start(String),
    #[error("cyclictest: {0}")]
    Cyclictest(String),
    #[error("JSON connection to {addr}: {what}: {source}")]
    Io {
        addr: String,
        what: &'static str,
        source: std::io::Error,
    },
    #[error("unexpected answer to {command}: {answer}")]
    Protocol { command: String, answer: String },
    #[error("shared memory of instance {instance}: {what}")]
    Shm { instance: String, what: String },
    /// Opening the core's services (the message names the instance and the service).
    #[error(transparent)]
    ShmOpen(#[from] OpenError),
    /// Publishing a command (the message names the command and the service).
    #[error(transparent)]
    ShmSend(#[from] SendError),
    #[error("{0}")]
    Setup(String),
}
