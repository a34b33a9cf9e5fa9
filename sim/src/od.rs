//! The object dictionary of the simulated drive: a fixed table of exactly the objects the MCM
//! drive profile uses (CiA 301 communication objects, the two RPDOs and two TPDOs, and the
//! CiA 402 objects of `docs/drive-profile.md`), with type, access and PDO-mappability, and the
//! values in a fixed array indexed by the table position ("slot").
//!
//! One manufacturer-specific object: 0x2100, the stored calibration. Sub 1 is the calibration
//! offset (i32, encoder counts: the raw position actual at joint angle 0), sub 2 says whether
//! it is valid (u8, 0 or 1). Read-write by SDO, not PDO-mappable, volatile: 0/0 at power-up and
//! cleared only by a power cycle (the encoder's count is lost then too), not by NMT reset node
//! or reset communication. The master reads it while booting a drive and writes it when a
//! calibration finds an axis's zero, so that a restart of the MCM keeps the calibration.
//!
//! Runs inside the cycle: lookups are a binary search over a `static` table; no allocation.
//! Values are stored raw, as the little-endian bits of their type (an `i8` of -3 is `0xFD`).
//!
//! ```
//! use mcm_sim::od::{self, Od, OdDefaults};
//! let mut od = Od::new(&OdDefaults {
//!     node_id: 5,
//!     rated_current_ma: 4000,
//!     rated_torque_mnm: 480,
//!     peak_current_permille: 2500,
//! });
//! assert_eq!(od.raw(od::DEVICE_TYPE), 0x0002_0192);
//! assert_eq!(od.raw(od::RPDO_COMM[0].cob_id), 0x8000_0205); // invalid after power-up
//! od.set_raw(od::MODES_OF_OPERATION, (-1i8) as u8 as u32);
//! assert_eq!(od.i32(od::MODES_OF_OPERATION), -1);
//! ```

use super::abort::SdoAbort;

/// Data type of an object (all the drive's objects fit in 32 bits).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DataType {
    U8,
    I8,
    U16,
    I16,
    U32,
    I32,
}

impl DataType {
    /// Size in bytes.
    pub const fn size(self) -> u8 {
        match self {
            DataType::U8 | DataType::I8 => 1,
            DataType::U16 | DataType::I16 => 2,
            DataType::U32 | DataType::I32 => 4,
        }
    }
    /// Size in bits, as in a PDO mapping entry.
    pub const fn bits(self) -> u8 {
        self.size() * 8
    }
    /// Mask of the valid raw bits.
    pub const fn mask(self) -> u32 {
        match self.size() {
            1 => 0xFF,
            2 => 0xFFFF,
            _ => 0xFFFF_FFFF,
        }
    }
    const fn signed(self) -> bool {
        matches!(self, DataType::I8 | DataType::I16 | DataType::I32)
    }
}

/// SDO access rights.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// Constant (read-only, never changes).
    Const,
    /// Read-only (the drive updates it).
    Ro,
    /// Write-only.
    Wo,
    /// Read-write.
    Rw,
}

/// Whether (and in which direction) an object can be mapped into a PDO.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mappable {
    No,
    /// Into an RPDO (master -> drive).
    Rx,
    /// Into a TPDO (drive -> master).
    Tx,
}

/// Where an object's power-up value comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InitValue {
    Fixed(u32),
    /// The value plus the node id (COB-IDs).
    PlusNodeId(u32),
    RatedCurrentMa,
    RatedTorqueMnm,
    PeakCurrentPermille,
}

/// One entry of the table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ObjectDef {
    pub index: u16,
    pub sub: u8,
    pub dtype: DataType,
    pub access: Access,
    pub mappable: Mappable,
    pub init: InitValue,
}

/// Drive-specific power-up values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OdDefaults {
    pub node_id: u8,
    /// 0x6075 motor rated current [mA].
    pub rated_current_ma: u32,
    /// 0x6076 motor rated torque [mNm].
    pub rated_torque_mnm: u32,
    /// 0x6073 default and upper bound: the drive's peak current in per-mille of rated.
    pub peak_current_permille: u16,
}

