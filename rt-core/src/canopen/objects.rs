//! Object dictionary indices of the MCM drive profile and COB-ID helpers (predefined
//! connection set, 11-bit ids).
//!
//! Runs inside the cycle: constants and `const fn`s only, no allocation.
//!
//! ```
//! use mcm_rt_core::canopen::objects::{classify, Service, ObjectAddr, STATUSWORD};
//! assert_eq!(classify(0x185), Service::Tpdo { pdo: 1, node: 5 });
//! assert_eq!(ObjectAddr::new(STATUSWORD, 0).to_string(), "0x6041:0");
//! ```

use core::fmt;

/// An object dictionary entry: index and sub-index.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ObjectAddr {
    pub index: u16,
    pub sub: u8,
}

impl ObjectAddr {
    pub const fn new(index: u16, sub: u8) -> ObjectAddr {
        ObjectAddr { index, sub }
    }
}

/// Spelled like the drive manuals: `0x1400:1`.
impl fmt::Display for ObjectAddr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "0x{:04X}:{}", self.index, self.sub)
    }
}

// CiA 301 communication objects.
pub const DEVICE_TYPE: u16 = 0x1000;
pub const ERROR_REGISTER: u16 = 0x1001;
pub const CONSUMER_HEARTBEAT_TIME: u16 = 0x1016;
pub const PRODUCER_HEARTBEAT_TIME: u16 = 0x1017;
/// RPDO k communication parameter is `RPDO_COMM + k - 1`.
pub const RPDO_COMM: u16 = 0x1400;
/// RPDO k mapping parameter is `RPDO_MAP + k - 1`.
pub const RPDO_MAP: u16 = 0x1600;
/// TPDO k communication parameter is `TPDO_COMM + k - 1`.
pub const TPDO_COMM: u16 = 0x1800;
/// TPDO k mapping parameter is `TPDO_MAP + k - 1`.
pub const TPDO_MAP: u16 = 0x1A00;

// CiA 402 objects.
pub const ERROR_CODE: u16 = 0x603F;
pub const CONTROLWORD: u16 = 0x6040;
pub const STATUSWORD: u16 = 0x6041;
/// Quick stop option code (i16): what the drive does on the controlword's quick stop.
pub const QUICK_STOP_OPTION_CODE: u16 = 0x605A;
/// Abort connection option code (i16): what the drive does when the master cuts the connection.
pub const ABORT_CONNECTION_OPTION_CODE: u16 = 0x6007;
pub const MODES_OF_OPERATION: u16 = 0x6060;
pub const MODES_OF_OPERATION_DISPLAY: u16 = 0x6061;
pub const POSITION_ACTUAL: u16 = 0x6064;
pub const TARGET_TORQUE: u16 = 0x6071;
pub const MAX_CURRENT: u16 = 0x6073;
/// Torque offset: the position loop's torque feed-forward [‰ of 0x6076].
pub const TORQUE_OFFSET: u16 = 0x60B2;
pub const MOTOR_RATED_CURRENT: u16 = 0x6075;
pub const MOTOR_RATED_TORQUE: u16 = 0x6076;
pub const CURRENT_ACTUAL: u16 = 0x6078;
pub const TARGET_POSITION: u16 = 0x607A;
pub const INTERPOLATION_TIME_PERIOD: u16 = 0x60C2;

/// 0x1000 of a CiA 402 servo drive: profile 402 (0x0192), type "servo drive" (0x0002).
pub const DEVICE_TYPE_CIA402_SERVO: u32 = 0x0002_0192;

/// 0x605A value the master writes at boot: slow down on the quick-stop ramp (0x6085), then
/// SWITCH ON DISABLED by itself (CiA 402 option 2). The master's state machine relies on it
/// ([`super::cia402`]: a drive it asks to quick-stop ends disabled, and QUICK STOP ACTIVE is
/// left through SWITCH ON DISABLED, never by transition 16).
pub const QUICK_STOP_OPTION_DISABLE: i16 = 2;

/// 0x6007 value the master writes at boot: when the master cuts the connection (its NMT stop),
/// the drive disables its voltage (SWITCH ON DISABLED: no current, the brake engaged), SYNC or
/// not (CiA 402 option 2). The master powers off a lost drive this way, one that SYNC and
/// PDOs may no longer reach (`Master::cut_off`, called from [`super::master::Master::cycle`]).
pub const ABORT_CONNECTION_DISABLE_VOLTAGE: i16 = 2;

