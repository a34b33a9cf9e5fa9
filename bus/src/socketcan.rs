//! The SocketCAN backend: [`SocketCanBus`] implements [`Bus`] over a raw, non-blocking
//! `socketcan::CanSocket` (Linux only).
//!
//! - `send` writes one frame and never blocks; a full transmit queue (`EAGAIN`/`ENOBUFS`) is
//!   [`BusError::TxQueueFull`].
//! - `recv(deadline_ns)` returns a queued frame at once, or waits with `ppoll(2)` at most until
//!   `deadline_ns` (`CLOCK_MONOTONIC`). Frames the MCM does not use (extended ids, remote
//!   frames) are skipped and counted; a bus-off error frame is [`BusError::BusOff`].
//! - Opening checks first whether the kernel supports CAN at all, so a machine without CAN
//!   (socket() fails with errno 97, `EAFNOSUPPORT`) gets an error saying exactly that.
//!
//! `send` and `recv` run inside the cycle: no allocation, no locks; `open` does not.
//!
//! ```no_run
//! use mcm_bus::{Bus, socketcan::SocketCanBus};
//! let mut bus = SocketCanBus::open("can0")?;
//! bus.send(&mcm_bus::Frame::new(0x080, &[]).unwrap())?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use super::{Bus, BusError, Frame};
use ::socketcan::{
    CanFrame, CanSocket, EmbeddedFrame, Frame as _, Socket, SocketOptions, StandardId,
};
use std::io;
use std::os::fd::AsRawFd;

/// Opening or setting up a CAN interface failed. Every message names the interface and the
/// OS error.
#[derive(Debug, thiserror::Error)]
pub enum SocketCanError {
    #[error(
        "cannot open CAN interface {interface}: this kernel has no SocketCAN support \
         (socket(AF_CAN, SOCK_RAW, CAN_RAW) failed with os error 97, EAFNOSUPPORT: address family \
         not supported by protocol); load the CAN modules (modprobe can_raw) or use bus.backend = \"sim\""
    )]
    NoKernelSupport { interface: String },
    #[error(
        "cannot open CAN interface {interface}: no such network interface (os error {errno}); \
         allowed: an existing CAN interface (see `ip link show type can`, or create one with \
         `ip link add dev vcan0 type vcan`)"
    )]
    NoSuchInterface { interface: String, errno: i32 },
    #[error("cannot open CAN interface {interface}: {source}")]
    Open {
        interface: String,
        #[source]
        source: io::Error,
    },
    #[error("cannot set up CAN interface {interface}: {what} failed: {source}")]
    Setup {
        interface: String,
        what: &'static str,
        #[source]
        source: io::Error,
    },
    #[error(
        "CAN interface name {interface:?} is not allowed: 1 to 15 bytes without '/', whitespace or NUL"
    )]
    BadName { interface: String },
}

/// A kernel frame the MCM's [`Frame`] cannot represent, or the reverse.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum FrameConversionError {
    #[error(
        "CAN frame with extended (29-bit) id 0x{id:08X} is not used by the MCM; allowed: 11-bit ids"
    )]
    ExtendedId { id: u32 },
    #[error("remote (RTR) frame on id 0x{id:03X} is not used by the MCM; allowed: data frames")]
    Remote { id: u32 },
    #[error("CAN error frame (error class 0x{class:08X}) is not a data frame")]
    ErrorFrame { class: u32 },
    #[error(
        "frame with id 0x{id:X} and length {len} is not a classic CAN frame; allowed: id <= 0x7FF, length <= 8"
    )]
    Invalid { id: u16, len: u8 },
}

/// MCM frame -> kernel frame.
pub fn to_can_frame(f: &Frame) -> Result<CanFrame, FrameConversionError> {
    let invalid = FrameConversionError::Invalid {
        id: f.id,
        len: f.len,
    };
    if f.len > 8 {
        return Err(invalid);
    }
    let id = StandardId::new(f.id).ok_or(invalid)?;
    CanFrame::new(id, f.payload()).ok_or(invalid)
}

/// Kernel frame -> MCM frame.
pub fn from_can_frame(f: &CanFrame) -> Result<Frame, FrameConversionError> {
    match f {
        CanFrame::Error(e) => Err(FrameConversionError::ErrorFrame {
            class: e.raw_id() & libc::CAN_ERR_MASK,
        }),
        CanFrame::Remote(r) => Err(FrameConversionError::Remote { id: r.raw_id() }),
        CanFrame::Data(d) if d.is_extended() => {
            Err(FrameConversionError::ExtendedId { id: d.raw_id() })
        }
        CanFrame::Data(d) => {
            let id = d.raw_id();
            let data = d.data();
            Frame::new(id as u16, data).ok_or(FrameConversionError::Invalid {
                id: id as u16,
                len: data.len() as u8,
            })
        }
    }
}

/// A raw CAN socket bound to one interface, in non-blocking mode.
pub struct SocketCanBus {
    socket: CanSocket,
    interface: &'static str,
    skipped: u64,
}

impl std::fmt::Debug for SocketCanBus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SocketCanBus")
            .field("interface", &self.interface)
            .field("skipped", &self.skipped)
            .finish()
    }
}

/// `Err(NoKernelSupport)` when this kernel cannot create CAN sockets at all.
pub fn check_kernel_support(interface: &str) -> Result<(), SocketCanError> {
    // SAFETY: socket(2) with constant arguments; the returned descriptor is closed below.
    let fd = unsafe {
        libc::socket(
            libc::AF_CAN,
            libc::SOCK_RAW | libc::SOCK_CLOEXEC,
            libc::CAN_RAW,
        )
    };
    if fd < 0 {
        let err = io::Error::last_os_error();
        return Err(match err.raw_os_error() {
            Some(libc::EAFNOSUPPORT) => SocketCanError::NoKernelSupport {
                interface: interface.to_owned(),
            },
            _ => SocketCanError::Open {
                interface: interface.to_owned(),
                source: err,
            },
        });
    }
    // SAFETY: `fd` is a descriptor we own and close exactly once.
    unsafe { libc::close(fd) };
    Ok(())
}

