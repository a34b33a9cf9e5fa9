//! A JSON protocol client over one TCP connection (blocking, one line per result). The command
//! lines are the contract's ([`Command::to_json`]), each encoded once; the result lines are read
//! as the contract's results ([`Answer::from_value`]).

use crate::error::BenchError;
use mcm_shared::protocol::results::{Answer, Status};
use mcm_shared::protocol::{self, Command};
use std::io::{BufRead, BufReader, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::LazyLock;
use std::time::{Duration, Instant};

/// Longest wait for one result line.
pub const READ_WAIT: Duration = Duration::from_secs(15);

/// The line of `cmd` as a client sends it (without the newline).
pub fn line(cmd: impl Into<Command>) -> String {
    cmd.into().to_json().to_string()
}

pub static STATUS: LazyLock<String> = LazyLock::new(|| line(protocol::Status { detail: false }));
pub static STATUS_DETAIL: LazyLock<String> =
    LazyLock::new(|| line(protocol::Status { detail: true }));
pub static HOLD: LazyLock<String> = LazyLock::new(|| line(protocol::Hold));
pub static INFO: LazyLock<String> = LazyLock::new(|| line(protocol::Info));

pub struct Client {
    addr: SocketAddr,
    stream: TcpStream,
    reader: BufReader<TcpStream>,
    line: String,
    /// When the last result line was read, before it was parsed.
    read_at: Instant,
}

impl Client {
    pub fn connect(addr: SocketAddr) -> Result<Client, BenchError> {
        let io = |what| {
            move |source| BenchError::Io {
                addr: addr.to_string(),
                what,
                source,
            }
        };
        let stream = TcpStream::connect(addr).map_err(io("connect"))?;
        stream.set_nodelay(true).map_err(io("set TCP_NODELAY"))?;
        stream
            .set_read_timeout(Some(READ_WAIT))
            .map_err(io("set the read timeout"))?;
        let reader = BufReader::new(stream.try_clone().map_err(io("clone the socket"))?);
        Ok(Client {
            addr,
            stream,
            reader,
            line: String::new(),
            read_at: Instant::now(),
        })
    }

    fn io(&self, what: &'static str, source: std::io::Error) -> BenchError {
        BenchError::Io {
            addr: self.addr.to_string(),
            what,
            source,
        }
    }

    /// Send one command line (`json` without the newline).
    pub fn send(&mut self, json: &str) -> Result<(), BenchError> {
        let mut line = String::with_capacity(json.len() + 1);
        line.push_str(json);
        line.push('\n');
        self.stream
            .write_all(line.as_bytes())
            .map_err(|e| self.io("send a command", e))
    }

    /// Read one result line.
    pub fn recv(&mut self) -> Result<Answer, BenchError> {
        self.line.clear();
        let n = self
            .reader
            .read_line(&mut self.line)
            .map_err(|e| self.io("read a result", e))?;
        self.read_at = Instant::now();
        if n == 0 {
            return Err(self.io(
                "read a result",
                std::io::Error::new(std::io::ErrorKind::UnexpectedEof, "connection closed"),
            ));
        }
        let problem = |what: String| BenchError::Protocol {
            command: "(any)".into(),
            answer: format!("{what}: {:?}", self.line),
        };
        let v = serde_json::from_str(&self.line).map_err(|e| problem(format!("not JSON ({e})")))?;
        Answer::from_value(&v).map_err(|e| problem(e.to_string()))
    }

    /// When the last result line was read (before it was parsed): a round trip ends here.
    pub fn read_at(&self) -> Instant {
        self.read_at
    }

    /// Send one command and read its result.
    pub fn request(&mut self, json: &str) -> Result<Answer, BenchError> {
        self.send(json)?;
        self.recv()
    }

    /// Send one command and require a result that is not an ERROR.
    pub fn ok(&mut self, json: &str) -> Result<Answer, BenchError> {
        let a = self.request(json)?;
        if is_error(&a) {
            return Err(BenchError::Protocol {
                command: json.into(),
                answer: a.to_value().to_string(),
            });
        }
        Ok(a)
    }

    /// Send one command that answers a status and return it (an ERROR or another result is
    /// an error naming it).
    pub fn status(&mut self, json: &str) -> Result<Status, BenchError> {
        match self.ok(json)? {
            Answer::Status(s) => Ok(*s),
            other => Err(BenchError::Protocol {
                command: json.into(),
                answer: other.to_value().to_string(),
            }),
        }
    }

    /// Poll the detailed status until `pred` holds (at most `wait`).
    pub fn wait_status(
        &mut self,
        what: &str,
        wait: Duration,
        pred: impl Fn(&Status) -> bool,
    ) -> Result<Status, BenchError> {
        let deadline = Instant::now() + wait;
        loop {
            let s = self.status(&STATUS_DETAIL)?;
            if pred(&s) {
                return Ok(s);
            }
            if Instant::now() > deadline {
                return Err(BenchError::Setup(format!(
                    "{what}: not reached within {wait:?}; last status: {}",
                    Answer::Status(Box::new(s)).to_value()
                )));
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Another handle of the socket (to shut it down from another thread).
    pub fn socket(&self) -> Result<TcpStream, BenchError> {
        self.stream
            .try_clone()
            .map_err(|e| self.io("clone the socket", e))
    }

    /// Change the socket's read timeout.
    pub fn set_read_timeout(&self, t: Duration) -> Result<(), BenchError> {
        self.stream
            .set_read_timeout(Some(t))
            .map_err(|e| self.io("set the read timeout", e))
    }
}

/// A generic ERROR result.
pub fn is_error(a: &Answer) -> bool {
    matches!(a, Answer::Generic(g) if !g.is_ok())
}

/// The status a result is, if it is one.
pub fn status_of(a: &Answer) -> Option<&Status> {
    match a {
        Answer::Status(s) => Some(s),
        _ => None,
    }
}

#[cfg(test)]
mod tests;
