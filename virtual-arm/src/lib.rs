//! # mcm-virtual-arm: a virtual P-Rob2 on a CAN bus
//!
//! The MCM's simulated robot (the `mcm-sim` crate: six CiA 402 drives, the arm's physics with
//! its mechanical stops, brakes and friction, the emergency switch) as a process on a SocketCAN
//! interface. A CANopen master, `mcm-rt` with `bus.backend = "socketcan"` or an integrator's
//! own, boots, configures and drives it frame by frame as it would the real arm; tests and
//! integrators inject faults and read the ground truth on a small local socket with the
//! contract's `sim` command ([`control`]). Its time runs with the master's SYNC and, when the
//! master is silent, with the wall clock ([`pace`]). `docs/virtual-arm.md` tells how to use it.
//!
//! - [`arm`]: the simulated drives between the wire and the physics;
//! - [`pace`]: when a period passes;
//! - [`control`]: the control socket;
//! - [`run`]: the process (sockets, log, loop); [`cli`]: its command line;
//! - [`memory_wire`]: an in-memory wire, to run it against a master without a kernel.
//!
//! ```
//! use mcm_bus::{Bus, Frame};
//! use mcm_virtual_arm::{arm::VirtualArm, memory_wire};
//! let cfg = mcm_shared::config::RobotConfig::prob2_default();
//! let (wire, mut master) = memory_wire::pair();
//! let mut arm = VirtualArm::new(&cfg, wire, 2, 0);
//! arm.poll(0, &mut |_| {});
//! let boot_up = master.recv(0).unwrap().unwrap();
//! assert_eq!((boot_up.id, boot_up.payload()), (0x701, &[0u8][..]));
//! ```

pub mod arm;
#[cfg(target_os = "linux")]
pub mod cli;
pub mod control;
pub mod memory_wire;
pub mod pace;
#[cfg(target_os = "linux")]
pub mod run;
