//! A candump logger for any bus: [`LoggingBus<B>`] wraps a [`Bus`] and records every frame sent and
//! received, with a `clock_gettime` timestamp and its direction, into a preallocated wait-free
//! single-producer single-consumer ring ([`rtrb`]). A separate, non-real-time writer thread drains
//! the ring and writes `candump -L` lines to a file:
//!
//! ```text
//! (1735270496.916858) can0 185#3702A0860100
//! (1735270496.916901) can0 205#0F00048701000000 T      <- with LogOptions::direction_suffix
//! ```
//!
//! The file holds frame lines only, as `candump -L` writes them, so that every reader of that
//! format takes it as it is (`canplayer`, python-can's `CanutilsLogReader`, `socketcan::dump`).
//! The cycle side (`send`/`recv`) never blocks and never allocates: when the ring is full the
//! frame is counted as dropped. The writer says so on stderr when the count changes, and at the
//! end how many frames it wrote and how many were dropped (also in [`LogSummary`]).
//! [`parse_line`] reads the lines back (comments and blank lines give `Ok(None)`).
//!
//! Runs inside the cycle: `LoggingBus::send`/`recv`. Not in the cycle: `new`, `finish`, the
//! writer thread, `parse_line`.

use super::{Bus, BusError, Frame};
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

/// Which way a frame went, like `candump -x`: `T` sent by us, `R` received.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    Transmitted,
    Received,
}

impl Direction {
    pub fn letter(self) -> char {
        match self {
            Direction::Transmitted => 'T',
            Direction::Received => 'R',
        }
    }
}

/// Clock of the timestamps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogClock {
    /// Wall clock, like candump.
    Realtime,
    /// Time since boot, comparable with the cycle's `CLOCK_MONOTONIC` deadlines.
    Monotonic,
}

/// Logger settings.
#[derive(Debug, Clone, PartialEq)]
pub struct LogOptions {
    /// Ring capacity in frames (rounded up to a power of two, at least 2).
    pub capacity: usize,
    pub clock: LogClock,
    /// Append ` T` / ` R` to every line (candump -x style).
    pub direction_suffix: bool,
    /// How long the writer sleeps when the ring is empty.
    pub poll_interval: Duration,
}

impl Default for LogOptions {
    /// 16384 frames (about 4 s of the P-Rob2's ~4000 frames/s), wall clock, no suffix, 10 ms.
    fn default() -> Self {
        LogOptions {
            capacity: 16384,
            clock: LogClock::Realtime,
            direction_suffix: false,
            poll_interval: Duration::from_millis(10),
        }
    }
}

/// The logger could not be started or writing failed.
#[derive(Debug, thiserror::Error)]
pub enum CandumpError {
    #[error("cannot create candump log {path}: {source}")]
    Create {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error("cannot start the candump writer thread for {path}: {source}")]
    Spawn {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error("writing candump log {path} failed: {source}")]
    Write {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error("the candump writer thread for {path} panicked")]
    WriterPanicked { path: PathBuf },
}

/// Counts at the end of a log.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LogSummary {
    pub written: u64,
    pub dropped: u64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct Record {
    t_ns: u64,
    frame: Frame,
    received: bool,
}

/// What the cycle side and the writer share besides the ring itself.
struct Shared {
    /// Ring capacity in records (`LogOptions::capacity` rounded up to a power of two, >= 2).
    capacity: usize,
    dropped: AtomicU64,
    stop: AtomicBool,
    /// The writer may drain (tests hold it back to force a full ring).
    go: AtomicBool,
}

/// The cycle's end of the ring: [`rtrb`] is wait-free and allocates only when it is created.
struct Producer {
    ring: rtrb::Producer<Record>,
    shared: Arc<Shared>,
}

impl Producer {
    /// Store one record; `false` (and counted as dropped) when the ring is full.
    fn push(&mut self, rec: Record) -> bool {
        if self.ring.push(rec).is_err() {
            self.shared.dropped.fetch_add(1, Ordering::Relaxed);
            return false;
        }
        true
    }
}

/// The writer's end of the ring.
struct Consumer {
    ring: rtrb::Consumer<Record>,
    shared: Arc<Shared>,
}

impl Consumer {
    fn pop(&mut self) -> Option<Record> {
        self.ring.pop().ok()
    }
}

/// A ring of at least `capacity` records (rounded up to a power of two, at least 2).
fn ring(capacity: usize, go: bool) -> (Producer, Consumer) {
    let capacity = capacity.max(2).next_power_of_two();
    let shared = Arc::new(Shared {
        capacity,
        dropped: AtomicU64::new(0),
        stop: AtomicBool::new(false),
        go: AtomicBool::new(go),
    });
    let (p, c) = rtrb::RingBuffer::new(capacity);
    (
        Producer {
            ring: p,
            shared: Arc::clone(&shared),
        },
        Consumer { ring: c, shared },
    )
}

