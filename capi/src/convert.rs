//! Reading the arguments of a C call: pointers checked for NULL, strings for UTF-8, the
//! protocol's numbers into the client's types. Each refusal names the function, the argument,
//! the value and what is allowed.

use crate::error::{
    Fail,
    mcm_error_t::{MCM_ERR_ARGUMENT, MCM_ERR_PROTOCOL},
};
use crate::types::{
    MCM_MAX_IK_SOLUTIONS, MCM_NUM_AXES, mcm_calibrate_t, mcm_control_options_t, mcm_ik_solutions_t,
    mcm_move_linear_t, mcm_pose_t, mcm_pvt_point_t, mcm_tool_t,
};
use mcm_client::mcm_shared::command::{
    Calibrate, CartesianFrame, MoveLinear, TorqueControl, VelocityControl,
};
use mcm_client::mcm_shared::tool::{Tcp, Tool};
use mcm_client::tcp::{InverseKinematicsResult, Pose, TorqueOptions, VelocityOptions};
use mcm_client::{Axis, Direction, PvtPoint, Which};
use std::ffi::{CStr, c_char};

/// `p` as a reference, or the NULL refusal.
///
/// # Safety
/// `p` is NULL or points to a valid, writable `T` not aliased during the call.
pub(crate) unsafe fn out<'a, T>(p: *mut T, function: &str, name: &str) -> Result<&'a mut T, Fail> {
    // SAFETY: the caller's promise (the header documents the argument).
    unsafe { p.as_mut() }.ok_or_else(|| Fail::null(function, name))
}

/// Write `value` to an optional output.
///
/// # Safety
/// `p` is NULL or points to a valid, writable `T`.
pub(crate) unsafe fn put<T>(p: *mut T, value: T) {
    // SAFETY: the caller's promise.
    if let Some(o) = unsafe { p.as_mut() } {
        *o = value;
    }
}

/// A NUL-terminated UTF-8 string argument.
///
/// # Safety
/// `p` is NULL or points to a NUL-terminated string valid during the call.
pub(crate) unsafe fn text<'a>(
    p: *const c_char,
    function: &str,
    name: &str,
) -> Result<&'a str, Fail> {
    if p.is_null() {
        return Err(Fail::null(function, name));
    }
    // SAFETY: not NULL; NUL-terminated by the caller's promise.
    unsafe { CStr::from_ptr(p) }.to_str().map_err(|e| {
        Fail::new(
            MCM_ERR_ARGUMENT,
            format!("{function}: argument `{name}` is not UTF-8 ({e}); pass UTF-8 text"),
        )
    })
}

/// Six values from a pointer to at least six doubles.
///
/// # Safety
/// `p` is NULL or points to six readable doubles.
pub(crate) unsafe fn six(
    p: *const f64,
    function: &str,
    name: &str,
) -> Result<[f64; MCM_NUM_AXES], Fail> {
    // SAFETY: the caller's promise.
    unsafe { numbers(p, function, name) }
}

/// Three values from a pointer to at least three doubles (a Cartesian vector).
///
/// # Safety
/// `p` is NULL or points to three readable doubles.
pub(crate) unsafe fn three(p: *const f64, function: &str, name: &str) -> Result<[f64; 3], Fail> {
    // SAFETY: the caller's promise.
    unsafe { numbers(p, function, name) }
}

/// `N` values from a pointer to at least `N` doubles.
///
/// # Safety
/// `p` is NULL or points to `N` readable doubles.
unsafe fn numbers<const N: usize>(
    p: *const f64,
    function: &str,
    name: &str,
) -> Result<[f64; N], Fail> {
    if p.is_null() {
        return Err(Fail::null(function, name));
    }
    let mut v = [0.0; N];
    // SAFETY: N readable doubles by the caller's promise; `v` holds N.
    unsafe { std::ptr::copy_nonoverlapping(p, v.as_mut_ptr(), N) };
    Ok(v)
}

/// Six values from a pointer to six doubles, or none for NULL (an optional argument).
///
/// # Safety
/// `p` is NULL or points to six readable doubles.
pub(crate) unsafe fn optional_six(
    p: *const f64,
    function: &str,
    name: &str,
) -> Result<Option<[f64; MCM_NUM_AXES]>, Fail> {
    if p.is_null() {
        return Ok(None);
    }
    // SAFETY: not NULL; the caller's promise for the rest.
    unsafe { six(p, function, name) }.map(Some)
}

