//! The bridge thread's doorbell: an `eventfd` that the async side rings after it queued a job,
//! so the bridge thread can sleep in one `poll(2)` on the doorbell and the core's state event
//! together (see `wait.rs`), with no thread in between.
//!
//! Ringing never blocks (the counter saturates long before it could); clearing reads the
//! counter back to zero. A ring that comes between the bridge's clear and its draining of the
//! job channel leaves the doorbell set, so the next wait returns at once: no job is missed.

use std::io;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd, RawFd};

/// Why the doorbell could not be made.
#[derive(Debug, thiserror::Error)]
#[error("creating the bridge's doorbell (eventfd) failed: {0}")]
pub struct DoorbellError(#[source] io::Error);

#[derive(Debug)]
pub struct Doorbell {
    fd: OwnedFd,
}

impl Doorbell {
    pub fn new() -> Result<Doorbell, DoorbellError> {
        // SAFETY: eventfd takes no pointers; a negative result is an error, checked below.
        let fd = unsafe { libc::eventfd(0, libc::EFD_NONBLOCK | libc::EFD_CLOEXEC) };
        if fd < 0 {
            return Err(DoorbellError(io::Error::last_os_error()));
        }
        // SAFETY: `fd` is a new, valid descriptor owned by nobody else.
        let fd = unsafe { OwnedFd::from_raw_fd(fd) };
        Ok(Doorbell { fd })
    }

    /// Wake the bridge thread (or make its next wait return at once).
    pub fn ring(&self) {
        let one: u64 = 1;
        // SAFETY: writes 8 bytes from a live u64 to our own eventfd. A failure can only be
        // EAGAIN (the counter near its maximum: the doorbell is set anyway), so it is ignored.
        let _ = unsafe {
            libc::write(
                self.fd.as_raw_fd(),
                (&one as *const u64).cast(),
                std::mem::size_of::<u64>(),
            )
        };
    }

    /// Reset the doorbell (before the jobs are taken from the channel).
    pub fn clear(&self) {
        let mut count: u64 = 0;
        // SAFETY: reads at most 8 bytes into a live u64 from our own eventfd; EAGAIN (not set)
        // is the only expected failure and means there is nothing to clear.
        let _ = unsafe {
            libc::read(
                self.fd.as_raw_fd(),
                (&mut count as *mut u64).cast(),
                std::mem::size_of::<u64>(),
            )
        };
    }

    pub fn fd(&self) -> RawFd {
        self.fd.as_raw_fd()
    }
}

#[cfg(test)]
mod tests;
