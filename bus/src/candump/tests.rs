use super::*;
use std::collections::VecDeque;

/// A bus that returns what was sent, for the logger tests.
#[derive(Default)]
struct Loopback(VecDeque<Frame>);

impl Bus for Loopback {
    fn send(&mut self, frame: &Frame) -> Result<(), BusError> {
        self.0.push_back(*frame);
        Ok(())
    }
    fn recv(&mut self, _deadline_ns: u64) -> Result<Option<Frame>, BusError> {
        Ok(self.0.pop_front())
    }
}

fn temp_path(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("mcm-candump-{}-{name}.log", std::process::id()))
}

fn frames() -> Vec<Frame> {
    vec![
        Frame::new(0x080, &[]).unwrap(),
        Frame::new(0x185, &[0x37, 0x02, 0xA0, 0x86, 0x01, 0x00, 0x00, 0x00]).unwrap(),
        Frame::new(0x605, &[0x40, 0x41, 0x60, 0, 0, 0, 0, 0]).unwrap(),
        Frame::new(0x77F, &[0x05]).unwrap(),
    ]
}

#[test]
fn lines_look_like_candump() {
    let mut s = Vec::new();
    let f = Frame::new(0x185, &[0x37, 0x02, 0xA0, 0x86, 0x01, 0x00]).unwrap();
    write_line(&mut s, 1_735_270_496_916_858_123, "can0", &f, None).unwrap();
    write_line(
        &mut s,
        1_002_135_000,
        "sim0",
        &Frame::new(0x80, &[]).unwrap(),
        Some(Direction::Transmitted),
    )
    .unwrap();
    assert_eq!(
        String::from_utf8(s).unwrap(),
        "(1735270496.916858) can0 185#3702A0860100\n(1.002135) sim0 080# T\n"
    );
}

#[test]
fn parser_reads_lines_and_refuses_garbage() {
    let l = parse_line("(1735270496.916858) can0 185#3702A0860100 R")
        .unwrap()
        .unwrap();
    assert_eq!(l.t_us, 1_735_270_496_916_858);
    assert_eq!(l.interface, "can0");
    assert_eq!(l.frame.to_string(), "185#3702A0860100");
    assert_eq!(l.direction, Some(Direction::Received));
    assert_eq!(parse_line("# comment").unwrap(), None);
    assert_eq!(parse_line("   ").unwrap(), None);
    for bad in [
        "(1.5) can0 080#",
        "1.000000 can0 080#",
        "(1.000000) can0 12345678#00",
        "(1.000000) can0 080#0",
        "(1.000000) can0 080#R",
        "(1.000000) can0 080#00 X",
        "(1.000000) can0 800#",
        "(1.000000) can0",
    ] {
        assert!(parse_line(bad).is_err(), "{bad}");
    }
    assert_eq!(
        parse_line("(1.000000) can0 080#0").unwrap_err().to_string(),
        "candump line \"(1.000000) can0 080#0\": data must be 0..=8 bytes as pairs of hex digits (no RTR, no CAN FD)"
    );
}

#[test]
fn ring_counts_drops_when_full_and_keeps_order() {
    let (mut p, mut c) = ring(3, true);
    assert_eq!(p.shared.capacity, 4);
    for i in 0..6 {
        let ok = p.push(Record {
            t_ns: i,
            ..Record::default()
        });
        assert_eq!(ok, i < 4);
    }
    assert_eq!(p.shared.dropped.load(Ordering::Relaxed), 2);
    assert_eq!(c.pop().unwrap().t_ns, 0);
    assert!(p.push(Record {
        t_ns: 10,
        ..Record::default()
    }));
    let rest: Vec<u64> = std::iter::from_fn(|| c.pop()).map(|r| r.t_ns).collect();
    assert_eq!(rest, [1, 2, 3, 10]);
}

