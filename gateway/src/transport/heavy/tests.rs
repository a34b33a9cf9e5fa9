use super::*;

#[tokio::test]
async fn short_and_long_inputs_are_both_parsed() {
    assert_eq!(parse(10, || 1 + 1).await, Some(2));
    assert_eq!(parse(HEAVY_BYTES + 1, || "long".len()).await, Some(4));
}

#[tokio::test]
async fn long_inputs_are_parsed_below_every_ordinary_thread() {
    // SAFETY: sched_getscheduler only reads the calling thread's policy.
    let policy = || unsafe { libc::sched_getscheduler(0) };
    assert_eq!(parse(HEAVY_BYTES + 1, policy).await, Some(libc::SCHED_IDLE));
    assert_ne!(
        parse(10, policy).await,
        Some(libc::SCHED_IDLE),
        "short: inline"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn long_inputs_take_turns() {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicUsize, Ordering};
    let (inside, most) = (Arc::new(AtomicUsize::new(0)), Arc::new(AtomicUsize::new(0)));
    let tasks: Vec<_> = (0..8)
        .map(|_| {
            let (inside, most) = (inside.clone(), most.clone());
            tokio::spawn(parse(HEAVY_BYTES * 2, move || {
                let now = inside.fetch_add(1, Ordering::SeqCst) + 1;
                most.fetch_max(now, Ordering::SeqCst);
                std::thread::sleep(std::time::Duration::from_millis(5));
                inside.fetch_sub(1, Ordering::SeqCst);
            }))
        })
        .collect();
    for t in tasks {
        assert_eq!(t.await.unwrap(), Some(()));
    }
    assert_eq!(most.load(Ordering::SeqCst), 1, "one heavy parse at a time");
}
