//! The bridge thread's one blocking call: `poll(2)` on the doorbell and, when open, the
//! listener of the core's state event, with a timeout.

use std::io;
use std::os::fd::RawFd;
use std::time::Duration;

/// Most descriptors waited on at once (the doorbell and the state event).
pub const MAX_FDS: usize = 2;

/// Which of the descriptors passed to [`wait_readable`] are readable (in the same order).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Readiness {
    pub ready: [bool; MAX_FDS],
}

/// Block until one of `fds` (at most [`MAX_FDS`]) is readable or `timeout` has passed (rounded
/// up to whole milliseconds, so a short wait never becomes a busy loop). An interrupted wait
/// returns as a timeout.
pub fn wait_readable(fds: &[RawFd], timeout: Duration) -> io::Result<Readiness> {
    let mut polls = [libc::pollfd {
        fd: -1,
        events: 0,
        revents: 0,
    }; MAX_FDS];
    let n = fds.len().min(MAX_FDS);
    for (p, fd) in polls.iter_mut().zip(&fds[..n]) {
        p.fd = *fd;
        p.events = libc::POLLIN;
    }
    let ms = timeout.as_micros().div_ceil(1000).min(i32::MAX as u128) as i32;
    // SAFETY: `polls` is a live array of `n` initialised pollfd structures.
    let r = unsafe { libc::poll(polls.as_mut_ptr(), n as libc::nfds_t, ms) };
    let mut out = Readiness::default();
    if r < 0 {
        let e = io::Error::last_os_error();
        return if e.kind() == io::ErrorKind::Interrupted {
            Ok(out)
        } else {
            Err(e)
        };
    }
    for (o, p) in out.ready.iter_mut().zip(&polls[..n]) {
        *o = p.revents & (libc::POLLIN | libc::POLLERR | libc::POLLHUP) != 0;
    }
    Ok(out)
}