fn valid_name(name: &str) -> bool {
    (1..=15).contains(&name.len())
        && !name
            .bytes()
            .any(|b| b == b'/' || b == 0 || b.is_ascii_whitespace())
}

impl SocketCanBus {
    /// Open `interface` (e.g. `can0`, `vcan0`), non-blocking, receiving bus-off error frames.
    ///
    /// The interface name is leaked once (a few bytes per open) so that the cyclic errors
    /// ([`BusError`]) can name it without allocating.
    pub fn open(interface: &str) -> Result<SocketCanBus, SocketCanError> {
        if !valid_name(interface) {
            return Err(SocketCanError::BadName {
                interface: interface.to_owned(),
            });
        }
        check_kernel_support(interface)?;
        let socket = CanSocket::open(interface).map_err(|e| match e.raw_os_error() {
            Some(libc::EAFNOSUPPORT) => SocketCanError::NoKernelSupport {
                interface: interface.to_owned(),
            },
            Some(errno @ libc::ENODEV) => SocketCanError::NoSuchInterface {
                interface: interface.to_owned(),
                errno,
            },
            _ => SocketCanError::Open {
                interface: interface.to_owned(),
                source: e,
            },
        })?;
        let setup = |what, r: io::Result<()>| {
            r.map_err(|source| SocketCanError::Setup {
                interface: interface.to_owned(),
                what,
                source,
            })
        };
        setup("set_nonblocking(true)", socket.set_nonblocking(true))?;
        setup(
            "set_error_filter(CAN_ERR_BUSOFF)",
            socket.set_error_filter(libc::CAN_ERR_BUSOFF),
        )?;
        Ok(SocketCanBus {
            socket,
            interface: Box::leak(interface.to_owned().into_boxed_str()),
            skipped: 0,
        })
    }

    pub fn interface(&self) -> &'static str {
        self.interface
    }

    /// Received frames skipped because the MCM does not use them (extended, remote, other
    /// error frames).
    pub fn skipped_frames(&self) -> u64 {
        self.skipped
    }

    fn os_error(&self, e: &io::Error) -> BusError {
        BusError::Os {
            interface: self.interface,
            errno: e.raw_os_error().unwrap_or(0),
        }
    }

    /// Wait until the socket is readable or `timeout_ns` passed. `Ok(())` in both cases.
    fn wait_readable(&self, timeout_ns: u64) -> Result<(), BusError> {
        let mut pfd = libc::pollfd {
            fd: self.socket.as_raw_fd(),
            events: libc::POLLIN,
            revents: 0,
        };
        let ts = libc::timespec {
            tv_sec: (timeout_ns / 1_000_000_000) as libc::time_t,
            tv_nsec: (timeout_ns % 1_000_000_000) as libc::c_long,
        };
        // SAFETY: `pfd` points to one valid pollfd, `ts` to a valid timespec, and a null
        // signal mask means "keep the current mask"; all outlive the call.
        let r = unsafe { libc::ppoll(&mut pfd, 1, &ts, core::ptr::null()) };
        if r < 0 {
            let e = io::Error::last_os_error();
            if e.kind() != io::ErrorKind::Interrupted {
                return Err(self.os_error(&e));
            }
        }
        Ok(())
    }
}

/// `CLOCK_MONOTONIC` in nanoseconds: the clock of [`Bus::recv`]'s deadlines.
pub fn monotonic_ns() -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; CLOCK_MONOTONIC always exists on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut ts) };
    (ts.tv_sec as u64)
        .saturating_mul(1_000_000_000)
        .saturating_add(ts.tv_nsec as u64)
}

impl Bus for SocketCanBus {
    fn send(&mut self, frame: &Frame) -> Result<(), BusError> {
        let Ok(cf) = to_can_frame(frame) else {
            // Frame::new never builds such a frame; refuse it like a driver would.
            return Err(BusError::Os {
                interface: self.interface,
                errno: libc::EINVAL,
            });
        };
        match self.socket.write_frame(&cf) {
            Ok(()) => Ok(()),
            Err(e)
                if e.kind() == io::ErrorKind::WouldBlock
                    || e.raw_os_error() == Some(libc::ENOBUFS) =>
            {
                Err(BusError::TxQueueFull {
                    interface: self.interface,
                    frame: *frame,
                })
            }
            Err(e) if e.raw_os_error() == Some(libc::ENETDOWN) => Err(BusError::BusOff {
                interface: self.interface,
            }),
            Err(e) => Err(self.os_error(&e)),
        }
    }

    fn recv(&mut self, deadline_ns: u64) -> Result<Option<Frame>, BusError> {
        loop {
            match self.socket.read_frame() {
                Ok(cf) => match from_can_frame(&cf) {
                    Ok(f) => return Ok(Some(f)),
                    Err(FrameConversionError::ErrorFrame { class })
                        if class & libc::CAN_ERR_BUSOFF != 0 =>
                    {
                        return Err(BusError::BusOff {
                            interface: self.interface,
                        });
                    }
                    Err(_) => {
                        self.skipped += 1;
                        continue;
                    }
                },
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => {}
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(self.os_error(&e)),
            }
            let now = monotonic_ns();
            if now >= deadline_ns {
                return Ok(None);
            }
            self.wait_readable(deadline_ns - now)?;
        }
    }
}

#[cfg(test)]
mod tests;
