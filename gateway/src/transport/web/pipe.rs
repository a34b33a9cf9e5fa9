//! The pipe between a page's WebSocket ([`super::socket`]) and the connection code that serves
//! it ([`crate::transport::json::connection::serve_stream`]): each message from the page is one
//! command line in ([`CommandReader`]), each result line out is one message to the page
//! ([`PageOut`]).
//!
//! The connection reads its next command only when it has run the one before, and each read
//! hands it at most one message, so the messages in the pipe are the page's commands waiting
//! to run. Among them, consecutive `hold`s are one: a `hold` that arrives while the last waiting
//! message is the same `hold` joins it, and when that `hold` has run, its result goes to the
//! page once for every `hold` it stands for (the page matches results to its commands by their
//! order). A flood of `hold`s thus keeps at most one `hold` running and one waiting, however
//! many arrive. The waiting messages are bounded in bytes ([`PIPE_BYTES`]), and so are the
//! results not yet sent: the page, then the connection, waits for room.

use mcm_shared::config::RobotConfig;
use mcm_shared::error_code::ErrorCode;
use mcm_shared::protocol::Command;
use serde_json::Value;
use std::collections::VecDeque;
use std::io;
use std::pin::Pin;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::task::{Context, Poll, Waker};
use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};

/// Bytes of waiting messages, and of results not yet sent, the pipe holds each way (at least
/// one message whatever its size).
pub const PIPE_BYTES: usize = 2 * mcm_shared::protocol::MAX_COMMAND_BYTES;

/// The longest message looked at as a possible `hold` (a `hold` is 18 bytes).
const HOLD_BYTES: usize = 256;

/// A message waiting to run, with its line end.
struct Waiting {
    line: Vec<u8>,
    /// How many `hold`s it stands for; 0: it is no `hold`.
    holds: u64,
}

#[derive(Default)]
struct State {
    waiting: VecDeque<Waiting>,
    waiting_bytes: usize,
    /// The page sends no more: the connection reads to the end of what waits.
    page_gone: bool,
    /// The connection reads no more.
    reader_gone: bool,
    reader: Option<Waker>,
    page_in: Option<Waker>,
    /// How many more times the taken `hold`'s result goes to the page.
    owed: u64,
    /// Result lines, each with the number of times it is sent.
    results: VecDeque<(String, u64)>,
    results_bytes: usize,
    /// The connection writes no more.
    writer_gone: bool,
    /// The page takes no more.
    page_out_gone: bool,
    writer: Option<Waker>,
    page_out: Option<Waker>,
}

type Shared = Arc<Mutex<State>>;

fn lock(s: &Shared) -> MutexGuard<'_, State> {
    s.lock().unwrap_or_else(PoisonError::into_inner)
}

fn wake(w: &mut Option<Waker>) {
    if let Some(w) = w.take() {
        w.wake();
    }
}

/// A new pipe for a page of a gateway with configuration `cfg`: the page's two ends and the
/// connection's two.
pub fn pipe(cfg: Arc<RobotConfig>) -> (PageIn, CommandReader, ResultWriter, PageOut) {
    let shared = Shared::default();
    (
        PageIn {
            shared: shared.clone(),
            cfg,
        },
        CommandReader {
            shared: shared.clone(),
            current: Vec::new(),
            pos: 0,
        },
        ResultWriter {
            shared: shared.clone(),
            partial: Vec::new(),
        },
        PageOut { shared },
    )
}

/// The connection is gone: the page's message cannot be run.
#[derive(Debug, PartialEq, Eq)]
pub struct Closed;

/// Where the page's messages go in.
pub struct PageIn {
    shared: Shared,
    cfg: Arc<RobotConfig>,
}

impl PageIn {
    /// Queue `message` as one command line, after waiting for room.
    pub async fn send(&self, message: Vec<u8>) -> Result<(), Closed> {
        let hold = is_hold(&message, &self.cfg);
        let mut line = Some(message);
        std::future::poll_fn(|cx| {
            let mut s = lock(&self.shared);
            if s.reader_gone {
                return Poll::Ready(Err(Closed));
            }
            let Some(msg) = line.take() else {
                return Poll::Ready(Ok(()));
            };
            if hold
                && let Some(last) = s.waiting.back_mut()
                && last.holds > 0
                && last.line[..last.line.len() - 1] == msg[..]
            {
                last.holds += 1;
                return Poll::Ready(Ok(()));
            }
            if !s.waiting.is_empty() && s.waiting_bytes + msg.len() + 1 > PIPE_BYTES {
                line = Some(msg);
                s.page_in = Some(cx.waker().clone());
                return Poll::Pending;
            }
            let mut l = msg;
            l.push(b'\n');
            s.waiting_bytes += l.len();
            s.waiting.push_back(Waiting {
                line: l,
                holds: u64::from(hold),
            });
            wake(&mut s.reader);
            Poll::Ready(Ok(()))
        })
        .await
    }
}