use Access::{Const, Ro, Rw, Wo};
use DataType::{I8, I16, I32, U8, U16, U32};
use InitValue::{Fixed, PlusNodeId};
use Mappable::{No, Rx, Tx};

const fn e(
    index: u16,
    sub: u8,
    dtype: DataType,
    access: Access,
    mappable: Mappable,
    init: InitValue,
) -> ObjectDef {
    ObjectDef {
        index,
        sub,
        dtype,
        access,
        mappable,
        init,
    }
}
const fn map(index: u16, sub: u8) -> ObjectDef {
    e(index, sub, U32, Rw, No, Fixed(0))
}

/// Number of objects (index:sub pairs) in the dictionary.
pub const LEN: usize = 88;

/// The table, sorted by (index, sub).
pub static TABLE: [ObjectDef; LEN] = [
    e(0x1000, 0, U32, Const, No, Fixed(0x0002_0192)), // device type: CiA 402 servo drive
    e(0x1001, 0, U8, Ro, Tx, Fixed(0)),               // error register
    e(0x1005, 0, U32, Ro, No, Fixed(0x80)),           // COB-ID SYNC (consumer)
    e(0x1011, 0, U8, Const, No, Fixed(1)),            // restore default parameters
    e(0x1011, 1, U32, Wo, No, Fixed(0)),
    e(0x1014, 0, U32, Ro, No, PlusNodeId(0x80)), // COB-ID EMCY
    e(0x1016, 0, U8, Const, No, Fixed(1)),       // consumer heartbeat time
    e(0x1016, 1, U32, Rw, No, Fixed(0)),
    e(0x1017, 0, U16, Rw, No, Fixed(0)), // producer heartbeat time [ms]
    e(0x1018, 0, U8, Const, No, Fixed(4)), // identity
    e(0x1018, 1, U32, Const, No, Fixed(0x0000_0A7E)),
    e(0x1018, 2, U32, Const, No, Fixed(0x0000_0402)),
    e(0x1018, 3, U32, Const, No, Fixed(0x0001_0000)),
    e(0x1018, 4, U32, Const, No, PlusNodeId(0x5000_0000)),
    e(0x1400, 0, U8, Const, No, Fixed(2)), // RPDO1 communication
    e(0x1400, 1, U32, Rw, No, PlusNodeId(0x8000_0200)),
    e(0x1400, 2, U8, Rw, No, Fixed(255)),
    e(0x1401, 0, U8, Const, No, Fixed(2)), // RPDO2 communication
    e(0x1401, 1, U32, Rw, No, PlusNodeId(0x8000_0300)),
    e(0x1401, 2, U8, Rw, No, Fixed(255)),
    e(0x1600, 0, U8, Rw, No, Fixed(0)), // RPDO1 mapping
    map(0x1600, 1),
    map(0x1600, 2),
    map(0x1600, 3),
    map(0x1600, 4),
    map(0x1600, 5),
    map(0x1600, 6),
    map(0x1600, 7),
    map(0x1600, 8),
    e(0x1601, 0, U8, Rw, No, Fixed(0)), // RPDO2 mapping
    map(0x1601, 1),
    map(0x1601, 2),
    map(0x1601, 3),
    map(0x1601, 4),
    map(0x1601, 5),
    map(0x1601, 6),
    map(0x1601, 7),
    map(0x1601, 8),
    e(0x1800, 0, U8, Const, No, Fixed(5)), // TPDO1 communication
    e(0x1800, 1, U32, Rw, No, PlusNodeId(0x8000_0180)),
    e(0x1800, 2, U8, Rw, No, Fixed(255)),
    e(0x1800, 5, U16, Rw, No, Fixed(0)), // event timer [ms], 0 = off
    e(0x1801, 0, U8, Const, No, Fixed(5)), // TPDO2 communication
    e(0x1801, 1, U32, Rw, No, PlusNodeId(0x8000_0280)),
    e(0x1801, 2, U8, Rw, No, Fixed(255)),
    e(0x1801, 5, U16, Rw, No, Fixed(0)), // event timer [ms], 0 = off
    e(0x1A00, 0, U8, Rw, No, Fixed(0)),  // TPDO1 mapping
    map(0x1A00, 1),
    map(0x1A00, 2),
    map(0x1A00, 3),
    map(0x1A00, 4),
    map(0x1A00, 5),
    map(0x1A00, 6),
    map(0x1A00, 7),
    map(0x1A00, 8),
    e(0x1A01, 0, U8, Rw, No, Fixed(0)), // TPDO2 mapping
    map(0x1A01, 1),
    map(0x1A01, 2),
    map(0x1A01, 3),
    map(0x1A01, 4),
    map(0x1A01, 5),
    map(0x1A01, 6),
    map(0x1A01, 7),
    map(0x1A01, 8),
    e(0x2100, 0, U8, Const, No, Fixed(2)), // stored calibration (volatile, kept until power-off)
    e(0x2100, 1, I32, Rw, No, Fixed(0)),   // calibration offset [counts at joint angle 0]
    e(0x2100, 2, U8, Rw, No, Fixed(0)),    // calibration valid (0/1)
    e(0x6007, 0, I16, Rw, No, Fixed(1)),   // abort connection option code: 1 (fault) at power-up
    e(0x603F, 0, U16, Ro, Tx, Fixed(0)),   // error code
    e(0x6040, 0, U16, Rw, Rx, Fixed(0)),   // controlword
    e(0x6041, 0, U16, Ro, Tx, Fixed(0)),   // statusword
    e(0x605A, 0, I16, Rw, No, Fixed(2)), // quick stop option: only 2 (ramp, then SWITCH ON DISABLED)
    e(0x6060, 0, I8, Rw, Rx, Fixed(0)),  // modes of operation
    e(0x6061, 0, I8, Ro, Tx, Fixed(0)),  // modes of operation display
    e(0x6064, 0, I32, Ro, Tx, Fixed(0)), // position actual [counts]
    e(0x606C, 0, I32, Ro, Tx, Fixed(0)), // velocity actual [counts/s]
    e(0x6071, 0, I16, Rw, Rx, Fixed(0)), // target torque [per-mille of 0x6076]
    e(0x6073, 0, U16, Rw, Rx, InitValue::PeakCurrentPermille), // max current [per-mille of 0x6075]
    e(0x6075, 0, U32, Rw, No, InitValue::RatedCurrentMa), // motor rated current [mA]
    e(0x6076, 0, U32, Rw, No, InitValue::RatedTorqueMnm), // motor rated torque [mNm]
    e(0x6077, 0, I16, Ro, Tx, Fixed(0)), // torque actual [per-mille of 0x6076]
    e(0x6078, 0, I16, Ro, Tx, Fixed(0)), // current actual [per-mille of 0x6075]
    e(0x607A, 0, I32, Rw, Rx, Fixed(0)), // target position [counts]
    e(0x60B2, 0, I16, Rw, Rx, Fixed(0)), // torque offset [per-mille of 0x6076], CSP feed-forward
    e(0x60C2, 0, U8, Const, No, Fixed(2)), // interpolation time period
    e(0x60C2, 1, U8, Rw, No, Fixed(1)),
    e(0x60C2, 2, I8, Rw, No, Fixed(0xFD)),
    e(0x6502, 0, U32, Const, No, Fixed(0x0000_0280)), // supported modes: CSP, CST
];

