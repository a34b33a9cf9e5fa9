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

fn monotonic_ns() -> u64 {
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
mod tests {
    use super::*;
    use ::socketcan::{ExtendedId, Id};

    #[test]
    fn frames_convert_both_ways() {
        for f in [
            Frame::new(0x080, &[]).unwrap(),
            Frame::new(0x185, &[0x37, 0x02, 0xA0, 0x86, 0x01, 0x00, 0xFE, 0xFF]).unwrap(),
            Frame::new(0x7FF, &[1]).unwrap(),
        ] {
            let cf = to_can_frame(&f).unwrap();
            assert_eq!(cf.raw_id(), u32::from(f.id));
            assert_eq!(cf.data(), f.payload());
            assert!(!cf.is_extended());
            assert_eq!(from_can_frame(&cf), Ok(f));
        }
    }

    #[test]
    fn unusable_frames_are_typed_errors() {
        let ext =
            CanFrame::new(Id::Extended(ExtendedId::new(0x1234_5678).unwrap()), &[1, 2]).unwrap();
        assert_eq!(
            from_can_frame(&ext),
            Err(FrameConversionError::ExtendedId { id: 0x1234_5678 })
        );
        let rtr = CanFrame::new_remote(StandardId::new(0x705).unwrap(), 1).unwrap();
        assert_eq!(
            from_can_frame(&rtr),
            Err(FrameConversionError::Remote { id: 0x705 })
        );
        let bad = Frame {
            id: 0x800,
            len: 0,
            data: [0; 8],
        };
        assert_eq!(
            to_can_frame(&bad).unwrap_err().to_string(),
            "frame with id 0x800 and length 0 is not a classic CAN frame; allowed: id <= 0x7FF, length <= 8"
        );
        let long = Frame {
            id: 0x100,
            len: 9,
            data: [0; 8],
        };
        assert!(to_can_frame(&long).is_err());
    }

    #[test]
    fn bad_interface_names_are_refused() {
        for name in ["", "a/b", "can 0", "sixteen_chars_xx"] {
            let err = SocketCanBus::open(name).unwrap_err();
            assert!(
                matches!(err, SocketCanError::BadName { .. }),
                "{name:?}: {err}"
            );
        }
    }

    #[test]
    fn opening_a_missing_interface_names_it_and_the_os_error() {
        let err = SocketCanBus::open("mcmnocan7").unwrap_err();
        let msg = err.to_string();
        println!("{msg}");
        assert!(msg.contains("mcmnocan7"), "{msg}");
        assert!(msg.contains("os error"), "{msg}");
        match check_kernel_support("mcmnocan7") {
            Err(SocketCanError::NoKernelSupport { .. }) => {
                // This machine has no CAN in its kernel (errno 97): that must be the error.
                assert!(
                    matches!(err, SocketCanError::NoKernelSupport { .. }),
                    "{err:?}"
                );
                assert!(
                    msg.contains("os error 97") && msg.contains("EAFNOSUPPORT"),
                    "{msg}"
                );
            }
            _ => assert!(
                matches!(
                    err,
                    SocketCanError::NoSuchInterface {
                        errno: libc::ENODEV,
                        ..
                    }
                ),
                "{err:?}"
            ),
        }
    }

    /// Talks to a real interface only when `MCM_TEST_CAN_IFACE` names one (e.g. `vcan0`).
    #[test]
    fn real_interface_round_trip_when_available() {
        let Ok(iface) = std::env::var("MCM_TEST_CAN_IFACE") else {
            let kernel = match check_kernel_support("vcan0") {
                Ok(()) => "this kernel supports CAN".to_owned(),
                Err(e) => e.to_string(),
            };
            println!(
                "skipped: MCM_TEST_CAN_IFACE is not set (set it to an existing CAN or vcan interface, \
                 e.g. vcan0, to run this test); {kernel}"
            );
            return;
        };
        let mut a = SocketCanBus::open(&iface).unwrap_or_else(|e| panic!("{e}"));
        let mut b = SocketCanBus::open(&iface).unwrap_or_else(|e| panic!("{e}"));
        // Nothing queued: a deadline in the past polls and returns at once.
        while b.recv(0).unwrap().is_some() {}
        assert_eq!(b.recv(0).unwrap(), None);
        let f = Frame::new(0x605, &[0x40, 0x41, 0x60, 0, 0, 0, 0, 0]).unwrap();
        a.send(&f).unwrap();
        let got = b.recv(monotonic_ns() + 1_000_000_000).unwrap();
        assert_eq!(got, Some(f));
        // With nothing on the bus, recv returns None, and not before its deadline.
        let start = monotonic_ns();
        if b.recv(start + 20_000_000).unwrap().is_none() {
            assert!(monotonic_ns() >= start + 20_000_000);
        }
    }
}
