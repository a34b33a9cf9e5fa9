//! A JSON protocol client over one TCP connection (blocking, one line per result).

use crate::error::BenchError;
use serde_json::Value;
use std::io::{BufRead, BufReader, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::{Duration, Instant};

/// Longest wait for one result line.
pub const READ_WAIT: Duration = Duration::from_secs(15);

pub const STATUS: &str = r#"{"command":"status"}"#;
pub const STATUS_DETAIL: &str = r#"{"command":"status","arguments":{"detail":true}}"#;
pub const HOLD: &str = r#"{"command":"hold"}"#;

pub struct Client {
    addr: SocketAddr,
    stream: TcpStream,
    reader: BufReader<TcpStream>,
    line: String,
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
    pub fn recv(&mut self) -> Result<Value, BenchError> {
        self.line.clear();
        let n = self
            .reader
            .read_line(&mut self.line)
            .map_err(|e| self.io("read a result", e))?;
        if n == 0 {
            return Err(self.io(
                "read a result",
                std::io::Error::new(std::io::ErrorKind::UnexpectedEof, "connection closed"),
            ));
        }
        serde_json::from_str(&self.line).map_err(|e| BenchError::Protocol {
            command: "(any)".into(),
            answer: format!("not JSON ({e}): {:?}", self.line),
        })
    }

    /// Send one command and read its result.
    pub fn request(&mut self, json: &str) -> Result<Value, BenchError> {
        self.send(json)?;
        self.recv()
    }

    /// Send one command and require a result that is not an ERROR.
    pub fn ok(&mut self, json: &str) -> Result<Value, BenchError> {
        let v = self.request(json)?;
        if is_error(&v) {
            return Err(BenchError::Protocol {
                command: json.into(),
                answer: v.to_string(),
            });
        }
        Ok(v)
    }

    /// Poll the detailed status until `pred` holds (at most `wait`).
    pub fn wait_status(
        &mut self,
        what: &str,
        wait: Duration,
        pred: impl Fn(&Value) -> bool,
    ) -> Result<Value, BenchError> {
        let deadline = Instant::now() + wait;
        loop {
            let s = self.request(STATUS_DETAIL)?;
            if pred(&s) {
                return Ok(s);
            }
            if Instant::now() > deadline {
                return Err(BenchError::Setup(format!(
                    "{what}: not reached within {wait:?}; last status: {s}"
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
pub fn is_error(v: &Value) -> bool {
    v["result_type"] == "generic" && v["error_status"] == "ERROR"
}

/// A status result (`result_type` "status").
pub fn is_status(v: &Value) -> bool {
    v["result_type"] == "status"
}

/// The robot time of a status result [s] (`axis_states.time[0]`).
pub fn status_time(v: &Value) -> Option<f64> {
    v["axis_states"]["time"][0].as_f64()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn classifies_results() {
        let e = json!({"result_type":"generic","error_status":"ERROR","error_message":"x"});
        let ok = json!({"result_type":"generic","error_status":"OK"});
        let s = json!({"result_type":"status","axis_states":{"time":[1.5,1.5]}});
        assert!(is_error(&e) && !is_error(&ok) && !is_error(&s));
        assert!(is_status(&s) && !is_status(&ok));
        assert_eq!(status_time(&s), Some(1.5));
        assert_eq!(status_time(&ok), None);
    }
}
