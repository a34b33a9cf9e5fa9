//! PDO engine of the simulated drive (CiA 301 §7.2.2; `docs/drive-profile.md`, "Cyclic data"): two
//! RPDOs and two TPDOs whose communication and mapping parameters live in the object dictionary
//! (0x1400/0x1401, 0x1600/0x1601, 0x1800/0x1801, 0x1A00/0x1A01).
//!
//! Runs inside the cycle: fixed-size state, no allocation. What it does:
//! - [`check_write`]: the rules for SDO writes to PDO parameters (COB-ID bit 31 = invalid,
//!   11-bit ids only, the id changes only while invalid; transmission types 1..=240, 254, 255;
//!   mapping only while the PDO is invalid, its count is 0 and the node is not OPERATIONAL;
//!   mapped objects must exist, be mappable in the PDO's direction and have their real length;
//!   at most 64 bits per PDO);
//! - RPDOs: [`PdoEngine::on_frame`] latches a synchronous RPDO (applied by
//!   [`PdoEngine::take_latched`] at the next SYNC) and returns an event-driven one at once;
//!   frames shorter than the mapping are ignored;
//! - TPDOs: [`PdoEngine::sync_tx`] sends synchronous TPDOs every n-th SYNC;
//!   [`PdoEngine::event_tx`] sends an event-driven TPDO when its data changed, once after
//!   [`PdoEngine::start`] (entering OPERATIONAL), and again whenever its event timer (sub 5,
//!   ms, 0 = off) has run out since it was last sent (the drive's clock advances at SYNC, so
//!   the timer is honoured at the first SYNC at or after it runs out). The inhibit time
//!   (sub 3) is not implemented.
//!
//! The caller (the drive) gates everything on the NMT state: PDOs only in OPERATIONAL.

use super::abort::SdoAbort;
use super::od::{self, Mappable, Od};
use mcm_bus::Frame;

/// Number of RPDOs and TPDOs of the drive.
pub const NUM_RPDO: usize = 2;
pub const NUM_TPDO: usize = 2;
const MAX_ENTRIES: usize = 8;

/// The object writes of one received PDO: (slot, raw value) in mapping order.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PdoWrites {
    entries: [(usize, u32); MAX_ENTRIES],
    len: usize,
}

impl PdoWrites {
    /// The writes, in mapping order.
    pub fn iter(&self) -> impl Iterator<Item = (usize, u32)> + '_ {
        self.entries[..self.len].iter().copied()
    }
}

/// What became of a received frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RxOutcome {
    /// Not one of this drive's valid RPDOs.
    NotMine,
    /// An RPDO, but shorter than its mapping: ignored.
    TooShort,
    /// A synchronous RPDO: latched for the next SYNC.
    Latched,
    /// An event-driven RPDO: apply these writes now.
    Apply(PdoWrites),
}

/// Runtime state of the PDOs (their parameters are in the object dictionary).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PdoEngine {
    latch: [Option<[u8; 8]>; NUM_RPDO],
    sync_count: [u8; NUM_TPDO],
    last_event: [Option<Frame>; NUM_TPDO],
    /// The drive's clock [ns] when each event-driven TPDO was last sent.
    sent_at_ns: [u64; NUM_TPDO],
    force_event: [bool; NUM_TPDO],
    tx_slots: [SlotMemo; NUM_TPDO],
    rx_slots: [SlotMemo; NUM_RPDO],
}

/// The slots one PDO's mapping entries resolve to, remembered by entry value: resolving an
/// entry searches the dictionary, and a PDO is packed or unpacked every cycle with the same
/// mapping. A cache of a pure function ([`mapped_slot`]), not state: any two compare equal.
#[derive(Debug, Clone, Copy, Default)]
struct SlotMemo {
    /// (entry value, its slot); the default entry 0 resolves to no slot, as `mapped_slot` says.
    known: [(u32, Option<usize>); MAX_ENTRIES],
}

impl PartialEq for SlotMemo {
    fn eq(&self, _: &SlotMemo) -> bool {
        true
    }
}

impl Eq for SlotMemo {}

impl SlotMemo {
    /// `mapped_slot(entry, dir)` for mapping entry `k` (1-based).
    fn slot(&mut self, k: usize, entry: u32, dir: Mappable) -> Option<usize> {
        let known = &mut self.known[k - 1];
        if known.0 != entry {
            *known = (entry, mapped_slot(entry, dir));
        }
        known.1
    }
}

const COB_ID_INVALID: u32 = 1 << 31;
const COB_ID_ALLOWED_BITS: u32 = COB_ID_INVALID | (1 << 30) | 0x7FF;

fn is_sync_type(t: u32) -> bool {
    (1..=240).contains(&t)
}

fn valid(od: &Od, cob_slot: usize) -> Option<u16> {
    let cob = od.raw(cob_slot);
    (cob & COB_ID_INVALID == 0).then_some((cob & 0x7FF) as u16)
}

