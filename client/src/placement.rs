//! Where a controller's thread runs: [`pin_current_thread`].
//!
//! A thread blocked in [`crate::shm::ShmClient::wait_state`] is woken by the core's state
//! event. When its CPU is idle, that wake-up costs what the CPU (on a virtual machine: the
//! hypervisor) needs to leave its idle state: on the 2-vCPU development VM from nothing to
//! about 35 µs of the sample's age, depending on the host's load. On the core's own CPU
//! (`cycle.cpu` of the robot configuration, 1 by default) the waiting thread is woken on a CPU
//! that is awake: it runs as soon as the core's cycle thread goes back to sleep. The core runs SCHED_FIFO, so a
//! controller there at normal priority (or SCHED_FIFO below `cycle.priority`) can never delay
//! a cycle; it only has to finish its answer before the next one. Give it a `SCHED_FIFO`
//! priority below the core's there, or other work on that CPU can delay it by a period.
//! `docs/clients.md` ("Where to run a shared-memory controller") and `docs/performance.md`
//! give the measured figures.
//!
//! ```no_run
//! // The core's CPU, from the robot configuration (`[cycle] cpu`).
//! mcm_client::placement::pin_current_thread(1)?;
//! let mut mcm = mcm_client::shm::ShmClient::connect("default")?;
//! let state = mcm.wait_state()?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

/// Why the thread could not be pinned.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PinError {
    /// The CPU number is beyond what `cpu_set_t` can name.
    #[error("CPU {cpu} cannot be named: allowed 0..{max}")]
    OutOfRange { cpu: usize, max: usize },
    /// The kernel refused (e.g. the CPU is offline, or outside this process's cpuset).
    #[error(
        "cannot pin the thread to CPU {cpu}: {reason}; allowed are the online CPUs of this process's cpuset"
    )]
    Refused { cpu: usize, reason: String },
}

/// Run the calling thread on `cpu` only (`sched_setaffinity`); other threads keep theirs.
pub fn pin_current_thread(cpu: usize) -> Result<(), PinError> {
    let max = 8 * std::mem::size_of::<libc::cpu_set_t>();
    if cpu >= max {
        return Err(PinError::OutOfRange { cpu, max });
    }
    // SAFETY: an all-zero cpu_set_t is the empty set (plain bit array).
    let mut set: libc::cpu_set_t = unsafe { std::mem::zeroed() };
    // SAFETY: `cpu` is below the set's capacity in bits (checked above).
    unsafe { libc::CPU_SET(cpu, &mut set) };
    // SAFETY: `set` is a valid cpu_set_t of the size passed; pid 0 is the calling thread.
    let rc = unsafe { libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set) };
    if rc != 0 {
        return Err(PinError::Refused {
            cpu,
            reason: std::io::Error::last_os_error().to_string(),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests;
