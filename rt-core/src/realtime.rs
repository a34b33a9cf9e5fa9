//! Real-time set-up of the cycle thread (locked memory, `SCHED_FIFO` priority, CPU pinning),
//! and the placement of every other thread of `mcm-rt` away from it.
//!
//! Runs once, before the cycle starts (not inside it).
//!
//! Only the cycle thread runs `SCHED_FIFO` on `cycle.cpu`. Every other thread (the flight
//! recorder's and the candump log's writers, the main thread that only waits) runs
//! `SCHED_OTHER` at normal priority on every CPU except the cycle's ([`helper_cpus`]): the
//! runner calls [`setup_helper_thread`] on the thread that will become the cycle thread
//! *before* it starts the helpers (they inherit policy and affinity from it), and only then
//! [`setup_current_thread`] turns it real-time.
//!
//! Each step is tried and its outcome kept; [`RtReport::problems`] lists the steps that failed,
//! so the caller can say so once, clearly, and refuse to run unless the user allowed it
//! (`mcm-rt --allow-non-realtime`, which the simulation launcher passes).

use std::fmt;
use std::sync::OnceLock;

/// The CPUs the process could use before any thread of it was placed (the first call of
/// [`setup_helper_thread`] or [`setup_current_thread`] narrows its own thread's set).
fn process_cpus() -> &'static [usize] {
    static CPUS: OnceLock<Vec<usize>> = OnceLock::new();
    CPUS.get_or_init(|| {
        core_affinity::get_core_ids()
            .unwrap_or_default()
            .iter()
            .map(|c| c.id)
            .collect()
    })
}

/// What the set-up achieved.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RtReport {
    pub memory_locked: Result<(), String>,
    pub fifo_priority: Result<u8, String>,
    pub pinned_cpu: Result<usize, String>,
}

impl RtReport {
    /// True when every step succeeded.
    pub fn is_realtime(&self) -> bool {
        self.memory_locked.is_ok() && self.fifo_priority.is_ok() && self.pinned_cpu.is_ok()
    }

    /// One line per failed step.
    pub fn problems(&self) -> Vec<String> {
        let mut v = Vec::new();
        if let Err(e) = &self.memory_locked {
            v.push(format!("memory not locked (mlockall): {e}"));
        }
        if let Err(e) = &self.fifo_priority {
            v.push(format!("no SCHED_FIFO priority: {e}"));
        }
        if let Err(e) = &self.pinned_cpu {
            v.push(format!("not pinned to a CPU: {e}"));
        }
        v
    }
}

impl fmt::Display for RtReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.fifo_priority, &self.pinned_cpu) {
            (Ok(p), Ok(c)) if self.memory_locked.is_ok() => {
                write!(
                    f,
                    "real-time: memory locked, SCHED_FIFO priority {p}, pinned to CPU {c}"
                )
            }
            _ => write!(f, "NOT real-time: {}", self.problems().join("; ")),
        }
    }
}

/// Lock memory, then give the calling thread `SCHED_FIFO` at `priority` and pin it to `cpu`.
pub fn setup_current_thread(priority: u8, cpu: usize) -> RtReport {
    // SAFETY: mlockall has no memory-safety preconditions; it only changes paging.
    let rc = unsafe { libc::mlockall(libc::MCL_CURRENT | libc::MCL_FUTURE) };
    let memory_locked = if rc == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error().to_string())
    };

    let fifo_priority = thread_priority::ThreadPriorityValue::try_from(priority)
        .map_err(|e| format!("cycle.priority = {priority}: {e}"))
        .and_then(|value| {
            thread_priority::set_thread_priority_and_policy(
                thread_priority::thread_native_id(),
                thread_priority::ThreadPriority::Crossplatform(value),
                thread_priority::ThreadSchedulePolicy::Realtime(
                    thread_priority::RealtimeThreadSchedulePolicy::Fifo,
                ),
            )
            .map_err(|e| format!("{e:?} (needs root or CAP_SYS_NICE and an RT budget)"))
        })
        .map(|()| priority);

    // The process's CPUs, not this thread's: it may have been placed as a helper first.
    let pinned_cpu = cpu_available(cpu, process_cpus()).and_then(|()| {
        if core_affinity::set_for_current(core_affinity::CoreId { id: cpu }) {
            Ok(cpu)
        } else {
            Err(format!(
                "cycle.cpu = {cpu}: sched_setaffinity to CPU {cpu} failed"
            ))
        }
    });

    RtReport {
        memory_locked,
        fifo_priority,
        pinned_cpu,
    }
}

/// `cycle.cpu` must be one of the CPUs this process may run on (`available`); the error names
/// the key, the value and what is allowed. Not a configuration check: the same file may be
/// written for the robot's computer and run, in simulation, on a smaller one
/// (`docs/safety.md`, "Bounds"), so only [`crate::preflight::check`] refuses it, when real-time
/// scheduling is required.
pub fn cpu_available(cpu: usize, available: &[usize]) -> Result<(), String> {
    if available.contains(&cpu) {
        Ok(())
    } else {
        Err(format!(
            "cycle.cpu = {cpu}: CPU {cpu} is not available to this process (available: {available:?})"
        ))
    }
}

/// The CPUs helper threads may use: every CPU of `available` except `cycle_cpu`, or all of
/// `available` when no other is left.
pub fn helper_cpus(available: &[usize], cycle_cpu: usize) -> Vec<usize> {
    let others: Vec<usize> = available
        .iter()
        .copied()
        .filter(|&c| c != cycle_cpu)
        .collect();
    if others.is_empty() {
        available.to_vec()
    } else {
        others
    }
}

/// Give the calling thread (and the threads it starts afterwards, which inherit it) the normal
/// policy (`SCHED_OTHER`, nice as it was) and the CPUs of [`helper_cpus`]. The first failing
/// step is named in the error.
pub fn setup_helper_thread(cycle_cpu: usize) -> Result<(), String> {
    let param = libc::sched_param { sched_priority: 0 };
    // SAFETY: `pthread_self()` is the calling thread, alive for the call; `param` is a valid
    // sched_param that outlives the call.
    let rc =
        unsafe { libc::pthread_setschedparam(libc::pthread_self(), libc::SCHED_OTHER, &param) };
    if rc != 0 {
        return Err(format!(
            "cannot set SCHED_OTHER: {}",
            std::io::Error::from_raw_os_error(rc)
        ));
    }
    let available = process_cpus();
    let cpus = helper_cpus(available, cycle_cpu);
    if cpus.is_empty() || cpus.len() == available.len() {
        return Ok(());
    }
    // SAFETY: cpu_set_t is plain data; all zero bits is the empty set CPU_ZERO gives.
    let mut set: libc::cpu_set_t = unsafe { std::mem::zeroed() };
    for &cpu in &cpus {
        // SAFETY: CPU_SET only writes bit `cpu` of `set`, which it bounds-checks itself.
        unsafe { libc::CPU_SET(cpu, &mut set) };
    }
    // SAFETY: pid 0 is the calling thread; `set` is a valid cpu_set_t of the size given.
    let rc = unsafe { libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set) };
    if rc != 0 {
        return Err(format!(
            "cannot keep the thread off CPU {cycle_cpu} (sched_setaffinity to {cpus:?}): {}",
            std::io::Error::last_os_error()
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests;