fn now_ns(clock: LogClock) -> u64 {
    let id = match clock {
        LogClock::Realtime => libc::CLOCK_REALTIME,
        LogClock::Monotonic => libc::CLOCK_MONOTONIC,
    };
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec and `id` a clock every Linux kernel has.
    unsafe { libc::clock_gettime(id, &mut ts) };
    (ts.tv_sec as u64)
        .saturating_mul(1_000_000_000)
        .saturating_add(ts.tv_nsec as u64)
}

/// Write one candump -L line (with newline).
pub fn write_line(
    out: &mut impl Write,
    t_ns: u64,
    interface: &str,
    frame: &Frame,
    direction: Option<Direction>,
) -> io::Result<()> {
    let t_us = t_ns / 1000;
    write!(
        out,
        "({}.{:06}) {} {}",
        t_us / 1_000_000,
        t_us % 1_000_000,
        interface,
        frame
    )?;
    if let Some(d) = direction {
        write!(out, " {}", d.letter())?;
    }
    out.write_all(b"\n")
}

/// Wraps a bus and logs every frame to a candump file (see the module documentation).
pub struct LoggingBus<B: Bus> {
    inner: B,
    producer: Producer,
    clock: LogClock,
    path: PathBuf,
    writer: Option<JoinHandle<io::Result<u64>>>,
}

impl<B: Bus> LoggingBus<B> {
    /// Create (truncate) `path` and start the writer thread. `interface` is the name written in
    /// every line (e.g. `can0`, or `sim0` for the simulation).
    pub fn new(
        inner: B,
        path: impl AsRef<Path>,
        interface: &str,
        options: LogOptions,
    ) -> Result<Self, CandumpError> {
        Self::build(inner, path.as_ref(), interface, options, true)
    }

    fn build(
        inner: B,
        path: &Path,
        interface: &str,
        options: LogOptions,
        go: bool,
    ) -> Result<Self, CandumpError> {
        let file = File::create(path).map_err(|source| CandumpError::Create {
            path: path.to_path_buf(),
            source,
        })?;
        let (producer, consumer) = ring(options.capacity, go);
        let iface = interface.to_owned();
        let clock = options.clock;
        let writer = std::thread::Builder::new()
            .name("mcm-candump".into())
            .spawn({
                let shown = path.display().to_string();
                move || writer_loop(consumer, BufWriter::new(file), &iface, &options, &shown)
            })
            .map_err(|source| CandumpError::Spawn {
                path: path.to_path_buf(),
                source,
            })?;
        Ok(LoggingBus {
            inner,
            producer,
            clock,
            path: path.to_path_buf(),
            writer: Some(writer),
        })
    }

    pub fn inner(&self) -> &B {
        &self.inner
    }

    pub fn inner_mut(&mut self) -> &mut B {
        &mut self.inner
    }

    /// Frames not logged so far because the ring was full.
    pub fn dropped(&self) -> u64 {
        self.producer.shared.dropped.load(Ordering::Relaxed)
    }

    fn log(&mut self, frame: &Frame, received: bool) {
        let rec = Record {
            t_ns: now_ns(self.clock),
            frame: *frame,
            received,
        };
        self.producer.push(rec);
    }

    fn shutdown(&mut self) -> Result<LogSummary, CandumpError> {
        let Some(handle) = self.writer.take() else {
            return Ok(LogSummary {
                written: 0,
                dropped: self.dropped(),
            });
        };
        self.producer.shared.go.store(true, Ordering::Release);
        self.producer.shared.stop.store(true, Ordering::Release);
        handle.thread().unpark();
        let written = handle
            .join()
            .map_err(|_| CandumpError::WriterPanicked {
                path: self.path.clone(),
            })?
            .map_err(|source| CandumpError::Write {
                path: self.path.clone(),
                source,
            })?;
        Ok(LogSummary {
            written,
            dropped: self.dropped(),
        })
    }

    /// Stop the writer after it has written everything in the ring and the end line; returns
    /// the counts (the inner bus is dropped).
    pub fn finish(mut self) -> Result<LogSummary, CandumpError> {
        self.shutdown()
    }
}

impl<B: Bus> Drop for LoggingBus<B> {
    fn drop(&mut self) {
        let _ = self.shutdown();
    }
}

impl<B: Bus> Bus for LoggingBus<B> {
    fn send(&mut self, frame: &Frame) -> Result<(), BusError> {
        let r = self.inner.send(frame);
        if r.is_ok() {
            self.log(frame, false);
        }
        r
    }

    fn recv(&mut self, deadline_ns: u64) -> Result<Option<Frame>, BusError> {
        let r = self.inner.recv(deadline_ns);
        if let Ok(Some(f)) = &r {
            self.log(f, true);
        }
        r
    }
}

