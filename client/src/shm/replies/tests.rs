use super::*;

fn reply(seq: u64, client_id: u64) -> Reply {
    Reply {
        seq,
        client_id,
        request_id: seq * 10,
        ..Reply::default()
    }
}

/// The blocks as the core leaves them after writing replies `1..=head`, but only those
/// `written` says (the others' slots still hold an older reply or none).
fn ring(head: u64, written: impl Fn(u64) -> bool) -> Vec<ReplyBlock> {
    let mut blocks = vec![ReplyBlock::default(); REPLY_BLOCKS];
    for n in 1..=head {
        let (key, slot) = reply_location(n);
        if written(n) {
            blocks[key as usize - 1].replies[slot] = reply(n, if n % 2 == 0 { 7 } else { 8 });
        }
    }
    blocks
}

#[test]
fn every_reply_is_handed_on_in_order_each_block_read_once() {
    let blocks = ring(40, |_| true);
    let mut reads = Vec::new();
    let mut got = Vec::new();
    let s = scan(
        2,
        40,
        |key| {
            reads.push(key);
            blocks[key as usize - 1]
        },
        |r| {
            if r.client_id == 7 {
                got.push(r.request_id)
            }
        },
    );
    assert_eq!(s.overwritten, 0);
    assert_eq!(got, (4..=40).step_by(2).map(|n| n * 10).collect::<Vec<_>>());
    // Replies 3 to 40 lie in the blocks of keys 1, 2 and 3.
    assert_eq!(reads, [1, 2, 3]);
}

#[test]
fn a_reader_too_far_behind_counts_the_replies_it_lost() {
    let head = KEPT + 100;
    // Fell 100 + 10 replies behind the ring: the first 100 are gone by number, and 10 more
    // were overwritten while being read (their slots hold newer ones than the ring says).
    let blocks = ring(head, |n| n > 110);
    let mut got = 0;
    let s = scan(0, head, |key| blocks[key as usize - 1], |_| got += 1);
    assert_eq!(s.overwritten, 110);
    assert_eq!(got, KEPT - 10);
}

#[test]
fn nothing_new_reads_nothing() {
    let no_block = |_| -> ReplyBlock { panic!("no read") };
    assert_eq!(
        scan(5, 5, no_block, |_| panic!("no reply")),
        Scan::default()
    );
    // A restarted core numbers from 1 again: nothing to read until it passes the old head.
    assert_eq!(
        scan(500, 3, no_block, |_| panic!("no reply")),
        Scan::default()
    );
}
