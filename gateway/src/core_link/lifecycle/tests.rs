//! The notices of [`CoreWatch`] and the shutdown's [`settle`], over a watch channel that plays
//! the bridge.

use super::*;

fn sample(flags: u32) -> Option<Box<StateSample>> {
    Some(Box::new(StateSample {
        flags,
        ..StateSample::default()
    }))
}

#[tokio::test]
async fn a_shutdown_then_silence_gives_two_notices_in_order() {
    let (tx, rx) = watch::channel(sample(0));
    let mut w = CoreWatch::new(rx);
    tx.send_replace(sample(STATE_SHUTTING_DOWN));
    assert_eq!(w.next().await, Notice::RtStopping);
    tx.send_replace(None);
    assert_eq!(w.next().await, Notice::RtStopped);
    tx.send_replace(sample(0));
    let quiet = tokio::time::timeout(CORE_CHECK * 5, w.next()).await;
    assert!(quiet.is_err(), "a core appearing is no error: {quiet:?}");
}

#[tokio::test]
async fn settle_waits_for_the_bridge_to_call_a_silent_core_gone_and_the_notice_is_due() {
    let (tx, rx) = watch::channel(sample(0));
    let mut w = CoreWatch::new(rx.clone());
    assert_eq!(w.due(), None, "nothing changed");
    // The core was killed; the bridge reads the last state it published, and notices its
    // silence a little later.
    let bridge = tokio::spawn(async move {
        tx.send_replace(sample(0));
        tokio::time::sleep(CORE_CHECK).await;
        tx.send_replace(None);
        tx
    });
    tokio::time::timeout(SETTLE_WAIT, settle(rx.clone()))
        .await
        .expect("settle returns once the bridge says the core is gone");
    assert!(rx.borrow().is_none());
    assert_eq!(w.due(), Some(Notice::RtVanished), "a notice is due");
    assert_eq!(w.due(), None, "told once");
    drop(bridge.await);
}

/// Time is paused: each wait below ends only when what it waits for happened, or its timeout
/// (auto-advanced) passed; nothing depends on the machine's speed.
#[tokio::test(start_paused = true)]
async fn settle_returns_at_once_without_a_core_and_after_two_new_states_of_a_running_one() {
    let (tx, rx) = watch::channel(None);
    let t0 = tokio::time::Instant::now();
    settle(rx.clone()).await;
    assert_eq!(t0.elapsed(), Duration::ZERO, "no core: nothing to wait for");
    tx.send_replace(sample(0));
    let t0 = tokio::time::Instant::now();
    let settling = settle(rx.clone());
    tokio::pin!(settling);
    let running = tokio::time::timeout(CORE_CHECK, &mut settling).await;
    assert!(running.is_err(), "a running core: it waits for new states");
    tx.send_replace(sample(0));
    let one = tokio::time::timeout(CORE_CHECK, &mut settling).await;
    assert!(
        one.is_err(),
        "one new state proves nothing (the bridge may have read a killed core's last one)"
    );
    tx.send_replace(sample(0));
    tokio::time::timeout(CORE_CHECK, &mut settling)
        .await
        .expect("the second new state settles it");
    assert!(
        t0.elapsed() < SETTLE_WAIT / 2,
        "settled by the states, not by the bound: {:?}",
        t0.elapsed()
    );
    let mut w = CoreWatch::new(rx);
    assert_eq!(w.due(), None, "the core runs: nothing to tell");
}

#[tokio::test]
async fn a_core_that_vanishes_is_told_as_such() {
    let (tx, rx) = watch::channel(sample(0));
    let mut w = CoreWatch::new(rx);
    tx.send_replace(None);
    let n = w.next().await;
    assert_eq!(n, Notice::RtVanished);
    // On JSON/TCP and ZeroMQ: a generic ERROR result with the same words.
    let v = n.result();
    assert_eq!(v["result_type"], "generic");
    assert_eq!(v["error_status"], "ERROR");
    assert_eq!(v["error_message"], n.text());
    assert!(
        n.text()
            .starts_with("mcm-rt stopped publishing its state without shutting down")
    );
}

#[tokio::test]
async fn last_words_are_the_notice_still_due_then_the_gateways_own() {
    let (tx, rx) = watch::channel(sample(0));
    let mut w = CoreWatch::new(rx);
    let running: Vec<Notice> = w.last_words().collect();
    assert_eq!(
        running,
        [Notice::GatewayStopping],
        "the core runs: nothing to tell of it"
    );
    tx.send_replace(None);
    let vanished: Vec<Notice> = w.last_words().collect();
    assert_eq!(vanished, [Notice::RtVanished, Notice::GatewayStopping]);
}
