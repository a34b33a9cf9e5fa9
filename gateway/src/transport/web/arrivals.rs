//! When the bytes of a page's WebSocket message began to arrive, so that a message trickled in
//! is cut like a slow JSON line: a message not complete within `[gateway.connections]
//! line_timeout_s` of its first byte closes the page's connection
//! ([`super::socket::session`]).
//!
//! [`Watched`] wraps the connection's TCP stream and notes the time of the first bytes read
//! after [`Arrivals::message_done`]; [`Arrivals::overdue`] resolves once that is longer ago than
//! the limit. Bytes that arrived together with the end of the message before count from the
//! next read.

use std::io;
use std::pin::Pin;
use std::sync::{Arc, Mutex, PoisonError};
use std::task::{Context, Poll};
use std::time::Duration;
use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};
use tokio::sync::Notify;
use tokio::time::Instant;

#[derive(Default)]
struct Clock {
    /// When the first bytes of the message now arriving were read.
    first: Mutex<Option<Instant>>,
    started: Notify,
}

/// The arrival clock of one connection; cheap to clone.
#[derive(Clone, Default)]
pub struct Arrivals(Arc<Clock>);

impl Arrivals {
    /// `stream`, noting its arrivals on this clock.
    pub fn watch<S>(&self, stream: S) -> Watched<S> {
        Watched {
            inner: stream,
            clock: self.clone(),
        }
    }

    /// A message is complete: the next bytes read start the next one.
    pub fn message_done(&self) {
        *self.0.first.lock().unwrap_or_else(PoisonError::into_inner) = None;
    }

    fn first(&self) -> Option<Instant> {
        *self.0.first.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Resolves when a message has been arriving for longer than `limit`.
    pub async fn overdue(&self, limit: Duration) {
        loop {
            let started = self.0.started.notified();
            if let Some(t) = self.first() {
                tokio::time::sleep_until(t + limit).await;
                return;
            }
            started.await;
        }
    }

    fn arrived(&self) {
        let mut first = self.0.first.lock().unwrap_or_else(PoisonError::into_inner);
        if first.is_none() {
            *first = Some(Instant::now());
            self.0.started.notify_waiters();
        }
    }
}

/// A stream whose reads are noted on an [`Arrivals`] clock.
pub struct Watched<S> {
    inner: S,
    clock: Arrivals,
}

impl<S: AsyncRead + Unpin> AsyncRead for Watched<S> {
    fn poll_read(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        let me = self.get_mut();
        let before = buf.filled().len();
        let read = Pin::new(&mut me.inner).poll_read(cx, buf);
        if matches!(read, Poll::Ready(Ok(()))) && buf.filled().len() > before {
            me.clock.arrived();
        }
        read
    }
}

impl<S: AsyncWrite + Unpin> AsyncWrite for Watched<S> {
    fn poll_write(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &[u8],
    ) -> Poll<io::Result<usize>> {
        Pin::new(&mut self.get_mut().inner).poll_write(cx, buf)
    }

    fn poll_flush(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().inner).poll_flush(cx)
    }

    fn poll_shutdown(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().inner).poll_shutdown(cx)
    }

    fn poll_write_vectored(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[io::IoSlice<'_>],
    ) -> Poll<io::Result<usize>> {
        Pin::new(&mut self.get_mut().inner).poll_write_vectored(cx, bufs)
    }

    fn is_write_vectored(&self) -> bool {
        self.inner.is_write_vectored()
    }
}
