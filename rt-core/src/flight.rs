//! The flight recorder: the last seconds of every cycle, kept in a preallocated ring, written
//! to a CSV file when a safety check trips.
//!
//! [`FlightRecorder::record`] and [`FlightRecorder::trigger`] run inside the cycle: they copy
//! one small record into a preallocated buffer and flip an atomic; they never allocate, lock,
//! block or touch a file. A separate writer thread (not real-time) writes the file.
//!
//! Two buffers take turns: the cycle records into one; on a trigger it hands that buffer to
//! the writer (through a wait-free [`rtrb`] ring) and goes on in the other. If the writer still
//! holds the other buffer (two errors within the time it takes to write one file), the second
//! dump is skipped and counted.
//!
//! A file appears only complete: the writer writes `<file>.tmp` and renames it to the file's
//! name when it is written, so a reader that finds the file (the gateway names it in the error
//! event) reads all of it.
//!
//! ```no_run
//! # use mcm_rt_core::flight::{FlightRecorder, Record};
//! # use mcm_shared::sample::ErrorRecord;
//! let (mut rec, writer) =
//!     FlightRecorder::start(1000, "/tmp/mcm-flight-recorder", "default").unwrap();
//! rec.record(&Record::default());
//! rec.trigger(&ErrorRecord::default()); // written to mcm_shared::sample::flight_recorder_file(..)
//! writer.stop(); // writes what is pending, then ends
//! ```

use mcm_shared::NUM_AXES;
use mcm_shared::sample::{ErrorRecord, StateSample, flight_recorder_file};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

/// One cycle as the recorder keeps it (user units: deg, deg/s, A).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Record {
    pub cycle: u64,
    pub t_ns: u64,
    pub mode: u32,
    pub flags: u32,
    /// Kind of the last command served in this cycle (0: none).
    pub command: u32,
    pub commanded: [f64; NUM_AXES],
    pub measured: [f64; NUM_AXES],
    pub velocity: [f64; NUM_AXES],
    pub current: [f64; NUM_AXES],
    pub following_error: [f64; NUM_AXES],
    pub i2t: [f64; NUM_AXES],
    pub sim_true: [f64; NUM_AXES],
}

impl Record {
    /// The record of a published state sample.
    pub fn of(s: &StateSample, command: u32) -> Record {
        Record {
            cycle: s.seq,
            t_ns: s.t_ns,
            mode: s.mode,
            flags: s.flags,
            command,
            commanded: s.commanded_position,
            measured: s.measured_position,
            velocity: s.velocity,
            current: s.current,
            following_error: s.following_error,
            i2t: s.i2t,
            sim_true: s.sim_true_position,
        }
    }
}

/// The last cycles: a ring of `records`, the next slot to write and how many are held.
/// Hand-written: `heapless::HistoryBuffer` does the same, but its capacity is a compile-time
/// constant and this one comes from the configuration.
struct History {
    records: Box<[Record]>,
    next: usize,
    held: usize,
}

impl History {
    fn new(capacity: usize) -> History {
        History {
            records: vec![Record::default(); capacity].into_boxed_slice(),
            next: 0,
            held: 0,
        }
    }

    /// Inside the cycle: a copy into the preallocated slots.
    fn push(&mut self, r: &Record) {
        let n = self.records.len();
        self.records[self.next] = *r;
        self.next = (self.next + 1) % n;
        self.held = (self.held + 1).min(n);
    }

    fn clear(&mut self) {
        self.next = 0;
        self.held = 0;
    }
}

/// A full history handed to the writer, with the error to write it for.
struct Dump {
    history: History,
    error: ErrorRecord,
}

struct Shared {
    stop: AtomicBool,
    written: AtomicU64,
    skipped: AtomicU64,
}

/// The cycle's side of the recorder.
pub struct FlightRecorder {
    active: History,
    /// The other buffer while the cycle holds it (otherwise the writer does, or it is on its
    /// way back in `from_writer`).
    spare: Option<History>,
    /// Buffers move between the cycle and the writer through two [`rtrb`] rings: moving a
    /// `Box` through them is wait-free and allocates nothing.
    to_writer: rtrb::Producer<Dump>,
    from_writer: rtrb::Consumer<History>,
    shared: Arc<Shared>,
}

/// The writer thread; stop it (or drop it) to flush pending files.
pub struct FlightWriter {
    shared: Arc<Shared>,
    handle: Option<std::thread::JoinHandle<()>>,
}

impl FlightWriter {
    /// Files written so far.
    pub fn written(&self) -> u64 {
        self.shared.written.load(Ordering::Relaxed)
    }

    /// Write what is pending, then stop the thread.
    pub fn stop(self) {
        drop(self);
    }
}

impl Drop for FlightWriter {
    /// A set-up that fails after the recorder started still ends its thread.
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Release);
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

impl FlightRecorder {
    /// Allocate two buffers of `capacity` records and start the writer thread, which writes
    /// into `dir` the files named by [`flight_recorder_file`] for `instance`.
    pub fn start(
        capacity: usize,
        dir: &str,
        instance: &str,
    ) -> std::io::Result<(FlightRecorder, FlightWriter)> {
        let capacity = capacity.max(1);
        let shared = Arc::new(Shared {
            stop: AtomicBool::new(false),
            written: AtomicU64::new(0),
            skipped: AtomicU64::new(0),
        });
        // Two buffers in all, one always with the cycle: one slot each way is enough.
        let (to_writer, from_cycle) = rtrb::RingBuffer::new(1);
        let (to_cycle, from_writer) = rtrb::RingBuffer::new(1);
        let writer = Writer {
            from_cycle,
            to_cycle,
            shared: shared.clone(),
            dir: dir.to_string(),
            instance: instance.to_string(),
        };
        let handle = std::thread::Builder::new()
            .name("mcm-flight-recorder".into())
            .spawn(move || writer.run())?;
        Ok((
            FlightRecorder {
                active: History::new(capacity),
                spare: Some(History::new(capacity)),
                to_writer,
                from_writer,
                shared: shared.clone(),
            },
            FlightWriter {
                shared,
                handle: Some(handle),
            },
        ))
    }

