//! The cycle against a bus that fails: every failed send and every failed receive is counted
//! once, the controller still steps, and at most [`RX_PER_CYCLE`] frames are read per cycle.

use super::{COMMANDS_PER_CYCLE, Cycle, RX_PER_CYCLE};
use mcm_bus::{Bus, BusError, Frame};
use mcm_shared::command::Request;
use mcm_shared::config::RobotConfig;
use mcm_shared::reply::Response;
use std::collections::VecDeque;

/// A bus double: hands out `rx` one frame per `recv`, then `Ok(None)` (or an error when
/// `fail_recv`); every `send` is counted and fails when `fail_send`.
#[derive(Default)]
struct TestBus {
    rx: VecDeque<Frame>,
    fail_recv: bool,
    fail_send: bool,
    sends: u64,
    recvs: u64,
}

impl Bus for TestBus {
    fn send(&mut self, frame: &Frame) -> Result<(), BusError> {
        self.sends += 1;
        if self.fail_send {
            return Err(BusError::TxQueueFull {
                interface: "test0",
                frame: *frame,
            });
        }
        Ok(())
    }

    fn recv(&mut self, _deadline_ns: u64) -> Result<Option<Frame>, BusError> {
        self.recvs += 1;
        if let Some(f) = self.rx.pop_front() {
            return Ok(Some(f));
        }
        if self.fail_recv {
            return Err(BusError::BusOff { interface: "test0" });
        }
        Ok(None)
    }
}

fn cycle(bus: TestBus) -> (Cycle<TestBus>, u64) {
    let cfg = RobotConfig::prob2_default();
    (Cycle::new(&cfg, bus).unwrap(), cfg.cycle_period_ns())
}

#[test]
fn a_bus_that_fails_both_ways_counts_each_failure_and_the_controller_still_steps() {
    let (mut c, period) = cycle(TestBus {
        fail_recv: true,
        fail_send: true,
        ..TestBus::default()
    });
    for k in 0..20 {
        c.run(k * period, &[]);
    }
    let bus = c.bus_mut();
    let (sends, recvs) = (bus.sends, bus.recvs);
    assert_eq!(recvs, 20, "one failed receive ends each cycle's reading");
    assert!(
        sends > 0,
        "the master sends (NMT, SYNC...) even with no answer"
    );
    assert_eq!(c.bus_errors(), 20 + sends, "each failed send and receive");
    assert_eq!(c.controller().view().cycle, 20);
}

#[test]
fn the_counters_reach_the_published_view() {
    // Two garbled frames of node 1 (a 2-byte TPDO1, a 3-byte EMCY), then a bus that fails.
    let garbled = [
        Frame::new(0x181, &[1, 2]).unwrap(),
        Frame::new(0x081, &[1, 2, 3]).unwrap(),
    ];
    let (mut c, period) = cycle(TestBus {
        rx: garbled.into_iter().collect(),
        fail_send: true,
        ..TestBus::default()
    });
    c.run(0, &[]);
    let bus = c.controller().view().bus;
    assert_eq!(bus.bad_frames, 2);
    assert_eq!(bus.frames_dropped, 0);
    assert_eq!(bus.events_dropped, 0);
    assert!(bus.bus_errors > 0, "the failed sends of this cycle");
    assert_eq!(bus.bus_errors, c.bus_errors());
    c.run(period, &[]);
    assert_eq!(c.controller().view().bus.bus_errors, c.bus_errors());
    assert_eq!(c.controller().view().bus.bad_frames, 2);
}

#[test]
fn a_healthy_bus_counts_no_errors() {
    let (mut c, period) = cycle(TestBus::default());
    for k in 0..20 {
        c.run(k * period, &[]);
    }
    assert!(c.bus_mut().sends > 0);
    assert_eq!(c.bus_errors(), 0);
    assert_eq!(
        c.controller().view().bus,
        mcm_shared::sample::BusCounters::default()
    );
}

#[test]
fn at_most_rx_per_cycle_frames_are_read_and_the_rest_wait() {
    let frame = Frame::new(0x701, &[0x05]).unwrap();
    let queued = RX_PER_CYCLE + 50;
    let (mut c, _) = cycle(TestBus {
        rx: std::iter::repeat_n(frame, queued).collect(),
        fail_recv: true,
        ..TestBus::default()
    });
    c.receive();
    assert_eq!(c.bus_mut().rx.len(), 50, "the rest stays queued");
    assert_eq!(
        c.bus_errors(),
        0,
        "the cycle stopped reading before the error"
    );
    c.step(0, &[]);
    c.receive();
    assert_eq!(c.bus_mut().rx.len(), 0);
    assert_eq!(
        c.bus_errors(),
        1,
        "the next read after the last frame failed"
    );
}

#[test]
fn commands_beyond_the_per_cycle_limit_are_left_to_the_caller() {
    let (mut c, _) = cycle(TestBus::default());
    let samples: Vec<_> = (0..COMMANDS_PER_CYCLE as u64 + 3)
        .map(|i| {
            let mut s = Request::Status.encode();
            (s.client_id, s.request_id) = (1, 100 + i);
            s
        })
        .collect();
    c.receive();
    c.step(0, &samples);
    let answered: Vec<u64> = c
        .replies()
        .iter()
        .map(|r| Response::decode(r).unwrap().request_id)
        .collect();
    let served: Vec<u64> = (0..COMMANDS_PER_CYCLE as u64).map(|i| 100 + i).collect();
    assert_eq!(answered, served, "the first COMMANDS_PER_CYCLE, in order");
}
