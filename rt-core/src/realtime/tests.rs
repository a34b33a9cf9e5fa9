use super::*;

#[test]
fn helpers_get_every_cpu_but_the_cycles() {
    assert_eq!(helper_cpus(&[0, 1, 2, 3], 1), [0, 2, 3]);
    assert_eq!(helper_cpus(&[0, 1], 0), [1]);
    // The only CPU, or a cycle CPU the process does not have: all of them.
    assert_eq!(helper_cpus(&[0], 0), [0]);
    assert_eq!(helper_cpus(&[0, 1], 7), [0, 1]);
}

#[test]
fn a_helper_thread_runs_normal_policy_off_the_cycle_cpu() {
    let available = process_cpus().to_vec();
    let cycle = available[0];
    let (policy, allowed) = std::thread::spawn(move || {
        setup_helper_thread(cycle).unwrap();
        // SAFETY: sched_getscheduler only reads the calling thread's policy.
        let policy = unsafe { libc::sched_getscheduler(0) };
        let allowed: Vec<usize> = core_affinity::get_core_ids()
            .unwrap()
            .iter()
            .map(|c| c.id)
            .collect();
        (policy, allowed)
    })
    .join()
    .unwrap();
    assert_eq!(policy, libc::SCHED_OTHER);
    assert_eq!(allowed, helper_cpus(&available, cycle));
    if available.len() > 1 {
        assert!(!allowed.contains(&cycle), "{allowed:?}");
    }
}

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

#[test]
fn a_missing_cycle_cpu_is_reported_naming_the_key() {
    assert_eq!(cpu_available(1, &[0, 1]), Ok(()));
    assert_eq!(
        cpu_available(99, &[0, 1]).unwrap_err(),
        "cycle.cpu = 99: CPU 99 is not available to this process (available: [0, 1])"
    );
    let r = RtReport {
        memory_locked: Ok(()),
        fifo_priority: Ok(80),
        pinned_cpu: cpu_available(99, &[0, 1]).map(|()| 99),
    };
    assert_eq!(
        r.to_string(),
        "NOT real-time: not pinned to a CPU: cycle.cpu = 99: CPU 99 is not available to this \
         process (available: [0, 1])"
    );
}
