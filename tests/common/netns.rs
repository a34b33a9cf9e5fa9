//! Private network namespaces for the ROS 2 tests: DDS finds its peers by multicast, which must
//! not go onto the machine's real network. Each test makes its own namespaces (`ip netns`), so
//! its DDS traffic stays inside them and no other test's participants are found.
//!
//! [`Netns::new`] makes one "host" with loopback up and multicast routed to it;
//! [`Netns::link`] joins two with a veth pair (each end with an address and the multicast
//! route), as two computers on one network. A namespace is deleted on drop. Making one needs
//! root (CAP_SYS_ADMIN) and iproute2's `ip`: without them [`Netns::new`] says why, and the test
//! is skipped, or fails under `CI`.

use std::ffi::OsStr;
use std::net::{SocketAddr, TcpStream};
use std::os::fd::{AsRawFd, FromRawFd};
use std::process::Command;
use std::sync::atomic::{AtomicU32, Ordering};

static NEXT: AtomicU32 = AtomicU32::new(0);

/// A network namespace this test made.
pub struct Netns {
    pub name: String,
}

fn ip(args: &[&str]) -> Result<(), String> {
    let out = Command::new("ip")
        .args(args)
        .output()
        .map_err(|e| format!("cannot run `ip` (iproute2): {e}"))?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "`ip {}` failed ({}): {}",
            args.join(" "),
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        ))
    }
}

impl Netns {
    /// A new namespace `mcm-<pid>-<n>-<tag>` with loopback up and multicast routed to it.
    pub fn new(tag: &str) -> Result<Netns, String> {
        let name = format!(
            "mcm-{}-{}-{tag}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        );
        ip(&["netns", "add", &name])?;
        let ns = Netns { name };
        ns.run(&["link", "set", "lo", "up"])?;
        ns.run(&["link", "set", "lo", "multicast", "on"])?;
        ns.run(&["route", "add", "224.0.0.0/4", "dev", "lo"])?;
        Ok(ns)
    }

    /// `ip -n NAME args...`.
    pub fn run(&self, args: &[&str]) -> Result<(), String> {
        let mut all = vec!["-n", &self.name];
        all.extend_from_slice(args);
        ip(&all)
    }

    /// A namespace, or `None` after saying `test` is skipped (a failure under `CI`) because it
    /// cannot be made.
    pub fn or_skip(test: &str, tag: &str) -> Option<Netns> {
        match Netns::new(tag) {
            Ok(n) => Some(n),
            Err(e) => {
                super::skip(
                    test,
                    &format!("cannot make a network namespace (needs root and iproute2): {e}"),
                );
                None
            }
        }
    }

    /// A TCP connection to `addr` made from inside this namespace (e.g. to the JSON port of an
    /// MCM that runs in it, bound to the namespace's own loopback). A socket stays in the
    /// namespace it was made in, so the test's threads use it like any other.
    pub fn connect(&self, addr: SocketAddr) -> std::io::Result<TcpStream> {
        let file = std::fs::File::open(format!("/run/netns/{}", self.name))?;
        // A thread of its own enters the namespace: the caller's thread stays where it is.
        std::thread::spawn(move || {
            // SAFETY: `file` is an open namespace file for the whole call; setns changes only
            // this (short-lived) thread's network namespace.
            if unsafe { libc::setns(file.as_raw_fd(), libc::CLONE_NEWNET) } != 0 {
                return Err(std::io::Error::last_os_error());
            }
            TcpStream::connect(addr)
        })
        .join()
        .expect("the connecting thread does not panic")
    }

    /// Every frame on every interface of this namespace for `duration` (an `AF_PACKET` socket,
    /// which needs root like the namespace itself), each with its Ethernet header: what a
    /// program watching the namespace's network sees.
    pub fn capture(&self, duration: std::time::Duration) -> std::io::Result<Vec<Vec<u8>>> {
        let file = std::fs::File::open(format!("/run/netns/{}", self.name))?;
        std::thread::spawn(move || {
            // SAFETY: `file` is an open namespace file for the whole call; setns changes only
            // this (short-lived) thread's network namespace.
            if unsafe { libc::setns(file.as_raw_fd(), libc::CLONE_NEWNET) } != 0 {
                return Err(std::io::Error::last_os_error());
            }
            let protocol = (libc::ETH_P_ALL as u16).to_be() as i32;
            // SAFETY: a plain socket(2) call; the descriptor is owned by `fd` below.
            let raw = unsafe { libc::socket(libc::AF_PACKET, libc::SOCK_RAW, protocol) };
            if raw < 0 {
                return Err(std::io::Error::last_os_error());
            }
            // SAFETY: `raw` is a descriptor this thread just opened and nothing else owns.
            let fd = unsafe { std::os::fd::OwnedFd::from_raw_fd(raw) };
            let timeout = libc::timeval {
                tv_sec: 0,
                tv_usec: 100_000,
            };
            // SAFETY: `timeout` is a valid timeval for the call's duration, its size given.
            let r = unsafe {
                libc::setsockopt(
                    fd.as_raw_fd(),
                    libc::SOL_SOCKET,
                    libc::SO_RCVTIMEO,
                    (&timeout as *const libc::timeval).cast(),
                    std::mem::size_of::<libc::timeval>() as libc::socklen_t,
                )
            };
            if r != 0 {
                return Err(std::io::Error::last_os_error());
            }
            let end = std::time::Instant::now() + duration;
            let mut seen = Vec::new();
            let mut frame = vec![0u8; 65536];
            while std::time::Instant::now() < end {
                // SAFETY: `frame` is writable for its whole length, which is passed.
                let n = unsafe {
                    libc::recv(fd.as_raw_fd(), frame.as_mut_ptr().cast(), frame.len(), 0)
                };
                if n > 0 {
                    seen.push(frame[..n as usize].to_vec());
                }
            }
            Ok(seen)
        })
        .join()
        .expect("the capturing thread does not panic")
    }

    /// A command that runs `program` inside this namespace.
    pub fn command(&self, program: impl AsRef<OsStr>) -> Command {
        let mut c = Command::new("ip");
        c.args(["netns", "exec", &self.name]).arg(program);
        c
    }

    /// Join `a` (address `10.<net>.0.1/24`) and `b` (`10.<net>.0.2/24`) by a veth pair, with
    /// multicast routed over it instead of loopback: two hosts on one network. Returns the two
    /// addresses.
    pub fn link(a: &Netns, b: &Netns, net: u8) -> Result<(String, String), String> {
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        let (va, vb) = (
            format!("vm{}a{n}", std::process::id() % 100_000),
            format!("vm{}b{n}", std::process::id() % 100_000),
        );
        ip(&["link", "add", &va, "type", "veth", "peer", "name", &vb])?;
        ip(&["link", "set", &va, "netns", &a.name])?;
        ip(&["link", "set", &vb, "netns", &b.name])?;
        let (addr_a, addr_b) = (format!("10.{net}.0.1"), format!("10.{net}.0.2"));
        for (ns, dev, addr) in [(a, &va, &addr_a), (b, &vb, &addr_b)] {
            ns.run(&["addr", "add", &format!("{addr}/24"), "dev", dev])?;
            ns.run(&["link", "set", dev, "up"])?;
            ns.run(&["link", "set", dev, "multicast", "on"])?;
            ns.run(&["route", "replace", "224.0.0.0/4", "dev", dev])?;
        }
        Ok((addr_a, addr_b))
    }
}

impl Drop for Netns {
    fn drop(&mut self) {
        // Deleting the namespace deletes its veth ends (and their peers).
        let _ = ip(&["netns", "del", &self.name]);
    }
}
