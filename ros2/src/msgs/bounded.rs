//! A sequence of a received message kept only up to a limit.
//!
//! A DDS peer decides how long a message's sequences are. [`Bounded`] reads a sequence to its
//! end (the encoding must be consumed), but keeps its elements only while there are at most `N`:
//! a longer one keeps none, only its length, and the node refuses the message with that length
//! and the limit (`crate::trajectory::check_size`). So an oversize goal costs the node no more
//! than one element at a time while it is read, and nothing afterwards.

use serde::de::{Deserialize, Deserializer, SeqAccess, Visitor};
use serde::ser::{Serialize, SerializeSeq, Serializer};
use std::fmt;
use std::marker::PhantomData;

/// A sequence with its length as sent, and its elements when there are at most `N`.
#[derive(Debug, Clone, PartialEq)]
pub struct Bounded<T, const N: usize> {
    items: Vec<T>,
    len: usize,
}

impl<T, const N: usize> Bounded<T, N> {
    /// The limit.
    pub const MAX: usize = N;

    /// The length as sent (also when the elements were not kept).
    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Whether the sequence was longer than `N` (its elements were not kept).
    pub fn oversize(&self) -> bool {
        self.len > N
    }

    /// Append an element (a sequence being built, not one received oversize).
    pub fn push(&mut self, item: T) {
        self.items.push(item);
        self.len = self.items.len();
    }

    /// Remove the last element (a sequence being built, not one received oversize).
    pub fn pop(&mut self) -> Option<T> {
        let last = self.items.pop();
        self.len = self.items.len();
        last
    }
}

impl<T, const N: usize> Default for Bounded<T, N> {
    fn default() -> Self {
        Bounded {
            items: Vec::new(),
            len: 0,
        }
    }
}

impl<T, const N: usize> From<Vec<T>> for Bounded<T, N> {
    fn from(items: Vec<T>) -> Self {
        let len = items.len();
        Bounded { items, len }
    }
}

/// The elements kept: all of them, or none for an oversize sequence.
impl<T, const N: usize> std::ops::Deref for Bounded<T, N> {
    type Target = [T];
    fn deref(&self) -> &[T] {
        &self.items
    }
}

impl<T, const N: usize> std::ops::DerefMut for Bounded<T, N> {
    fn deref_mut(&mut self) -> &mut [T] {
        &mut self.items
    }
}

impl<'a, T, const N: usize> IntoIterator for &'a Bounded<T, N> {
    type Item = &'a T;
    type IntoIter = std::slice::Iter<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.items.iter()
    }
}

impl<'a, T, const N: usize> IntoIterator for &'a mut Bounded<T, N> {
    type Item = &'a mut T;
    type IntoIter = std::slice::IterMut<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.items.iter_mut()
    }
}

impl<T: PartialEq, const N: usize> PartialEq<Vec<T>> for Bounded<T, N> {
    fn eq(&self, other: &Vec<T>) -> bool {
        self.len == other.len() && self.items == *other
    }
}

impl<T: Serialize, const N: usize> Serialize for Bounded<T, N> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(self.items.len()))?;
        for item in &self.items {
            seq.serialize_element(item)?;
        }
        seq.end()
    }
}

impl<'de, T: Deserialize<'de>, const N: usize> Deserialize<'de> for Bounded<T, N> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Elements<T, const N: usize>(PhantomData<T>);
        impl<'de, T: Deserialize<'de>, const N: usize> Visitor<'de> for Elements<T, N> {
            type Value = Bounded<T, N>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "a sequence")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut items = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(N));
                let mut len = 0usize;
                while let Some(item) = seq.next_element::<T>()? {
                    len += 1;
                    if len <= N {
                        items.push(item);
                    } else if !items.is_empty() {
                        items = Vec::new();
                    }
                }
                Ok(Bounded { items, len })
            }
        }
        d.deserialize_seq(Elements::<T, N>(PhantomData))
    }
}

#[cfg(test)]
mod tests;
