//! # mcm-capi: the C ABI of the MCM client library
//!
//! One implementation for every language: these `extern "C"` functions wrap `mcm-client`
//! (its TCP client and its shared-memory client with the control loop). The C header
//! `include/mcm/mcm.h` is generated from this crate by cbindgen (`cbindgen.toml`; the test
//! `capi/tests/header.rs` fails when the checked-in header differs from what cbindgen generates
//! now), and `include/mcm/mcm.hpp` is a C++17 header-only RAII layer over it.
//! `docs/clients.md` ("C and C++") says how to build, install and use both.
//!
//! The rules every function keeps:
//!
//! - It returns an [`mcm_error_t`] (`MCM_OK` or why not) and writes its results through
//!   pointers. A required pointer that is NULL is `MCM_ERR_NULL_POINTER`, never undefined
//!   behaviour; an output pointer documented as optional may be NULL.
//! - No panic crosses the ABI: every entry point runs under `catch_unwind`; a caught panic (a
//!   bug of this library) is `MCM_ERR_PANIC`.
//! - A failed call keeps its message (the MCM's own words where the MCM answered) in the handle
//!   (`mcm_tcp_last_error`, `mcm_shm_last_error`) and in the calling thread
//!   (`mcm_last_error`, also for the connect functions, which have no handle yet), with the
//!   MCM's error code (`mcm_*_last_reject`, an `mcm_error_code_t`). A successful call leaves
//!   them as they were, so
//!   that it does not allocate.
//! - A handle is used by one thread at a time; a shared-memory handle only on the thread that
//!   created it (iceoryx2's ports are bound to their thread).
//!
//! Functions marked "real-time safe" in the header (`mcm_shm_wait_state`, `mcm_shm_latest`,
//! `mcm_shm_set_torques`, `mcm_shm_set_velocities`, `mcm_shm_control` itself once running, the
//! accessors) neither lock nor block on success, and the reads allocate nothing; sending a
//! command (`set_torques`, `set_velocities`, each answer of the loop) makes one small
//! allocation inside iceoryx2 0.10's publisher (its loan), none of this library's own
//! (`tests/end_to_end/capi_realtime.rs` counts them). Everything else may allocate and block.

#![allow(non_camel_case_types)]
// The C functions check their pointers; the caller's promise is the header's documentation.
#![allow(clippy::missing_safety_doc)]

mod code;
mod convert;
mod error;
mod shm;
mod tcp;
mod text;
mod types;
// Generated (capi/tests/wrappers): the functions of the commands for both transports.
#[rustfmt::skip]
mod commands;

pub use code::*;
pub use commands::*;
pub use error::*;
pub use shm::*;
pub use tcp::*;
pub use text::*;
pub use types::*;
