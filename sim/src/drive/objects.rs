//! The drive's objects as the SDO server sees them: access rights, lengths, the PDO rules
//! and value ranges of SDO writes, and the side effects of a written object (controlword ->
//! CiA 402 state machine, modes of operation, heartbeat times, PDO parameters).
//!
//! Runs inside the cycle: no allocation; every refusal is a typed [`SdoAbort`].

use super::{RESTORE_SIGNATURE, SimDrive, valid_mode};
use crate::FrameSink;
use crate::abort::SdoAbort;
use crate::nmt::NmtState;
use crate::od::{self, Access, Od};
use crate::pdo;
use crate::sdo_server::ObjectAccess;

impl SimDrive {
    fn check_range(&self, slot: usize, raw: u32) -> Result<(), SdoAbort> {
        let def = Od::def(slot);
        let bad = |allowed| {
            Err(SdoAbort::ValueRange {
                index: def.index,
                sub: def.sub,
                value: raw,
                allowed,
            })
        };
        match slot {
            od::MODES_OF_OPERATION if !valid_mode(raw) => bad("0 (none), 8 (CSP) or 10 (CST)"),
            od::MAX_CURRENT if raw > u32::from(self.p.od_defaults.peak_current_permille) => bad(
                "0 up to the drive's peak current (the power-up value of 0x6073), per-mille of 0x6075",
            ),
            od::RATED_CURRENT | od::RATED_TORQUE if raw == 0 => bad("at least 1"),
            od::CONSUMER_HEARTBEAT if raw & 0xFF80_0000 != 0 => {
                bad("(node id 0..=127 << 16) | time in ms")
            }
            od::QUICK_STOP_OPTION if raw as u16 as i16 != od::QUICK_STOP_OPTION_SUPPORTED => {
                bad("2 (quick-stop ramp, then SWITCH ON DISABLED), the only option this drive has")
            }
            od::ABORT_CONNECTION_OPTION if !(0..=3).contains(&(raw as u16 as i16)) => {
                bad("0 (no action), 1 (fault), 2 (disable voltage) or 3 (quick stop)")
            }
            od::CALIBRATION_VALID if raw > 1 => bad("0 (not calibrated) or 1 (valid)"),
            od::RESTORE_DEFAULTS if raw != RESTORE_SIGNATURE => bad("0x64616F6C (\"load\")"),
            od::INTERPOLATION_INDEX if !(-6..=0).contains(&(raw as u8 as i8)) => {
                bad("-6..=0 (period = units x 10^index s)")
            }
            _ => Ok(()),
        }
    }

    /// Store an SDO-written value and act on it.
    fn store(&mut self, slot: usize, raw: u32, out: &mut dyn FrameSink) {
        self.od.set_raw(slot, raw);
        match slot {
            od::CONTROLWORD => {
                let t = self.sm.write_controlword(raw as u16, !self.safe_torque_off);
                self.on_transition(t, out);
            }
            od::MODES_OF_OPERATION => self.mode_written(),
            od::PRODUCER_HEARTBEAT => self.producer.configure(raw as u16, self.time_ns),
            od::CONSUMER_HEARTBEAT => self.consumer.configure(raw),
            _ => self.pdo.comm_written(slot),
        }
    }
}

/// The drive seen by its SDO server, with the sink for frames its writes cause (EMCY).
pub(super) struct SdoContext<'a> {
    pub(super) drive: &'a mut SimDrive,
    pub(super) out: &'a mut dyn FrameSink,
}

impl ObjectAccess for SdoContext<'_> {
    fn sdo_read(&mut self, index: u16, sub: u8) -> Result<(u32, u8), SdoAbort> {
        let slot = Od::lookup(index, sub)?;
        let def = Od::def(slot);
        if def.access == Access::Wo {
            return Err(SdoAbort::ReadOfWriteOnly { index, sub });
        }
        self.drive.refresh_statusword();
        Ok((self.drive.od.raw(slot), def.dtype.size()))
    }

    fn sdo_write(
        &mut self,
        index: u16,
        sub: u8,
        raw: u32,
        size: Option<u8>,
    ) -> Result<(), SdoAbort> {
        let slot = Od::lookup(index, sub)?;
        let def = Od::def(slot);
        if matches!(def.access, Access::Const | Access::Ro) {
            return Err(SdoAbort::WriteToReadOnly { index, sub });
        }
        if let Some(given) = size
            && given != def.dtype.size()
        {
            return Err(SdoAbort::LengthMismatch {
                index,
                sub,
                expected: def.dtype.size(),
                given,
            });
        }
        let raw = raw & def.dtype.mask();
        let d = &mut *self.drive;
        pdo::check_write(&d.od, d.nmt == NmtState::Operational, slot, raw)?;
        d.check_range(slot, raw)?;
        d.store(slot, raw, self.out);
        Ok(())
    }
}
