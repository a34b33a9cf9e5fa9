use super::{DdsEnded, DdsThreads};
use std::sync::mpsc::channel;

#[test]
fn a_thread_that_ends_is_seen() {
    let (started_tx, started) = channel();
    let (end_tx, end) = channel::<()>();
    let t = std::thread::Builder::new()
        .name("RustDDS check".into())
        .spawn(move || {
            started_tx.send(()).expect("the test waits");
            let _ = end.recv();
        })
        .expect("a thread");
    started.recv().expect("the thread started");
    let threads = DdsThreads::find();
    assert_eq!(threads.check(), Ok(()));
    assert!(
        !threads.tids.is_empty(),
        "the thread named RustDDS was found"
    );
    drop(end_tx);
    t.join().expect("the thread ends");
    assert_eq!(
        threads.check(),
        Err(DdsEnded {
            ended: 1,
            total: threads.tids.len()
        })
    );
}