#[test]
fn logged_file_parses_line_by_line() {
    let path = temp_path("roundtrip");
    let opts = LogOptions {
        direction_suffix: true,
        ..LogOptions::default()
    };
    let mut bus = LoggingBus::new(Loopback::default(), &path, "sim0", opts).unwrap();
    for f in frames() {
        bus.send(&f).unwrap();
        assert_eq!(bus.recv(0).unwrap(), Some(f));
    }
    assert_eq!(bus.recv(0).unwrap(), None);
    let summary = bus.finish().unwrap();
    assert_eq!(
        summary,
        LogSummary {
            written: 8,
            dropped: 0
        }
    );
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    // Frame lines only: a `#` line is no candump line (python-can's reader refuses it).
    assert_eq!(lines.len(), 8, "{text}");
    assert!(lines.iter().all(|l| l.starts_with('(')), "{text}");
    let parsed: Vec<LogLine> = lines
        .iter()
        .filter_map(|l| parse_line(l).unwrap())
        .collect();
    assert_eq!(parsed.len(), 8);
    for (k, l) in parsed.iter().enumerate() {
        assert_eq!(l.interface, "sim0");
        assert_eq!(l.frame, frames()[k / 2]);
        let dir = if k % 2 == 0 {
            Direction::Transmitted
        } else {
            Direction::Received
        };
        assert_eq!(l.direction, Some(dir));
    }
    assert!(parsed.windows(2).all(|w| w[0].t_us <= w[1].t_us));
    #[cfg(target_os = "linux")]
    {
        let frame_lines: String = lines
            .iter()
            .filter(|l| !l.starts_with('#'))
            .map(|l| format!("{l}\n"))
            .collect();
        let mut reader = ::socketcan::dump::Reader::from_reader(frame_lines.as_bytes());
        for (k, line) in parsed.iter().enumerate() {
            let rec = reader.next_record().unwrap().unwrap();
            assert_eq!(rec.device, "sim0");
            assert_eq!(format!("{:X}", rec.frame), frames()[k / 2].to_string());
            assert_eq!(rec.t_us, line.t_us);
        }
        assert!(reader.next_record().unwrap().is_none());
    }
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn full_ring_counts_drops_and_reports_them_in_the_summary() {
    let path = temp_path("drops");
    let opts = LogOptions {
        capacity: 8,
        clock: LogClock::Monotonic,
        ..LogOptions::default()
    };
    // The writer is held back so that the ring fills deterministically.
    let mut bus = LoggingBus::build(Loopback::default(), &path, "can0", opts, false).unwrap();
    for k in 0..20u8 {
        bus.send(&Frame::new(0x200, &[k]).unwrap()).unwrap();
    }
    assert_eq!(bus.dropped(), 12);
    let summary = bus.finish().unwrap();
    assert_eq!(
        summary,
        LogSummary {
            written: 8,
            dropped: 12
        }
    );
    let text = std::fs::read_to_string(&path).unwrap();
    // The drops are counted in the summary (and said on stderr), not written into the log.
    assert!(text.lines().all(|l| l.starts_with('(')), "{text}");
    let first: Vec<u8> = text
        .lines()
        .filter_map(|l| parse_line(l).unwrap())
        .map(|l| l.frame.data[0])
        .collect();
    assert_eq!(first, [0, 1, 2, 3, 4, 5, 6, 7]);
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn dropping_the_bus_ends_the_log() {
    let path = temp_path("drop");
    {
        let mut bus =
            LoggingBus::new(Loopback::default(), &path, "can0", LogOptions::default()).unwrap();
        bus.send(&Frame::new(0x080, &[]).unwrap()).unwrap();
    }
    let text = std::fs::read_to_string(&path).unwrap();
    // Complete (flushed) when the bus is dropped: the one frame, and nothing else.
    assert_eq!(text.lines().count(), 1, "{text}");
    assert!(text.ends_with("080#\n"), "{text}");
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn unwritable_path_is_named() {
    let err = LoggingBus::new(
        Loopback::default(),
        "/nonexistent-dir/x.log",
        "can0",
        LogOptions::default(),
    )
    .err()
    .unwrap();
    assert!(
        err.to_string()
            .starts_with("cannot create candump log /nonexistent-dir/x.log:"),
        "{err}"
    );
}
