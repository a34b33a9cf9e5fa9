//! An in-memory CAN wire with two ends, for running the virtual arm against a master in one
//! process without a kernel (the tests do): a frame one end sends is received by the other, in
//! order, at once; nothing is lost. Single-threaded (`Rc`).
//!
//! ```
//! use mcm_bus::{Bus, Frame};
//! let (mut a, mut b) = mcm_virtual_arm::memory_wire::pair();
//! a.send(&Frame::new(0x080, &[]).unwrap()).unwrap();
//! assert_eq!(b.recv(0).unwrap().map(|f| f.id), Some(0x080));
//! assert_eq!(a.recv(0).unwrap(), None);
//! ```

use mcm_bus::{Bus, BusError, Frame};
use std::cell::RefCell;
use std::collections::VecDeque;
use std::rc::Rc;

type Queue = Rc<RefCell<VecDeque<Frame>>>;

/// One end of the wire.
#[derive(Debug)]
pub struct End {
    rx: Queue,
    tx: Queue,
}

/// Two connected ends.
pub fn pair() -> (End, End) {
    let (a, b) = (Queue::default(), Queue::default());
    (
        End {
            rx: Rc::clone(&a),
            tx: Rc::clone(&b),
        },
        End { rx: b, tx: a },
    )
}

impl Bus for End {
    fn send(&mut self, frame: &Frame) -> Result<(), BusError> {
        self.tx.borrow_mut().push_back(*frame);
        Ok(())
    }

    /// The deadline is not waited for: a frame is there or not.
    fn recv(&mut self, _deadline_ns: u64) -> Result<Option<Frame>, BusError> {
        Ok(self.rx.borrow_mut().pop_front())
    }
}
