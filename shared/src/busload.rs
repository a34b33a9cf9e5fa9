//! Worst-case bus load of the cyclic traffic, checked against `bus.load_budget` at start-up.
//!
//! Frame length (classic CAN, 11-bit id, `s` data bytes, worst-case bit stuffing, Davis et
//! al. 2007): `bits(s) = 47 + 8 s + floor((33 + 8 s) / 4)`, i.e. 55 bits for SYNC, 65 for a
//! heartbeat, 135 for an 8-byte PDO. Per cycle the MCM sends SYNC and, per axis, RPDO1 and
//! TPDO1 (8 bytes each), and one RPDO2 (5 bytes: each drive's mode, current limit and
//! feed-forward restated on its axis's turn, one axis a cycle); heartbeats (every drive at
//! `bus.drive_heartbeat_ms`, the master at `bus.master_heartbeat_ms`) and the repeats of each
//! drive's TPDO2 (1 byte, event timer
//! [`TPDO2_EVENT_TIMER_MS`]) are added as rates. The event-driven frames (an RPDO2 on a change
//! and its repeats, TPDO2 on a change), EMCY and SDO are not periodic and are left out: the
//! budget is what leaves room for them.
//!
//! In the contract because both sides use it: `mcm-rt` checks it once at start-up (not in the
//! cycle), the gateway shows it on the browser pendant.
//!
//! ```
//! use mcm_shared::busload::frame_bits_worst_case;
//! assert_eq!(frame_bits_worst_case(8), 135);
//! assert_eq!(frame_bits_worst_case(0), 55);
//! ```

use crate::config::RobotConfig;

/// TPDO2's event timer (0x1801:5) [ms]: the drive sends its mode display on every change and
/// again at least this often, so a lost TPDO2 is made good within this time (the master does
/// not depend on one event-driven frame to confirm a mode). Written to the drives at boot
/// (`mcm_rt_core::canopen::boot`).
pub const TPDO2_EVENT_TIMER_MS: u16 = 100;

/// Worst-case length of a classic CAN frame with an 11-bit id and `len` data bytes, including
/// stuff bits and the 3-bit interframe space.
pub const fn frame_bits_worst_case(len: u8) -> u32 {
    let s = len as u32;
    47 + 8 * s + (33 + 8 * s) / 4
}

/// The same frame without any stuff bits (best case).
pub const fn frame_bits_unstuffed(len: u8) -> u32 {
    47 + 8 * len as u32
}

/// Bytes of the cyclic PDOs (RPDO1 and TPDO1 of the MCM drive profile; the core's PDO types
/// take their lengths from here).
pub const CYCLIC_RPDO_BYTES: u8 = 8;
pub const CYCLIC_TPDO_BYTES: u8 = 8;
/// Bytes of RPDO2 (mode, current limit, torque feed-forward), one of which goes out every cycle.
pub const RPDO2_BYTES: u8 = 5;

/// The computed load and every number that went into it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BusLoad {
    pub axes: u32,
    pub rpdo_bits: u32,
    pub tpdo_bits: u32,
    /// The one RPDO2 of each cycle.
    pub rpdo2_bits: u32,
    pub sync_bits: u32,
    /// `axes * (rpdo_bits + tpdo_bits) + rpdo2_bits + sync_bits`.
    pub bits_per_cycle: u32,
    pub rate_hz: u32,
    pub bitrate: u32,
    pub heartbeat_producers: u32,
    pub heartbeat_bits_per_s: f64,
    /// Period of each drive's TPDO2 repeat [ms] (its event timer; 0 = none).
    pub tpdo2_period_ms: u16,
    /// The TPDO2 repeats of all drives [bit/s].
    pub tpdo2_bits_per_s: f64,
    /// Total worst-case bits per second.
    pub bits_per_s: f64,
    /// Fraction of the bit rate (0.67 = 67 %).
    pub load: f64,
    pub budget: f64,
    /// Highest cycle rate that fits the budget with these frames.
    pub max_rate_hz: f64,
}

