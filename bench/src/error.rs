//! What can stop the benchmark.

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
    #[error("{0}")]
    Setup(String),
}