/// The pose `p` points to. Its quaternion is checked by the MCM, which words a refusal itself.
///
/// # Safety
/// `p` is NULL or points to a readable `mcm_pose_t`.
pub(crate) unsafe fn pose(p: *const mcm_pose_t, function: &str) -> Result<Pose, Fail> {
    // SAFETY: the caller's promise.
    let p = unsafe { p.as_ref() }.ok_or_else(|| Fail::null(function, "pose"))?;
    Ok(p.into())
}

/// The solutions of an `inverse_kinematics` answer; more than the struct holds is an answer
/// this library cannot read.
pub(crate) fn ik_solutions(
    r: &InverseKinematicsResult,
    function: &str,
) -> Result<mcm_ik_solutions_t, Fail> {
    let n = r.solutions.len();
    if n > MCM_MAX_IK_SOLUTIONS {
        return Err(Fail::new(
            MCM_ERR_PROTOCOL,
            format!(
                "{function}: the MCM answered {n} solutions; this library holds at most \
                 {MCM_MAX_IK_SOLUTIONS} (an MCM of another version?)"
            ),
        ));
    }
    let mut out = mcm_ik_solutions_t {
        count: n as u32,
        ..Default::default()
    };
    out.solutions[..n].copy_from_slice(&r.solutions);
    Ok(out)
}

/// The frame of a Cartesian velocity: 0 the base frame, 1 the tool's.
pub(crate) fn frame(number: u32, function: &str) -> Result<CartesianFrame, Fail> {
    CartesianFrame::from_code(f64::from(number)).ok_or_else(|| {
        Fail::new(
            MCM_ERR_ARGUMENT,
            format!(
                "{function}: argument `frame` = {number} is not allowed; expected 0 (base) or 1 \
                 (tool)"
            ),
        )
    })
}

/// An axis number 1 to 6.
pub(crate) fn axis(number: u32, function: &str) -> Result<Axis, Fail> {
    u8::try_from(number).ok().and_then(Axis::new).ok_or_else(|| {
        Fail::new(
            MCM_ERR_ARGUMENT,
            format!("{function}: argument `axis` = {number} is not allowed; expected an axis number from 1 to 6"),
        )
    })
}

fn direction(value: i32, function: &str, name: &str) -> Result<Direction, Fail> {
    match value {
        0 | 1 => Ok(Direction::Positive),
        -1 => Ok(Direction::Negative),
        v => Err(Fail::new(
            MCM_ERR_ARGUMENT,
            format!(
                "{function}: argument `{name}` = {v} is not allowed; expected 1 (or 0: the default) or -1"
            ),
        )),
    }
}

/// The calibration options (NULL: the defaults).
///
/// # Safety
/// `p` is NULL or points to a valid `mcm_calibrate_t`.
pub(crate) unsafe fn calibrate(
    p: *const mcm_calibrate_t,
    function: &str,
) -> Result<mcm_client::mcm_shared::command::Calibrate, Fail> {
    // SAFETY: the caller's promise.
    let c = unsafe { p.as_ref() }.copied().unwrap_or_default();
    let which = match c.which {
        0 => Which::All,
        7 => Which::Elbow,
        8 => Which::Wrist,
        n => Which::Axis(axis(n, function).map_err(|_| {
            Fail::new(
                MCM_ERR_ARGUMENT,
                format!("{function}: argument `which` = {n} is not allowed; expected 0 (all), 1 to 6 (an axis), 7 (elbow) or 8 (wrist)"),
            )
        })?),
    };
    Ok(mcm_client::mcm_shared::command::Calibrate {
        which,
        elbow_direction: direction(c.elbow_direction, function, "elbow_direction")?,
        wrist_direction: direction(c.wrist_direction, function, "wrist_direction")?,
        force_mechanical_stop: c.force_mechanical_stop,
    })
}

/// The torque/velocity options (NULL: the protocol's defaults).
///
/// # Safety
/// `p` is NULL or points to a valid `mcm_control_options_t`.
pub(crate) unsafe fn control_options(p: *const mcm_control_options_t) -> mcm_control_options_t {
    // SAFETY: the caller's promise.
    unsafe { p.as_ref() }
        .copied()
        .unwrap_or_else(|| crate::types::mcm_control_options_default())
}

impl From<mcm_control_options_t> for TorqueOptions {
    fn from(o: mcm_control_options_t) -> Self {
        TorqueOptions {
            timeout_s: timeout(o.timeout_s),
            dt_status_s: (o.dt_status_s > 0.0).then_some(o.dt_status_s),
            gravity_compensation: o.gravity_compensation,
        }
    }
}

impl From<mcm_control_options_t> for TorqueControl {
    /// `dt_status_s` has no meaning over shared memory (every state is read).
    fn from(o: mcm_control_options_t) -> Self {
        TorqueControl {
            timeout_s: timeout(o.timeout_s),
            gravity_compensation: o.gravity_compensation,
        }
    }
}

