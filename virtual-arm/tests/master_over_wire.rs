//! The virtual arm answers the real CANopen master (rt-core's `Cycle`) over a wire exactly as
//! the in-process simulated bus does: the same frames come back, cycle by cycle, through boot,
//! enabling and a whole calibration, the core publishes the same state every cycle, and the arm
//! ends in the same true state, bit for bit.

use mcm_bus::{Bus, BusError, Frame};
use mcm_rt_core::cycle::Cycle;
use mcm_rt_core::publish::CycleClock;
use mcm_rt_core::runner::run_cycle;
use mcm_shared::command::{Calibrate, Request};
use mcm_shared::config::RobotConfig;
use mcm_shared::sample::{AXIS_CALIBRATED, AXIS_ENABLED, CommandSample};
use mcm_sim::{SimBus, SimControl};
use mcm_virtual_arm::arm::{Event, VirtualArm};
use mcm_virtual_arm::memory_wire;

/// A bus that keeps every frame the master receives, with its cycle.
struct Recording<B> {
    inner: B,
    cycle: u64,
    seen: Vec<(u64, Frame)>,
}

impl<B: Bus> Bus for Recording<B> {
    fn send(&mut self, frame: &Frame) -> Result<(), BusError> {
        self.inner.send(frame)
    }

    fn recv(&mut self, deadline_ns: u64) -> Result<Option<Frame>, BusError> {
        let f = self.inner.recv(deadline_ns)?;
        if let Some(f) = f {
            self.seen.push((self.cycle, f));
        }
        Ok(f)
    }
}

fn recording<B>(inner: B) -> Recording<B> {
    Recording {
        inner,
        cycle: 0,
        seen: Vec::new(),
    }
}

fn command(k: u64, cycle: u64) -> Vec<CommandSample> {
    let request = match k {
        400 => Request::Hold,
        800 => Request::Calibrate(Calibrate::default()),
        _ => return Vec::new(),
    };
    let mut s = request.encode();
    s.client_id = 1;
    s.request_id = cycle;
    vec![s]
}

#[test]
fn the_master_sees_the_same_arm_over_the_wire_as_in_process() {
    let cfg = RobotConfig::prob2_default();
    let period = cfg.cycle_period_ns();
    let cycles = 4400; // 22 s: boot, enabling, a calibration of every axis
    let mut local = Cycle::new(&cfg, recording(SimBus::new(&cfg))).unwrap();
    let (arm_end, master_end) = memory_wire::pair();
    let mut remote = Cycle::new(&cfg, recording(master_end)).unwrap();
    let start = 1_000_000_000;
    let mut arm = VirtualArm::new(&cfg, arm_end, 2, start);
    for k in 0..cycles {
        let now = start + k * period;
        let commands = command(k, k);
        local.bus_mut().cycle = k;
        remote.bus_mut().cycle = k;
        arm.poll(now, &mut |e| {
            assert!(e == Event::FirstSync && k == 1, "cycle {k}: {e:?}");
        });
        let clock = CycleClock::virtual_time(now, period);
        run_cycle(&mut local, None, now, &clock, &commands);
        run_cycle(&mut remote, None, now, &clock, &commands);
        assert!(
            local.state() == remote.state(),
            "cycle {k}: the published states differ"
        );
    }
    // The last cycle's frames reach the arm (in-process they did within `run`).
    arm.poll(start + cycles * period, &mut |e| panic!("{e:?}"));
    let (a, b) = (&local.bus_mut().seen, &remote.bus_mut().seen);
    for (i, (x, y)) in a.iter().zip(b.iter()).enumerate() {
        assert_eq!(x, y, "frame {i}: in-process {x:?}, over the wire {y:?}");
    }
    assert_eq!(a.len(), b.len(), "frames received by the master");
    // At least a TPDO1 per drive and cycle once they run (after the first 2 s).
    assert!(a.len() as u64 > 6 * (cycles - 400), "{} frames", a.len());
    let truth = local.bus_mut().inner.truth();
    assert_eq!(arm.truth(), truth);
    let c = arm.counters();
    assert_eq!(
        (c.syncs, c.periods_without_sync, c.tx_dropped),
        (cycles, 0, 0)
    );
    let flags = remote.state().axis_flags;
    assert!(
        flags
            .iter()
            .all(|f| f & AXIS_CALIBRATED != 0 && f & AXIS_ENABLED != 0),
        "every axis calibrated and enabled over the wire: {flags:?}"
    );
}