/// Bit 31 of a PDO COB-ID entry: the PDO is invalid (disabled).
pub const PDO_COB_ID_INVALID: u32 = 0x8000_0000;

/// A PDO mapping entry `0xIIIISSLL` (index, sub-index, length in bits).
pub const fn mapping_entry(index: u16, sub: u8, bits: u8) -> u32 {
    ((index as u32) << 16) | ((sub as u32) << 8) | bits as u32
}

// Function codes (COB-ID base values) of the predefined connection set.
pub const NMT_ID: u16 = 0x000;
pub const SYNC_ID: u16 = 0x080;
pub const EMCY_BASE: u16 = 0x080;
pub const TPDO1_BASE: u16 = 0x180;
pub const RPDO1_BASE: u16 = 0x200;
pub const TPDO2_BASE: u16 = 0x280;
pub const RPDO2_BASE: u16 = 0x300;
pub const SDO_TX_BASE: u16 = 0x580;
pub const SDO_RX_BASE: u16 = 0x600;
pub const HEARTBEAT_BASE: u16 = 0x700;

pub const fn emcy_id(node: u8) -> u16 {
    EMCY_BASE + node as u16
}
/// COB-ID of TPDO `pdo` (1..=4) of `node`.
pub const fn tpdo_id(pdo: u8, node: u8) -> u16 {
    TPDO1_BASE + 0x100 * (pdo as u16 - 1) + node as u16
}
/// COB-ID of RPDO `pdo` (1..=4) of `node`.
pub const fn rpdo_id(pdo: u8, node: u8) -> u16 {
    RPDO1_BASE + 0x100 * (pdo as u16 - 1) + node as u16
}
/// SDO server -> client (responses).
pub const fn sdo_tx_id(node: u8) -> u16 {
    SDO_TX_BASE + node as u16
}
/// SDO client -> server (requests).
pub const fn sdo_rx_id(node: u8) -> u16 {
    SDO_RX_BASE + node as u16
}
/// NMT error control (heartbeat, boot-up).
pub const fn heartbeat_id(node: u8) -> u16 {
    HEARTBEAT_BASE + node as u16
}

/// What a COB-ID carries, from the point of view of a bus observer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Service {
    Nmt,
    Sync,
    Emcy {
        node: u8,
    },
    Time,
    /// Drive -> master process data.
    Tpdo {
        pdo: u8,
        node: u8,
    },
    /// Master -> drive process data.
    Rpdo {
        pdo: u8,
        node: u8,
    },
    /// SDO response (server -> client).
    SdoResponse {
        node: u8,
    },
    /// SDO request (client -> server).
    SdoRequest {
        node: u8,
    },
    /// Heartbeat or boot-up.
    Heartbeat {
        node: u8,
    },
    /// Anything outside the predefined connection set (e.g. LSS).
    Other {
        id: u16,
    },
}

/// Split an 11-bit COB-ID into function code and node id.
pub const fn classify(id: u16) -> Service {
    let node = (id & 0x7F) as u8;
    let function = id & 0x780;
    if id == NMT_ID {
        return Service::Nmt;
    }
    if id == SYNC_ID {
        return Service::Sync;
    }
    if id == 0x100 {
        return Service::Time;
    }
    if node == 0 || id > 0x7FF {
        return Service::Other { id };
    }
    match function {
        0x080 => Service::Emcy { node },
        0x180 => Service::Tpdo { pdo: 1, node },
        0x280 => Service::Tpdo { pdo: 2, node },
        0x380 => Service::Tpdo { pdo: 3, node },
        0x480 => Service::Tpdo { pdo: 4, node },
        0x200 => Service::Rpdo { pdo: 1, node },
        0x300 => Service::Rpdo { pdo: 2, node },
        0x400 => Service::Rpdo { pdo: 3, node },
        0x500 => Service::Rpdo { pdo: 4, node },
        0x580 => Service::SdoResponse { node },
        0x600 => Service::SdoRequest { node },
        0x700 => Service::Heartbeat { node },
        _ => Service::Other { id },
    }
}

#[cfg(test)]
mod tests;