impl From<mcm_control_options_t> for VelocityOptions {
    fn from(o: mcm_control_options_t) -> Self {
        VelocityOptions {
            timeout_s: timeout(o.timeout_s),
            dt_status_s: (o.dt_status_s > 0.0).then_some(o.dt_status_s),
        }
    }
}

impl From<mcm_control_options_t> for VelocityControl {
    fn from(o: mcm_control_options_t) -> Self {
        VelocityControl {
            timeout_s: timeout(o.timeout_s),
        }
    }
}

/// The checked options of `calibrate`, for either client.
pub(crate) struct CalibrateArgs(Calibrate);

impl From<CalibrateArgs> for Calibrate {
    fn from(c: CalibrateArgs) -> Self {
        c.0
    }
}

/// [`calibrate`], for either client.
///
/// # Safety
/// As [`calibrate`].
pub(crate) unsafe fn calibrate_args(
    p: *const mcm_calibrate_t,
    function: &str,
) -> Result<CalibrateArgs, Fail> {
    // SAFETY: the caller's promise.
    unsafe { calibrate(p, function) }.map(CalibrateArgs)
}

/// `count` PVT points from `p`.
///
/// # Safety
/// `p` is NULL or points to `count` readable points.
pub(crate) unsafe fn points(
    p: *const mcm_pvt_point_t,
    count: usize,
    function: &str,
) -> Result<Vec<PvtPoint>, Fail> {
    if p.is_null() {
        return Err(Fail::null(function, "points"));
    }
    // SAFETY: not NULL, `count` readable points (the caller's promise).
    let pts = unsafe { std::slice::from_raw_parts(p, count) };
    Ok(pts.iter().map(PvtPoint::from).collect())
}

/// The tool `p` points to, checked as the MCM checks it (`Tool::new`).
///
/// # Safety
/// `p` is NULL or points to a readable `mcm_tool_t`.
pub(crate) unsafe fn tool(p: *const mcm_tool_t, function: &str) -> Result<Tool, Fail> {
    // SAFETY: the caller's promise.
    let t = unsafe { p.as_ref() }.ok_or_else(|| Fail::null(function, "tool"))?;
    let tcp = Tcp {
        position: t.tcp_position,
        orientation: t.tcp_orientation,
    };
    Tool::new(tcp, t.mass, t.center_of_mass, Some(t.inertia)).map_err(|e| {
        Fail::new(
            MCM_ERR_ARGUMENT,
            format!("{function}: argument `tool`: {e}"),
        )
    })
}

/// A `move_linear` line; 0 for its speed or acceleration is the MCM's default. Its values are
/// the MCM's to check (it words a refusal itself).
///
/// # Safety
/// `p` is NULL or points to a valid `mcm_move_linear_t`.
pub(crate) unsafe fn move_linear(
    p: *const mcm_move_linear_t,
    function: &str,
) -> Result<MoveLinear, Fail> {
    // SAFETY: the caller's promise.
    let l = unsafe { p.as_ref() }.ok_or_else(|| Fail::null(function, "line"))?;
    let given = |x: f64| (x != 0.0).then_some(x);
    Ok(MoveLinear {
        position: l.position,
        orientation: l.has_orientation.then_some(l.orientation),
        velocity: given(l.velocity),
        acceleration: given(l.acceleration),
    })
}

/// An axis number as the JSON protocol's: the MCM words a wrong axis itself
/// (`MCM_ERR_INVALID`); only what does not fit the protocol's number is refused here.
pub(crate) fn protocol_axis(number: u32, function: &str) -> Result<u8, Fail> {
    u8::try_from(number).map_err(|_| {
        Fail::new(
            MCM_ERR_ARGUMENT,
            format!(
                "{function}: argument `axis` = {number} is not allowed; expected an axis number from 1 to 6"
            ),
        )
    })
}

/// A timeout [s] of the options: negative is none.
pub(crate) fn timeout(t: f64) -> Option<f64> {
    (t >= 0.0).then_some(t)
}

/// A wait [s] as a duration (negative or not a number: refused).
pub(crate) fn seconds(s: f64, function: &str, name: &str) -> Result<std::time::Duration, Fail> {
    std::time::Duration::try_from_secs_f64(s).map_err(|_| {
        Fail::new(
            MCM_ERR_ARGUMENT,
            format!(
                "{function}: argument `{name}` = {s} is not allowed; expected seconds, 0 or more"
            ),
        )
    })
}

#[cfg(test)]
mod tests;
