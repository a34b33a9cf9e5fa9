//! The requests of a shared-memory client whose reply a call waits for, and their replies once
//! read from the reply blocks. A call sends its requests through [`Pending::send_each`], which
//! forgets the whole batch when a send fails, and forgets what it waited for when it ends, so
//! nothing is waited for after its call.

use super::SendError;
use mcm_shared::sample::Reply;
use std::collections::{HashMap, HashSet};

#[derive(Debug, Default)]
pub(crate) struct Pending {
    waiting: HashSet<u64>,
    answers: HashMap<u64, Reply>,
    /// Replies were overwritten while a request waited.
    lost: bool,
}

impl Pending {
    /// Send each of `requests` in order with `send` (which publishes one and returns its
    /// request id), the ids into `ids`; every request sent is waited for. When a send fails,
    /// none of the batch is waited for any more (the replies of those sent are dropped as they
    /// come) and its error is returned.
    pub(crate) fn send_each<R>(
        &mut self,
        requests: &[R],
        ids: &mut [u64],
        mut send: impl FnMut(&R) -> Result<u64, SendError>,
    ) -> Result<(), SendError> {
        for (k, req) in requests.iter().enumerate() {
            match send(req) {
                Ok(id) => {
                    self.waiting.insert(id);
                    ids[k] = id;
                }
                Err(e) => {
                    self.forget(&ids[..k]);
                    return Err(e);
                }
            }
        }
        Ok(())
    }

    /// A reply read from the reply blocks: kept when a call waits for it (`true`).
    pub(crate) fn offer(&mut self, r: &Reply) -> bool {
        if self.waiting.contains(&r.request_id) {
            self.answers.insert(r.request_id, *r);
            true
        } else {
            false
        }
    }

    /// Replies were overwritten before they were read: a request waiting now may never see its
    /// reply.
    pub(crate) fn overwritten(&mut self) {
        if !self.waiting.is_empty() {
            self.lost = true;
        }
    }

    /// The reply to `id` once read; it is no longer waited for.
    pub(crate) fn take(&mut self, id: u64) -> Option<Reply> {
        let r = self.answers.remove(&id)?;
        self.waiting.remove(&id);
        Some(r)
    }

    /// Stop waiting for `ids`; whether replies were overwritten while they waited (then
    /// forgotten too, when nothing else waits).
    pub(crate) fn forget(&mut self, ids: &[u64]) -> bool {
        for id in ids {
            self.waiting.remove(id);
            self.answers.remove(id);
        }
        let lost = self.lost;
        if self.waiting.is_empty() {
            self.lost = false;
        }
        lost
    }

    /// Whether no request is waited for and no reply kept.
    #[cfg(test)]
    pub(crate) fn is_empty(&self) -> bool {
        self.waiting.is_empty() && self.answers.is_empty()
    }
}

#[cfg(test)]
mod tests;
