//! Fixed-capacity FIFO ring of PVT points: the queue of `pvt_points` (docs/protocol.md,
//! "pvt_points"). Every operation is O(1) per point, allocation- and panic-free: usable
//! **inside the cycle**.
//!
//! A batch (one `pvt_points` command) is queued atomically: either all of its points fit and are
//! appended, or nothing is queued and [`QueueFull`] says how many were offered and how many
//! places were free. Points are plain data; validating them (e.g. with
//! [`super::PvtSegment::check`] from [`PvtQueue::last`] through the batch) is the caller's job,
//! before pushing.
//!
//! The ring is stored inline (`N` × 96 bytes, ≈ 96 KiB for the default 1024): create it once
//! at start-up (e.g. in a `Box` or a long-lived struct) and reuse it with [`PvtQueue::clear`].
//!
//! ```
//! use mcm_rt_core::trajectory::{PvtPoint, PvtQueue};
//! let mut q: PvtQueue<4> = PvtQueue::new();
//! q.push_batch(&[PvtPoint::default(); 3]).unwrap();
//! let err = q.push_batch(&[PvtPoint::default(); 2]).unwrap_err();
//! assert_eq!((err.offered, err.free, q.len()), (2, 1, 3)); // nothing of the batch was queued
//! assert!(q.pop().is_some());
//! ```

use super::QueueFull;
use mcm_shared::NUM_AXES;

/// Default capacity; the protocol requires at least 1000 points.
pub const DEFAULT_PVT_CAPACITY: usize = 1024;
const _: () = assert!(DEFAULT_PVT_CAPACITY >= 1000);

/// One PVT point of all six axes (rad, rad/s). Points are spaced by the stream's `dt`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PvtPoint {
    pub position: [f64; NUM_AXES],
    pub velocity: [f64; NUM_AXES],
}

impl PvtPoint {
    pub const ZERO: PvtPoint = PvtPoint {
        position: [0.0; NUM_AXES],
        velocity: [0.0; NUM_AXES],
    };
}

/// FIFO ring of at most `N` PVT points (`N` > 0, checked at compile time): a
/// [`heapless::Deque`] with the all-or-nothing batch push the protocol needs.
#[derive(Clone)]
pub struct PvtQueue<const N: usize = DEFAULT_PVT_CAPACITY> {
    buf: heapless::Deque<PvtPoint, N>,
}

impl<const N: usize> PvtQueue<N> {
    /// An empty queue.
    pub const fn new() -> Self {
        const { assert!(N > 0, "a PvtQueue needs a capacity > 0") };
        PvtQueue {
            buf: heapless::Deque::new(),
        }
    }

    pub const fn capacity(&self) -> usize {
        N
    }

    pub fn len(&self) -> usize {
        self.buf.len()
    }

    pub fn is_empty(&self) -> bool {
        self.buf.is_empty()
    }

    pub fn is_full(&self) -> bool {
        self.buf.is_full()
    }

    /// Free places.
    pub fn free(&self) -> usize {
        N - self.buf.len()
    }

    /// Appends all `points` in order, or none of them if they do not all fit.
    pub fn push_batch(&mut self, points: &[PvtPoint]) -> Result<(), QueueFull> {
        let free = self.free();
        if points.len() > free {
            return Err(QueueFull {
                offered: points.len(),
                free,
                capacity: N,
            });
        }
        for p in points {
            // Cannot fail: the room was checked above.
            let _ = self.buf.push_back(*p);
        }
        Ok(())
    }

    /// Appends one point (a batch of one).
    pub fn push(&mut self, point: PvtPoint) -> Result<(), QueueFull> {
        self.push_batch(core::slice::from_ref(&point))
    }

    /// Removes and returns the oldest point.
    pub fn pop(&mut self) -> Option<PvtPoint> {
        self.buf.pop_front()
    }

    /// The oldest point, without removing it.
    pub fn peek(&self) -> Option<&PvtPoint> {
        self.buf.front()
    }

    /// The `i`-th point from the oldest (0 = oldest), if queued.
    pub fn get(&self, i: usize) -> Option<&PvtPoint> {
        let (older, newer) = self.buf.as_slices();
        match i.checked_sub(older.len()) {
            None => older.get(i),
            Some(j) => newer.get(j),
        }
    }

    /// The newest point: where the next batch must continue from.
    pub fn last(&self) -> Option<&PvtPoint> {
        self.buf.back()
    }

    /// Points from oldest to newest.
    pub fn iter(&self) -> impl Iterator<Item = &PvtPoint> + '_ {
        self.buf.iter()
    }

    /// Drops every queued point.
    pub fn clear(&mut self) {
        self.buf.clear();
    }
}

impl<const N: usize> Default for PvtQueue<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> core::fmt::Debug for PvtQueue<N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("PvtQueue")
            .field("len", &self.len())
            .field("capacity", &N)
            .finish()
    }
}

#[cfg(test)]
mod tests;