/// The slot of `index:sub`, at compile time (fails to compile if the object is missing).
pub const fn slot(index: u16, sub: u8) -> usize {
    let mut i = 0;
    while i < LEN {
        if TABLE[i].index == index && TABLE[i].sub == sub {
            return i;
        }
        i += 1;
    }
    panic!("object not in the simulated drive's dictionary");
}

pub const DEVICE_TYPE: usize = slot(0x1000, 0);
pub const ERROR_REGISTER: usize = slot(0x1001, 0);
pub const RESTORE_DEFAULTS: usize = slot(0x1011, 1);
pub const CONSUMER_HEARTBEAT: usize = slot(0x1016, 1);
pub const PRODUCER_HEARTBEAT: usize = slot(0x1017, 0);
/// 0x2100:1, the stored calibration offset [counts]; survives NMT resets, not power cycles.
pub const CALIBRATION_OFFSET: usize = slot(0x2100, 1);
/// 0x2100:2, the stored calibration is valid (0/1).
pub const CALIBRATION_VALID: usize = slot(0x2100, 2);
/// Index of the stored calibration, which no NMT reset touches.
pub const CALIBRATION_INDEX: u16 = 0x2100;
pub const ERROR_CODE: usize = slot(0x603F, 0);
/// 0x6007, abort connection option code (i16): what the drive does when its connection to the
/// master is cut by the master's NMT stop (`SimDrive::on_frame`): 0 nothing, 1 fault, 2 disable
/// voltage (SWITCH ON DISABLED, the brake engaged), 3 quick stop. 1 at power-up.
pub const ABORT_CONNECTION_OPTION: usize = slot(0x6007, 0);
pub const CONTROLWORD: usize = slot(0x6040, 0);
pub const STATUSWORD: usize = slot(0x6041, 0);
/// 0x605A, quick stop option code (i16); the drive supports option 2 only
/// ([`QUICK_STOP_OPTION_SUPPORTED`]).
pub const QUICK_STOP_OPTION: usize = slot(0x605A, 0);
/// The one quick stop option code the simulated drive implements: slow down on the quick-stop
/// ramp, then SWITCH ON DISABLED (`crate::cia402`).
pub const QUICK_STOP_OPTION_SUPPORTED: i16 = 2;
pub const MODES_OF_OPERATION: usize = slot(0x6060, 0);
pub const MODES_DISPLAY: usize = slot(0x6061, 0);
pub const POSITION_ACTUAL: usize = slot(0x6064, 0);
pub const VELOCITY_ACTUAL: usize = slot(0x606C, 0);
pub const TARGET_TORQUE: usize = slot(0x6071, 0);
pub const MAX_CURRENT: usize = slot(0x6073, 0);
pub const RATED_CURRENT: usize = slot(0x6075, 0);
pub const RATED_TORQUE: usize = slot(0x6076, 0);
pub const TORQUE_ACTUAL: usize = slot(0x6077, 0);
pub const CURRENT_ACTUAL: usize = slot(0x6078, 0);
pub const TARGET_POSITION: usize = slot(0x607A, 0);
pub const TORQUE_OFFSET: usize = slot(0x60B2, 0);
pub const INTERPOLATION_UNITS: usize = slot(0x60C2, 1);
pub const INTERPOLATION_INDEX: usize = slot(0x60C2, 2);

