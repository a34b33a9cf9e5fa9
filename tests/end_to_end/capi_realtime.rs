//! The C API's real-time promise, checked (`capi/include/mcm/mcm.h`, `docs/clients.md`): of
//! the functions the header marks real-time safe, the reads (`mcm_shm_wait_state`,
//! `mcm_shm_latest`) allocate nothing, and a command sent (`mcm_shm_set_torques`, each answer
//! of the running `mcm_shm_control`) at most once: the loan inside iceoryx2 0.10's publisher
//! (`Publisher::send_copy` allocates its loan state), none of the library's own.
//!
//! Against the real launcher with the simulated arm: a counting global allocator
//! ([`mcm_shared::alloc_count`]) counts the allocations of the test thread only, while the C
//! functions run through the `mcm_c` library as a C program would call them.

use crate::common;

use common::Mcm;
use mcm_c::*;
use mcm_shared::alloc_count::{self, CountingAlloc};
use std::ffi::{CString, c_void};

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

/// Allocations of this thread while `f` runs.
fn allocations_in(f: impl FnOnce()) -> u64 {
    alloc_count::count(f).1.allocations
}

fn ok(what: &str, code: mcm_error_t) {
    if code != mcm_error_t::MCM_OK {
        // SAFETY: mcm_last_error returns a NUL-terminated string of this thread.
        let msg = unsafe { std::ffi::CStr::from_ptr(mcm_last_error()) };
        panic!("{what}: {code:?}: {}", msg.to_string_lossy());
    }
}

/// What the control callback counts: the allocations between its first and its last call.
struct Loop {
    calls: u64,
    stop_after: u64,
    allocs_at_first: u64,
    allocs_running: Option<u64>,
}

extern "C" fn callback(
    _state: *const mcm_state_t,
    out: *mut mcm_control_output_t,
    user: *mut c_void,
) -> i32 {
    // SAFETY: `user` is the `Loop` passed to mcm_shm_control below; `out` is valid for this call.
    let (l, out) = unsafe { (&mut *user.cast::<Loop>(), &mut *out) };
    l.calls += 1;
    out.values = [0.0; 6];
    if l.calls == 1 {
        l.allocs_at_first = alloc_count::counted().allocations;
        alloc_count::set_counting(true);
    }
    if l.calls == l.stop_after {
        alloc_count::set_counting(false);
        l.allocs_running = Some(alloc_count::counted().allocations - l.allocs_at_first);
        return MCM_CONTROL_FINISH;
    }
    MCM_CONTROL_CONTINUE
}

#[test]
fn the_real_time_functions_allocate_nothing() {
    let mcm = Mcm::start("capi-rt");
    let instance = CString::new(mcm.instance.clone()).unwrap();
    let mut h: *mut mcm_shm_client_t = std::ptr::null_mut();
    // SAFETY: valid C string and out-pointer; the handle is used on this thread only and
    // closed once at the end.
    unsafe {
        ok("connect", mcm_shm_connect(instance.as_ptr(), &mut h));
        let mut calibrated = false;
        ok(
            "calibrate_if_needed",
            mcm_shm_calibrate_if_needed(h, &mut calibrated),
        );
        let options = mcm_control_options_t {
            timeout_s: 0.5,
            dt_status_s: 0.0,
            gravity_compensation: true,
        };
        ok("torque_control", mcm_shm_torque_control(h, &options));

        let mut state = mcm_state_t::default();
        let zero = [0.0f64; 6];
        // Warm-up: the first send of a publisher sets up its connection to the core.
        ok("wait_state", mcm_shm_wait_state(h, &mut state));
        ok("set_torques", mcm_shm_set_torques(h, zero.as_ptr()));
        let first = state.seq;
        let (mut reads, mut sends) = (0, 0);
        for _ in 0..200 {
            reads += allocations_in(|| {
                ok("wait_state", mcm_shm_wait_state(h, &mut state));
                ok("latest", mcm_shm_latest(h, &mut state));
            });
            sends += allocations_in(|| ok("set_torques", mcm_shm_set_torques(h, zero.as_ptr())));
        }
        assert!(
            state.seq >= first + 200,
            "200 new states: {first} -> {}",
            state.seq
        );
        assert_eq!(
            reads, 0,
            "wait_state and latest allocated {reads} times in 200 cycles"
        );
        assert!(
            sends <= 200,
            "set_torques allocated {sends} times in 200 calls: more than iceoryx2's one loan each"
        );

        let mut l = Loop {
            calls: 0,
            stop_after: 200,
            allocs_at_first: 0,
            allocs_running: None,
        };
        let mut summary = mcm_control_summary_t::default();
        ok(
            "control",
            mcm_shm_control(
                h,
                Some(callback),
                (&mut l as *mut Loop).cast(),
                &mut summary,
            ),
        );
        assert_eq!(l.calls, 200, "{summary:?}");
        let running = l.allocs_running.expect("the loop ran to its last callback");
        assert!(
            running <= summary.sent,
            "the running control loop allocated {running} times for {} answers sent: more than \
             iceoryx2's one loan each ({summary:?})",
            summary.sent
        );
        ok("hold", mcm_shm_hold(h));
        mcm_shm_close(h);
    }
}