impl BusLoad {
    /// Compute the load of `axes` axes at `rate_hz` on a `bitrate` bus with the given
    /// heartbeat periods (`drive_hb_ms` for each drive, `master_hb_ms` for the master; 0 =
    /// no heartbeat) and each drive's TPDO2 repeated every `tpdo2_ms` (0 = not repeated).
    pub fn compute(
        axes: u32,
        rate_hz: u32,
        bitrate: u32,
        drive_hb_ms: u16,
        master_hb_ms: u16,
        tpdo2_ms: u16,
        budget: f64,
    ) -> BusLoad {
        let rpdo_bits = frame_bits_worst_case(CYCLIC_RPDO_BYTES);
        let tpdo_bits = frame_bits_worst_case(CYCLIC_TPDO_BYTES);
        let rpdo2_bits = frame_bits_worst_case(RPDO2_BYTES);
        let sync_bits = frame_bits_worst_case(0);
        let bits_per_cycle = axes * (rpdo_bits + tpdo_bits) + rpdo2_bits + sync_bits;
        let hb_bits = f64::from(frame_bits_worst_case(1));
        let per_s = |ms: u16| if ms == 0 { 0.0 } else { 1000.0 / f64::from(ms) };
        let heartbeat_bits_per_s =
            hb_bits * (f64::from(axes) * per_s(drive_hb_ms) + per_s(master_hb_ms));
        let heartbeat_producers =
            if drive_hb_ms == 0 { 0 } else { axes } + u32::from(master_hb_ms != 0);
        let tpdo2_bits_per_s = hb_bits * f64::from(axes) * per_s(tpdo2_ms);
        let periodic_bits_per_s = heartbeat_bits_per_s + tpdo2_bits_per_s;
        let bits_per_s = f64::from(bits_per_cycle) * f64::from(rate_hz) + periodic_bits_per_s;
        let bitrate_f = f64::from(bitrate.max(1));
        BusLoad {
            axes,
            rpdo_bits,
            tpdo_bits,
            rpdo2_bits,
            sync_bits,
            bits_per_cycle,
            rate_hz,
            bitrate,
            heartbeat_producers,
            heartbeat_bits_per_s,
            tpdo2_period_ms: tpdo2_ms,
            tpdo2_bits_per_s,
            bits_per_s,
            load: bits_per_s / bitrate_f,
            budget,
            max_rate_hz: ((budget * bitrate_f - periodic_bits_per_s) / f64::from(bits_per_cycle))
                .max(0.0),
        }
    }

    /// The load of a robot configuration.
    pub fn of_config(cfg: &RobotConfig) -> BusLoad {
        let b = &cfg.bus;
        BusLoad::compute(
            cfg.axes.len() as u32,
            cfg.cycle.rate_hz,
            b.bitrate,
            b.drive_heartbeat_ms,
            b.master_heartbeat_ms,
            TPDO2_EVENT_TIMER_MS,
            b.load_budget,
        )
    }

    /// Bus time of one cycle's frames [µs].
    pub fn cycle_bus_time_us(&self) -> f64 {
        f64::from(self.bits_per_cycle) * 1e6 / f64::from(self.bitrate.max(1))
    }

    /// `Ok(self)` within the budget, else the error with all numbers.
    pub fn check(self) -> Result<BusLoad, BusLoadError> {
        if self.load <= self.budget {
            Ok(self)
        } else {
            Err(BusLoadError::OverBudget(self))
        }
    }
}

/// Check the configuration's cyclic bus load against `bus.load_budget`.
pub fn check_config(cfg: &RobotConfig) -> Result<BusLoad, BusLoadError> {
    BusLoad::of_config(cfg).check()
}

/// The configured traffic does not fit the bus.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum BusLoadError {
    #[error(
        "worst-case bus load {:.1} % exceeds bus.load_budget {:.1} %: per cycle {} bits \
         ({} axes x (RPDO1 {} + TPDO1 {} bits) + RPDO2 {} bits + SYNC {} bits) = {:.0} us at \
         {} bit/s, x cycle.rate_hz {} = {:.0} bit/s, plus heartbeats {:.0} bit/s \
         ({} producers x {} bits), \
         plus TPDO2 repeats {:.0} bit/s ({} drives x {} bits every {} ms); \
         allowed: cycle.rate_hz <= {:.0} Hz at this bit rate, or a higher bus.bitrate",
        .0.load * 100.0, .0.budget * 100.0, .0.bits_per_cycle, .0.axes, .0.rpdo_bits, .0.tpdo_bits,
        .0.rpdo2_bits, .0.sync_bits, .0.cycle_bus_time_us(), .0.bitrate, .0.rate_hz,
        f64::from(.0.bits_per_cycle) * f64::from(.0.rate_hz), .0.heartbeat_bits_per_s,
        .0.heartbeat_producers, frame_bits_worst_case(1), .0.tpdo2_bits_per_s, .0.axes,
        frame_bits_worst_case(1), .0.tpdo2_period_ms, .0.max_rate_hz.floor()
    )]
    OverBudget(BusLoad),
}

#[cfg(test)]
mod tests;