/// Slots of one PDO's communication parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PdoCommSlots {
    pub cob_id: usize,
    pub transmission: usize,
}
/// Slots of the TPDOs' event timers (sub 5, ms, 0 = off): an event-driven TPDO is also sent
/// when this long has passed since it was last sent. Sub 3 (inhibit time) is not implemented.
pub const TPDO_EVENT_TIMER: [usize; 2] = [slot(0x1800, 5), slot(0x1801, 5)];
/// Slot of a PDO mapping's sub 0 (count); entries follow at `count + 1 ..= count + 8`.
pub type PdoMapSlot = usize;

pub const RPDO_COMM: [PdoCommSlots; 2] = [
    PdoCommSlots {
        cob_id: slot(0x1400, 1),
        transmission: slot(0x1400, 2),
    },
    PdoCommSlots {
        cob_id: slot(0x1401, 1),
        transmission: slot(0x1401, 2),
    },
];
pub const TPDO_COMM: [PdoCommSlots; 2] = [
    PdoCommSlots {
        cob_id: slot(0x1800, 1),
        transmission: slot(0x1800, 2),
    },
    PdoCommSlots {
        cob_id: slot(0x1801, 1),
        transmission: slot(0x1801, 2),
    },
];
pub const RPDO_MAP: [PdoMapSlot; 2] = [slot(0x1600, 0), slot(0x1601, 0)];
pub const TPDO_MAP: [PdoMapSlot; 2] = [slot(0x1A00, 0), slot(0x1A01, 0)];