/// Drain the ring into `out` (the file `path`) until told to stop.
fn writer_loop(
    mut c: Consumer,
    mut out: BufWriter<File>,
    iface: &str,
    opt: &LogOptions,
    path: &str,
) -> io::Result<u64> {
    let mut written = 0u64;
    let mut reported_dropped = 0u64;
    loop {
        let stopping = c.shared.stop.load(Ordering::Acquire);
        if !c.shared.go.load(Ordering::Acquire) {
            std::thread::park_timeout(opt.poll_interval);
            continue;
        }
        let mut n = 0;
        while let Some(rec) = c.pop() {
            let dir = opt.direction_suffix.then_some(if rec.received {
                Direction::Received
            } else {
                Direction::Transmitted
            });
            write_line(&mut out, rec.t_ns, iface, &rec.frame, dir)?;
            n += 1;
        }
        written += n;
        let dropped = c.shared.dropped.load(Ordering::Relaxed);
        if dropped != reported_dropped && !stopping {
            // Not in the file: a comment line is no candump line, and readers refuse it.
            eprintln!(
                "mcm-candump: {path}: {dropped} frames dropped so far (log ring of {} full)",
                c.shared.capacity
            );
            reported_dropped = dropped;
        }
        if stopping {
            break;
        }
        if n == 0 {
            out.flush()?;
            std::thread::park_timeout(opt.poll_interval);
        }
    }
    out.flush()?;
    let dropped = c.shared.dropped.load(Ordering::Relaxed);
    eprintln!("mcm-candump: {path}: end of log, {written} frames written, {dropped} dropped");
    Ok(written)
}

/// One parsed candump line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LogLine<'a> {
    /// Timestamp in microseconds.
    pub t_us: u64,
    pub interface: &'a str,
    pub frame: Frame,
    pub direction: Option<Direction>,
}

/// A line is not a candump -L line of a classic 11-bit frame.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("candump line {line:?}: {problem}")]
pub struct LogParseError {
    pub line: String,
    pub problem: &'static str,
}

fn hex_nibble(b: u8) -> Option<u8> {
    (b as char).to_digit(16).map(|v| v as u8)
}

/// Parse `(sec.usec) iface ID#DATA [T|R]`. Blank lines and `#` comments give `Ok(None)`.
pub fn parse_line(line: &str) -> Result<Option<LogLine<'_>>, LogParseError> {
    let err = |problem| LogParseError {
        line: line.to_owned(),
        problem,
    };
    let trimmed = line.trim();
    if trimmed.is_empty() || trimmed.starts_with('#') {
        return Ok(None);
    }
    let mut fields = trimmed.split_ascii_whitespace();
    let ts = fields.next().ok_or_else(|| err("empty line"))?;
    let ts = ts
        .strip_prefix('(')
        .and_then(|t| t.strip_suffix(')'))
        .ok_or_else(|| err("timestamp must be (seconds.microseconds)"))?;
    let (sec, usec) = ts
        .split_once('.')
        .ok_or_else(|| err("timestamp must be (seconds.microseconds)"))?;
    if usec.len() != 6 {
        return Err(err("timestamp needs exactly 6 digits of microseconds"));
    }
    let sec: u64 = sec
        .parse()
        .map_err(|_| err("timestamp seconds are not a number"))?;
    let usec: u64 = usec
        .parse()
        .map_err(|_| err("timestamp microseconds are not a number"))?;
    let interface = fields.next().ok_or_else(|| err("missing interface"))?;
    let body = fields.next().ok_or_else(|| err("missing frame"))?;
    let direction = match fields.next() {
        None => None,
        Some("T") | Some("t") => Some(Direction::Transmitted),
        Some("R") | Some("r") => Some(Direction::Received),
        Some(_) => return Err(err("direction must be T or R")),
    };
    if fields.next().is_some() {
        return Err(err("unexpected text after the direction"));
    }
    let (id, data) = body
        .split_once('#')
        .ok_or_else(|| err("frame must be ID#DATA"))?;
    if id.len() != 3 {
        return Err(err("only 3-digit (11-bit) ids are supported"));
    }
    let id = u16::from_str_radix(id, 16).map_err(|_| err("id is not hex"))?;
    let bytes = data.as_bytes();
    if bytes.len() % 2 != 0 || bytes.len() > 16 {
        return Err(err(
            "data must be 0..=8 bytes as pairs of hex digits (no RTR, no CAN FD)",
        ));
    }
    let mut payload = [0u8; 8];
    for (i, pair) in bytes.chunks(2).enumerate() {
        let (Some(h), Some(l)) = (hex_nibble(pair[0]), hex_nibble(pair[1])) else {
            return Err(err("data is not hex"));
        };
        payload[i] = h << 4 | l;
    }
    let frame = Frame::new(id, &payload[..bytes.len() / 2]).ok_or_else(|| err("id above 0x7FF"))?;
    Ok(Some(LogLine {
        t_us: sec * 1_000_000 + usec,
        interface,
        frame,
        direction,
    }))
}

#[cfg(test)]
mod tests;
