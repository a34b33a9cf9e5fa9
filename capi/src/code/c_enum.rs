//! GENERATED from the table of codes in `shared/src/error_code.rs` (`ErrorCode::ALL`,
//! numbered by `capi/src/code.rs`'s `number`); do not edit by hand:
//! `MCM_UPDATE_CAPI=1 cargo test -p mcm-capi --lib code::tests` writes it anew.
//!
//! The C enum of the MCM's error codes, written out for cbindgen (which does not expand
//! macros) and so into `include/mcm/mcm.h`.

/// The MCM's code of a failed call (`mcm_*_last_reject`), of an event and of
/// `mcm_state_t.last_error` (a check): the protocol's `error_code`, as a number.
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum mcm_error_code_t {
    /// No code (a call that did not fail, or a failure the MCM did not answer).
    MCM_CODE_NONE = 0,
    MCM_CODE_WRONG_MODE = 1,
    MCM_CODE_NOT_CALIBRATED = 2,
    MCM_CODE_EMERGENCY_STOP = 3,
    MCM_CODE_DRIVE_DISCONNECTED = 4,
    MCM_CODE_DRIVE_FAULT = 5,
    MCM_CODE_OUT_OF_RANGE = 6,
    MCM_CODE_NOT_AVAILABLE = 7,
    MCM_CODE_NOT_SIMULATED = 8,
    MCM_CODE_QUEUE_FULL = 9,
    MCM_CODE_POSITION_LIMIT = 10,
    MCM_CODE_VELOCITY_LIMIT = 11,
    MCM_CODE_BRAKING_DISTANCE = 12,
    MCM_CODE_FOLLOWING_ERROR = 13,
    MCM_CODE_CALIBRATION_FAILED = 14,
    MCM_CODE_ABORTED = 15,
    MCM_CODE_BUSY = 16,
    MCM_CODE_PVT_POINT = 17,
    MCM_CODE_UNREACHABLE = 18,
    MCM_CODE_NOT_OWNER = 19,
    MCM_CODE_SHUTTING_DOWN = 20,
    MCM_CODE_OVERLOAD = 21,
    MCM_CODE_NOT_IDENTIFIABLE = 22,
    MCM_CODE_INVALID_JSON = 100,
    MCM_CODE_INVALID_COMMAND = 101,
    MCM_CODE_UNKNOWN_COMMAND = 102,
    MCM_CODE_UNKNOWN_ARGUMENT = 103,
    MCM_CODE_MISSING_ARGUMENT = 104,
    MCM_CODE_INVALID_ARGUMENT = 105,
    MCM_CODE_LINE_TOO_LONG = 106,
    MCM_CODE_LINE_TIMEOUT = 107,
    MCM_CODE_IDLE_TIMEOUT = 108,
    MCM_CODE_EVICTED = 109,
    MCM_CODE_TOO_MANY_CONNECTIONS = 110,
    MCM_CODE_TOO_MANY_REQUESTS = 111,
    MCM_CODE_NETWORK_REFUSED = 112,
    MCM_CODE_NOT_AUTHENTICATED = 113,
    MCM_CODE_WRONG_SECRET = 114,
    MCM_CODE_REMOTE_SIM_REFUSED = 115,
    MCM_CODE_CORE_UNAVAILABLE = 116,
    MCM_CODE_OUTCOME_UNKNOWN = 117,
    MCM_CODE_VERSION_MISMATCH = 118,
    MCM_CODE_CORE_STOPPING = 119,
    MCM_CODE_CORE_STOPPED = 120,
    MCM_CODE_CORE_VANISHED = 121,
    MCM_CODE_GATEWAY_STOPPING = 122,
    MCM_CODE_EVENTS_LOST = 123,
    MCM_CODE_INTERNAL_ERROR = 124,
}