/// The dictionary of one drive: current values and power-up values.
#[derive(Debug, Clone, PartialEq)]
pub struct Od {
    values: [u32; LEN],
    defaults: [u32; LEN],
}

impl Od {
    /// A dictionary with every object at its power-up value.
    pub fn new(d: &OdDefaults) -> Od {
        let mut defaults = [0u32; LEN];
        for (slot, def) in TABLE.iter().enumerate() {
            let v = match def.init {
                Fixed(v) => v,
                PlusNodeId(v) => v + u32::from(d.node_id),
                InitValue::RatedCurrentMa => d.rated_current_ma,
                InitValue::RatedTorqueMnm => d.rated_torque_mnm,
                InitValue::PeakCurrentPermille => u32::from(d.peak_current_permille),
            };
            defaults[slot] = v & def.dtype.mask();
        }
        Od {
            values: defaults,
            defaults,
        }
    }

    /// Communication reset: objects 0x1000..=0x1FFF back to their power-up values.
    pub fn reset_communication(&mut self) {
        self.reset_where(|i| i < 0x2000);
    }

    /// Application reset: objects from 0x2000 on back to their power-up values, except the
    /// stored calibration 0x2100 (cleared only by a power cycle, i.e. a new [`Od`]).
    pub fn reset_application(&mut self) {
        self.reset_where(|i| i >= 0x2000 && i != CALIBRATION_INDEX);
    }

    fn reset_where(&mut self, pick: impl Fn(u16) -> bool) {
        for (slot, def) in TABLE.iter().enumerate() {
            if pick(def.index) {
                self.values[slot] = self.defaults[slot];
            }
        }
    }

    /// The slot of `index:sub`, or the abort for a missing object / sub-index.
    pub fn lookup(index: u16, sub: u8) -> Result<usize, SdoAbort> {
        match TABLE.binary_search_by(|d| (d.index, d.sub).cmp(&(index, sub))) {
            Ok(slot) => Ok(slot),
            Err(_) if TABLE.iter().any(|d| d.index == index) => {
                Err(SdoAbort::SubIndexDoesNotExist { index, sub })
            }
            Err(_) => Err(SdoAbort::ObjectDoesNotExist { index }),
        }
    }

    /// The definition of a slot.
    pub fn def(slot: usize) -> &'static ObjectDef {
        &TABLE[slot]
    }

    /// Raw bits of a value.
    pub fn raw(&self, slot: usize) -> u32 {
        self.values[slot]
    }

    /// Store raw bits (masked to the object's width). No access checks: the drive's own write.
    pub fn set_raw(&mut self, slot: usize, raw: u32) {
        self.values[slot] = raw & TABLE[slot].dtype.mask();
    }

    /// The value as a signed number (sign-extended for signed types).
    pub fn i32(&self, slot: usize) -> i32 {
        let raw = self.values[slot];
        let t = TABLE[slot].dtype;
        if !t.signed() {
            return raw as i32;
        }
        let shift = 32 - u32::from(t.bits());
        ((raw << shift) as i32) >> shift
    }

    /// Store a signed number (two's complement, truncated to the object's width).
    pub fn set_i32(&mut self, slot: usize, v: i32) {
        self.set_raw(slot, v as u32);
    }
}

#[cfg(test)]
mod tests;
