//! Real-time set-up of the cycle thread: locked memory, `SCHED_FIFO` priority, CPU pinning.
//!
//! Runs once, before the cycle starts (not inside it).
//!
//! Each step is tried and its outcome kept; [`RtReport::problems`] lists the steps that failed,
//! so the caller can say so once, clearly, and refuse to run unless the user allowed it
//! (`mcm-rt --allow-non-realtime`, which the simulation launcher passes).

use std::fmt;

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
        .map_err(|e| format!("priority {priority}: {e}"))
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

    let cores = core_affinity::get_core_ids().unwrap_or_default();
    let pinned_cpu = match cores.iter().find(|c| c.id == cpu) {
        Some(core) if core_affinity::set_for_current(*core) => Ok(cpu),
        Some(_) => Err(format!("sched_setaffinity to CPU {cpu} failed")),
        None => Err(format!(
            "CPU {cpu} is not available (available: {:?})",
            cores.iter().map(|c| c.id).collect::<Vec<_>>()
        )),
    };

    RtReport {
        memory_locked,
        fifo_priority,
        pinned_cpu,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn report_lists_each_failed_step() {
        let r = RtReport {
            memory_locked: Ok(()),
            fifo_priority: Err("EPERM".into()),
            pinned_cpu: Err("CPU 9 is not available".into()),
        };
        assert!(!r.is_realtime());
        assert_eq!(r.problems().len(), 2);
        let text = r.to_string();
        assert!(
            text.starts_with("NOT real-time") && text.contains("EPERM"),
            "{text}"
        );
        let ok = RtReport {
            memory_locked: Ok(()),
            fifo_priority: Ok(80),
            pinned_cpu: Ok(1),
        };
        assert!(ok.is_realtime());
        assert_eq!(
            ok.to_string(),
            "real-time: memory locked, SCHED_FIFO priority 80, pinned to CPU 1"
        );
    }
}