/// The slot a mapping entry `0xIIIISSLL` refers to, if it is mappable in `dir`.
fn mapped_slot(entry: u32, dir: Mappable) -> Option<usize> {
    let slot = Od::lookup((entry >> 16) as u16, (entry >> 8) as u8).ok()?;
    let def = Od::def(slot);
    (def.mappable == dir && u32::from(def.dtype.bits()) == entry & 0xFF).then_some(slot)
}

/// For a mapping slot: (count slot, comm slots, direction).
fn mapping_of(slot: usize) -> Option<(usize, od::PdoCommSlots, Mappable)> {
    let within = |base: usize| (base..=base + MAX_ENTRIES).contains(&slot);
    (0..NUM_RPDO)
        .find(|&i| within(od::RPDO_MAP[i]))
        .map(|i| (od::RPDO_MAP[i], od::RPDO_COMM[i], Mappable::Rx))
        .or_else(|| {
            (0..NUM_TPDO)
                .find(|&i| within(od::TPDO_MAP[i]))
                .map(|i| (od::TPDO_MAP[i], od::TPDO_COMM[i], Mappable::Tx))
        })
}

fn comm_of(slot: usize) -> Option<od::PdoCommSlots> {
    od::RPDO_COMM
        .iter()
        .chain(od::TPDO_COMM.iter())
        .find(|c| c.cob_id == slot || c.transmission == slot)
        .copied()
}

/// Check an SDO write of `value` to `slot` against the PDO rules; `Ok` for non-PDO objects.
pub fn check_write(od: &Od, operational: bool, slot: usize, value: u32) -> Result<(), SdoAbort> {
    let def = Od::def(slot);
    let (index, sub) = (def.index, def.sub);
    if let Some(comm) = comm_of(slot) {
        if slot == comm.transmission {
            if !(is_sync_type(value) || value == 254 || value == 255) {
                return Err(SdoAbort::ValueRange {
                    index,
                    sub,
                    value,
                    allowed: "1..=240 (synchronous), 254 or 255 (event)",
                });
            }
        } else if value & !COB_ID_ALLOWED_BITS != 0 {
            return Err(SdoAbort::ValueRange {
                index,
                sub,
                value,
                allowed: "an 11-bit COB-ID, bit 30 and bit 31 (invalid)",
            });
        } else if let Some(id) = valid(od, slot)
            && value & COB_ID_INVALID == 0
            && (value & 0x7FF) as u16 != id
        {
            return Err(SdoAbort::ValueRange {
                index,
                sub,
                value,
                allowed: "a new COB-ID only while the PDO is invalid (bit 31 set)",
            });
        }
        return Ok(());
    }
    let Some((count_slot, comm, dir)) = mapping_of(slot) else {
        return Ok(());
    };
    if operational || valid(od, comm.cob_id).is_some() {
        return Err(SdoAbort::DeviceState { index, sub });
    }
    if slot != count_slot {
        if od.raw(count_slot) != 0 {
            return Err(SdoAbort::DeviceState { index, sub });
        }
        if value != 0 && mapped_slot(value, dir).is_none() {
            return Err(SdoAbort::NotMappable {
                index,
                sub,
                entry: value,
            });
        }
        return Ok(());
    }
    if value as usize > MAX_ENTRIES {
        return Err(SdoAbort::ValueRange {
            index,
            sub,
            value,
            allowed: "0..=8 mapping entries",
        });
    }
    let mut bits = 0;
    for k in 1..=value as usize {
        let entry = od.raw(count_slot + k);
        if mapped_slot(entry, dir).is_none() {
            return Err(SdoAbort::NotMappable {
                index,
                sub: k as u8,
                entry,
            });
        }
        bits += entry & 0xFF;
    }
    if bits > 64 {
        return Err(SdoAbort::MappingTooLong {
            index,
            count: value as u8,
            bits,
        });
    }
    Ok(())
}

fn unpack(od: &Od, map: usize, data: &[u8], memo: &mut SlotMemo) -> Option<PdoWrites> {
    let mut w = PdoWrites::default();
    let mut at = 0;
    for k in 1..=(od.raw(map) as usize).min(MAX_ENTRIES) {
        let slot = memo.slot(k, od.raw(map + k), Mappable::Rx)?;
        let n = usize::from(Od::def(slot).dtype.size());
        let bytes = data.get(at..at + n)?;
        let mut raw = [0u8; 4];
        raw[..n].copy_from_slice(bytes);
        w.entries[w.len] = (slot, u32::from_le_bytes(raw));
        w.len += 1;
        at += n;
    }
    Some(w)
}

