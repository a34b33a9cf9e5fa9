//! Steps most programs begin with, built from the commands: get the arm calibrated, and wait
//! (bounded) until the state shows what a command was for.

use super::{Error, Status, TcpClient};
use std::time::{Duration, Instant};

/// How often [`TcpClient::wait_until`] asks for the state.
const POLL: Duration = Duration::from_millis(10);

impl TcpClient {
    /// Enter HOLD (which powers the drives from OFF or ERROR) and, when an axis is not
    /// calibrated yet, calibrate all axes with the default directions; `true` when it
    /// calibrated. The arm ends in HOLD either way.
    pub fn calibrate_if_needed(&mut self) -> Result<bool, Error> {
        self.hold()?;
        let calibrated = self
            .status_detail()?
            .detail
            .is_some_and(|d| d.all_calibrated);
        if !calibrated {
            self.calibrate(Default::default())?;
        }
        Ok(!calibrated)
    }

    /// Read the state (`status`) until `arrived` holds for it, at most `timeout`; that state.
    /// `what` names the condition in the error ([`Error::NotReached`]) when it does not hold
    /// in time.
    pub fn wait_until(
        &mut self,
        what: &str,
        timeout: Duration,
        mut arrived: impl FnMut(&Status) -> bool,
    ) -> Result<Status, Error> {
        let deadline = Instant::now() + timeout;
        loop {
            let s = self.status()?;
            if arrived(&s) {
                return Ok(s);
            }
            if Instant::now() >= deadline {
                return Err(Error::NotReached {
                    what: what.to_string(),
                    waited: timeout,
                    last: Box::new(s),
                });
            }
            std::thread::sleep(POLL);
        }
    }
}
