use super::*;
use proptest::prelude::*;
use std::collections::VecDeque;

fn pt(x: f64) -> PvtPoint {
    PvtPoint {
        position: [x; NUM_AXES],
        velocity: [-x; NUM_AXES],
    }
}

fn contents<const N: usize>(q: &PvtQueue<N>) -> Vec<f64> {
    q.iter().map(|p| p.position[0]).collect()
}

#[test]
fn batch_push_is_all_or_nothing() {
    let mut q: PvtQueue<8> = PvtQueue::new();
    q.push_batch(&[pt(1.0), pt(2.0), pt(3.0), pt(4.0), pt(5.0)])
        .unwrap();
    let err = q
        .push_batch(&[pt(6.0), pt(7.0), pt(8.0), pt(9.0)])
        .unwrap_err();
    assert_eq!(
        err,
        QueueFull {
            offered: 4,
            free: 3,
            capacity: 8
        }
    );
    assert!(
        err.to_string()
            .contains("4 points offered but only 3 of 8 places are free"),
        "{err}"
    );
    assert_eq!(contents(&q), [1.0, 2.0, 3.0, 4.0, 5.0]);
    q.push_batch(&[pt(6.0), pt(7.0), pt(8.0)]).unwrap();
    assert!(q.is_full());
    assert_eq!(q.push_batch(&[]), Ok(()));
    assert_eq!(
        q.push(pt(9.0)),
        Err(QueueFull {
            offered: 1,
            free: 0,
            capacity: 8
        })
    );
    assert_eq!(q.last(), Some(&pt(8.0)));
    q.clear();
    assert_eq!(
        (q.len(), q.pop(), q.peek(), q.last()),
        (0, None, None, None)
    );
}

#[test]
fn wraps_around_in_fifo_order() {
    let mut q: PvtQueue<4> = PvtQueue::new();
    q.push_batch(&[pt(1.0), pt(2.0), pt(3.0)]).unwrap();
    assert_eq!(q.pop(), Some(pt(1.0)));
    assert_eq!(q.pop(), Some(pt(2.0)));
    q.push_batch(&[pt(4.0), pt(5.0), pt(6.0)]).unwrap(); // crosses the end of the array
    assert_eq!(q.peek(), Some(&pt(3.0)));
    assert_eq!(q.get(3), Some(&pt(6.0)));
    assert_eq!(q.get(4), None);
    assert_eq!(contents(&q), [3.0, 4.0, 5.0, 6.0]);
    let popped: Vec<_> = std::iter::from_fn(|| q.pop()).collect();
    assert_eq!(popped, [pt(3.0), pt(4.0), pt(5.0), pt(6.0)]);
}

#[test]
fn default_capacity_holds_the_protocols_thousand_points() {
    let mut q: Box<PvtQueue> = Box::default();
    assert!(q.capacity() >= 1000);
    let batch = [pt(0.5); 1000];
    q.push_batch(&batch).unwrap();
    assert_eq!(q.len(), 1000);
}

#[derive(Clone, Debug)]
enum Op {
    Push(usize),
    Pop,
    Clear,
}

proptest! {
    #[test]
    fn behaves_like_a_bounded_deque(
        ops in proptest::collection::vec(
            prop_oneof![4 => (0..7usize).prop_map(Op::Push), 5 => Just(Op::Pop), 1 => Just(Op::Clear)],
            0..200,
        )
    ) {
        let mut q: PvtQueue<10> = PvtQueue::new();
        let mut model: VecDeque<f64> = VecDeque::new();
        let mut next = 0.0;
        for op in ops {
            match op {
                Op::Push(n) => {
                    let batch: Vec<PvtPoint> = (0..n).map(|k| pt(next + k as f64)).collect();
                    let fits = model.len() + n <= 10;
                    let r = q.push_batch(&batch);
                    prop_assert_eq!(r.is_ok(), fits);
                    if fits {
                        model.extend((0..n).map(|k| next + k as f64));
                        next += n as f64;
                    } else {
                        prop_assert_eq!(r, Err(QueueFull { offered: n, free: 10 - model.len(), capacity: 10 }));
                    }
                }
                Op::Pop => prop_assert_eq!(q.pop().map(|p| p.position[0]), model.pop_front()),
                Op::Clear => { q.clear(); model.clear(); }
            }
            prop_assert_eq!(q.len(), model.len());
            prop_assert_eq!(contents(&q), model.iter().copied().collect::<Vec<_>>());
            prop_assert_eq!(q.last().map(|p| p.position[0]), model.back().copied());
        }
    }
}