fn pack(od: &Od, map: usize, id: u16, memo: &mut SlotMemo) -> Frame {
    let mut f = Frame {
        id,
        len: 0,
        data: [0; 8],
    };
    for k in 1..=(od.raw(map) as usize).min(MAX_ENTRIES) {
        let Some(slot) = memo.slot(k, od.raw(map + k), Mappable::Tx) else {
            continue;
        };
        let n = usize::from(Od::def(slot).dtype.size());
        let at = usize::from(f.len);
        if at + n > 8 {
            break;
        }
        f.data[at..at + n].copy_from_slice(&od.raw(slot).to_le_bytes()[..n]);
        f.len += n as u8;
    }
    f
}

impl PdoEngine {
    /// Entering OPERATIONAL: counters restart and every event-driven TPDO is sent once.
    pub fn start(&mut self) {
        *self = PdoEngine {
            force_event: [true; NUM_TPDO],
            ..PdoEngine::default()
        };
    }

    /// Leaving OPERATIONAL (or a reset): latched data is dropped.
    pub fn stop(&mut self) {
        *self = PdoEngine::default();
    }

    /// A PDO's communication parameter was written: restart that PDO's runtime state.
    pub fn comm_written(&mut self, slot: usize) {
        for i in 0..NUM_RPDO {
            if od::RPDO_COMM[i].cob_id == slot || od::RPDO_COMM[i].transmission == slot {
                self.latch[i] = None;
            }
        }
        for i in 0..NUM_TPDO {
            if od::TPDO_COMM[i].cob_id == slot || od::TPDO_COMM[i].transmission == slot {
                self.sync_count[i] = 0;
                self.last_event[i] = None;
                self.force_event[i] = true;
            }
        }
    }

    /// A frame received while OPERATIONAL.
    pub fn on_frame(&mut self, od: &Od, frame: &Frame) -> RxOutcome {
        for i in 0..NUM_RPDO {
            let comm = od::RPDO_COMM[i];
            if valid(od, comm.cob_id) != Some(frame.id) {
                continue;
            }
            let Some(writes) = unpack(od, od::RPDO_MAP[i], frame.payload(), &mut self.rx_slots[i])
            else {
                return RxOutcome::TooShort;
            };
            if is_sync_type(od.raw(comm.transmission)) {
                self.latch[i] = Some(frame.data);
                return RxOutcome::Latched;
            }
            return RxOutcome::Apply(writes);
        }
        RxOutcome::NotMine
    }

    /// At SYNC: the writes of the synchronous RPDOs received since the last SYNC.
    pub fn take_latched(&mut self, od: &Od) -> [Option<PdoWrites>; NUM_RPDO] {
        let mut out = [None; NUM_RPDO];
        for (i, o) in out.iter_mut().enumerate() {
            if let Some(data) = self.latch[i].take() {
                *o = unpack(od, od::RPDO_MAP[i], &data, &mut self.rx_slots[i]);
            }
        }
        out
    }

    /// At SYNC, after sampling: the synchronous TPDOs due at this SYNC.
    pub fn sync_tx(&mut self, od: &Od) -> [Option<Frame>; NUM_TPDO] {
        let mut out = [None; NUM_TPDO];
        for (i, o) in out.iter_mut().enumerate() {
            let comm = od::TPDO_COMM[i];
            let t = od.raw(comm.transmission);
            let Some(id) = valid(od, comm.cob_id) else {
                continue;
            };
            if !is_sync_type(t) {
                continue;
            }
            self.sync_count[i] = self.sync_count[i].saturating_add(1);
            if u32::from(self.sync_count[i]) >= t {
                self.sync_count[i] = 0;
                *o = Some(pack(od, od::TPDO_MAP[i], id, &mut self.tx_slots[i]));
            }
        }
        out
    }

    /// Event-driven TPDOs whose data changed since they were last sent, that are due once
    /// after [`PdoEngine::start`], or whose event timer has run out at `now_ns` (the drive's
    /// clock).
    pub fn event_tx(&mut self, od: &Od, now_ns: u64) -> [Option<Frame>; NUM_TPDO] {
        let mut out = [None; NUM_TPDO];
        for (i, o) in out.iter_mut().enumerate() {
            let comm = od::TPDO_COMM[i];
            let t = od.raw(comm.transmission);
            let Some(id) = valid(od, comm.cob_id) else {
                continue;
            };
            if t != 254 && t != 255 {
                continue;
            }
            let f = pack(od, od::TPDO_MAP[i], id, &mut self.tx_slots[i]);
            let timer_ns = u64::from(od.raw(od::TPDO_EVENT_TIMER[i])) * 1_000_000;
            let timer_out = timer_ns > 0 && now_ns >= self.sent_at_ns[i].saturating_add(timer_ns);
            if self.force_event[i] || self.last_event[i] != Some(f) || timer_out {
                self.force_event[i] = false;
                self.last_event[i] = Some(f);
                self.sent_at_ns[i] = now_ns;
                *o = Some(f);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests;