impl Drop for PageIn {
    fn drop(&mut self) {
        let mut s = lock(&self.shared);
        s.page_gone = true;
        wake(&mut s.reader);
    }
}

/// Whether `message` is a `hold` (and nothing else: one line, no more than one command).
fn is_hold(message: &[u8], cfg: &RobotConfig) -> bool {
    message.len() <= HOLD_BYTES
        && !message.contains(&b'\n')
        && std::str::from_utf8(message)
            .is_ok_and(|t| matches!(Command::from_json(t, cfg), Ok(Command::Hold(_))))
}

/// The connection's input: one waiting message per read at most.
pub struct CommandReader {
    shared: Shared,
    current: Vec<u8>,
    pos: usize,
}

impl AsyncRead for CommandReader {
    fn poll_read(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        let me = self.get_mut();
        if me.pos == me.current.len() {
            let mut s = lock(&me.shared);
            match s.waiting.pop_front() {
                Some(w) => {
                    s.waiting_bytes -= w.line.len();
                    // The result written next answers the `hold`s this one stands for.
                    s.owed = w.holds.saturating_sub(1);
                    wake(&mut s.page_in);
                    me.current = w.line;
                    me.pos = 0;
                }
                None if s.page_gone => return Poll::Ready(Ok(())),
                None => {
                    s.reader = Some(cx.waker().clone());
                    return Poll::Pending;
                }
            }
        }
        let n = buf.remaining().min(me.current.len() - me.pos);
        buf.put_slice(&me.current[me.pos..me.pos + n]);
        me.pos += n;
        Poll::Ready(Ok(()))
    }
}

impl Drop for CommandReader {
    fn drop(&mut self) {
        let mut s = lock(&self.shared);
        s.reader_gone = true;
        wake(&mut s.page_in);
    }
}

/// The connection's output, cut into result lines.
pub struct ResultWriter {
    shared: Shared,
    partial: Vec<u8>,
}

impl AsyncWrite for ResultWriter {
    fn poll_write(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bytes: &[u8],
    ) -> Poll<io::Result<usize>> {
        let me = self.get_mut();
        let mut s = lock(&me.shared);
        if s.page_out_gone {
            return Poll::Ready(Err(io::ErrorKind::BrokenPipe.into()));
        }
        if s.results_bytes >= PIPE_BYTES {
            s.writer = Some(cx.waker().clone());
            return Poll::Pending;
        }
        me.partial.extend_from_slice(bytes);
        while let Some(end) = me.partial.iter().position(|b| *b == b'\n') {
            let line: Vec<u8> = me.partial.drain(..=end).take(end).collect();
            let line = String::from_utf8_lossy(&line).into_owned();
            let mut times = 1;
            // What the connection writes while a command runs comes before its result.
            if s.owed > 0 && !is_interjection(&line) {
                times += std::mem::take(&mut s.owed);
            }
            s.results_bytes += line.len();
            s.results.push_back((line, times));
        }
        wake(&mut s.page_out);
        Poll::Ready(Ok(bytes.len()))
    }

    fn poll_flush(self: Pin<&mut Self>, _: &mut Context<'_>) -> Poll<io::Result<()>> {
        Poll::Ready(Ok(()))
    }

    fn poll_shutdown(self: Pin<&mut Self>, _: &mut Context<'_>) -> Poll<io::Result<()>> {
        Poll::Ready(Ok(()))
    }
}

impl Drop for ResultWriter {
    fn drop(&mut self) {
        let mut s = lock(&self.shared);
        s.writer_gone = true;
        wake(&mut s.page_out);
    }
}

/// Whether `line` is one the connection may write while a command runs (a safety error: it
/// names its `check`; or the notice that some were lost), not that command's result.
fn is_interjection(line: &str) -> bool {
    serde_json::from_str::<Value>(line).is_ok_and(|v| {
        v.get("check").is_some() || v["error_code"] == ErrorCode::EventsLost.as_str()
    })
}

/// Where the results come out for the page.
pub struct PageOut {
    shared: Shared,
}

impl PageOut {
    /// The next result line and how many times to send it; `None` when the connection ended.
    pub async fn next(&mut self) -> Option<(String, u64)> {
        std::future::poll_fn(|cx| {
            let mut s = lock(&self.shared);
            match s.results.pop_front() {
                Some((line, times)) => {
                    s.results_bytes -= line.len();
                    wake(&mut s.writer);
                    Poll::Ready(Some((line, times)))
                }
                None if s.writer_gone => Poll::Ready(None),
                None => {
                    s.page_out = Some(cx.waker().clone());
                    Poll::Pending
                }
            }
        })
        .await
    }
}

impl Drop for PageOut {
    fn drop(&mut self) {
        let mut s = lock(&self.shared);
        s.page_out_gone = true;
        wake(&mut s.writer);
    }
}

#[cfg(test)]
mod tests;
