//! Steps most programs begin with, built from the commands: get the arm calibrated, and wait
//! (bounded) until the state shows what a command was for.

use super::{RequestError, ShmClient, WaitUntilError};
use mcm_shared::command::Calibrate;
use mcm_shared::sample::{STATE_ALL_CALIBRATED, StateSample};
use std::time::{Duration, Instant};

impl ShmClient {
    /// Enter HOLD (which powers the drives from OFF or ERROR) and, when an axis is not
    /// calibrated yet, calibrate all axes with the default directions; `true` when it
    /// calibrated. The arm ends in HOLD either way.
    pub fn calibrate_if_needed(&mut self) -> Result<bool, RequestError> {
        self.hold()?;
        let calibrated = self.latest().flags & STATE_ALL_CALIBRATED != 0;
        if !calibrated {
            self.calibrate(Calibrate::default())?;
        }
        Ok(!calibrated)
    }

    /// Read every state ([`ShmClient::wait_state`]) until `arrived` holds for one, at most
    /// `timeout`; that state. `what` names the condition in the error
    /// ([`WaitUntilError::NotReached`]) when it does not hold in time.
    pub fn wait_until(
        &mut self,
        what: &str,
        timeout: Duration,
        mut arrived: impl FnMut(&StateSample) -> bool,
    ) -> Result<StateSample, WaitUntilError> {
        let deadline = Instant::now() + timeout;
        loop {
            let s = self.wait_state()?;
            if arrived(&s) {
                return Ok(s);
            }
            if Instant::now() >= deadline {
                return Err(WaitUntilError::NotReached {
                    what: what.to_string(),
                    waited: timeout,
                    last_seq: s.seq,
                });
            }
        }
    }
}