    /// Dumps skipped because the writer was still busy with the previous one.
    pub fn skipped(&self) -> u64 {
        self.shared.skipped.load(Ordering::Relaxed)
    }

    /// Keep one cycle. Inside the cycle: a copy into the preallocated ring.
    pub fn record(&mut self, r: &Record) {
        self.active.push(r);
    }

    /// Hand the recorded cycles to the writer, to be written for `error`; go on recording in
    /// the other buffer.
    pub fn trigger(&mut self, error: &ErrorRecord) {
        let Some(mut other) = self.spare.take().or_else(|| self.from_writer.pop().ok()) else {
            self.shared.skipped.fetch_add(1, Ordering::Relaxed);
            return;
        };
        other.clear();
        let history = std::mem::replace(&mut self.active, other);
        let dump = Dump {
            history,
            error: *error,
        };
        if let Err(rtrb::PushError::Full(dump)) = self.to_writer.push(dump) {
            // Cannot happen (the writer holds at most one buffer); keep both buffers anyway.
            self.spare = Some(std::mem::replace(&mut self.active, dump.history));
            self.shared.skipped.fetch_add(1, Ordering::Relaxed);
        }
    }
}

/// The writer thread's side (not real-time).
struct Writer {
    from_cycle: rtrb::Consumer<Dump>,
    to_cycle: rtrb::Producer<History>,
    shared: Arc<Shared>,
    dir: String,
    instance: String,
}

impl Writer {
    fn run(mut self) {
        loop {
            let stopping = self.shared.stop.load(Ordering::Acquire);
            while let Ok(Dump { history, error }) = self.from_cycle.pop() {
                let path = flight_recorder_file(&self.dir, &self.instance, &error);
                let result = write_csv(&path, &history.records, history.next, history.held);
                // Give the buffer back; the ring has room (one buffer is in flight at a time).
                let _ = self.to_cycle.push(history);
                match result {
                    Ok(()) => {
                        self.shared.written.fetch_add(1, Ordering::Relaxed);
                        // The trip in the log (the journal under systemd), once its file is
                        // there: the clients were told by the gateway; the operator reads it
                        // here.
                        eprintln!("mcm-rt: {}", trip_line(&error, &path));
                    }
                    Err(e) => {
                        eprintln!(
                            "mcm-rt: cannot write the flight recorder file {}: {e}",
                            path.display()
                        );
                    }
                }
            }
            if stopping {
                return;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

/// A safety trip in words, with the flight recorder's file, as the log shows it.
fn trip_line(error: &ErrorRecord, path: &Path) -> String {
    let what = match mcm_shared::reply::SafetyError::decode(error) {
        Ok(Some(e)) => e.to_string(),
        Ok(None) => "safety check tripped (no record)".to_string(),
        Err(e) => format!("safety check tripped, but its record cannot be read ({e})"),
    };
    format!("{what}; flight recorder: {}", path.display())
}

/// Write the file at `path` with `body` so that it appears only complete: into `<path>.tmp`,
/// renamed to `path` once written (removed if writing fails). Outside the cycle.
fn write_whole(
    path: &Path,
    body: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    let written = std::fs::File::create(&tmp).and_then(|file| {
        let mut f = std::io::BufWriter::new(file);
        body(&mut f)?;
        f.flush()
    });
    match written {
        Ok(()) => std::fs::rename(&tmp, path),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}

fn write_csv(path: &Path, records: &[Record], next: usize, held: usize) -> std::io::Result<()> {
    write_whole(path, |f| write_rows(f, records, next, held))
}

/// The CSV of the `held` records of the ring `records` that ends before `next`, oldest first.
fn write_rows(
    f: &mut dyn Write,
    records: &[Record],
    next: usize,
    held: usize,
) -> std::io::Result<()> {
    write!(f, "cycle,t_s,mode,flags,command")?;
    for name in [
        "commanded_deg",
        "measured_deg",
        "velocity_deg_s",
        "current_a",
        "following_error_deg",
        "i2t",
        "sim_true_deg",
    ] {
        for axis in 1..=NUM_AXES {
            write!(f, ",{name}_{axis}")?;
        }
    }
    writeln!(f)?;
    let n = records.len();
    let start = (next + n - held) % n;
    for k in 0..held {
        let r = &records[(start + k) % n];
        let mode = mcm_shared::mode::Mode::try_from(r.mode)
            .map(|m| m.as_str())
            .unwrap_or("?");
        write!(
            f,
            "{},{:.6},{mode},{},{}",
            r.cycle,
            r.t_ns as f64 / 1e9,
            r.flags,
            r.command
        )?;
        for arr in [
            &r.commanded,
            &r.measured,
            &r.velocity,
            &r.current,
            &r.following_error,
            &r.i2t,
            &r.sim_true,
        ] {
            for x in arr.iter() {
                write!(f, ",{x:.6}")?;
            }
        }
        writeln!(f)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests;
